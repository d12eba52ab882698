//! The data-facing stage before any fit: the noise is measured ([`super::noise`]), spikes are found
//! and excluded ([`super::outliers`]) when asked, and a tolerance below what the noise allows is
//! flagged. The fit then runs on the kept points; corners are judged later by each pipeline at the
//! tolerance's and the noise's scale ([`super::corners`]).
//!
//! The noise is measured again without the spikes when any were found (a spike spoils the block it
//! falls in).
//!
//! # A tolerance below the noise
//!
//! Points with noise `σ` across the curve lie up to the largest of `n` Gaussian deviations from the
//! curve they sample: no curve within a smaller tolerance of every point can be fair, it must follow
//! the noise. The *meaningful tolerance* ([`meaningful_tolerance`]) is the level the noise alone
//! stays below on every point with probability `1 −` [`NOISE_EXCESS_PROBABILITY`] (and at least
//! [`NOISE_TOLERANCE_SIGMAS`] `σ`). A tolerance below it is *noise limited*
//! ([`Screening::noise_limited`]).
//!
//! The fitting methods then fit to the meaningful tolerance instead of the one asked for, and say so
//! (one warning line, [`Screening::noise_warning`]; the report's `noise_limited`, `tolerance_used`).
//! Why rather than refusing: the data hold no more than that: every curve within the requested
//! tolerance of the points is further from the measured shape than the meaningful fit is (it adds
//! the noise to it), so the fit a CAD user can use is the one that averages the noise, held to the
//! smallest tolerance the points can verify. It is never silent (the warning and the report state
//! both tolerances), and the cost is that of any fit at that tolerance (seconds), not of a search
//! through hundreds of control points that chase the noise. A user who needs the requested
//! tolerance learns from the same line that it takes better data (less noise), not another run.

use super::noise::estimate_noise;
use super::outliers::{find_outliers, Outlier};
use crate::nurbs::Vec3;
use crate::tolerance::Tolerance;

/// A tolerance below this many noise `σ` can only be met by following the noise (the floor of
/// [`meaningful_tolerance`]): the largest of `n` Gaussian deviations is about `σ √(2 ln n)`, 4.3 σ to
/// 5.3 σ for `n` = 10^4 to 10^6.
pub const NOISE_TOLERANCE_SIGMAS: f64 = 5.0;

/// The chance that the noise alone puts some point beyond the [`meaningful_tolerance`]: 1 %.
pub const NOISE_EXCESS_PROBABILITY: f64 = 0.01;

/// The smallest tolerance that `n` points with noise `σ` can be held to without following the noise
/// (module doc): `z σ` with `z` the level the largest of the `n` noise distances exceeds with
/// probability [`NOISE_EXCESS_PROBABILITY`], at least [`NOISE_TOLERANCE_SIGMAS`]. `σ` is the
/// root-mean-square distance across the curve ([`super::noise`]), for planar and space curves
/// alike; at a given RMS a Gaussian distance has its heaviest tail when the noise lies along one
/// direction (`|N(0, σ²)|`, `P(> zσ) = erfc(z/√2)`; noise shared evenly between a space curve's
/// two normal directions has the lighter Rayleigh tail `e^(−z²)`), so that tail is the one used:
/// the tolerance holds however a space curve's noise is directed.
///
/// ```
/// use fairfit::fit::screening::meaningful_tolerance;
/// // up to about 17,000 points the floor of 5 σ holds; 10^6 points need 5.73 σ
/// assert_eq!(meaningful_tolerance(1.0, 10_000), 5.0);
/// assert!((meaningful_tolerance(1.0, 1_000_000) - 5.73).abs() < 0.01);
/// assert!((meaningful_tolerance(2.0, 1_000_000) / 2.0 - 5.73).abs() < 0.01);
/// ```
pub fn meaningful_tolerance(sigma: f64, n: usize) -> f64 {
    // P(one point beyond z σ)
    let tail = normal_two_sided_tail;
    let p = NOISE_EXCESS_PROBABILITY / n.max(1) as f64;
    let mut z = NOISE_TOLERANCE_SIGMAS;
    if tail(z) > p {
        // the tail falls monotonically: bisection on [5, 40]
        let (mut lo, mut hi) = (z, 40.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if tail(mid) > p {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        z = hi;
    }
    z * sigma
}

/// `P(|N(0, 1)| > z)` for `z ≥ 5`, by the asymptotic series of the Gaussian tail (relative error
/// below 3e-4 there): `2 φ(z)/z · (1 − 1/z² + 3/z⁴ − 15/z⁶)`.
fn normal_two_sided_tail(z: f64) -> f64 {
    let phi = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let w = 1.0 / (z * z);
    2.0 * phi / z * (1.0 - w * (1.0 - 3.0 * w * (1.0 - 5.0 * w)))
}

/// What to do with spikes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum OutlierMode {
    /// Keep every point (spikes are still named when the tolerance fails because of them).
    #[default]
    Off,
    /// Find isolated spikes far beyond the tolerance and the noise and exclude them.
    Auto,
}

/// What the screening found.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Screening {
    /// Noise standard deviation across the curve (the points' units; 0 for too few points).
    pub noise_sigma: f64,
    /// Whether `noise_sigma` is white noise rather than a residual of the data's shape or of a
    /// point-to-point pattern ([`super::noise::NoiseEstimate::resolved`]).
    pub noise_resolved: bool,
    /// `Some(t)` when the tolerance is below the [`meaningful_tolerance`] `t` and `σ` is resolved:
    /// the fitting methods then fit to `t` (module doc). An unresolved `σ` is not independent noise,
    /// so the bound does not apply and it never limits the tolerance.
    pub noise_limited: Option<f64>,
    /// The tolerance screened against (the one asked for, in the points' units).
    pub tolerance: f64,
    /// Excluded points (indices into the input), in index order; empty with [`OutlierMode::Off`].
    pub outliers: Vec<Outlier>,
}

