//! The least-squares baseline: the fewest control points the kind's least-squares knots need to
//! meet the tolerance (`CurveKind::baseline`), which bounds every count the method tries, and
//! the count and knots the count descent starts from (`CurveKind::start`: the baseline's, or a
//! fixed count above it with knots inserted where they help most).

use crate::optim::context::FitContext;
use crate::optim::kind::CurveKind;

/// What the baseline starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BaselineInput {
    /// A fixed count (`--control-points`): the descent starts there, knots inserted above the
    /// baseline's count where they help most; `None` starts at the baseline's count.
    pub control_points: Option<usize>,
}

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

/// The baseline of `kind` and the descent's start (module doc).
pub(crate) fn run<K: CurveKind>(
    ctx: &FitContext,
    kind: &K,
    input: BaselineInput,
) -> BaselineOutput {
    let b = kind.baseline(&mut ctx.stats());
    let (n, knots) = kind.start(&b, input.control_points);
    BaselineOutput {
        baseline: b.count,
        n,
        knots,
    }
}
