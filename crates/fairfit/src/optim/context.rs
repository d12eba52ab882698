//! The context every stage of a pipeline reads: the prepared data, the tolerance in its
//! normalised units, the options, the tuning, the progress callback, and the statistics the
//! stages add to.

use super::options::IntegratedOptions;
use super::progress::Stage;
use super::result::{IntegratedResult, OptimStats};
use super::search::prepare::Prepared;
use super::tuning::Tuning;
use crate::tolerance::Tolerance;
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Instant;

/// The progress callback `(stage, done, total)` ([`Stage`]).
pub(crate) type Progress<'a> = dyn Fn(Stage, usize, usize) + Sync + 'a;

/// One fit's context (module doc).
pub(crate) struct FitContext<'a> {
    /// The prepared (normalised, parameterised) data.
    pub prep: &'a Prepared,
    /// The tolerance in normalised units.
    pub tol: f64,
    /// The fit's options.
    pub opts: &'a IntegratedOptions,
    /// The method's measured thresholds.
    pub tuning: &'a Tuning,
    /// The progress callback.
    pub progress: &'a Progress<'a>,
    /// What the stages did so far (locked by one stage at a time; stages that run beside each
    /// other keep their own counts and add them after joining, in a fixed order).
    pub stats: Mutex<OptimStats>,
}

impl<'a> FitContext<'a> {
    /// The context of a fit of `prep` under `opts`, statistics empty.
    pub fn new(
        prep: &'a Prepared,
        opts: &'a IntegratedOptions,
        tuning: &'a Tuning,
        progress: &'a Progress<'a>,
    ) -> Self {
        FitContext {
            prep,
            tol: tolerance_of(opts, prep.scale),
            opts,
            tuning,
            progress,
            stats: Mutex::new(OptimStats::default()),
        }
    }

    /// The statistics, for one stage to add to.
    pub fn stats(&self) -> MutexGuard<'_, OptimStats> {
        self.stats.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The statistics the stages gathered.
    pub fn into_stats(self) -> OptimStats {
        self.stats
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
    }

    /// The pipeline's result: its last stage's `result` with the statistics of every stage (the
    /// fit started at `start`) and the least-squares baseline's count `baseline`.
    pub fn conclude(
        self,
        mut result: IntegratedResult,
        baseline: usize,
        start: Instant,
    ) -> IntegratedResult {
        let mut stats = self.into_stats();
        stats.absorb(&mut result.stats, start);
        IntegratedResult {
            baseline_control_points: baseline,
            stats,
            ..result
        }
    }
}

/// The band fairing's subproblem budget under `opts` (0: no band fairing).
pub(crate) fn band_solves(opts: &IntegratedOptions) -> usize {
    if opts.band_fairing {
        opts.band_solves
    } else {
        0
    }
}
/// The tolerance in normalised units.
pub(crate) fn tolerance_of(opts: &IntegratedOptions, scale: f64) -> f64 {
    match opts.tolerance {
        Tolerance::Relative(r) => r,
        Tolerance::Absolute(t) => t / scale,
    }
}
