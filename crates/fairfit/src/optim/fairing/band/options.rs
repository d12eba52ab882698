//! The settings and the outcome of a band-fairing pass.

use super::super::control_map::EndCondition;
use super::super::tuning::{BandTuning, StepTuning};
use crate::optim::search::objective::CandidateEval;

/// Settings of [`super::band_fair`].
#[derive(Clone, Debug, PartialEq)]
pub struct BandOptions {
    /// Most convex subproblems solved.
    pub max_solves: usize,
    /// The cones use the radius `tol (1 − margin)`, a little inside the band, so that the solver's
    /// own feasibility tolerance cannot push a point outside.
    pub margin: f64,
    /// Stop after two accepted steps in a row that lower `F` (with sign targets: the merit) by
    /// less than this fraction and do not cut the sign-target violation by a tenth, or when a
    /// subproblem's model predicts less than this fraction.
    pub min_rel_gain: f64,
    /// A per-span fairness target `F*`: steps may not raise `max_j F_j` above it (or above the
    /// starting curve's, if larger).
    pub span_cap: Option<f64>,
    /// Weight of the tangential part of a point's deviation in its cone (1: the whole distance,
    /// which guarantees the tolerance at fixed feet; below 1 the curve may also slide along itself,
    /// and the measured deviation decides).
    pub tangent_weight: f64,
    /// Whether a step may not add curvature extrema (sign changes of `dκ/ds` at the Gauss nodes):
    /// lowering `F` alone tends to flatten `dκ/ds` into many small ripples.
    pub keep_extrema: bool,
    /// Persistence threshold of the curvature extrema to remove
    /// ([`super::super::curvature_signs::target_signs`]): runs of one
    /// sign of `dκ/ds` whose curvature change is below this fraction of the curvature range get
    /// the sign of their neighbours as a target, imposed by an exact (L1) penalty on the
    /// linearised `dκ/ds` at the nodes. 0: no targets.
    pub extrema_persistence: f64,
    /// Whether the sign targets also hold `dκ/ds` at both ends of every knot span (at
    /// 1e-6 of the span from the knot, with the target of the span's nearest Gauss
    /// node): `dκ/ds` jumps at a knot, and a wrong-signed sliver between the knot and the first
    /// Gauss node (0.5 % of the span in) is a pair of real curvature extrema that neither the nodes
    /// nor the measurer's 192 samples per span see ([`crate::fair::exact_extrema`]).
    pub edge_signs: bool,
    /// Whether an open curve's end points stay on the data's end points or move within the band
    /// ([`EndCondition`]; [`super::band_fair`] only, a mapped call takes its map's).
    pub ends: EndCondition,
    /// The step schedule of a pass (penalty weight, `μ` updates, solves per subproblem).
    pub step: StepTuning,
}

impl BandOptions {
    /// The options with the defaults of `tuning` (no span cap, extrema kept, edge signs on, ends
    /// pinned).
    pub fn tuned(tuning: &BandTuning) -> Self {
        BandOptions {
            max_solves: tuning.max_solves,
            margin: tuning.margin,
            min_rel_gain: tuning.min_rel_gain,
            span_cap: None,
            tangent_weight: tuning.tangent_weight,
            keep_extrema: true,
            extrema_persistence: tuning.extrema_persistence,
            edge_signs: true,
            ends: EndCondition::Pinned,
            step: tuning.step.clone(),
        }
    }
}

impl Default for BandOptions {
    fn default() -> Self {
        BandOptions::tuned(&BandTuning::default())
    }
}

/// The outcome of [`super::band_fair`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandFaired {
    /// The measurement of the faired curve (left in the workspace).
    pub eval: CandidateEval,
    /// Accepted steps.
    pub steps: usize,
    /// Convex subproblems solved.
    pub solves: usize,
    /// Whether the stage ended because no step of its last subproblem was accepted (rather than
    /// by small gains, the model's convergence or the budget).
    pub stalled: bool,
}
