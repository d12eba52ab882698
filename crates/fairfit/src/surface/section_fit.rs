//! Least-squares fitting of one ordered section on a given (shared) knot vector, with the end points
//! interpolated, an optional smoothing term and orthogonal parameter correction (Hoschek).
//!
//! A private stand-in for the fitting engineer's `fit::lsq` so the surface pipeline works on its own:
//! the systems here are small (a few dozen control points), so dense normal equations with a Cholesky
//! factorisation are used.

#![allow(clippy::needless_range_loop)]

use super::linalg::{cholesky, cholesky_solve, constrain_solution, Dense};
use super::periodic_fit::lsq_periodic_control_points;
use super::seam_tie::lsq_tied_control_points;
use super::section_corners::hold_params;
use crate::diffgeo::CurveProjector;
use crate::errors::{Error, Result};
use crate::nurbs::basis::{basis_funs_into, ders_basis_funs_into};
use crate::nurbs::knots::{find_span, is_clamped, is_periodic};
use crate::nurbs::{NurbsCurve, Vec3};

/// Chord-length parameters of ordered points, normalised to `[0, 1]`.
pub(crate) fn chord_length_params(points: &[Vec3]) -> Result<Vec<f64>> {
    if points.len() < 2 {
        return Err(Error::InvalidData(format!(
            "a section needs at least 2 points, got {}",
            points.len()
        )));
    }
    let mut t = Vec::with_capacity(points.len());
    t.push(0.0);
    let mut s = 0.0;
    for w in points.windows(2) {
        s += w[0].distance(w[1]);
        t.push(s);
    }
    if s.is_nan() || s <= 0.0 || !s.is_finite() {
        return Err(Error::InvalidData(
            "a section has zero length (all points coincide)".into(),
        ));
    }
    for v in t.iter_mut() {
        *v /= s;
    }
    if let Some(last) = t.last_mut() {
        *last = 1.0;
    }
    Ok(t)
}

/// Gram matrix of second derivatives `G_ij = ∫ N_i''(u) N_j''(u) du` (Gauss-Legendre, 4 nodes per span),
/// the parametric bending energy used as smoothing term.
pub(crate) fn bending_gram(degree: usize, knots: &[f64], n_ctrl: usize) -> Dense {
    const GX: [f64; 4] = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    const GW: [f64; 4] = [
        0.347_854_845_137_453_9,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_9,
    ];
    let p = degree;
    let mut g = Dense::zeros(n_ctrl);
    if p < 2 {
        return g;
    }
    let (mut left, mut right) = (vec![0.0; p + 1], vec![0.0; p + 1]);
    let mut ndu = vec![0.0; (p + 1) * (p + 1)];
    let mut a = vec![0.0; 2 * (p + 1)];
    let mut ders = vec![0.0; 3 * (p + 1)];
    for span in p..n_ctrl {
        let (a0, b0) = (knots[span], knots[span + 1]);
        if b0 <= a0 {
            continue;
        }
        for (x, w) in GX.iter().zip(GW) {
            let u = 0.5 * (a0 + b0) + 0.5 * (b0 - a0) * x;
            let jac = 0.5 * (b0 - a0) * w;
            ders_basis_funs_into(
                span, u, p, 2, knots, &mut left, &mut right, &mut ndu, &mut a, &mut ders,
            );
            let d2 = &ders[2 * (p + 1)..3 * (p + 1)];
            for r in 0..=p {
                for c in 0..=p {
                    *g.at(span - p + r, span - p + c) += jac * d2[r] * d2[c];
                }
            }
        }
    }
    g
}

/// A point the least-squares curve passes through exactly: `C(u) = point` (an airfoil's leading edge
/// at its common parameter, [`crate::fit::airfoil`]), imposed as one equality constraint on the
/// normal equations ([`super::linalg`]'s `constrain_solution`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pin<const C: usize> {
    /// The parameter of the pinned point.
    pub(crate) u: f64,
    /// The point the curve passes through at `u`.
    pub(crate) point: [f64; C],
}

