//! Residual-driven knot vectors, as FITPACK's `fpcurf` (scipy's `splprep`) places knots: start
//! with no interior knot, fit by least squares, and insert the next knot at the middle data
//! parameter of the knot span whose squared residuals sum highest, until the count is reached.
//!
//! Averaging and curvature-adaptive knots ([`crate::fit::knot_placement`]) spread knots by the
//! data's parameters or turning; this rule puts them where the fit misses most, which on an
//! airfoil crowds them around the leading edge where its curvature falls off. It is a seed of the
//! knot search of the degree search's own count search ([`crate::optim::stages::degree_candidates`]).

use super::objective::{evaluate_candidate, set_knots, EvalWorkspace, FitData};
use crate::nurbs::NurbsCurve;

/// The interior knots of `n` control points at degree `data.degree` placed by the residual rule
/// (module doc): knots at data parameters, each span of the result holding a data parameter
/// strictly inside. `None` when a least-squares system fails or no span can be split.
pub(crate) fn residual_knots(data: &FitData, n: usize) -> Option<Vec<f64>> {
    let p = data.degree;
    let u = &data.params;
    let mut interior: Vec<f64> = Vec::new();
    let mut ws = EvalWorkspace::default();
    while interior.len() + p + 1 < n {
        set_knots(p, &interior, &mut ws);
        let e = evaluate_candidate(data, f64::NEG_INFINITY, &mut ws);
        if !e.solved {
            return None;
        }
        let curve = NurbsCurve::bspline(p, ws.knots.clone(), ws.ctrl.clone()).ok()?;
        // span sums of squared residuals; a point on a knot counts half to each side (FITPACK)
        let spans = interior.len() + 1;
        let mut sums = vec![0.0; spans];
        for (i, &ui) in u.iter().enumerate() {
            let r2 = (data.points[i] - curve.point(ws.foot_params[i])).norm_squared();
            let j = interior.partition_point(|&k| k < ui);
            if j < interior.len() && interior[j] == ui {
                sums[j] += 0.5 * r2;
                sums[j + 1] += 0.5 * r2;
            } else {
                sums[j] += r2;
            }
        }
        // the worst span with at least three parameters strictly inside: its middle one becomes a
        // knot, and both halves keep a parameter strictly inside
        let mut best: Option<(f64, usize)> = None;
        for j in 0..spans {
            let lo = if j == 0 { 0.0 } else { interior[j - 1] };
            let hi = if j == interior.len() {
                1.0
            } else {
                interior[j]
            };
            let first = u.partition_point(|&x| x <= lo);
            let end = u.partition_point(|&x| x < hi);
            if end >= first + 3 && best.is_none_or(|(s, _)| sums[j] > s) {
                best = Some((sums[j], first + (end - first) / 2));
            }
        }
        let (_, i) = best?;
        let at = interior.partition_point(|&k| k < u[i]);
        interior.insert(at, u[i]);
    }
    Some(interior)
}

#[cfg(test)]
mod tests {
    use super::residual_knots;
    use crate::nurbs::Vec3;
    use crate::optim::search::objective::FitData;

    /// 101 uniform parameters on [0, 1]; points `(x, f(x))` with `x` the parameter.
    fn data(f: impl Fn(f64) -> f64) -> FitData {
        let params: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
        FitData {
            points: params.iter().map(|&x| Vec3([x, f(x), 0.0])).collect(),
            params,
            degree: 3,
            planar: true,
            corrections: 0,
            ends: Default::default(),
            bands: Default::default(),
        }
    }

    #[test]
    fn knots_go_to_the_middle_parameter_of_the_worst_span() {
        // flat on [0, 0.5], a quartic on the right: (x - 0.5)^4 for x > 0.5 (slope at most 0.5,
        // so the orthogonal residuals are close to the vertical misfit)
        let d = data(|x: f64| (x - 0.5).max(0.0).powi(4));
        // one span holds all 101 parameters: its middle one, 0.5, is the first knot
        assert_eq!(residual_knots(&d, 5), Some(vec![0.5]));
        // with a knot at 0.5 the left half is nearly flat (its residuals are the C2 join's small
        // spill-over), so the second knot splits the right span (0.5, 1] at its middle parameter: the 49
        // parameters strictly inside are 0.51 ... 0.99, the middle one 0.75
        assert_eq!(residual_knots(&d, 6), Some(vec![0.5, 0.75]));
        // no interior knot at the cubic's smallest count
        assert_eq!(residual_knots(&d, 4), Some(vec![]));
    }

    #[test]
    fn knots_are_data_parameters_with_one_strictly_inside_every_span() {
        // a cubic polynomial is fitted exactly by the Bezier segment: every residual is rounding
        // noise, but the knots still come from data parameters and keep a parameter in every span
        let d = data(|x: f64| x * x * x - x);
        let k = residual_knots(&d, 10).unwrap();
        assert_eq!(k.len(), 6);
        let mut edges = vec![0.0];
        edges.extend(&k);
        edges.push(1.0);
        for w in edges.windows(2) {
            assert!(d.params.iter().any(|&u| u > w[0] && u < w[1]), "{k:?}");
            assert!(w[0] < w[1]);
        }
        for x in &k {
            assert!(d.params.contains(x));
        }
    }
}
