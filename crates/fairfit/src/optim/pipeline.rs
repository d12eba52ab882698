//! The entry points of the integrated method: [`fit_integrated`] first screens the data
//! ([`crate::fit::screening`]: noise, spikes, and a tolerance below the noise raised to the
//! meaningful one); open data with corners then go to [`super::cornered`] on every point (corners
//! are judged before any reduction; each piece between corners is reduced on its own there), and
//! other data are first reduced when dense
//! ([`super::stages::reduce`]: representative points of tolerance-sized arcs, verified and
//! repaired against every input point), then sends the (reduced) data to the pipeline for its
//! shape, closed data to [`super::closed`], open data to [`super::cornered`] (which fits data
//! without corners by the open pipeline, [`super::open`]); nothing calls back in here.

use super::closed;
use super::context::tolerance_of;
use super::cornered;
use super::kind::open::finish;
use super::options::{validate, IntegratedOptions};
use super::progress::Stage;
use super::result::IntegratedResult;
use super::search::prepare::{averaging_interior_knots, prepare};
use super::stages::reduce;
use super::tuning::Tuning;
use crate::errors::{Error, Result};
use crate::fit::closure::Closure;
use crate::fit::screening::screen;
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::Vec3;
use std::time::Instant;

/// Fits a fair cubic B-spline to ordered `points` by the integrated method.
///
/// ```
/// use fairfit::prelude::*;
/// let pts: Vec<Vec3> = (0..60)
///     .map(|i| {
///         let t = i as f64 / 59.0 * 1.5;
///         Vec3([2.0 * t.cos(), t.sin(), 0.0])
///     })
///     .collect();
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
/// let r = fit_integrated(&pts, &opts).unwrap();
/// assert!(r.met && r.quality.max_deviation <= r.tolerance);
/// assert!(r.curve.n_control_points() <= r.baseline_control_points);
/// ```
pub fn fit_integrated(points: &[Vec3], opts: &IntegratedOptions) -> Result<IntegratedResult> {
    fit_integrated_with_stages(points, opts, &|_, _, _| {})
}

/// [`fit_integrated`] reporting its progress to `progress` as `(stage, done, total)`: the
/// [`Stage`] the fit is in and how far it is (from the thread running the work concerned, see
/// [`Stage`]). The result does not depend on the callback.
///
/// ```
/// use fairfit::prelude::*;
/// use std::sync::Mutex;
/// let pts: Vec<Vec3> = (0..40)
///     .map(|i| {
///         let t = i as f64 / 39.0;
///         Vec3::new(t, (2.0 * t).sin(), 0.0)
///     })
///     .collect();
/// let seen = Mutex::new(Vec::new());
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
/// let r = fit_integrated_with_stages(&pts, &opts, &|stage, done, total| {
///     assert!(done <= total, "{stage}: {done} of {total}");
///     seen.lock().unwrap().push(stage);
/// })
/// .unwrap();
/// let seen = seen.into_inner().unwrap();
/// assert!(r.met);
/// assert_eq!(seen[..2], [Stage::Screening, Stage::Baseline]);
/// assert!(seen.iter().any(|s| matches!(s, Stage::CountSearch { control_points } if *control_points >= 4)));
/// assert!(seen.contains(&Stage::BandFairing));
/// ```
pub fn fit_integrated_with_stages(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<IntegratedResult> {
    let start = Instant::now();
    validate(opts)?;
    let tuning = Tuning::default();
    // screening: noise measured, spikes excluded (`opts.outliers`) before any other stage
    let tol = crate::fit::points::absolute_tolerance(opts.tolerance, points);
    progress(Stage::Screening, 0, 1);
    let (screening, kept) = screen(points, tol, opts.outliers);
    let points = kept.as_deref().unwrap_or(points);
    // a tolerance below the noise: fitted to the meaningful one (`fit::screening` module doc)
    let raised;
    let opts = match screening.noise_limited {
        Some(t) => {
            raised = IntegratedOptions {
                tolerance: crate::tolerance::Tolerance::Absolute(t),
                ..opts.clone()
            };
            &raised
        }
        None => opts,
    };
    // points dropped by the screening: the indices of weights and points to interpolate no longer
    // match, so the search does not see them (the caller's exact hold still does)
    let unbanded;
    let opts = if kept.is_some() && !opts.point_constraints.is_none() {
        unbanded = IntegratedOptions {
            point_constraints: Default::default(),
            ..opts.clone()
        };
        &unbanded
    } else {
        opts
    };
    // closed or open, decided once on the screened points at the tolerance held (`closed::closure`);
    // a gap closed there is passed on as `ClosedMode::Closed`: the loop through the points as they are
    let closure = closed::closure(points, opts);
    let gap_closed;
    let opts = match closure {
        Closure::Gap(_) => {
            gap_closed = IntegratedOptions {
                closed: ClosedMode::Closed,
                ..opts.clone()
            };
            &gap_closed
        }
        _ => opts,
    };
    let fit = |pts: &[Vec3], o: &IntegratedOptions| {
        // reduced data: the representatives are other points
        let plain = IntegratedOptions {
            point_constraints: Default::default(),
            ..o.clone()
        };
        dispatch(pts, &plain, progress, start)
    };
    let mut r =
        if !closed::closed_as_given(points, opts.closed) && cornered::has_corners(points, opts) {
            // corners are judged on every point (a representative of the reduced form averages a
            // corner away); the pieces between them are reduced each on its own
            cornered::fit(points, opts, progress, start)
        } else {
            match reduce::Dense::of(points, opts, &tuning.reduce) {
                None => dispatch(points, opts, progress, start),
                Some(dense) => {
                    progress(Stage::Reduce, 0, 1);
                    dense.fit(opts, &tuning.reduce, &fit)
                }
            }
        }?;
    r.screening = screening;
    r.closure = closure;
    Ok(r)
}

/// The data to the pipeline for their shape (module doc).
fn dispatch(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
    start: Instant,
) -> Result<IntegratedResult> {
    if closed::closed_as_given(points, opts.closed) {
        closed::fit(points, opts, progress, start)
    } else {
        cornered::fit(points, opts, progress, start)
    }
}

/// The least-squares fit with averaging knots and `n_ctrl` control points (the baseline the
/// integrated method starts from), measured like the integrated result.
pub fn fit_lsq_baseline(
    points: &[Vec3],
    n_ctrl: usize,
    opts: &IntegratedOptions,
) -> Result<IntegratedResult> {
    validate(opts)?;
    let prep = prepare(points, opts.degree)?;
    if n_ctrl < opts.degree + 1 || n_ctrl > prep.data.points.len() {
        return Err(Error::InvalidSetting {
            option: "control_points",
            reason: format!(
                "{n_ctrl} control points: need between {} and {}",
                opts.degree + 1,
                prep.data.points.len()
            ),
        });
    }
    let tol = tolerance_of(opts, prep.scale);
    let knots = averaging_interior_knots(&prep.data.params, opts.degree, n_ctrl);
    let r = finish(&prep, &knots, f64::NEG_INFINITY, tol, opts, None)?;
    Ok(IntegratedResult {
        screening: Default::default(),
        baseline_control_points: n_ctrl,
        ..r
    })
}
