//! The settings of the integrated method: [`IntegratedOptions`], the [`Tolerance`] it fits to,
//! and their validation.

use super::fairing::BandOptions;
use super::fairing::EndCondition;
use super::fairing::PolishOptions;
use crate::errors::{Error, Result};

/// The allowed maximum orthogonal deviation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// A fraction of the largest side of the data's bounding box.
    Relative(f64),
    /// An absolute distance in the data's units.
    Absolute(f64),
}

/// Settings of [`fit_integrated`](super::fit_integrated).
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratedOptions {
    /// Curve degree (3; the fairness metric needs ≥ 3); with [`Self::max_degree`], the lowest
    /// degree searched and the reference of the degree search.
    pub degree: usize,
    /// Degree search (`--degree auto`): also fit every degree from `degree + 1` up to this one and
    /// keep one by the rule of [`super::stages::degree_search`] (never more curvature extrema than the fit
    /// at `degree`; more control points only up to the least-squares baseline, or one above it
    /// where the fit at `degree` kept the baseline's count, and at 5 % of F per point). `None`
    /// fits `degree` only.
    pub max_degree: Option<usize>,
    /// The fitting tolerance.
    pub tolerance: Tolerance,
    /// Per-span fairness target `F*` (every span must reach `F_j ≤ F*`).
    pub span_fairness: Option<f64>,
    /// Seed of the swarm's random streams.
    pub seed: u64,
    /// Particles per swarm.
    pub particles: usize,
    /// Iterations of the full swarm at the final count.
    pub max_iterations: usize,
    /// Iterations of a feasibility probe at a smaller count.
    pub probe_iterations: usize,
    /// Evaluations of the final pattern search.
    pub refine_evaluations: usize,
    /// Whether the smoothing weight λ is searched along with the knots.
    pub search_smoothing: bool,
    /// Most control points added above the smallest feasible count for fairness (every extra
    /// count is finished in full before the count is chosen, [`super::stages::count_search`]).
    pub max_extra_control_points: usize,
    /// A higher degree is kept only if F shrinks by at least this factor per degree
    /// ([`super::stages::degree_search`]; the count search has its own factor, 1.05 per point, module
    /// `count_search`).
    pub fairness_gain: f64,
    /// A fixed number of control points (no count search) instead of the fewest meeting the
    /// tolerance.
    pub control_points: Option<usize>,
    /// Corner threshold in degrees (turning angle at a data point, as in the least-squares method):
    /// the data are split at corners, the pieces fitted separately and joined C0 ([`super::corners`]).
    /// `None` fits one smooth curve through everything.
    pub corner_angle_deg: Option<f64>,
    /// Whether the final control points are refined by local fairing moves within the tolerance
    /// ([`super::polish`]).
    pub polish: bool,
    /// Closed-curve handling as in the least-squares method (default: closed when the last point
    /// repeats the first); closed data are fitted by [`super::closed`].
    pub closed: crate::fit::tolerance::ClosedMode,
    /// Whether the final control points are first faired inside the tolerance band by sequential
    /// convex programming ([`super::band_fairing`]; with `polish`, the polish then finishes).
    pub band_fairing: bool,
    /// Most convex subproblems of the band fairing.
    pub band_solves: usize,
    /// Most curve measurements of the polish.
    pub polish_evaluations: usize,
    /// Whether an open curve's end points stay on the data's first and last points, or the chosen
    /// curve is faired once more with them moving within the tolerance ([`EndCondition`],
    /// [`super::stages::release_ends`]). Not applicable to
    /// closed curves (no end points); the pieces between corners keep theirs pinned (they are
    /// joined there).
    pub ends: EndCondition,
}

impl Default for IntegratedOptions {
    fn default() -> Self {
        IntegratedOptions {
            degree: 3,
            max_degree: None,
            tolerance: Tolerance::Relative(1e-3),
            span_fairness: None,
            seed: 0,
            particles: 16,
            max_iterations: 30,
            probe_iterations: 10,
            refine_evaluations: 100,
            search_smoothing: true,
            max_extra_control_points: 1,
            fairness_gain: 1.1,
            control_points: None,
            polish: true,
            band_fairing: true,
            band_solves: BandOptions::default().max_solves,
            polish_evaluations: PolishOptions::default().max_evaluations,
            corner_angle_deg: Some(crate::fit::shape::DEFAULT_CORNER_ANGLE_DEG),
            closed: crate::fit::tolerance::ClosedMode::Auto,
            ends: EndCondition::Pinned,
        }
    }
}

impl IntegratedOptions {
    /// Whether the degree is searched ([`Self::max_degree`] above [`Self::degree`]).
    pub fn searches_degree(&self) -> bool {
        self.max_degree.is_some_and(|d| d > self.degree)
    }

    /// These options at the single degree `degree` (no degree search).
    pub fn at_degree(&self, degree: usize) -> IntegratedOptions {
        IntegratedOptions {
            degree,
            max_degree: None,
            ..self.clone()
        }
    }
}

pub(crate) fn validate(opts: &IntegratedOptions) -> Result<()> {
    if opts.degree < 3 || opts.degree > super::search::objective::MAX_DEGREE {
        return Err(Error::InvalidDegree {
            degree: opts.degree,
            reason: format!(
                "the integrated method needs a degree from 3 to {}",
                super::search::objective::MAX_DEGREE
            ),
        });
    }
    if let Some(d) = opts.max_degree {
        if d < opts.degree || d > super::search::objective::MAX_DEGREE {
            return Err(Error::InvalidDegree {
                degree: d,
                reason: format!(
                    "the highest degree searched must be from {} to {}",
                    opts.degree,
                    super::search::objective::MAX_DEGREE
                ),
            });
        }
    }
    let t = match opts.tolerance {
        Tolerance::Relative(r) => r,
        Tolerance::Absolute(t) => t,
    };
    if !(t.is_finite() && t > 0.0) {
        return Err(Error::InvalidOption(format!(
            "the tolerance must be positive, got {t}"
        )));
    }
    if let Some(f) = opts.span_fairness {
        if !(f.is_finite() && f > 0.0) {
            return Err(Error::InvalidOption(format!(
                "the span fairness target must be positive, got {f}"
            )));
        }
    }
    if let Some(n) = opts.control_points {
        if n < opts.degree + 1 {
            return Err(Error::InvalidOption(format!(
                "{n} control points are too few for degree {} (need at least {})",
                opts.degree,
                opts.degree + 1
            )));
        }
    }
    if opts.particles == 0 {
        return Err(Error::InvalidOption(
            "at least one particle is needed".into(),
        ));
    }
    if !(opts.fairness_gain.is_finite() && opts.fairness_gain >= 1.0) {
        return Err(Error::InvalidOption(format!(
            "the fairness gain per added control point must be a finite factor >= 1, got {}",
            opts.fairness_gain
        )));
    }
    if let Some(a) = opts.corner_angle_deg {
        if !(a.is_finite() && a > 0.0 && a <= 180.0) {
            return Err(Error::InvalidOption(format!(
                "the corner angle must be in (0, 180] degrees, got {a}"
            )));
        }
    }
    Ok(())
}
