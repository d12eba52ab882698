//! Orthogonal deviation of data points from a fitted curve: each point is projected onto the curve near
//! its parameter, giving the orthogonal distance and the foot parameter (used for parameter correction).
//! Newton from the hint ([`super::foot`]) is tried first; points it does not settle go to the
//! sampled-then-Newton projection of [`crate::diffgeo::CurveProjector`].

use super::foot::FootFinder;
use crate::diffgeo::CurveProjector;
use crate::nurbs::scale::{normalising_factor, scaled_curve};
use crate::nurbs::{NurbsCurve, Vec3};

/// Samples per knot span used by the projector.
const SAMPLES_PER_SPAN: usize = 8;

/// Deviation of points from a curve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deviation {
    /// Largest orthogonal distance.
    pub max: f64,
    /// Root mean square of the orthogonal distances.
    pub rms: f64,
    /// Orthogonal distance of each point.
    pub per_point: Vec<f64>,
    /// Foot parameter of each point.
    pub params: Vec<f64>,
}

/// Orthogonal deviation of `points` from `curve`, projecting each point near `params_hint[k]` (its
/// fitting parameter; pass an empty slice to search the whole curve).
///
/// ```
/// use fairfit::fit::max_orthogonal_deviation;
/// use fairfit::{NurbsCurve, Vec3};
/// let line = NurbsCurve::bspline(1, vec![0.0, 0.0, 1.0, 1.0],
///     vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0)]).unwrap();
/// let q = [Vec3::new(0.5, 0.1, 0.0), Vec3::new(1.5, -0.3, 0.0)];
/// let d = max_orthogonal_deviation(&line, &q, &[0.2, 0.8]);
/// assert!((d.max - 0.3).abs() < 1e-12);
/// assert!((d.params[0] - 0.25).abs() < 1e-12, "{:?}", d);
/// ```
pub fn max_orthogonal_deviation(
    curve: &NurbsCurve,
    points: &[Vec3],
    params_hint: &[f64],
) -> Deviation {
    // far from unit size (beyond 2^±64) squared distances overflow or underflow: measure an exactly
    // rescaled copy (a power of two) and scale the distances back
    let f = normalising_factor(curve.control_points());
    if f != 1.0 {
        if let Ok(scaled) = scaled_curve(curve, f) {
            let q: Vec<Vec3> = points.iter().map(|&p| p * f).collect();
            let mut d = deviation_at_scale(&scaled, &q, params_hint);
            let back = 1.0 / f;
            d.max *= back;
            d.rms *= back;
            d.per_point.iter_mut().for_each(|x| *x *= back);
            return d;
        }
    }
    deviation_at_scale(curve, points, params_hint)
}

/// [`max_orthogonal_deviation`] at the geometry's own scale.
fn deviation_at_scale(curve: &NurbsCurve, points: &[Vec3], params_hint: &[f64]) -> Deviation {
    let mut finder = FootFinder::new(curve);
    let mut proj: Option<CurveProjector> = None;
    let mut per_point = Vec::with_capacity(points.len());
    let mut params = Vec::with_capacity(points.len());
    let (mut max, mut sum2) = (0.0f64, 0.0);
    for (k, &q) in points.iter().enumerate() {
        let (u, distance) = match (params_hint.get(k), finder.as_mut()) {
            (Some(&h), Some(f)) => {
                let foot = f.refine(q, h);
                if foot.converged {
                    (foot.u, foot.distance)
                } else {
                    let pr = proj
                        .get_or_insert_with(|| CurveProjector::new(curve, SAMPLES_PER_SPAN))
                        .project_near(q, h);
                    if pr.distance <= foot.distance {
                        (pr.u, pr.distance)
                    } else {
                        (foot.u, foot.distance)
                    }
                }
            }
            (hint, _) => {
                let p = proj.get_or_insert_with(|| CurveProjector::new(curve, SAMPLES_PER_SPAN));
                let pr = match hint {
                    Some(&h) => p.project_near(q, h),
                    None => p.project(q),
                };
                (pr.u, pr.distance)
            }
        };
        max = max.max(distance);
        sum2 += distance * distance;
        per_point.push(distance);
        params.push(u);
    }
    let rms = if points.is_empty() {
        0.0
    } else {
        (sum2 / points.len() as f64).sqrt()
    };
    Deviation {
        max,
        rms,
        per_point,
        params,
    }
}

