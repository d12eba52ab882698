//! The integrated method's entry point with typed progress ([`Stage`]).

use super::integrated::{fit_integrated_with_progress, IntegratedOptions, IntegratedResult};
use super::progress::{untyped, Stage};
use crate::errors::Result;
use crate::nurbs::Vec3;

/// [`fit_integrated`](super::fit_integrated) reporting its progress as [`Stage`] values to
/// `progress` (from the thread running the search concerned; see [`Stage`]).
///
/// ```
/// use fairfit::prelude::*;
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// let pts: Vec<Vec3> = (0..40)
///     .map(|i| {
///         let t = i as f64 / 39.0;
///         Vec3::new(t, (2.0 * t).sin(), 0.0)
///     })
///     .collect();
/// let reports = AtomicUsize::new(0);
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
/// let r = fit_integrated_with_stages(&pts, &opts, &|stage| {
///     let Stage::KnotSearch { control_points, .. } = stage else { return };
///     assert!(control_points >= 4);
///     reports.fetch_add(1, Ordering::Relaxed);
/// })
/// .unwrap();
/// assert!(r.met && reports.load(Ordering::Relaxed) > 0);
/// ```
pub fn fit_integrated_with_stages(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &(dyn Fn(Stage) + Sync),
) -> Result<IntegratedResult> {
    fit_integrated_with_progress(points, opts, &untyped(progress))
}