impl<const C: usize> Pin<C> {
    /// The index of the first control point acting at `u` on `knots` (`n_ctrl` control points, degree
    /// `p`) and the `p + 1` basis values there.
    pub(crate) fn basis(&self, p: usize, knots: &[f64], n_ctrl: usize) -> (usize, Vec<f64>) {
        let span = find_span(n_ctrl - 1, p, self.u, knots);
        let (mut left, mut right, mut nb) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
        basis_funs_into(span, self.u, p, knots, &mut left, &mut right, &mut nb);
        (span - p, nb)
    }
}

/// Least-squares control points (in `C` coordinates, e.g. 3 for points, 4 for homogeneous points) of a
/// degree-`degree` B-spline on `knots` through `data` at `params`, first and last data interpolated.
/// `smoothing` >= 0 weights the bending energy `∫ |C''(u)|² du` against the mean squared residual (both
/// scale like length², so the weight is scale-free; parameters are assumed in `[0, 1]`). With `pin` the
/// curve passes through the pinned point exactly (the least squares under that constraint).
pub(crate) fn lsq_control_points<const C: usize>(
    data: &[[f64; C]],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    pin: Option<&Pin<C>>,
) -> Result<Vec<[f64; C]>> {
    let m = data.len();
    if m < 2 || params.len() != m {
        return Err(Error::Fit("least squares needs at least 2 points".into()));
    }
    lsq_held_pinned(
        data,
        params,
        degree,
        knots,
        smoothing,
        (&[data[0]], &[data[m - 1]]),
        pin,
    )
}

/// [`lsq_control_points`] with the leading control points held at `front` and the trailing ones at
/// `back` (each at least one: the first and last data points are not fitted, they are taken as held by
/// the end control points of a clamped knot vector, `front[0]` and `back[back.len() - 1]`). Holding two
/// at an end fixes the end derivative as well (skinning's v end tangents).
pub(crate) fn lsq_control_points_held<const C: usize>(
    data: &[[f64; C]],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    front: &[[f64; C]],
    back: &[[f64; C]],
) -> Result<Vec<[f64; C]>> {
    lsq_held_pinned(data, params, degree, knots, smoothing, (front, back), None)
}

/// [`lsq_control_points_held`] (the held control points `(front, back)`) with an optional [`Pin`].
fn lsq_held_pinned<const C: usize>(
    data: &[[f64; C]],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    (front, back): (&[[f64; C]], &[[f64; C]]),
    pin: Option<&Pin<C>>,
) -> Result<Vec<[f64; C]>> {
    let p = degree;
    let n_ctrl = knots.len() - p - 1;
    let m = data.len();
    if m < 2 || params.len() != m {
        return Err(Error::Fit("least squares needs at least 2 points".into()));
    }
    if n_ctrl < 2 {
        return Err(Error::Fit(
            "least squares needs at least 2 control points".into(),
        ));
    }
    let (a, b) = (front.len(), back.len());
    if a == 0 || b == 0 || a + b > n_ctrl {
        return Err(Error::Fit(format!(
            "least squares cannot hold {a} leading and {b} trailing of {n_ctrl} control points"
        )));
    }
    let mut ctrl = vec![[0.0; C]; n_ctrl];
    ctrl[..a].copy_from_slice(front);
    ctrl[n_ctrl - b..].copy_from_slice(back);
    if a + b == n_ctrl {
        return Ok(ctrl);
    }
    let held = |idx: usize| idx < a || idx >= n_ctrl - b;
    let nu = n_ctrl - a - b;
    let mut ntn = Dense::zeros(nu);
    let mut rhs = vec![[0.0; C]; nu];
    let (mut left, mut right, mut nb) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
    for k in 1..m - 1 {
        let u = params[k];
        let span = find_span(n_ctrl - 1, p, u, knots);
        basis_funs_into(span, u, p, knots, &mut left, &mut right, &mut nb);
        let first = span - p;
        // residual after the held control points
        let mut r = data[k];
        for (j, &nj) in nb.iter().enumerate() {
            let idx = first + j;
            if held(idx) {
                for c in 0..C {
                    r[c] -= nj * ctrl[idx][c];
                }
            }
        }
        for (j, &nj) in nb.iter().enumerate() {
            let idx = first + j;
            if held(idx) {
                continue;
            }
            for c in 0..C {
                rhs[idx - a][c] += nj * r[c];
            }
            for (l, &nl) in nb.iter().enumerate() {
                let jdx = first + l;
                if held(jdx) {
                    continue;
                }
                *ntn.at(idx - a, jdx - a) += nj * nl;
            }
        }
    }
    if smoothing > 0.0 {
        let g = bending_gram(p, knots, n_ctrl);
        // objective / m = mean squared residual + smoothing * ∫ |C''(u)|² du: scale-free weight
        let lam = smoothing * m as f64;
        for i in a..n_ctrl - b {
            for j in 0..n_ctrl {
                let gij = lam * g.get(i, j);
                if held(j) {
                    for c in 0..C {
                        rhs[i - a][c] -= gij * ctrl[j][c];
                    }
                } else {
                    *ntn.at(i - a, j - a) += gij;
                }
            }
        }
    }
    cholesky(&mut ntn)?;
    cholesky_solve(&ntn, &mut rhs);
    if let Some(pin) = pin {
        // the constraint on the free control points: the held ones move to its right-hand side
        let (first, nb) = pin.basis(p, knots, n_ctrl);
        let mut row = vec![0.0; nu];
        let mut target = pin.point;
        for (j, &nj) in nb.iter().enumerate() {
            let idx = first + j;
            if held(idx) {
                for c in 0..C {
                    target[c] -= nj * ctrl[idx][c];
                }
            } else {
                row[idx - a] = nj;
            }
        }
        constrain_solution(&ntn, &mut rhs, &row, target);
    }
    ctrl[a..n_ctrl - b].copy_from_slice(&rhs);
    Ok(ctrl)
}

