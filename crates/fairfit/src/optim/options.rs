//! The settings of the integrated method: [`IntegratedOptions`] (built by
//! [`IntegratedOptions::new`] and chained setters), its work [`Budget`], and their validation.
//!
//! Three kinds of values live here, kept apart:
//! - **settings** a user chooses (tolerance, degree or degree search, control points, corners, closed
//!   mode, ends, seed, span fairness, band fairing and polish on or off): public fields with a setter
//!   each;
//! - the **budget** (swarm sizes, iterations, solver and polish evaluations, extra control points
//!   tried): a [`Budget`] value, set as a whole by [`IntegratedOptions::budget`];
//! - **tuning** of the method's policy (the price per degree, whether the smoothing weight is
//!   searched): crate-private, measured rather than chosen.
//!
//! Invariant: `validate` accepts an options value exactly when every stage can run with it, and its
//! errors name the offending setting ([`Error::InvalidSetting`]) by the setter that sets it.

use super::fairing::{BandOptions, EndCondition, PolishOptions};
use crate::errors::{Error, Result};
use crate::fit::end_constraints::{EndConstraint, EndConstraints};
use crate::fit::point_constraints::PointConstraints;
use crate::fit::tolerance::ClosedMode;
use crate::tolerance::Tolerance;

/// A field that keeps [`Budget`] open to new members: it cannot be named outside the crate, so a
/// budget is written as `Budget { particles: 32, ..Budget::default() }`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NonExhaustive(());

/// How much work the integrated method may do. [`Budget::default`] is the budget the method's
/// defaults were measured with (the command-line tool's); larger values search longer and never
/// change what a setting means.
///
/// ```
/// use fairfit::prelude::*;
/// let budget = Budget { particles: 32, max_iterations: 60, ..Budget::default() };
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).budget(budget);
/// assert_eq!(opts.current_budget().particles, 32);
/// assert_eq!(opts.current_budget().probe_iterations, Budget::default().probe_iterations);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Particles per swarm (at least 1; default 16).
    pub particles: usize,
    /// Iterations of the full swarm at a candidate count (default 30).
    pub max_iterations: usize,
    /// Iterations of a feasibility probe at a smaller count (default 10).
    pub probe_iterations: usize,
    /// Evaluations of the pattern search refining the swarm's best (default 100).
    pub refine_evaluations: usize,
    /// Most convex subproblems of the band fairing of one curve.
    pub band_solves: usize,
    /// Most curve measurements of the polish of one curve.
    pub polish_evaluations: usize,
    /// Most control points tried above the smallest count meeting the tolerance (each is finished in
    /// full before the count is chosen; default 1).
    pub max_extra_control_points: usize,
    /// Keeps the struct open to new members (write `..Budget::default()`).
    pub non_exhaustive: NonExhaustive,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            particles: 16,
            max_iterations: 30,
            probe_iterations: 10,
            refine_evaluations: 100,
            band_solves: BandOptions::default().max_solves,
            polish_evaluations: PolishOptions::default().max_evaluations,
            max_extra_control_points: 1,
            non_exhaustive: NonExhaustive(()),
        }
    }
}

