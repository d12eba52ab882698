//! Knot placement for least-squares approximation with clamped knot vectors on `[0, 1]`.
//!
//! - [`averaging_knots`]: the *symmetric* averaging rule (method reconstruction §6.3, as in geomdl's
//!   `compute_knot_vector2`): interior knot `j` sits at the fractional data index `t_j = j m / (n − p + 1)`,
//!   interpolated linearly between the neighbouring parameters. Because `t` is computed in exact integer
//!   arithmetic, reversed data give exactly mirrored knots (the Piegl–Tiller eq. 9.69 form is biased
//!   toward 0, NURBS-Python issue #120).
//! - [`curvature_adaptive_knots`]: equal increments of a density that blends the parameter increments
//!   with the turning of the data, `|θ_k|^α` (after Li et al. 2005, "Adaptive knot placement in B-spline
//!   curve approximation"), so knots crowd where the data turn fast.
//!
//! Both place knots at fractional data indices at least one index apart, which guarantees that every
//! knot span holds a data parameter (the Schoenberg–Whitney condition), so the normal equations are
//! positive definite.

use crate::errors::{Error, Result};
use crate::nurbs::Vec3;

/// The symmetric averaging knot vector (clamped, `n_ctrl + degree + 1` values) for `params` in `[0, 1]`.
///
/// ```
/// use fairfit::fit::knot_placement::averaging_knots;
/// let u: Vec<f64> = (0..10).map(|k| k as f64 / 9.0).collect();
/// let k = averaging_knots(&u, 3, 6).unwrap();
/// // 10 uniform parameters, 6 control points: interior knots at 1/3 and 2/3
/// assert!((k[4] - 1.0 / 3.0).abs() < 1e-15 && (k[5] - 2.0 / 3.0).abs() < 1e-15);
/// ```
pub fn averaging_knots(params: &[f64], degree: usize, n_ctrl: usize) -> Result<Vec<f64>> {
    check_counts(params, degree, n_ctrl)?;
    let m = params.len() - 1;
    let segs = n_ctrl - degree; // n − p + 1 knot spans
    let mut t = Vec::with_capacity(segs.saturating_sub(1));
    for j in 1..segs {
        let num = j * m;
        t.push((num / segs) as f64 + (num % segs) as f64 / segs as f64);
    }
    Ok(clamped_from_indices(params, degree, &mut t))
}