/// Over-relaxation of the parameter correction: the foot-point update converges linearly (tangential
/// drift); stepping 1.5 times the update roughly halves the iterations needed (measured on cubics).
const RELAXATION: f64 = 1.5;

/// Newton on `f(u) = C'(u)·(C(u) − q)` from `u0`, clamped to the domain, accepting only improving steps;
/// returns the best parameter and its distance (never worse than at `u0`).
pub(crate) fn newton_from(curve: &NurbsCurve, q: Vec3, u0: f64, d: &mut [Vec3; 3]) -> (f64, f64) {
    let (a, b) = curve.domain();
    let mut u = u0.clamp(a, b);
    curve.derivatives_into(u, 2, d);
    let mut best = (u, (d[0] - q).norm());
    for _ in 0..12 {
        let r = d[0] - q;
        let f = d[1].dot(r);
        let fp = d[2].dot(r) + d[1].norm_squared();
        if fp <= 0.0 {
            break;
        }
        let next = (u - f / fp).clamp(a, b);
        if next == u {
            break;
        }
        curve.derivatives_into(next, 2, d);
        let dist = (d[0] - q).norm();
        if dist >= best.1 {
            break;
        }
        u = next;
        best = (u, dist);
    }
    best
}

/// One section fitted on a given knot vector.
#[derive(Clone, Debug)]
pub struct SectionFit {
    /// The fitted B-spline curve.
    pub curve: NurbsCurve,
    /// The parameters of the data points on the curve after parameter correction.
    pub params: Vec<f64>,
    /// Largest orthogonal distance from a data point to the curve.
    pub max_deviation: f64,
    /// Root mean square of the orthogonal distances.
    pub rms_deviation: f64,
    /// Index of the data point with the largest distance.
    pub worst_point: usize,
    /// Orthogonal distance of every data point.
    pub deviations: Vec<f64>,
}