/// Settings of [`fit_integrated`](super::fit_integrated), built from a tolerance by
/// chained setters.
///
/// ```
/// use fairfit::prelude::*;
/// let opts = IntegratedOptions::new(Tolerance::Absolute(0.01))
///     .degree_search(5) // degrees 3 to 5, one kept
///     .corner_angle(None) // one smooth curve, no corners
///     .ends(EndCondition::Free)
///     .seed(7);
/// assert!(opts.searches_degree());
/// assert_eq!((opts.degree, opts.max_degree, opts.corner_angle_deg), (3, Some(5), None));
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct IntegratedOptions {
    /// Curve degree (3; the fairness metric needs ≥ 3); with [`Self::max_degree`], the lowest
    /// degree searched and the reference of the degree search. Set by [`Self::degree`].
    pub degree: usize,
    /// Degree search (`--degree auto`): also fit every degree from `degree + 1` up to this one and
    /// keep one by the rule of `optim/stages/degree_search.rs` (never more curvature extrema than the fit
    /// at `degree`; more control points only up to the least-squares baseline, or one above it
    /// where the fit at `degree` kept the baseline's count, and at 5 % of F per point). `None`
    /// fits `degree` only. Set by [`Self::degree_search`].
    pub max_degree: Option<usize>,
    /// The fitting tolerance. Set by [`Self::new`] and [`Self::tolerance`].
    pub tolerance: Tolerance,
    /// Per-span fairness target `F*` (every span must reach `F_j ≤ F*`). Set by
    /// [`Self::span_fairness`].
    pub span_fairness: Option<f64>,
    /// Seed of the swarm's random streams. Set by [`Self::seed`].
    pub seed: u64,
    /// Particles per swarm ([`Budget::particles`]).
    pub(crate) particles: usize,
    /// Iterations of the full swarm at the final count ([`Budget::max_iterations`]).
    pub(crate) max_iterations: usize,
    /// Iterations of a feasibility probe at a smaller count ([`Budget::probe_iterations`]).
    pub(crate) probe_iterations: usize,
    /// Evaluations of the final pattern search ([`Budget::refine_evaluations`]).
    pub(crate) refine_evaluations: usize,
    /// Most control points added above the smallest feasible count for fairness (every extra
    /// count is finished in full before the count is chosen, [`super::stages::count_search`];
    /// [`Budget::max_extra_control_points`]).
    pub(crate) max_extra_control_points: usize,
    /// A fixed number of control points (no count search) instead of the fewest meeting the
    /// tolerance. Set by [`Self::control_points`].
    pub control_points: Option<usize>,
    /// Corner threshold in degrees (turning angle at a data point, as in the least-squares method):
    /// the data are split at corners, the pieces fitted separately and joined C0 (`optim/corners.rs`).
    /// `None` fits one smooth curve through everything. Set by [`Self::corner_angle`].
    pub corner_angle_deg: Option<f64>,
    /// Whether isolated spikes are found and excluded before the fit ([`crate::fit::screening`]);
    /// the noise is measured either way. Set by [`Self::outliers`].
    pub outliers: crate::fit::screening::OutlierMode,
    /// Whether the final control points are refined by local fairing moves within the tolerance
    /// (`optim/fairing/polish.rs`). Set by [`Self::polish`].
    pub polish: bool,
    /// Closed-curve handling as in the least-squares method (default: closed when the last point
    /// repeats the first); closed data are fitted by `optim/closed.rs`. Set by [`Self::closed`].
    pub closed: ClosedMode,
    /// Whether the final control points are first faired inside the tolerance band by sequential
    /// convex programming (`optim/fairing/band/`; with `polish`, the polish then finishes). Set by
    /// [`Self::band_fairing`].
    pub band_fairing: bool,
    /// Most convex subproblems of the band fairing ([`Budget::band_solves`]).
    pub(crate) band_solves: usize,
    /// Most curve measurements of the polish ([`Budget::polish_evaluations`]).
    pub(crate) polish_evaluations: usize,
    /// Whether an open curve's end points stay on the data's first and last points, or the chosen
    /// curve is faired once more with them moving within the tolerance ([`EndCondition`],
    /// `optim/stages/release_ends.rs`). Not applicable to
    /// closed curves (no end points); the pieces between corners keep theirs pinned (they are
    /// joined there). Set by [`Self::ends`].
    pub ends: EndCondition,
    /// G0/G1/G2 conditions at the ends of an open curve ([`crate::fit::end_constraints`]): every
    /// least-squares solve of the knot search and the final fairing honour them. Set by
    /// [`Self::start`] and [`Self::end`].
    pub end_conditions: EndConstraints,
    /// Per-point weights and points to interpolate (indices of the points passed in), held
    /// inside the search (`PointBands` in `optim/search/objective/`) on open data without
    /// corners that are neither reduced nor screened down; elsewhere ignored here (the exact hold
    /// is [`crate::fit::point_constraints::fit_with_point_constraints_inside`]'s). Set by
    /// [`Self::point_constraints`].
    pub point_constraints: PointConstraints,
    /// The deviation factor of every point fitted (empty: all 1), on open data without corners
    /// and without [`Self::point_constraints`]: point `k` is held within `tolerance / factor_k`.
    /// Set by the reduction of dense data ([`super::stages::reduce`]): each representative's own
    /// share of the tolerance (its bin's spread deducted), every factor at most 1, so a pipeline
    /// that ignores them holds every representative to the tightest share.
    pub(crate) tolerance_factors: Vec<f64>,
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
            max_extra_control_points: 1,
            control_points: None,
            polish: true,
            band_fairing: true,
            band_solves: BandOptions::default().max_solves,
            polish_evaluations: PolishOptions::default().max_evaluations,
            corner_angle_deg: Some(crate::fit::shape::DEFAULT_CORNER_ANGLE_DEG),
            outliers: crate::fit::screening::OutlierMode::Off,
            closed: crate::fit::tolerance::ClosedMode::Auto,
            ends: EndCondition::Pinned,
            end_conditions: EndConstraints::default(),
            point_constraints: PointConstraints::default(),
            tolerance_factors: Vec::new(),
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

/// The builder: every setter takes and returns the options, so settings chain.
impl IntegratedOptions {
    /// The default settings at `tolerance`: a cubic (no degree search), the fewest control points
    /// meeting the tolerance, corners above 60°, closed when the last point repeats the first,
    /// pinned ends, seed 0, band fairing and polish on, [`Budget::default`].
    ///
    /// ```
    /// use fairfit::prelude::*;
    /// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
    /// assert_eq!(opts, IntegratedOptions::default());
    /// ```
    pub fn new(tolerance: Tolerance) -> Self {
        IntegratedOptions {
            tolerance,
            ..IntegratedOptions::default()
        }
    }

    /// The fitting tolerance.
    pub fn tolerance(mut self, tolerance: Tolerance) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// The curve degree (3 to 7), or with [`Self::degree_search`] the lowest degree searched.
    pub fn degree(mut self, degree: usize) -> Self {
        self.degree = degree;
        self
    }

    /// Searches every degree from [`Self::degree`] up to `max_degree` and keeps one (the
    /// command-line tool's `--degree auto` is `degree_search(5)`); `None` fits one degree.
    pub fn degree_search(mut self, max_degree: impl Into<Option<usize>>) -> Self {
        self.max_degree = max_degree.into();
        self
    }

    /// A fixed number of control points (distinct ones, for a closed curve) instead of the fewest
    /// meeting the tolerance; `None` searches the count.
    pub fn control_points(mut self, n: impl Into<Option<usize>>) -> Self {
        self.control_points = n.into();
        self
    }

    /// The turning angle in degrees, in (0, 180]
    /// ([`check_corner_angle`](crate::fit::shape::check_corner_angle)), above which a data point
    /// is a corner (a C0 knot); `None` fits one smooth curve through every point.
    pub fn corner_angle(mut self, degrees: impl Into<Option<f64>>) -> Self {
        self.corner_angle_deg = degrees.into();
        self
    }

    /// `OutlierMode::Auto` excludes isolated spikes before the fit (listed in
    /// [`IntegratedResult::screening`](super::IntegratedResult::screening)); the default keeps
    /// every point.
    ///
    /// ```
    /// use fairfit::fit::screening::OutlierMode;
    /// use fairfit::prelude::*;
    /// let mut pts: Vec<Vec3> = (0..200)
    ///     .map(|i| {
    ///         let t = i as f64 / 199.0 * 1.5;
    ///         Vec3::new(2.0 * t.cos(), t.sin(), 0.0)
    ///     })
    ///     .collect();
    /// pts[77] = pts[77] * 1.1; // a spike
    /// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).outliers(OutlierMode::Auto);
    /// let r = fit_integrated(&pts, &opts).unwrap();
    /// assert_eq!(r.screening.outliers[0].index, 77);
    /// assert!(r.met && r.screening.noise_sigma < 1e-6);
    /// ```
    pub fn outliers(mut self, mode: crate::fit::screening::OutlierMode) -> Self {
        self.outliers = mode;
        self
    }

    /// Whether the data are fitted as a closed curve ([`ClosedMode::Auto`]: when the last point
    /// repeats the first, or when the ends are a gap apart that the data continue smoothly through
    /// at the tolerance's scale, [`crate::fit::closure`]).
    pub fn closed(mut self, mode: ClosedMode) -> Self {
        self.closed = mode;
        self
    }

    /// The end condition of an open curve without corners ([`EndCondition::Pinned`] by default).
    pub fn ends(mut self, ends: EndCondition) -> Self {
        self.ends = ends;
        self
    }

    /// The condition at the first point of an open curve: a point, a tangent direction (G1) or a
    /// tangent and curvature (G2), [`EndConstraint`].
    ///
    /// ```
    /// use fairfit::prelude::*;
    /// use fairfit::fit::end_constraints::{achieved, EndConstraint};
    /// let pts: Vec<Vec3> = (0..50)
    ///     .map(|i| {
    ///         let t = i as f64 / 49.0;
    ///         Vec3::new(t.cos(), t.sin(), 0.0)
    ///     })
    ///     .collect();
    /// // the unit circle at angle 0: tangent +y, curvature 1
    /// let g2 = EndConstraint::curvature(Vec3::new(0.0, 1.0, 0.0), 1.0);
    /// let r = fit_integrated(&pts, &IntegratedOptions::new(Tolerance::Relative(1e-3)).start(g2)).unwrap();
    /// let a = achieved(&r.curve, false, &g2);
    /// assert!(r.met && a.tangent_angle < 1e-9 && a.curvature_relative < 1e-9);
    /// ```
    pub fn start(mut self, condition: EndConstraint) -> Self {
        self.end_conditions.start = condition;
        self
    }

    /// The condition at the last point of an open curve ([`Self::start`]; the tangent is the
    /// direction the curve arrives in).
    pub fn end(mut self, condition: EndConstraint) -> Self {
        self.end_conditions.end = condition;
        self
    }

    /// Per-point weights and points to interpolate held inside the search (the field's docs).
    pub fn point_constraints(mut self, pc: PointConstraints) -> Self {
        self.point_constraints = pc;
        self
    }

    /// The seed of the swarm's random streams (the same seed gives the same curve, at any thread
    /// count).
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// A per-span fairness target `F*` every knot span must reach (`F_j ≤ F*`); `None` for none.
    pub fn span_fairness(mut self, target: impl Into<Option<f64>>) -> Self {
        self.span_fairness = target.into();
        self
    }

    /// Whether the control points are faired inside the tolerance band (sequential convex
    /// programming) before the polish.
    pub fn band_fairing(mut self, on: bool) -> Self {
        self.band_fairing = on;
        self
    }

    /// Whether the control points are finished by local fairing moves within the tolerance.
    pub fn polish(mut self, on: bool) -> Self {
        self.polish = on;
        self
    }

    /// How much work the method may do.
    pub fn budget(mut self, budget: Budget) -> Self {
        let Budget {
            particles,
            max_iterations,
            probe_iterations,
            refine_evaluations,
            band_solves,
            polish_evaluations,
            max_extra_control_points,
            non_exhaustive: _,
        } = budget;
        self.particles = particles;
        self.max_iterations = max_iterations;
        self.probe_iterations = probe_iterations;
        self.refine_evaluations = refine_evaluations;
        self.band_solves = band_solves;
        self.polish_evaluations = polish_evaluations;
        self.max_extra_control_points = max_extra_control_points;
        self
    }

    /// The budget these options run with.
    pub fn current_budget(&self) -> Budget {
        Budget {
            particles: self.particles,
            max_iterations: self.max_iterations,
            probe_iterations: self.probe_iterations,
            refine_evaluations: self.refine_evaluations,
            band_solves: self.band_solves,
            polish_evaluations: self.polish_evaluations,
            max_extra_control_points: self.max_extra_control_points,
            non_exhaustive: NonExhaustive(()),
        }
    }
}

/// An [`Error::InvalidSetting`] naming `option`.
fn invalid(option: &'static str, reason: String) -> Error {
    Error::InvalidSetting { option, reason }
}

/// Checks that every stage can run with `opts`; the error names the offending setting.
pub(crate) fn validate(opts: &IntegratedOptions) -> Result<()> {
    let max = super::search::objective::MAX_DEGREE;
    if opts.degree < 3 || opts.degree > max {
        return Err(invalid(
            "degree",
            format!(
                "the integrated method needs a degree from 3 to {max}, got {}",
                opts.degree
            ),
        ));
    }
    if let Some(d) = opts.max_degree {
        if d < opts.degree || d > max {
            return Err(invalid(
                "degree_search",
                format!(
                    "the highest degree searched must be from {} to {max}, got {d}",
                    opts.degree
                ),
            ));
        }
    }
    let t = match opts.tolerance {
        Tolerance::Relative(r) => r,
        Tolerance::Absolute(t) => t,
    };
    if !(t.is_finite() && t > 0.0) {
        return Err(invalid(
            "tolerance",
            format!("the tolerance must be positive, got {t}"),
        ));
    }
    if let Some(f) = opts.span_fairness {
        if !(f.is_finite() && f > 0.0) {
            return Err(invalid(
                "span_fairness",
                format!("the span fairness target must be positive, got {f}"),
            ));
        }
    }
    if let Some(n) = opts.control_points {
        if n < opts.degree + 1 {
            return Err(invalid(
                "control_points",
                format!(
                    "{n} control points are too few for degree {} (need at least {})",
                    opts.degree,
                    opts.degree + 1
                ),
            ));
        }
    }
    if opts.particles == 0 {
        return Err(invalid(
            "budget",
            "at least one particle is needed (particles = 0)".into(),
        ));
    }
    opts.end_conditions.validate()?;
    if !opts.end_conditions.is_none() && opts.ends == EndCondition::Free {
        return Err(invalid(
            "ends",
            "free ends cannot carry start or end conditions (they fix the end points)".into(),
        ));
    }
    if let Some(a) = opts.corner_angle_deg {
        crate::fit::shape::check_corner_angle(a)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The setting an invalid `opts` is refused for, and the message.
    fn refused(opts: &IntegratedOptions) -> (&'static str, String) {
        match validate(opts) {
            Err(Error::InvalidSetting { option, reason }) => (option, reason),
            other => panic!("expected a refused setting, got {other:?}"),
        }
    }

    #[test]
    fn the_defaults_and_the_builder_defaults_are_valid() {
        assert!(validate(&IntegratedOptions::default()).is_ok());
        assert!(
            validate(&IntegratedOptions::new(Tolerance::Absolute(0.5)).degree_search(7)).is_ok()
        );
        assert_eq!(
            IntegratedOptions::default().current_budget(),
            Budget::default()
        );
    }

    #[test]
    fn every_refusal_names_its_setting() {
        let o = IntegratedOptions::default;
        assert_eq!(
            refused(&o().control_points(3)),
            (
                "control_points",
                "3 control points are too few for degree 3 (need at least 4)".into()
            )
        );
        assert_eq!(refused(&o().degree(2)).0, "degree");
        assert_eq!(refused(&o().degree(8)).0, "degree");
        assert_eq!(refused(&o().degree(4).degree_search(3)).0, "degree_search");
        assert_eq!(refused(&o().degree_search(8)).0, "degree_search");
        assert_eq!(
            refused(&o().tolerance(Tolerance::Absolute(-1.0))),
            ("tolerance", "the tolerance must be positive, got -1".into())
        );
        assert_eq!(
            refused(&o().tolerance(Tolerance::Relative(f64::NAN))).0,
            "tolerance"
        );
        assert_eq!(refused(&o().span_fairness(0.0)).0, "span_fairness");
        assert_eq!(refused(&o().corner_angle(0.0)).0, "corner_angle");
        assert_eq!(refused(&o().corner_angle(f64::NAN)).0, "corner_angle");
        let no_particles = Budget {
            particles: 0,
            ..Budget::default()
        };
        assert_eq!(refused(&o().budget(no_particles)).0, "budget");
    }
}
