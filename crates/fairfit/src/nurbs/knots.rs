//! Knot vectors: validation, span search (NURBS Book A2.1), multiplicities.

use crate::errors::{Error, Result};

/// Relative tolerance used to decide whether two knots coincide.
pub const KNOT_EPS: f64 = 1e-12;

/// Highest degree accepted anywhere (and the most degree elevation produces). Evaluation needs
/// `(p + 1)²` scratch values and `O(p²)` work per point, so a degree read from a file (up to
/// `usize::MAX`) must be bounded; no practical curve or surface comes near it (the CLI fits degree 15
/// at most).
pub const MAX_DEGREE: usize = 40;

/// Checks a knot vector for a curve of `degree` with `n_ctrl` control points.
///
/// Requires `1 <= degree <= MAX_DEGREE`, `len == n_ctrl + degree + 1`, finite values, non-decreasing
/// order, a range `U[last] - U[0]` that is finite in `f64`, interior multiplicities `<= degree + 1`
/// and a non-empty domain `[U[p], U[n+1]]`. Clamped and unclamped vectors are accepted.
pub fn validate_knots(knots: &[f64], degree: usize, n_ctrl: usize, what: &str) -> Result<()> {
    if degree == 0 {
        return Err(Error::InvalidDegree {
            degree,
            reason: "the degree must be at least 1".into(),
        });
    }
    if degree > MAX_DEGREE {
        return Err(Error::InvalidDegree {
            degree,
            reason: format!("{what}: the degree must be at most {MAX_DEGREE}"),
        });
    }
    if n_ctrl < degree + 1 {
        return Err(Error::InvalidDegree {
            degree,
            reason: format!(
                "{what}: degree {degree} needs at least {} control points, got {n_ctrl}",
                degree + 1
            ),
        });
    }
    let expected = n_ctrl + degree + 1;
    if knots.len() != expected {
        return Err(Error::InvalidKnots(format!(
            "{what}: expected {expected} knots (control points {n_ctrl} + degree {degree} + 1), got {}",
            knots.len()
        )));
    }
    if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
        return Err(Error::InvalidKnots(format!(
            "{what}: knot {i} is not finite ({})",
            knots[i]
        )));
    }
    if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
        return Err(Error::InvalidKnots(format!(
            "{what}: knots must not decrease, but knot {} = {} > knot {} = {}",
            i,
            knots[i],
            i + 1,
            knots[i + 1]
        )));
    }
    // every basis function divides by knot differences: a range beyond f64 (e.g. -1e308 to 1e308)
    // would make them infinite and every point 0
    let (first, last) = (knots[0], knots[knots.len() - 1]);
    if !(last - first).is_finite() {
        return Err(Error::InvalidKnots(format!(
            "{what}: the knots run from {first:e} to {last:e}, a range beyond the floating-point limit; rescale the parameters"
        )));
    }
    // nor so short (subnormal, below about 5.6e-309) that 1 / range overflows: every point would be
    // undefined (plot, eval and info would each fail differently)
    if last > first && !(1.0 / (last - first)).is_finite() {
        return Err(Error::InvalidKnots(format!(
            "{what}: the knots run from {first:e} to {last:e}, a range below the floating-point limit; rescale the parameters"
        )));
    }
    let (a, b) = (knots[degree], knots[n_ctrl]);
    if b - a <= 0.0 {
        return Err(Error::InvalidKnots(format!(
            "{what}: the domain [{a}, {b}] is empty"
        )));
    }
    // interior multiplicity at most p+1 (p+1 gives a discontinuity, still a valid B-spline)
    let mut i = 0;
    while i < knots.len() {
        let mut j = i;
        while j + 1 < knots.len() && knots[j + 1] == knots[i] {
            j += 1;
        }
        let mult = j - i + 1;
        if i > 0 && j + 1 < knots.len() && mult > degree + 1 {
            return Err(Error::InvalidKnots(format!(
                "{what}: interior knot {} has multiplicity {mult}, more than degree + 1 = {}",
                knots[i],
                degree + 1
            )));
        }
        i = j + 1;
    }
    Ok(())
}

/// Index `i` of the knot span `[U[i], U[i+1])` holding `u`, with `p <= i <= n` (NURBS Book A2.1).
///
/// `n` is the index of the last control point. Parameters at or beyond `U[n+1]` map to the last
/// non-empty span, so the end of the domain evaluates correctly. Binary search: O(log n).
#[inline]
pub fn find_span(n: usize, p: usize, u: f64, knots: &[f64]) -> usize {
    if u >= knots[n + 1] {
        // last non-empty span
        let mut i = n;
        while i > p && knots[i] >= knots[n + 1] {
            i -= 1;
        }
        return i;
    }
    if u <= knots[p] {
        let mut i = p;
        while i < n && knots[i + 1] <= knots[p] {
            i += 1;
        }
        return i;
    }
    let (mut low, mut high) = (p, n + 1);
    let mut mid = (low + high) / 2;
    while u < knots[mid] || u >= knots[mid + 1] {
        if u < knots[mid] {
            high = mid;
        } else {
            low = mid;
        }
        mid = (low + high) / 2;
    }
    mid
}

