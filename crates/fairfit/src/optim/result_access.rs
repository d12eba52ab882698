//! What a caller reads off an [`IntegratedResult`] beyond its fields: the smoothing weight in use.

use super::encoding::LOG_LAMBDA_OFF;
use super::integrated::IntegratedResult;

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
