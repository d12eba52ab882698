//! The data-facing stage before any fit: the noise is measured ([`super::noise`]), spikes are found
//! and excluded ([`super::outliers`]) when asked, and a tolerance below what the noise allows is
//! flagged. The fit then runs on the kept points; corners are judged later by each pipeline at the
//! tolerance's and the noise's scale ([`super::corners`]).
//!
//! The noise is measured again without the spikes when any were found (a spike spoils the block it
//! falls in).

use super::noise::estimate_noise;
use super::outliers::{find_outliers, Outlier};
use crate::nurbs::Vec3;

/// A tolerance below this many noise `σ` can only be met by following the noise: the largest of `n`
/// Gaussian deviations is about `σ √(2 ln n)`, 4.3 σ to 5.3 σ for `n` = 10^4 to 10^6.
pub const NOISE_TOLERANCE_SIGMAS: f64 = 5.0;

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
    /// `Some(t)` when the tolerance is below [`NOISE_TOLERANCE_SIGMAS`] `σ` and `σ` is resolved: `t`
    /// is that bound, the smallest tolerance the noise leaves meaningful. An unresolved `σ` is not
    /// independent noise, so the bound does not apply and it never limits the tolerance.
    pub noise_limited: Option<f64>,
    /// Excluded points (indices into the input), in index order; empty with [`OutlierMode::Off`].
    pub outliers: Vec<Outlier>,
}

impl Screening {
    /// The one-line warning for a tolerance below the noise, if there is one.
    pub fn noise_warning(&self, tol: f64) -> Option<String> {
        self.noise_limited.map(|t| {
            format!(
                "warning: the tolerance {tol:.3e} is below the noise (σ ≈ {:.3e}): the fit follows the noise; a tolerance of at least {t:.2e} is meaningful",
                self.noise_sigma
            )
        })
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
    let limit = NOISE_TOLERANCE_SIGMAS * noise.sigma;
    let screening = Screening {
        noise_sigma: noise.sigma,
        noise_resolved: noise.resolved,
        noise_limited: (noise.resolved && tol < limit).then_some(limit),
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
