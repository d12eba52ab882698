//! `--pareto` for a periodic closed curve (closed data without corners): the front of (maximum
//! orthogonal deviation, F) at the result's number of distinct control points `n_u`.
//!
//! As for open curves ([`super::front`]), the multi-objective swarm ([`crate::optim::search::mopso`]) runs over
//! the encoded breakpoints and smoothing weight, here of the periodic problem
//! ([`crate::optim::search::periodic::ClosedProblem`]: seam fixed at the first point, periodic least squares, every
//! point measured, F over the whole loop), seeded with the result's breakpoints and smoothing and
//! with equal index steps; members deviating more than [`DEVIATION_CAP`](super::front::DEVIATION_CAP) tolerances are left out.
//! Every member is written like the fit's closed curves (unclamped periodic knots, `n_u + p`
//! control points whose last `p` repeat the first), so it is `C^(p−1)` at the seam. Members are the
//! least-squares curves of their knots (no band fairing or polish, as for open curves).

use super::front::{front_archive, ParetoCurve};
use crate::errors::{Error, Result};
use crate::nurbs::Vec3;
use crate::optim::context::tolerance_of;
use crate::optim::kind::periodic::{distinct_control_points, equal_breaks, finish_periodic};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::IntegratedResult;
use crate::optim::search::encoding::LOG_LAMBDA_RANGE;
use crate::optim::search::periodic::{ClosedData, ClosedProblem};
use crate::optim::search::prepare::prepare;
use crate::optim::search::problem::CountProblem;

/// The front of the periodic result `r` fitted to the distinct closed points `points` (the repeated
/// closing point removed) under `opts`.
pub fn pareto_front_periodic(
    points: &[Vec3],
    opts: &IntegratedOptions,
    r: &IntegratedResult,
) -> Result<Vec<ParetoCurve>> {
    let p = opts.degree;
    let prep = prepare(points, p)?;
    let data = ClosedData::new(&prep)?;
    let n_u = distinct_control_points(&r.curve);
    let k = r.curve.knots();
    if n_u + p != r.curve.n_control_points() || k.len() != n_u + 2 * p + 1 {
        return Err(Error::InvalidOption(
            "--pareto: the closed result is not a periodic curve".into(),
        ));
    }
    let tol = tolerance_of(opts, prep.scale);
    let problem = ClosedProblem::new(&data, n_u, 1e-4, true, tol, None);
    let coord = problem.smoothing_coord().unwrap_or(0);
    let mut seeds = Vec::new();
    // the result's breakpoints (its knots between the seam at 0 and 1)
    let interior = &k[p + 1..p + n_u];
    for (knots, ll) in [
        (interior.to_vec(), r.log_lambda),
        (equal_breaks(&data.params, n_u), LOG_LAMBDA_RANGE.0),
    ] {
        if knots.len() + 1 != n_u {
            continue;
        }
        let mut x = problem.position(&knots);
        x[coord] = ll.clamp(LOG_LAMBDA_RANGE.0, LOG_LAMBDA_RANGE.1);
        seeds.push(x);
    }
    let archive = front_archive(&problem, &seeds, opts, tol);
    let raw = IntegratedOptions {
        polish: false,
        band_fairing: false,
        ..opts.clone()
    };
    let mut out = Vec::with_capacity(archive.members.len());
    for m in &archive.members {
        let Some(knots) = problem.decode(&m.position) else {
            continue;
        };
        let f = finish_periodic(
            &prep,
            &data,
            &knots,
            problem.log_lambda(&m.position),
            tol,
            &raw,
        )?;
        out.push(ParetoCurve {
            curve: f.curve,
            quality: f.quality,
        });
    }
    Ok(out)
}