impl Screening {
    /// The one-line warning for a tolerance below the noise, if there is one: the requested
    /// tolerance `tol`, `σ`, and the meaningful tolerance the fit holds instead (module doc).
    pub fn noise_warning(&self, tol: f64) -> Option<String> {
        self.noise_limited.map(|t| {
            format!(
                "warning: the tolerance {tol:.3e} is below the noise (σ ≈ {:.3e}): fitted to {t:.3e} instead, the smallest tolerance that does not follow the noise",
                self.noise_sigma
            )
        })
    }

    /// The tolerance a fit holds: the meaningful tolerance when the requested `tol` is noise
    /// limited, else `tol`.
    pub fn tolerance_used(&self, tol: f64) -> f64 {
        self.noise_limited.unwrap_or(tol)
    }
}

/// Screens `points` at tolerance `tol` (the points' units); returns the findings and the kept points
/// (`None` when nothing was excluded).
///
/// ```
/// use fairfit::fit::screening::{screen, OutlierMode};
/// use fairfit::nurbs::Vec3;
/// let mut pts: Vec<Vec3> = (0..500)
///     .map(|i| {
///         let a = i as f64 / 499.0 * 3.0;
///         Vec3::new(a.cos(), a.sin(), 0.0)
///     })
///     .collect();
/// pts[200] = pts[200] * 1.1;
/// let (s, kept) = screen(&pts, 1e-3, OutlierMode::Auto);
/// assert_eq!(s.outliers.len(), 1);
/// assert_eq!((s.outliers[0].index, kept.unwrap().len()), (200, 499));
/// assert!(s.noise_sigma < 1e-6 && s.noise_limited.is_none());
/// ```
pub fn screen(points: &[Vec3], tol: f64, mode: OutlierMode) -> (Screening, Option<Vec<Vec3>>) {
    let mut noise = estimate_noise(points);
    let (outliers, kept) = match mode {
        OutlierMode::Off => (Vec::new(), None),
        OutlierMode::Auto => {
            // spikes inflate the first σ (and with it the threshold): measure again without the
            // ones found and look again, until σ settles
            let mut found = find_outliers(points, tol, noise);
            let mut kept = None;
            for _ in 0..MAX_ROUNDS {
                if found.is_empty() {
                    break;
                }
                let k = without(points, &found);
                let again = estimate_noise(&k);
                kept = Some(k);
                let settled = again.sigma >= SETTLED * noise.sigma;
                noise = again;
                if settled {
                    break;
                }
                found = find_outliers(points, tol, noise);
                kept = None;
            }
            if !found.is_empty() && kept.is_none() {
                let k = without(points, &found);
                noise = estimate_noise(&k);
                kept = Some(k);
            }
            (found, kept)
        }
    };
    let fitted = kept.as_deref().unwrap_or(points);
    let limit = meaningful_tolerance(noise.sigma, fitted.len());
    let screening = Screening {
        noise_sigma: noise.sigma,
        noise_resolved: noise.resolved,
        noise_limited: (noise.resolved && tol < limit).then_some(limit),
        tolerance: tol,
        outliers,
    };
    (screening, kept)
}

/// Rounds of outlier search with a re-measured noise.
const MAX_ROUNDS: usize = 4;
/// The noise has settled when a new measure keeps this share of the last.
const SETTLED: f64 = 0.9;

/// `points` without the `found` ones.
fn without(points: &[Vec3], found: &[Outlier]) -> Vec<Vec3> {
    let mut drop = vec![false; points.len()];
    found.iter().for_each(|o| drop[o.index] = true);
    points
        .iter()
        .zip(&drop)
        .filter(|(_, &d)| !d)
        .map(|(&p, _)| p)
        .collect()
}