/// A cheaper deviation for the question "is every point within `tol`?": the algebraic distance
/// `|C(ū_k) − Q_k|` bounds the orthogonal one from above, so only points whose algebraic distance
/// exceeds `tol` are projected. Per point, the value is the orthogonal distance for those points and
/// the algebraic one (already `<= tol`) for the others; `max <= tol` exactly when the orthogonal
/// maximum is. `params` hold foot parameters for projected points and the given ones otherwise.
pub fn screened_deviation(
    curve: &NurbsCurve,
    points: &[Vec3],
    params: &[f64],
    tol: f64,
) -> Deviation {
    screened(curve, points, params, tol, false)
}

/// [`screened_deviation`], stopping at the first point found beyond `tol` when `early_exit` (then
/// only `max > tol` is meaningful: the other entries may be unverified upper bounds).
pub(crate) fn screened(
    curve: &NurbsCurve,
    points: &[Vec3],
    params: &[f64],
    tol: f64,
    early_exit: bool,
) -> Deviation {
    let mut per_point = vec![Vec3::ZERO; points.len()];
    curve.points_into(params, &mut per_point);
    let dist: Vec<f64> = per_point
        .iter()
        .zip(points)
        .map(|(c, q)| (*c - *q).norm())
        .collect();
    let mode = if early_exit {
        Screen::FirstMiss
    } else {
        Screen::All
    };
    screened_from(curve, points, params, dist, tol, mode, &[])
}

/// How much of the deviation a screening must establish.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Screen {
    /// Every point (see [`screened_deviation`]).
    All,
    /// Only whether some point misses the tolerance: stop at the first one.
    FirstMiss,
    /// Only which knot spans hold a point that misses the tolerance, as the refinement's span
    /// splitting reads it (a point exactly on a span's first knot counts for the span before too).
    /// Once a point's span(s) are known to miss, its projection is skipped and its (algebraic, above
    /// the tolerance) distance kept.
    SpanMiss,
}

