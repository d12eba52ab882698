//! The curve kinds: what differs between an open curve (`open`) and a periodic closed curve
//! (`periodic`) is behind one trait, `CurveKind`; the stages above
//! ([`super::stages`]) are written once against it.
//!
//! A kind knows, for one prepared data set and tolerance: the least-squares baseline it starts
//! from, the knot search at any control-point count (the swarm problem), knots spread over the
//! data at any count, the single-knot removals and the best single insertion, and how a knot
//! vector is finished into the returned curve (band fairing, polish, measurement).

pub(crate) mod open;
pub(crate) mod periodic;

use super::result::{IntegratedResult, OptimStats};
use super::search::problem::CountProblem;
use crate::errors::Result;

/// The least-squares baseline of one data set: the fewest control points meeting the tolerance
/// with the kind's least-squares knots, and those knots.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Baseline {
    /// Control points of the baseline (distinct ones on a periodic curve).
    pub count: usize,
    /// Interior knots (breakpoints) at `count`, when the kind's least-squares method gave them
    /// (`None`: the spread knots at `count`).
    pub knots: Option<Vec<f64>>,
}

/// One curve kind on one prepared data set and tolerance (module doc).
pub(crate) trait CurveKind: Sync {
    /// The knot search at one count.
    type Problem: CountProblem;
    /// The least-squares baseline; its candidate evaluations are counted in `stats`.
    fn baseline(&self, stats: &mut OptimStats) -> Baseline;
    /// The count and knots the count descent starts from: the baseline's, or with a fixed count
    /// `fixed` above it, knots added where they help most.
    fn start(&self, baseline: &Baseline, fixed: Option<usize>) -> (usize, Vec<f64>);
    /// The problem with `n` control points (`n` distinct ones for a periodic curve).
    fn problem(&self, n: usize) -> Self::Problem;
    /// Interior knots spread over the data for `n` control points (a seed at every count).
    fn spread_knots(&self, n: usize) -> Vec<f64>;
    /// `knots` with one knot more where it helps most (smoothing `log10 λ`).
    fn insertion(&self, knots: &[f64], log_lambda: f64) -> Vec<f64>;
    /// Every single-knot removal of `knots`, refitted without smoothing and sorted by the
    /// maximum deviation: `(deviation, knots)`.
    fn removal_candidates(&self, knots: &[f64]) -> Vec<(f64, Vec<f64>)>;
    /// The final curve (band fairing, polish) of interior knots and smoothing.
    fn finish(&self, interior: &[f64], log_lambda: f64) -> Result<IntegratedResult>;
}
