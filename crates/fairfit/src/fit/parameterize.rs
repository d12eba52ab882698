//! Parameterisation of ordered points: uniform, chord length and centripetal (method reconstruction
//! §6.2), mapped onto `[0, 1]`.
//!
//! The default is **centripetal** (Lee 1989, exponent 1/2): it follows the data's arc length closely
//! enough for the least-squares fit to be accurate, yet gives more parameter room than chord length to
//! regions where the points are dense and turn fast (an airfoil's leading edge), which avoids the
//! overshoots and loops chord length produces there, and it is less sensitive to uneven spacing. Knot
//! placement by averaging follows the parameters, so the extra room becomes extra knots where the shape
//! needs them. Parameter correction later moves the parameters toward the orthogonal feet anyway.

use crate::errors::{Error, Result};
use crate::nurbs::Vec3;

/// How data parameters are assigned.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parameterization {
    /// `ū_k = k / m`.
    Uniform,
    /// Increments proportional to the chord `|Q_k − Q_{k−1}|`.
    ChordLength,
    /// Increments proportional to `|Q_k − Q_{k−1}|^{1/2}` (the default; see the module docs).
    #[default]
    Centripetal,
}

impl Parameterization {
    /// The exponent applied to chord lengths (0 for uniform).
    pub fn exponent(self) -> f64 {
        match self {
            Parameterization::Uniform => 0.0,
            Parameterization::ChordLength => 1.0,
            Parameterization::Centripetal => 0.5,
        }
    }
}

/// Parameters of `points` in `[0, 1]` (first 0, last 1) for an open curve.
///
/// ```
/// use fairfit::fit::parameterize::{parameterize, Parameterization};
/// use fairfit::Vec3;
/// let q = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0)];
/// let u = parameterize(&q, Parameterization::ChordLength).unwrap();
/// assert_eq!(u, vec![0.0, 0.25, 1.0]);
/// ```
pub fn parameterize(points: &[Vec3], method: Parameterization) -> Result<Vec<f64>> {
    let mut out = Vec::with_capacity(points.len());
    parameterize_into(points, method, false, &mut out)?;
    Ok(out)
}

/// Parameters written into `out`. With `closed`, the closing chord `Q_m → Q_0` counts too and the
/// parameters lie in `[0, 1)` (the point after the last is `Q_0` again at 1).
pub(crate) fn parameterize_into(
    points: &[Vec3],
    method: Parameterization,
    closed: bool,
    out: &mut Vec<f64>,
) -> Result<()> {
    out.clear();
    if points.len() < 2 {
        return Err(Error::InvalidData(format!(
            "at least 2 points are needed to parameterise, got {}",
            points.len()
        )));
    }
    let e = method.exponent();
    let mut acc = 0.0;
    out.push(0.0);
    for w in points.windows(2) {
        acc += step(w[1] - w[0], e);
        out.push(acc);
    }
    let total = if closed {
        out.pop();
        let last = points[points.len() - 1];
        let closing = step(points[0] - last, e);
        out.push(acc);
        acc + closing
    } else {
        acc
    };
    if !total.is_finite() {
        return Err(Error::InvalidData(
            "the points are too far apart to measure (coordinates near the floating-point limit): rescale the data".into(),
        ));
    }
    if total.is_nan() || total <= 0.0 {
        return Err(Error::InvalidData(
            "all points coincide: the data have no length to parameterise".into(),
        ));
    }
    for u in out.iter_mut() {
        *u /= total;
    }
    if !closed {
        if let Some(l) = out.last_mut() {
            *l = 1.0;
        }
    }
    Ok(())
}

fn step(d: Vec3, e: f64) -> f64 {
    if e == 0.0 {
        1.0
    } else {
        d.norm().powf(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts() -> Vec<Vec3> {
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(4.0, 9.0, 0.0),
            Vec3::new(4.0, 10.0, 0.0),
        ]
    }

    #[test]
    fn three_rules_against_hand_values() {
        let u = parameterize(&pts(), Parameterization::Uniform).unwrap();
        assert_eq!(u, vec![0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]);
        let c = parameterize(&pts(), Parameterization::ChordLength).unwrap();
        assert!((c[1] - 4.0 / 14.0).abs() < 1e-15 && (c[2] - 13.0 / 14.0).abs() < 1e-15);
        let s = parameterize(&pts(), Parameterization::Centripetal).unwrap();
        assert!((s[1] - 2.0 / 6.0).abs() < 1e-15 && (s[2] - 5.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn closed_counts_the_closing_chord() {
        let sq = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let mut u = Vec::new();
        parameterize_into(&sq, Parameterization::ChordLength, true, &mut u).unwrap();
        assert_eq!(u, vec![0.0, 0.25, 0.5, 0.75]);
    }

    #[test]
    fn coincident_points_are_an_error() {
        let p = [Vec3::new(1.0, 1.0, 0.0); 3];
        assert!(parameterize(&p, Parameterization::ChordLength).is_err());
    }
}