/// The points of `points` farther than `tol` from their neighbours' curve, for an error line when a
/// fit without outlier removal fails: at most `max` of them, largest first.
pub fn spikes_beyond(points: &[Vec3], tol: f64, max: usize) -> Vec<Outlier> {
    let mut found = find_outliers(points, tol, estimate_noise(points));
    found.sort_by(|a, b| b.distance.total_cmp(&a.distance));
    found.truncate(max);
    found
}

/// The screened input of one curve fit ([`screen_input`]): the points to fit, what the screening
/// found and the tolerance the least-squares fits hold.
#[derive(Clone, Debug)]
pub struct ScreenedInput {
    /// The points the fit runs on: the input without the excluded spikes.
    pub points: Vec<Vec3>,
    /// What the screening found; `None` when the tolerance asked for is not a usable number (not
    /// finite or not positive: the fit then refuses it with its own message).
    pub screening: Option<Screening>,
    /// The tolerance asked for.
    pub asked: Tolerance,
}

impl ScreenedInput {
    /// The tolerance asked for in the points' units (of the input, before any spike was excluded),
    /// `None` when it is not a usable number.
    pub fn absolute_tolerance(&self) -> Option<f64> {
        self.screening.as_ref().map(|s| s.tolerance)
    }

    /// The tolerance the least-squares methods fit to: the meaningful tolerance when the one asked
    /// for is below the noise (module doc), else the one asked for. The integrated method screens
    /// its points itself and raises its own tolerance the same way.
    pub fn fit_tolerance(&self) -> Tolerance {
        match self.screening.as_ref().and_then(|s| s.noise_limited) {
            Some(t) => Tolerance::Absolute(t),
            None => self.asked,
        }
    }

    /// The one-line warning for a tolerance below the noise (`warning: …`), if there is one.
    pub fn warning(&self) -> Option<String> {
        let s = self.screening.as_ref()?;
        s.noise_warning(s.tolerance)
    }
}

/// The screening stage of a curve fit, the one call of `fairfit curve` and the Python package's
/// `fit_curve` before they fit: the tolerance made absolute on `points`, then [`screen`] with
/// `mode` (noise measured, spikes excluded with [`OutlierMode::Auto`], a tolerance below the noise
/// flagged). A tolerance that is not a finite positive number screens nothing.
///
/// ```
/// use fairfit::fit::screening::{screen_input, OutlierMode};
/// use fairfit::fit::Tolerance;
/// use fairfit::nurbs::Vec3;
/// let mut pts: Vec<Vec3> = (0..500)
///     .map(|i| {
///         let a = i as f64 / 499.0 * 3.0;
///         Vec3::new(a.cos(), a.sin(), 0.0)
///     })
///     .collect();
/// pts[200] = pts[200] * 1.1;
/// let s = screen_input(pts, Tolerance::Relative(5e-4), OutlierMode::Auto);
/// assert_eq!((s.points.len(), s.screening.as_ref().unwrap().outliers[0].index), (499, 200));
/// // relative to the bounding box's largest side, 1 - cos 3 (x from cos 3 to 1)
/// assert!((s.absolute_tolerance().unwrap() - 5e-4 * (1.0 - 3f64.cos())).abs() < 1e-15);
/// assert_eq!(s.fit_tolerance(), Tolerance::Relative(5e-4));
/// assert!(s.warning().is_none());
/// ```
pub fn screen_input(points: Vec<Vec3>, tolerance: Tolerance, mode: OutlierMode) -> ScreenedInput {
    let tol = super::points::absolute_tolerance(tolerance, &points);
    if !(tol.is_finite() && tol > 0.0) {
        return ScreenedInput {
            points,
            screening: None,
            asked: tolerance,
        };
    }
    let (s, kept) = screen(&points, tol, mode);
    ScreenedInput {
        points: kept.unwrap_or(points),
        screening: Some(s),
        asked: tolerance,
    }
}

/// The spikes of `points` that keep tolerance `tol` out of reach, as a sentence (at most five,
/// largest first; `None` when there are none): what a fit that keeps every point says when it
/// misses the tolerance. The caller adds how to exclude them.
pub fn spikes_note(points: &[Vec3], tol: f64) -> Option<String> {
    let found = spikes_beyond(points, tol, 5);
    if found.is_empty() {
        return None;
    }
    let list: Vec<String> = found
        .iter()
        .map(|o| format!("point {} ({:.2e} off)", o.index, o.distance))
        .collect();
    Some(format!(
        "isolated spikes keep the tolerance out of reach: {}",
        list.join(", ")
    ))
}
