//! What the integrated method returns: the fitted curve with its [`FitQuality`], and the
//! optimiser's statistics ([`OptimStats`], one [`DegreeTrial`] per degree of a degree search).

use super::search::encoding::LOG_LAMBDA_OFF;
use crate::nurbs::NurbsCurve;
use serde::Serialize;
use std::time::Instant;

/// What the optimiser did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OptimStats {
    /// Candidate evaluations (least-squares solves) in total.
    pub evaluations: usize,
    /// Swarm iterations in total.
    pub iterations: usize,
    /// Control-point counts tried, in order.
    pub counts_tried: Vec<usize>,
    /// `(count, F)` of every full knot search (F infinite when the tolerance was not met).
    pub fairness_by_count: Vec<(usize, f64)>,
    /// Accepted control-point moves of the final polish (`optim/fairing/polish.rs`).
    pub polish_moves: usize,
    /// Every degree's fit, in degree order, when the degree was searched
    /// ([`IntegratedOptions::max_degree`](super::IntegratedOptions::max_degree); empty otherwise). Evaluations, iterations and seconds
    /// then count all degrees; the other fields are the chosen degree's.
    pub degrees_tried: Vec<DegreeTrial>,
    /// Wall time in seconds.
    pub seconds: f64,
    /// Whether the chosen curve's end points were free in its last fairing pass
    /// ([`EndCondition::Free`](super::EndCondition::Free) on an open curve without corners; `optim/stages/release_ends.rs`).
    pub free_ends: bool,
}

impl OptimStats {
    /// Adds the evaluations and iterations of the chosen result's `finished` statistics and takes
    /// its polish moves and degree trials; the wall time is measured from `start`.
    pub(crate) fn absorb(&mut self, finished: &mut OptimStats, start: Instant) {
        self.evaluations += finished.evaluations;
        self.iterations += finished.iterations;
        self.polish_moves = finished.polish_moves;
        self.degrees_tried = std::mem::take(&mut finished.degrees_tried);
        self.seconds = start.elapsed().as_secs_f64();
    }
}

/// The measured quality of a fitted curve (in the input's units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitQuality {
    /// Maximum orthogonal deviation.
    pub max_deviation: f64,
    /// RMS orthogonal deviation.
    pub rms_deviation: f64,
    /// Whole-curve fairness F.
    pub fairness: f64,
    /// max_j F_j.
    pub max_span_fairness: f64,
}

/// The result of [`fit_integrated`](super::fit_integrated).
#[derive(Clone, Debug)]
pub struct IntegratedResult {
    /// The fitted curve.
    pub curve: NurbsCurve,
    /// Its quality.
    pub quality: FitQuality,
    /// The tolerance in the input's units: the one the fit holds, the meaningful tolerance of the
    /// screening when the one asked for is below the noise (`screening.noise_limited`; the one
    /// asked for is `screening.tolerance`).
    pub tolerance: f64,
    /// Whether the tolerance (and `F*`) was met.
    pub met: bool,
    /// `log10 λ` of the smoothing weight used (`-inf` for none).
    pub log_lambda: f64,
    /// Control points of the least-squares baseline (averaging knots) meeting the tolerance.
    pub baseline_control_points: usize,
    /// Optimiser statistics.
    pub stats: OptimStats,
    /// The screening stage's findings ([`crate::fit::screening`]): the measured noise, a tolerance
    /// below it, the excluded spikes (indices into the input).
    pub screening: crate::fit::screening::Screening,
    /// Whether the data were fitted as a closed curve, and across which gap when their ends were a
    /// gap apart ([`crate::fit::closure`]; decided on the screened points at `tolerance`).
    pub closure: crate::fit::closure::Closure,
}

/// One degree's integrated fit, as the degree search saw it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DegreeTrial {
    /// The curve degree.
    pub degree: usize,
    /// Distinct control points of the fit.
    pub control_points: usize,
    /// Its fairness `F`.
    pub fairness: f64,
    /// Its interior curvature extrema.
    pub curvature_extrema: usize,
    /// Whether it met the tolerance (and `F*`).
    pub tolerance_met: bool,
}

impl IntegratedResult {
    /// `log10 λ` of the smoothing weight the curve was fitted with, or `None` when none was used
    /// (`λ = 0`: the knot search's smoothing coordinate at or below its off value, or no smoothing
    /// searched).
    ///
    /// ```
    /// use fairfit::prelude::*;
    /// let pts: Vec<Vec3> = (0..40)
    ///     .map(|i| {
    ///         let t = i as f64 / 39.0;
    ///         Vec3::new(t, t * t, 0.0)
    ///     })
    ///     .collect();
    /// let r = fit_integrated(&pts, &IntegratedOptions::new(Tolerance::Relative(1e-3))).unwrap();
    /// if let Some(l) = r.log10_smoothing() {
    ///     assert!(l.is_finite() && l < 0.0);
    /// }
    /// ```
    pub fn log10_smoothing(&self) -> Option<f64> {
        (self.log_lambda.is_finite() && self.log_lambda > LOG_LAMBDA_OFF).then_some(self.log_lambda)
    }
}