/// Curvature-adaptive knots: interior knots at equal increments of the density
/// `(1 − blend) Δū_k + blend · ψ_k / Σψ`, with `ψ_k` the mean of `|θ|^alpha` (θ the turning angle between
/// neighbouring chords) at the two ends of data interval `k`. `blend = 0` gives parameter-uniform knots;
/// sensible values are `alpha = 0.5`, `blend = 0.5`.
pub fn curvature_adaptive_knots(
    points: &[Vec3],
    params: &[f64],
    degree: usize,
    n_ctrl: usize,
    alpha: f64,
    blend: f64,
) -> Result<Vec<f64>> {
    check_counts(params, degree, n_ctrl)?;
    if points.len() != params.len() {
        return Err(Error::InvalidOption(format!(
            "{} points but {} parameters",
            points.len(),
            params.len()
        )));
    }
    if !(0.0..=1.0).contains(&blend) || alpha.is_nan() || alpha <= 0.0 {
        return Err(Error::InvalidOption(format!(
            "curvature-adaptive knots need alpha > 0 and blend in [0, 1], got {alpha}, {blend}"
        )));
    }
    let m = params.len() - 1;
    let turn: Vec<f64> = (0..=m)
        .map(|k| {
            if k == 0 || k == m {
                0.0
            } else {
                turning_angle(points[k - 1], points[k], points[k + 1]).powf(alpha)
            }
        })
        .collect();
    let psi: Vec<f64> = (0..m).map(|k| 0.5 * (turn[k] + turn[k + 1])).collect();
    let psi_total: f64 = psi.iter().sum();
    let span = params[m] - params[0];
    let dens: Vec<f64> = (0..m)
        .map(|k| {
            let chord = (params[k + 1] - params[k]) / span;
            if psi_total > 0.0 {
                (1.0 - blend) * chord + blend * psi[k] / psi_total
            } else {
                chord
            }
        })
        .collect();
    let total: f64 = dens.iter().sum();
    let segs = n_ctrl - degree;
    let mut t = Vec::with_capacity(segs - 1);
    let (mut k, mut acc) = (0usize, 0.0);
    for j in 1..segs {
        let target = total * j as f64 / segs as f64;
        while k < m - 1 && acc + dens[k] < target {
            acc += dens[k];
            k += 1;
        }
        let frac = if dens[k] > 0.0 {
            ((target - acc) / dens[k]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        t.push(k as f64 + frac);
    }
    Ok(clamped_from_indices(params, degree, &mut t))
}

/// The turning angle (radians, in `[0, π]`) between chords `a→b` and `b→c`; 0 for degenerate chords.
pub(crate) fn turning_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (d1, d2) = (b - a, c - b);
    let (n1, n2) = (d1.norm(), d2.norm());
    if n1 == 0.0 || n2 == 0.0 {
        return 0.0;
    }
    let cross = d1.cross(d2).norm();
    cross.atan2(d1.dot(d2))
}

/// True when every non-empty interior knot span `[U_i, U_{i+1})` of a clamped knot vector holds at
/// least one parameter (the Schoenberg–Whitney condition for least squares with interpolated ends).
pub fn satisfies_schoenberg_whitney(params: &[f64], knots: &[f64], degree: usize) -> bool {
    let n1 = knots.len() - degree - 1;
    let mut k = 0;
    for i in degree..n1 {
        let (a, b) = (knots[i], knots[i + 1]);
        if b <= a {
            continue;
        }
        while k < params.len() && params[k] < a {
            k += 1;
        }
        let last = i + 1 == n1;
        if k >= params.len() || !(params[k] < b || (last && params[k] <= b)) {
            return false;
        }
    }
    true
}

fn check_counts(params: &[f64], degree: usize, n_ctrl: usize) -> Result<()> {
    if degree == 0 {
        return Err(Error::InvalidDegree {
            degree,
            reason: "the degree must be at least 1".into(),
        });
    }
    if n_ctrl < degree + 1 {
        return Err(Error::InvalidOption(format!(
            "degree {degree} needs at least {} control points, got {n_ctrl}",
            degree + 1
        )));
    }
    if n_ctrl > params.len() {
        return Err(Error::InvalidOption(format!(
            "{n_ctrl} control points need at least as many data points, got {}",
            params.len()
        )));
    }
    if params
        .windows(2)
        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(Error::InvalidData(
            "data parameters must increase strictly".into(),
        ));
    }
    Ok(())
}

/// `t_j >= t_{j-1} + 1`, `t_0 >= 1`.
fn spread_forward(t: &mut [f64]) {
    let mut prev = 0.0;
    for v in t.iter_mut() {
        *v = v.max(prev + 1.0);
        prev = *v;
    }
}

/// `t_j <= t_{j+1} - 1`, `t_last <= m - 1`.
fn spread_backward(t: &mut [f64], m: usize) {
    let mut next = m as f64;
    for v in t.iter_mut().rev() {
        *v = v.min(next - 1.0);
        next = *v;
    }
}

