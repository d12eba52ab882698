//! Numbers as every writer prints them: a negative zero is written as `0`.
//!
//! `-0.0` (e.g. `-(0 · x)`, a mirrored coordinate, a rounded `-0.001`) is the same number as `0.0`
//! but shows up in files as `-0.`, `-0.0` or `-0.00`, which only confuses readers and `diff`. The
//! STEP, IGES, JSON, sample, mesh and SVG writers and the CLI's JSON output all go through these.

/// `x`, with a negative zero replaced by `0.0` (every other value, NaN included, unchanged).
pub fn unsigned_zero(x: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x
    }
}

/// The coordinates of a point, each through [`unsigned_zero`].
pub(crate) fn unsigned_zeros<const N: usize>(p: [f64; N]) -> [f64; N] {
    p.map(unsigned_zero)
}

/// `x` with `decimals` digits after the point (`format!("{x:.decimals$}")`), without the sign of a
/// value that rounds to zero: `-0.001` to 2 decimals is `0.00`, not `-0.00`.
pub fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.bytes().all(|b| b == b'0' || b == b'.') => rest.to_string(),
        _ => s,
    }
}

/// Replaces every number `-0.0` in `v` (at any depth) by `0.0`.
pub fn clear_negative_zeros(v: &mut serde_json::Value) {
    use serde_json::Value;
    match v {
        Value::Number(n) if n.as_f64().is_some_and(|x| x == 0.0 && x.is_sign_negative()) => {
            *v = Value::from(0.0);
        }
        Value::Array(a) => a.iter_mut().for_each(clear_negative_zeros),
        Value::Object(o) => o.values_mut().for_each(clear_negative_zeros),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_zero_becomes_zero_and_nothing_else_changes() {
        assert!(unsigned_zero(-0.0).is_sign_positive());
        assert_eq!(unsigned_zero(-0.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(unsigned_zero(-1e-300), -1e-300);
        assert_eq!(unsigned_zero(2.5), 2.5);
        assert!(unsigned_zero(f64::NAN).is_nan());
        assert_eq!(
            format!("{:?}", unsigned_zeros([-0.0, 1.0, -0.0])),
            "[0.0, 1.0, 0.0]"
        );
    }

    #[test]
    fn fixed_drops_the_sign_of_a_rounded_zero_only() {
        assert_eq!(fixed(-0.001, 2), "0.00");
        assert_eq!(fixed(-0.0, 2), "0.00");
        assert_eq!(fixed(-0.0, 0), "0");
        assert_eq!(fixed(-0.005001, 2), "-0.01");
        assert_eq!(fixed(-12.344, 2), "-12.34");
        assert_eq!(fixed(1.23456, 3), "1.235");
        assert_eq!(fixed(f64::NEG_INFINITY, 2), "-inf");
    }
}
