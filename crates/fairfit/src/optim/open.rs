//! The open-curve pipeline: the integrated method on open data without corners, as named stages
//! ([`super::stages`]) on the open curve kind (`OpenKind`).

use super::context::{FitContext, Progress};
use super::fairing::EndCondition;
use super::kind::open::OpenKind;
use super::options::IntegratedOptions;
use super::progress::Stage;
use super::result::IntegratedResult;
use super::search::prepare::Prepared;
use super::stages::baseline::{self, BaselineInput};
use super::stages::count_search::{self, CountSearchInput};
use super::stages::degree_candidates;
use super::stages::descent::{self, DescentInput};
use super::stages::own_count_search::{self, CountsSeen, DegreeSearchInput};
use super::stages::release_ends::{self, ReleaseInput};
use super::tuning::Tuning;
use crate::errors::{Error, Result};
use std::time::Instant;

/// The integrated fit of the prepared open data `prep` (no corners) under `opts`: least-squares
/// baseline → count descent → count search (with the next degree's first candidate beside it) →
/// degree search → release ends.
pub(crate) fn fit(
    prep: &Prepared,
    opts: &IntegratedOptions,
    progress: &Progress<'_>,
    start: Instant,
) -> Result<IntegratedResult> {
    check_fixed_count(prep, opts)?;
    let tuning = Tuning::default();
    let ctx = FitContext::new(prep, opts, &tuning, progress);
    let kind = OpenKind {
        prep,
        tol: ctx.tol,
        opts,
        tuning: &tuning,
    };

    (ctx.progress)(Stage::Baseline, 0, 1);
    let base = baseline::run(
        &ctx,
        &kind,
        BaselineInput {
            control_points: opts.control_points,
        },
    );
    let lowest = tuning.descent.min_control_points;
    let down = descent::run(&ctx, &kind, DescentInput::open(&base, opts, lowest));
    let counts = CountSearchInput::after(&down, prep.data.points.len().min(base.baseline));
    let (counted, first) = rayon::join(
        || count_search::run(&ctx, &kind, counts),
        || degree_candidates::first_beside(&ctx, &down.knots),
    );
    let counted = counted?;
    let mut chosen = counted.result;
    if opts.searches_degree() {
        (ctx.progress)(Stage::DegreeSearch, 0, 1);
        let seen = CountsSeen::when_counts_free(opts, &counts, &counted.choice);
        let input = DegreeSearchInput {
            reference: chosen,
            first,
            seen,
        };
        chosen = own_count_search::raise_open(&ctx, input)?.result;
    }
    (ctx.progress)(Stage::ReleaseEnds, 0, 1);
    let released = release_ends::run(&ctx, ReleaseInput { chosen })?;
    ctx.stats().free_ends = opts.ends == EndCondition::Free;
    Ok(ctx.conclude(released.result, base.baseline, start))
}

/// A fixed count needs a data parameter strictly inside every knot span (Schoenberg–Whitney).
fn check_fixed_count(prep: &Prepared, opts: &IntegratedOptions) -> Result<()> {
    let m1 = prep.data.points.len();
    if let Some(n) = opts.control_points {
        if n + 1 > m1 {
            return Err(Error::InvalidSetting {
                option: "control_points",
                reason: format!(
                    "{n} control points are too many for {m1} points (at most {})",
                    m1 - 1
                ),
            });
        }
    }
    Ok(())
}
