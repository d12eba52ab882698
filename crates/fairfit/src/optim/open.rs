//! The open-curve pipeline: the integrated method on open data without corners, as named stages
//! ([`super::stages`]) on the open curve kind (`OpenKind`).

use super::context::FitContext;
use super::fairing::EndCondition;
use super::kind::open::OpenKind;
use super::options::IntegratedOptions;
use super::progress::Stage;
use super::result::IntegratedResult;
use super::search::prepare::Prepared;
use super::stages::count_search::CountStart;
use super::stages::degree_candidates;
use super::stages::descent::DescentInput;
use super::stages::own_count_search::{self, CountsSeen};
use super::stages::{baseline, count_search, descent, release_ends};
use super::tuning::Tuning;
use crate::errors::{Error, Result};
use std::time::Instant;

/// The integrated fit of the prepared open data `prep` (no corners) under `opts`: least-squares
/// baseline → count descent → count search (with the next degree's first candidate beside it) →
/// degree search → release ends.
pub(crate) fn fit(
    prep: &Prepared,
    opts: &IntegratedOptions,
    progress: &super::context::Progress<'_>,
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
    let (p, fixed) = (opts.degree, opts.control_points);

    (ctx.progress)(Stage::Baseline, 0, 1);
    let base = baseline::run(&ctx, &kind);
    let down = descent::run(
        &ctx,
        &kind,
        DescentInput {
            n: base.n,
            knots: base.knots,
            lowest: fixed
                .unwrap_or(p + 1)
                .max(p + 1)
                .max(ctx.tuning.descent.min_control_points),
            force: false,
            second: true,
            trim_to: fixed,
        },
    );
    let start_at = CountStart {
        n: down.n,
        knots: &down.knots,
        descent: &down.met,
        limit: prep.data.points.len().min(base.baseline),
        alt: &down.alt,
    };
    let (counted, first) = rayon::join(
        || count_search::run(&ctx, &kind, start_at),
        || degree_candidates::first_beside(&ctx, &down.knots),
    );
    let (mut result, choice) = counted?;
    if opts.searches_degree() {
        // a fixed count, or no extra points, leaves the next degree no counts of its own
        let seen = (fixed.is_none() && opts.max_extra_control_points > 0)
            .then(|| CountsSeen::of(&start_at, &choice));
        (ctx.progress)(Stage::DegreeSearch, 0, 1);
        result = own_count_search::raise_open(&ctx, result, first, seen)?;
    }
    (ctx.progress)(Stage::ReleaseEnds, 0, 1);
    let mut result = release_ends::run(&ctx, result)?;
    let mut stats = ctx.into_stats();
    stats.free_ends = opts.ends == EndCondition::Free;
    stats.absorb(&mut result.stats, start);
    Ok(IntegratedResult {
        screening: Default::default(),
        baseline_control_points: base.baseline,
        stats,
        ..result
    })
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
