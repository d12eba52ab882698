//! The least-squares baseline: the fewest control points the kind's least-squares knots need to
//! meet the tolerance (`CurveKind::baseline`), which bounds every count the method tries, and
//! the count and knots the count descent starts from (`CurveKind::start`: the baseline's, or a
//! fixed count above it with knots inserted where they help most).

use crate::optim::context::FitContext;
use crate::optim::kind::CurveKind;

/// Where the count descent starts.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BaselineOutput {
    /// Control points of the least-squares baseline.
    pub baseline: usize,
    /// The count the descent starts from.
    pub n: usize,
    /// Its interior knots.
    pub knots: Vec<f64>,
}

/// The baseline of `kind` and the descent's start (module doc), with the fixed count of the
/// options.
pub(crate) fn run<K: CurveKind>(ctx: &FitContext, kind: &K) -> BaselineOutput {
    let b = kind.baseline(&mut ctx.stats());
    let (n, knots) = kind.start(&b, ctx.opts.control_points);
    BaselineOutput {
        baseline: b.count,
        n,
        knots,
    }
}