/// [`screened`] from the algebraic distances `dist[k] = |C(ū_k) − Q_k|`, already computed (by the
/// least-squares solve, [`super::lsq::LsqSolver::residual_norms_into`]); `spans[k]` is the knot span
/// of point `k` (read by [`Screen::SpanMiss`] only).
pub(crate) fn screened_from(
    curve: &NurbsCurve,
    points: &[Vec3],
    params: &[f64],
    mut dist: Vec<f64>,
    tol: f64,
    mode: Screen,
    spans: &[usize],
) -> Deviation {
    let early_exit = matches!(mode, Screen::FirstMiss);
    let mut foot = params.to_vec();
    if dist.iter().any(|&d| d > tol) {
        let mut finder = FootFinder::new(curve);
        let mut proj: Option<CurveProjector> = None;
        let knots = curve.knots();
        let mut span_missed = match mode {
            Screen::SpanMiss => vec![false; knots.len()],
            _ => Vec::new(),
        };
        // a probe looks first at the point farthest off algebraically, the likeliest to miss `tol`
        // (each point is judged on its own, so the order changes nothing but the time to a miss)
        let first = early_exit
            .then(|| (0..dist.len()).max_by(|&a, &b| dist[a].total_cmp(&dist[b])))
            .flatten();
        let rest = (0..points.len()).filter(|&k| Some(k) != first);
        for k in first.into_iter().chain(rest) {
            if dist[k] <= tol {
                continue;
            }
            // the span (and the one before, for a point on its first knot) already misses
            let span = match mode {
                Screen::SpanMiss => {
                    let s = spans[k];
                    let on_knot = s > 0 && params[k] == knots[s];
                    if span_missed[s] && (!on_knot || span_missed[s - 1]) {
                        continue;
                    }
                    Some((s, on_knot))
                }
                _ => None,
            };
            let mut missed = |dk: f64| {
                if let (Some((s, on_knot)), true) = (span, dk > tol) {
                    span_missed[s] = true;
                    if on_knot {
                        span_missed[s - 1] = true;
                    }
                }
            };
            // Newton from the parameter: any curve point bounds the distance from above
            if let Some(f) = finder.as_mut() {
                let ft = f.refine_until(points[k], params[k], tol);
                if ft.distance < dist[k] {
                    dist[k] = ft.distance;
                    foot[k] = ft.u;
                }
                if dist[k] <= tol {
                    continue;
                }
                // a converged foot is the local one, as in `max_orthogonal_deviation`
                if ft.converged {
                    if early_exit {
                        return Deviation {
                            max: dist[k],
                            rms: f64::NAN,
                            per_point: dist,
                            params: foot,
                        };
                    }
                    missed(dist[k]);
                    continue;
                }
            }
            let pr = proj
                .get_or_insert_with(|| CurveProjector::new(curve, SAMPLES_PER_SPAN))
                .project_near(points[k], params[k]);
            if pr.distance < dist[k] {
                dist[k] = pr.distance;
                foot[k] = pr.u;
            }
            if early_exit && dist[k] > tol {
                return Deviation {
                    max: dist[k],
                    rms: f64::NAN,
                    per_point: dist,
                    params: foot,
                };
            }
            missed(dist[k]);
        }
    }
    let max = dist.iter().copied().fold(0.0, f64::max);
    let rms = if dist.is_empty() {
        0.0
    } else {
        (dist.iter().map(|d| d * d).sum::<f64>() / dist.len() as f64).sqrt()
    };
    Deviation {
        max,
        rms,
        per_point: dist,
        params: foot,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_offsets_measured_orthogonally() {
        // rational quadratic quarter circle; points at radius 1 + e_k have distance |e_k|
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            Some(vec![1.0, s, 1.0]),
        )
        .unwrap();
        let pts: Vec<Vec3> = (0..20)
            .map(|k| {
                let a = 0.05 + 1.4 * k as f64 / 19.0;
                let r = 1.0 + 0.01 * ((k % 5) as f64 - 2.0);
                Vec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect();
        let hint: Vec<f64> = (0..20).map(|k| k as f64 / 19.0).collect();
        let d = max_orthogonal_deviation(&c, &pts, &hint);
        assert!((d.max - 0.02).abs() < 1e-12, "{}", d.max);
        for (k, e) in d.per_point.iter().enumerate() {
            let want = 0.01 * ((k % 5) as f64 - 2.0).abs();
            assert!((e - want).abs() < 1e-12, "k={k}: {e} vs {want}");
        }
        let screened = screened_deviation(&c, &pts, &hint, 0.015);
        assert!((screened.max - 0.02).abs() < 1e-12);
        assert!(screened
            .per_point
            .iter()
            .all(|&e| e <= 0.015 || (e - 0.02).abs() < 1e-12));
        let full = max_orthogonal_deviation(&c, &pts, &[]);
        assert!((full.max - d.max).abs() < 1e-14);
    }

    #[test]
    fn span_miss_screening_flags_the_same_spans_as_the_full_one() {
        use crate::nurbs::knots::find_span;
        // a wavy polyline fitted badly by a cubic with 3 spans; one parameter sits on a knot
        let mut params: Vec<f64> = (0..60).map(|k| k as f64 / 59.0).collect();
        params[20] = 1.0 / 3.0;
        let pts: Vec<Vec3> = params
            .iter()
            .map(|&u| Vec3::new(u, 0.2 * (9.0 * u).sin() + 0.05 * (31.0 * u).cos(), 0.0))
            .collect();
        let knots = vec![0.0, 0.0, 0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0, 1.0, 1.0];
        let c = crate::fit::fit_fixed_knots(&pts, &params, 3, &knots, &Default::default()).unwrap();
        let spans: Vec<usize> = params.iter().map(|&u| find_span(5, 3, u, &knots)).collect();
        let alg: Vec<f64> = pts
            .iter()
            .zip(c.points(&params))
            .map(|(q, p)| (*q - p).norm())
            .collect();
        let flags = |d: &Deviation| {
            let mut bad = [false; 10];
            for (k, e) in d.per_point.iter().enumerate() {
                if *e > 0.01 {
                    bad[spans[k]] = true;
                    if params[k] == knots[spans[k]] {
                        bad[spans[k] - 1] = true;
                    }
                }
            }
            bad
        };
        let full = screened_from(&c, &pts, &params, alg.clone(), 0.01, Screen::All, &spans);
        let part = screened_from(&c, &pts, &params, alg, 0.01, Screen::SpanMiss, &spans);
        assert!(full.max > 0.01 && part.max > 0.01);
        assert_eq!(flags(&full), flags(&part));
        assert!(flags(&full).iter().filter(|&&b| b).count() >= 2);
        // fewer points were projected: some keep their algebraic distance
        assert!(full.per_point != part.per_point);
    }
}