/// Spreads fractional indices at least one apart inside `[1, m − 1]` (keeping order), then builds
/// the clamped knot vector on `[params[0], params[m]]`.
fn clamped_from_indices(params: &[f64], degree: usize, t: &mut [f64]) -> Vec<f64> {
    let m = params.len() - 1;
    let s = t.len();
    // forward-then-backward and backward-then-forward repairs, averaged: both are feasible (the
    // constraints are convex) and the average treats both ends alike, so reversal mirrors exactly
    let mut fb = t.to_vec();
    spread_forward(&mut fb);
    spread_backward(&mut fb, m);
    spread_backward(t, m);
    spread_forward(t);
    for (v, w) in t.iter_mut().zip(&fb) {
        *v = 0.5 * (*v + w);
    }
    let mut knots = Vec::with_capacity(s + 2 * (degree + 1));
    knots.extend(std::iter::repeat_n(params[0], degree + 1));
    for &v in t.iter() {
        let i = (v.floor() as usize).min(m - 1);
        let a = v - i as f64;
        knots.push((1.0 - a) * params[i] + a * params[i + 1]);
    }
    knots.extend(std::iter::repeat_n(params[m], degree + 1));
    knots
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::parameterize::{parameterize, Parameterization};

    fn wavy(n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|k| {
                let x = k as f64 / (n - 1) as f64;
                Vec3::new(x + 0.1 * x * x, (6.0 * x).sin() * 0.3 + x * x * x, 0.0)
            })
            .collect()
    }

    #[test]
    fn symmetric_rule_matches_the_reference_values() {
        // method §6.3: 10 uniform params, n = 5, p = 3 → {1/3, 2/3}; 101 params, n = 9 → 1/7 first
        let u: Vec<f64> = (0..101).map(|k| k as f64 / 100.0).collect();
        let k = averaging_knots(&u, 3, 10).unwrap();
        assert!((k[4] - 1.0 / 7.0).abs() < 1e-15, "{}", k[4]);
        assert_eq!(k.len(), 14);
    }

    #[test]
    fn reversed_data_give_mirrored_knots() {
        for n_ctrl in [4, 5, 9, 17, 33] {
            let pts = wavy(57);
            let u = parameterize(&pts, Parameterization::Centripetal).unwrap();
            let rev: Vec<Vec3> = pts.iter().rev().copied().collect();
            let ur = parameterize(&rev, Parameterization::Centripetal).unwrap();
            for (kf, kr) in [
                (
                    averaging_knots(&u, 3, n_ctrl),
                    averaging_knots(&ur, 3, n_ctrl),
                ),
                (
                    curvature_adaptive_knots(&pts, &u, 3, n_ctrl, 0.5, 0.5),
                    curvature_adaptive_knots(&rev, &ur, 3, n_ctrl, 0.5, 0.5),
                ),
            ] {
                let (kf, kr) = (kf.unwrap(), kr.unwrap());
                for (a, b) in kf.iter().zip(kr.iter().rev()) {
                    assert!(
                        (a - (1.0 - b)).abs() < 1e-12,
                        "n={n_ctrl}: {a} vs {}",
                        1.0 - b
                    );
                }
            }
        }
    }

    #[test]
    fn every_span_holds_a_parameter() {
        // very uneven parameters: dense cluster then sparse
        let mut u: Vec<f64> = (0..40).map(|k| 0.01 * k as f64 / 39.0).collect();
        u.extend((1..10).map(|k| 0.01 + 0.99 * k as f64 / 9.0));
        let pts: Vec<Vec3> = u.iter().map(|&x| Vec3::new(x, x * x, 0.0)).collect();
        for n in 4..=u.len() {
            let k = averaging_knots(&u, 3, n).unwrap();
            assert!(satisfies_schoenberg_whitney(&u, &k, 3), "n={n}");
            let k = curvature_adaptive_knots(&pts, &u, 3, n, 0.5, 0.9).unwrap();
            assert!(satisfies_schoenberg_whitney(&u, &k, 3), "adaptive n={n}");
            assert!(k.windows(2).all(|w| w[1] >= w[0]));
        }
    }

    #[test]
    fn adaptive_knots_crowd_where_the_data_turn() {
        // a straight run then a tight arc: most knots go to the arc
        let mut pts: Vec<Vec3> = (0..50)
            .map(|k| Vec3::new(k as f64 / 49.0 * 5.0, 0.0, 0.0))
            .collect();
        for k in 1..50 {
            let a = std::f64::consts::PI * k as f64 / 49.0;
            pts.push(Vec3::new(5.0 + 0.3 * a.sin(), 0.3 - 0.3 * a.cos(), 0.0));
        }
        let u = parameterize(&pts, Parameterization::ChordLength).unwrap();
        let arc_start = u[49];
        let k_avg = averaging_knots(&u, 3, 14).unwrap();
        let k_ad = curvature_adaptive_knots(&pts, &u, 3, 14, 0.5, 0.8).unwrap();
        let count = |k: &[f64]| k[4..14].iter().filter(|&&x| x > arc_start).count();
        assert!(
            count(&k_ad) > count(&k_avg) + 2,
            "{} vs {}",
            count(&k_ad),
            count(&k_avg)
        );
    }

    #[test]
    fn turning_angles() {
        let o = Vec3::ZERO;
        let x = Vec3::new(1.0, 0.0, 0.0);
        let y = Vec3::new(1.0, 1.0, 0.0);
        assert!((turning_angle(o, x, y) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!(turning_angle(o, x, Vec3::new(2.0, 0.0, 0.0)).abs() < 1e-15);
    }
}
