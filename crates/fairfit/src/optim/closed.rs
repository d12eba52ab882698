//! The closed-data pipeline.
//!
//! Data are closed when the last point repeats the first ([`crate::fit::shape::looks_closed`]), when
//! their ends are a gap apart that the data continue smoothly through at the tolerance's scale
//! ([`closure`], [`crate::fit::closure`]: fitted as a loop through the points as they are, the gap
//! its closing step), or when the caller says so ([`ClosedMode::Closed`]); a repeated point is
//! dropped. Then, as in the least-squares method:
//!
//! - with corners (turning angle above the threshold, every point — the first included — judged
//!   with its two neighbours on the loop), the loop is cut at its first corner and fitted as open
//!   data from that corner back to it ([`super::cornered`], the other corners kept as C0 knots):
//!   the result is a clamped curve whose two ends meet at the corner;
//! - without corners, the curve is **periodic** (`kind::periodic`) and fitted by the open
//!   pipeline's stages on the periodic kind: the least-squares baseline, the count descent
//!   (greedy removals and swarm probes, no second descent), the count search, and the degree
//!   search from the chosen curve. `--control-points N` fixes `n_u = N` distinct control points.
//!   The ends are not released (a periodic curve has none).

use super::context::{FitContext, Progress};
use super::cornered;
use super::fairing::EndCondition;
use super::kind::periodic::PeriodicKind;
use super::options::IntegratedOptions;
use super::progress::Stage;
use super::result::IntegratedResult;
use super::search::periodic::ClosedData;
use super::search::prepare::{prepare, Prepared};
use super::stages::baseline::{self, BaselineInput};
use super::stages::count_search::{self, CountSearchInput};
use super::stages::degree_candidates::{self, PeriodicDegreeInput};
use super::stages::descent::{self, DescentInput};
use super::tuning::Tuning;
use crate::errors::{Error, Result};
use crate::fit::closure::Closure;
use crate::fit::corners::corners_at_tolerance;
use crate::fit::points::absolute_tolerance;
use crate::fit::shape::looks_closed;
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::Vec3;
use std::time::Instant;

/// How [`fit_integrated`](super::fit_integrated) fits `points` under `opts`: open or closed as
/// `opts.closed` says, and with [`ClosedMode::Auto`] by [`closure_at_tolerance`](crate::fit::closure::closure_at_tolerance) at the tolerance of
/// `opts` (in the points' units) and its corner angle (the default one when corners are off); with
/// end conditions only a repeated point closes the data (the conditions ask for ends). The fit
/// decides on the screened points at the tolerance it holds; its decision is
/// [`IntegratedResult::closure`].
pub fn closure(points: &[Vec3], opts: &IntegratedOptions) -> Closure {
    opts.closed.closure(
        points,
        !opts.end_conditions.is_none(),
        || absolute_tolerance(opts.tolerance, points),
        opts.corner_angle_deg,
    )
}

/// Whether `points` are fitted as a closed curve under `opts` ([`closure`]).
pub fn is_closed(points: &[Vec3], opts: &IntegratedOptions) -> bool {
    closure(points, opts).is_closed()
}

/// Whether `points` are closed under `mode` by the last point repeating the first alone: the
/// pipeline's test once [`closure`] has been decided (a gap closed by it is passed on as
/// [`ClosedMode::Closed`]), so that reduced points, whose spacing is not the data's, are not judged
/// again.
pub(crate) fn closed_as_given(points: &[Vec3], mode: ClosedMode) -> bool {
    match mode {
        ClosedMode::Open => false,
        ClosedMode::Closed => true,
        ClosedMode::Auto => looks_closed(points),
    }
}

/// The integrated fit of the closed data `points` (module doc).
pub(crate) fn fit(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &Progress<'_>,
    start: Instant,
) -> Result<IntegratedResult> {
    if !opts.end_conditions.is_none() {
        return Err(Error::InvalidSetting {
            option: if opts.end_conditions.start.is_none() {
                "end"
            } else {
                "start"
            },
            reason: "closed data have no ends to hold a condition (fit them as open data: --open, or closed=False in Python)".into(),
        });
    }
    let mut pts = points.to_vec();
    if looks_closed(&pts) {
        pts.pop();
    }
    let prep = prepare(&pts, opts.degree)?;
    if let Some(angle) = opts.corner_angle_deg {
        let tol = super::context::tolerance_of(opts, prep.scale);
        let found = corners_at_tolerance(&prep.data.points, true, angle, tol);
        if let Some(&c0) = found.first() {
            // cut the loop at its first corner: an open curve from the corner back to it
            let mut seq: Vec<Vec3> = pts[c0..].iter().chain(&pts[..c0]).copied().collect();
            seq.push(pts[c0]);
            let open = IntegratedOptions {
                closed: ClosedMode::Open,
                // the open curve from a corner back to it closes there
                ends: EndCondition::Pinned,
                // the per-point factors index the unrotated points
                tolerance_factors: Vec::new(),
                ..opts.clone()
            };
            return cornered::fit(&seq, &open, progress, start);
        }
    }
    fit_periodic(&prep, opts, progress, start)
}

/// The periodic pipeline on the prepared distinct points of a closed curve without corners.
fn fit_periodic(
    prep: &Prepared,
    opts: &IntegratedOptions,
    progress: &Progress<'_>,
    start: Instant,
) -> Result<IntegratedResult> {
    let data = ClosedData::new(prep)?;
    let p = opts.degree;
    let m = data.points.len();
    // every span needs a data parameter inside (Schoenberg–Whitney): at most m − 1 spans
    let max_n = m - 1;
    let fixed = opts.control_points;
    if let Some(n) = fixed {
        if n < p + 1 || n > max_n {
            return Err(Error::InvalidSetting {
                option: "control_points",
                reason: format!(
                    "{n} control points do not fit a closed curve of degree {p} through {m} points \
                     (give between {} and {max_n})",
                    p + 1
                ),
            });
        }
    }
    let tuning = Tuning::default();
    let ctx = FitContext::new(prep, opts, &tuning, progress);
    let kind = PeriodicKind {
        prep,
        data: &data,
        tol: ctx.tol,
        opts,
        tuning: &tuning,
    };

    (ctx.progress)(Stage::Baseline, 0, 1);
    let base = baseline::run(
        &ctx,
        &kind,
        BaselineInput {
            control_points: fixed,
        },
    );
    let down = descent::run(&ctx, &kind, DescentInput::periodic(&base, opts));
    let counts = CountSearchInput::after(&down, max_n.min(base.baseline));
    let mut chosen = count_search::run(&ctx, &kind, counts)?.result;
    if opts.searches_degree() {
        (ctx.progress)(Stage::DegreeSearch, 0, 1);
        let input = PeriodicDegreeInput { reference: chosen };
        chosen = degree_candidates::raise_periodic(&ctx, input)?.result;
    }
    Ok(ctx.conclude(chosen, base.baseline, start))
}
