//! Parameter correction (Hoschek; method reconstruction §6.6): fit, project every point onto the curve
//! near its parameter, refit with the foot parameters, for a configurable number of rounds. A round is
//! kept only when it lowers the maximum orthogonal deviation and keeps
//! the feet in order (out-of-order feet are points projected onto the wrong part of the curve).

use super::deviation::{max_orthogonal_deviation, screened_from, Deviation, Screen};
use super::end_constraints::EndConstraints;
use super::lsq::{LsqOptions, LsqSolver};
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, Vec3};

/// A fitted curve, the parameters it was fitted with, and its orthogonal deviation.
#[derive(Clone, Debug)]
pub struct CorrectedFit {
    /// The curve.
    pub curve: NurbsCurve,
    /// Parameters used for the final solve.
    pub params: Vec<f64>,
    /// Orthogonal deviation of the points (its `params` are the foot parameters).
    pub deviation: Deviation,
    /// Correction rounds that were kept.
    pub rounds_kept: usize,
}

/// Fits with fixed `knots`, then runs up to `rounds` parameter corrections, stopping early once the
/// maximum deviation is `<= stop_below` or a round does not improve it. With `rounds == 0` and
/// `stop_below > 0` the deviation is the screened one: exact for points that
/// miss `stop_below`, an upper bound below it for the others ([`super::deviation::screened_deviation`]).
///
/// ```
/// use fairfit::fit::correction::fit_with_correction;
/// use fairfit::fit::lsq::{LsqOptions, LsqSolver};
/// use fairfit::fit::parameterize::{parameterize, Parameterization};
/// use fairfit::Vec3;
/// // a quarter circle with 50 points, uniform parameters (poor), 6 control points
/// let q: Vec<Vec3> = (0..50).map(|k| { let a = 1.5707963 * (k as f64 / 49.0).powi(2);
///     Vec3::new(a.cos(), a.sin(), 0.0) }).collect();
/// let u = parameterize(&q, Parameterization::Uniform).unwrap();
/// let knots = fairfit::nurbs::knots::uniform_clamped(3, 6);
/// let mut s = LsqSolver::new(3);
/// let none = fit_with_correction(&mut s, &q, &u, &knots, &LsqOptions::default(), 0, 0.0).unwrap();
/// let five = fit_with_correction(&mut s, &q, &u, &knots, &LsqOptions::default(), 5, 0.0).unwrap();
/// assert!(five.deviation.max < 0.8 * none.deviation.max);
/// ```
pub fn fit_with_correction(
    solver: &mut LsqSolver,
    points: &[Vec3],
    params: &[f64],
    knots: &[f64],
    opts: &LsqOptions,
    rounds: usize,
    stop_below: f64,
) -> Result<CorrectedFit> {
    let ends = opts.end_tangents.map(|(a, b)| (Some(a), Some(b)));
    let ends = ends.unwrap_or((None, None));
    fit_corrected(
        solver,
        points,
        params,
        knots,
        opts,
        ends,
        None,
        rounds,
        stop_below,
        Screen::All,
    )
}

/// [`fit_with_correction`]; without rounds, `screen` says how much of the screened deviation is
/// needed ([`Screen::FirstMiss`] for trials that only ask whether the tolerance holds,
/// [`Screen::SpanMiss`] for the refinement's span splitting). `ends`: optional start and end
/// derivatives ([`LsqSolver::solve_with_ends`]); `conditions`: end conditions and whether the data
/// are planar ([`LsqSolver::solve_constrained`], in place of `ends`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_corrected(
    solver: &mut LsqSolver,
    points: &[Vec3],
    params: &[f64],
    knots: &[f64],
    opts: &LsqOptions,
    ends: (Option<Vec3>, Option<Vec3>),
    conditions: Option<(&EndConstraints, bool)>,
    rounds: usize,
    stop_below: f64,
    screen: Screen,
) -> Result<CorrectedFit> {
    let p = solver.degree();
    let mut ctrl = Vec::with_capacity(knots.len());
    let solve = |solver: &mut LsqSolver, params: &[f64], ctrl: &mut Vec<Vec3>| match conditions {
        Some((c, planar)) => {
            solver.solve_constrained(points, params, knots, None, opts, c, planar, ctrl)
        }
        None => solver.solve_with_ends(points, params, knots, None, opts, ends, ctrl),
    };
    solve(solver, params, &mut ctrl)?;
    let curve = if rounds == 0 {
        bspline_from_solve(p, knots, std::mem::take(&mut ctrl))?
    } else {
        bspline_from_solve(p, knots, ctrl.clone())?
    };
    // without correction only the tolerance decision matters: project only the points that miss it
    let deviation = if rounds == 0 && stop_below > 0.0 {
        let mut dist = Vec::with_capacity(points.len());
        solver.residual_norms_into(points, curve.control_points(), &mut dist);
        let spans = solver.data_spans();
        screened_from(&curve, points, params, dist, stop_below, screen, spans)
    } else {
        max_orthogonal_deviation(&curve, points, params)
    };
    let mut best = CorrectedFit {
        curve,
        params: params.to_vec(),
        deviation,
        rounds_kept: 0,
    };
    for _ in 0..rounds {
        if best.deviation.max <= stop_below {
            break;
        }
        let mut trial = best.deviation.params.clone();
        if !opts.closed {
            if let (Some(f), Some(l)) = (params.first(), params.last()) {
                trial[0] = *f;
                let n = trial.len();
                trial[n - 1] = *l;
            }
        }
        // feet out of order mean some points projected onto the wrong part of the curve: refitting
        // with them would fold the curve, so the correction stops here
        if trial.windows(2).any(|w| w[1] <= w[0]) {
            break;
        }
        if solve(solver, &trial, &mut ctrl).is_err() {
            break;
        }
        let curve = bspline_from_solve(p, knots, ctrl.clone())?;
        let deviation = max_orthogonal_deviation(&curve, points, &trial);
        if deviation.max >= best.deviation.max {
            break;
        }
        best = CorrectedFit {
            curve,
            params: trial,
            deviation,
            rounds_kept: best.rounds_kept + 1,
        };
    }
    Ok(best)
}

/// The curve of a least-squares solve: its knots were validated by the solve, so only the control
/// points are checked (finite ones make a valid curve; otherwise [`NurbsCurve::bspline`] names the
/// problem).
fn bspline_from_solve(p: usize, knots: &[f64], ctrl: Vec<Vec3>) -> Result<NurbsCurve> {
    if ctrl.iter().all(|c| c.is_finite()) {
        let n = ctrl.len();
        Ok(NurbsCurve::from_parts_unchecked(
            p,
            knots.to_vec(),
            ctrl,
            vec![1.0; n],
        ))
    } else {
        NurbsCurve::bspline(p, knots.to_vec(), ctrl)
    }
}
