//! The final fairing stages of the integrated method on a periodic (closed) curve: band fairing
//! ([`super::band`]) and the polish ([`mod@super::polish`]), as for open curves, moving the
//! `n_u` distinct control points of the periodic curve ([`ControlMap::periodic`]) so that the
//! curve stays periodic and `C^(p−1)` at the seam, with every data point (the seam point
//! included) held within the tolerance.
//!
//! Both stages work on the clamped form the periodic measure leaves in the workspace; the distinct
//! control points are then recovered from it ([`ControlMap::variables_of`]) and written back as the
//! periodic control points (the last `p` repeating the first).

use super::band::{band_fair_mapped, BandOptions};
use super::control_map::ControlMap;
use super::polish::{polish_mapped, PolishOptions};
use crate::errors::Result;
use crate::optim::search::objective::CandidateEval;
use crate::optim::search::periodic::{ClosedData, ClosedWorkspace};

/// What [`fair_periodic`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicFaired {
    /// The measurement of the faired curve.
    pub eval: CandidateEval,
    /// Accepted polish moves.
    pub moves: usize,
    /// Curve measurements of the polish.
    pub evaluations: usize,
}

/// Fairs the periodic curve left in `ws` by [`crate::optim::search::periodic::evaluate_closed`] within `tol`
/// (and the per-span target `span_cap`): band fairing first (at most `band` convex subproblems,
/// none when 0), then the polish (at most `polish_evaluations` measurements). On
/// return `ws.ctrl` holds the faired periodic control points (`ws.knots` unchanged) and
/// `ws.eval` its clamped form, measured.
pub fn fair_periodic(
    data: &ClosedData,
    ws: &mut ClosedWorkspace,
    tol: f64,
    span_cap: Option<f64>,
    band: usize,
    polish_evaluations: usize,
) -> Result<PeriodicFaired> {
    let p = data.degree();
    let n_u = ws.ctrl.len() - p;
    let map = ControlMap::periodic(p, &ws.knots, n_u, data.points.len())?;
    let ev = &mut ws.eval;
    if band > 0 {
        let start = ev.foot_params.clone();
        let bo = BandOptions {
            span_cap,
            max_solves: band,
            ..BandOptions::default()
        };
        band_fair_mapped(&data.measure, ev, &start, tol, &bo, &map);
    }
    let start = ev.foot_params.clone();
    let po = PolishOptions {
        span_cap,
        max_evaluations: polish_evaluations,
        ..PolishOptions::default()
    };
    let pol = polish_mapped(&data.measure, ev, &start, tol, &po, &map);
    let z = map.variables_of(&ev.ctrl);
    ws.ctrl.clear();
    ws.ctrl.extend((0..n_u + p).map(|i| z[i % n_u]));
    Ok(PeriodicFaired {
        eval: pol.eval,
        moves: pol.moves,
        evaluations: pol.evaluations,
    })
}