/// Multiplicity of the value `u` in `knots` (exact comparison).
pub fn multiplicity(knots: &[f64], u: f64) -> usize {
    knots.iter().filter(|&&k| k == u).count()
}

/// The distinct knot values inside the domain `[U[p], U[n+1]]`, including both ends, ascending.
pub fn distinct_breakpoints(knots: &[f64], degree: usize) -> Vec<f64> {
    let n1 = knots.len() - degree - 1;
    let (a, b) = (knots[degree], knots[n1]);
    let mut out: Vec<f64> = Vec::new();
    for &k in &knots[degree..=n1] {
        if k >= a && k <= b && out.last().is_none_or(|&l| k > l) {
            out.push(k);
        }
    }
    out
}

/// True when the first and last `degree + 1` knots are equal (clamped, "open" knot vector).
pub fn is_clamped(knots: &[f64], degree: usize) -> bool {
    let m = knots.len();
    knots[..=degree].iter().all(|&k| k == knots[0])
        && knots[m - degree - 1..].iter().all(|&k| k == knots[m - 1])
}

/// True when `knots` is a periodic knot vector of degree `degree` as
/// [`crate::fit::lsq::periodic_knots`] builds it: unclamped, at least `degree + 1` distinct spans, and
/// `knots[i + n_u] − knots[i]` equal to the domain's length for every `i` (relative 1e-12), where `n_u`
/// is the number of distinct control points (`knots.len() − 2·degree − 1`).
///
/// ```
/// use fairfit::fit::lsq::periodic_knots;
/// use fairfit::nurbs::knots::is_periodic;
/// let k = periodic_knots(&[0.0, 0.2, 0.5, 0.7, 1.0], 3);
/// assert!(is_periodic(&k, 3));
/// assert!(!is_periodic(&[0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0], 3)); // clamped
/// assert!(!is_periodic(&[-0.3, -0.2, -0.1, 0.0, 0.4, 1.0, 1.1, 1.2, 1.3], 3)); // spans do not repeat
/// ```
pub fn is_periodic(knots: &[f64], degree: usize) -> bool {
    let p = degree;
    if p == 0 || knots.len() < 2 * p + 2 {
        return false;
    }
    let n = knots.len() - p - 1;
    if n < 2 * p + 1 || is_clamped(knots, p) {
        return false;
    }
    let nu = n - p;
    let period = knots[n] - knots[p];
    let tol = 1e-12
        * period
            .abs()
            .max(knots.iter().fold(0.0f64, |a, &x| a.max(x.abs())));
    period > 0.0
        && (0..knots.len() - nu).all(|i| ((knots[i + nu] - knots[i]) - period).abs() <= tol)
}

/// A clamped knot vector on `[0, 1]` with `n_ctrl` control points and uniform interior knots.
pub fn uniform_clamped(degree: usize, n_ctrl: usize) -> Vec<f64> {
    let spans = n_ctrl - degree;
    let mut k = vec![0.0; degree + 1];
    for i in 1..spans {
        k.push(i as f64 / spans as f64);
    }
    k.extend(std::iter::repeat_n(1.0, degree + 1));
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn span_search_matches_linear_scan() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0];
        let (n, p) = (7, 3);
        for k in 0..=1000 {
            let u = k as f64 / 1000.0;
            let s = find_span(n, p, u, &knots);
            assert!(
                knots[s] <= u && (u < knots[s + 1] || (u == 1.0 && s == n)),
                "u={u} s={s}"
            );
            assert!(knots[s] < knots[s + 1]);
        }
    }

    #[test]
    fn validation_names_the_problem() {
        let e = validate_knots(&[0.0, 0.0, 1.0], 1, 2, "curve").unwrap_err();
        assert!(e.to_string().contains("expected 4 knots"), "{e}");
        let e = validate_knots(&[0.0, 0.5, 0.2, 1.0], 1, 2, "curve").unwrap_err();
        assert!(e.to_string().contains("must not decrease"), "{e}");
        let e = validate_knots(&[0.0, f64::NAN, 1.0, 1.0], 1, 2, "curve").unwrap_err();
        assert!(e.to_string().contains("not finite"), "{e}");
        assert!(validate_knots(&uniform_clamped(3, 7), 3, 7, "curve").is_ok());
        // finite knots whose range overflows: every basis function would be 0
        let e = validate_knots(&[-1e308, -1e308, 1e308, 1e308], 1, 2, "curve").unwrap_err();
        assert!(
            e.to_string().contains("beyond the floating-point limit"),
            "{e}"
        );
        assert!(validate_knots(&[0.0, 0.0, 1e308, 1e308], 1, 2, "curve").is_ok());
    }
}