/// Fits `points` (initial parameters `params`) on `knots`, then corrects the parameters by orthogonal
/// projection `corrections` times (keeping the best fit seen), and measures orthogonal deviations.
///
/// A clamped knot vector interpolates the first and last point; an unclamped one must be periodic (else
/// [`Error::InvalidKnots`])
/// ([`crate::fit::lsq::periodic_knots`]) and fits the closed section (last point = first) periodically
/// (the private `periodic_fit` module); its deviations are measured on the clamped copy (same geometry on
/// `[0, 1]`), the first and last parameters stay at the seam.
pub fn fit_section(
    points: &[Vec3],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    corrections: usize,
) -> Result<SectionFit> {
    fit_section_with(
        points,
        params,
        degree,
        knots,
        smoothing,
        corrections,
        true,
        0,
        &[],
        None,
    )
}

/// [`fit_section`]; with `global = false` the distances come from Newton started at each point's
/// current parameter only (fast, may overestimate a distance, never underestimates it), for searches.
/// `seam_tie > 0` on a clamped knot vector ties the end derivatives of a closed section up to that order
/// ([`super::seam_tie`]; untied when there are too few control points). `held` lists the points whose
/// parameters stay fixed (the corners held as C0 knots, [`super::section_corners`]): the parameter
/// correction keeps them and never moves another point across one. `pin = Some((k, u))` makes the
/// curve pass through point `k` exactly at `u` (an airfoil's leading edge, [`crate::fit::airfoil`]),
/// in every solver (open, periodic, tied seam), and holds that point's parameter at `u` like a held
/// corner's (without a knot there).
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_section_with(
    points: &[Vec3],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    corrections: usize,
    global: bool,
    seam_tie: usize,
    held: &[(usize, f64)],
    pin: Option<(usize, f64)>,
) -> Result<SectionFit> {
    let data: Vec<[f64; 3]> = points.iter().map(|p| p.0).collect();
    let pinned = pin
        .map(|(k, u)| -> Result<Pin<3>> {
            let q = data.get(k).ok_or_else(|| {
                Error::InvalidData(format!("pinned point {k} of {} points", data.len()))
            })?;
            Ok(Pin { u, point: *q })
        })
        .transpose()?;
    // the held parameters, the pinned point's among them (in point order)
    let mut holds = held.to_vec();
    if let Some((k, u)) = pin {
        holds.push((k, u));
        holds.sort_by_key(|&(i, _)| i);
    }
    let periodic = !is_clamped(knots, degree);
    if periodic && !is_periodic(knots, degree) {
        return Err(Error::InvalidKnots(
            "a section's knot vector must be clamped or periodic (fit::lsq::periodic_knots)".into(),
        ));
    }
    let mut params = params.to_vec();
    if pin.is_some() {
        hold_params(&mut params, &holds);
    }
    let mut best: Option<SectionFit> = None;
    let mut stalls = 0;
    let mut last_rms = f64::INFINITY;
    for _ in 0..=corrections {
        let tied = if periodic || seam_tie == 0 {
            None
        } else {
            lsq_tied_control_points(
                &data,
                &params,
                degree,
                knots,
                smoothing,
                seam_tie,
                pinned.as_ref(),
            )?
        };
        let ctrl = match tied {
            Some(c) => c,
            None if periodic => lsq_periodic_control_points(
                &data,
                &params,
                degree,
                knots,
                smoothing,
                pinned.as_ref(),
            )?,
            None => lsq_control_points(&data, &params, degree, knots, smoothing, pinned.as_ref())?,
        };
        let curve =
            NurbsCurve::bspline(degree, knots.to_vec(), ctrl.into_iter().map(Vec3).collect())?;
        let clamped = if periodic {
            Some(curve.clamped()?)
        } else {
            None
        };
        let measured = clamped.as_ref().unwrap_or(&curve);
        let proj = global.then(|| CurveProjector::new(measured, 8));
        let mut devs = vec![0.0; points.len()];
        let mut new_params = params.clone();
        let mut der = [Vec3::ZERO; 3];
        let (mut maxd, mut sum2, mut worst) = (0.0f64, 0.0, 0);
        for (k, q) in points.iter().enumerate() {
            let (mut u, mut d) = newton_from(measured, *q, params[k], &mut der);
            if let Some(pr) = proj.as_ref().map(|p| p.project_near(*q, params[k])) {
                if pr.distance < d {
                    (u, d) = (pr.u, pr.distance);
                }
            }
            devs[k] = d;
            if k > 0 && k + 1 < points.len() {
                new_params[k] = params[k] + RELAXATION * (u - params[k]);
            }
            sum2 += d * d;
            if d > maxd {
                maxd = d;
                worst = k;
            }
        }
        let fit = SectionFit {
            curve,
            params: params.clone(),
            max_deviation: maxd,
            rms_deviation: (sum2 / points.len() as f64).sqrt(),
            worst_point: worst,
            deviations: devs,
        };
        // the sum of squared distances decreases monotonically under foot-point correction; stop when it
        // stalls, keep the fit with the smallest largest distance
        if fit.rms_deviation < last_rms * (1.0 - 1e-9) {
            stalls = 0;
        } else {
            stalls += 1;
        }
        last_rms = last_rms.min(fit.rms_deviation);
        if best
            .as_ref()
            .is_none_or(|b| fit.max_deviation < b.max_deviation)
        {
            best = Some(fit);
        }
        if stalls >= 3 {
            break;
        }
        // keep parameters strictly increasing so the next system stays well posed
        for k in 1..new_params.len() {
            if new_params[k] < new_params[k - 1] {
                new_params[k] = new_params[k - 1];
            }
        }
        hold_params(&mut new_params, &holds);
        params = new_params;
    }
    best.ok_or_else(|| Error::Fit("no section fit computed".into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_a_cubic_on_its_own_knots() {
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
        let ctrl = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(2.0, -1.0, 0.5),
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(4.0, 0.0, 1.0),
        ];
        let truth = NurbsCurve::bspline(3, knots.clone(), ctrl).unwrap();
        let us: Vec<f64> = (0..40).map(|k| (k as f64 / 39.0).powf(1.3)).collect();
        let pts = truth.points(&us);
        // exact parameters: exact reproduction
        let f = fit_section(&pts, &us, 3, &knots, 0.0, 0).unwrap();
        assert!(f.max_deviation < 1e-12, "{}", f.max_deviation);
        // chord-length parameters plus parameter correction converge towards the same curve
        let t = chord_length_params(&pts).unwrap();
        let f0 = fit_section(&pts, &t, 3, &knots, 0.0, 0).unwrap();
        let f = fit_section(&pts, &t, 3, &knots, 0.0, 30).unwrap();
        assert!(
            f.max_deviation < 0.2 * f0.max_deviation,
            "{} vs {}",
            f.max_deviation,
            f0.max_deviation
        );
    }

    #[test]
    fn unclamped_knots_must_be_periodic() {
        // a circle sampled closed (last point = first)
        let pts: Vec<Vec3> = (0..=40)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 40.0;
                Vec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let us: Vec<f64> = (0..=40).map(|k| k as f64 / 40.0).collect();
        let periodic = crate::fit::lsq::periodic_knots(&[0.0, 0.25, 0.5, 0.75, 1.0], 3);
        let f = fit_section(&pts, &us, 3, &periodic, 0.0, 0).unwrap();
        // 4 distinct control points of a uniform periodic cubic: the least-squares circle is off by
        // 1.45 % of the radius (a clamped or open fit would not even close)
        assert!(f.max_deviation < 0.02, "{}", f.max_deviation);
        let closed = f.curve.point(0.0) - f.curve.point(1.0);
        assert!(closed.norm() < 1e-12, "{}", closed.norm());
        // unclamped but not periodic: a typed error, not a silent open curve
        let mut skewed = periodic.clone();
        skewed[0] -= 0.1;
        let e = fit_section(&pts, &us, 3, &skewed, 0.0, 0).unwrap_err();
        assert!(matches!(e, Error::InvalidKnots(_)), "{e}");
    }

    #[test]
    fn degenerate_sections_are_errors() {
        assert!(chord_length_params(&[Vec3::ZERO]).is_err());
        assert!(chord_length_params(&[Vec3::ZERO, Vec3::ZERO]).is_err());
    }
}
