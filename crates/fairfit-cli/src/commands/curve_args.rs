//! The arguments of `fairfit curve` and their value types (method, parameterisation, knot rule, ends,
//! degree), shared by the command (`curve.rs`) and its optimising methods (`curve_optim.rs`).

use super::outputs::OutputArgs;
use clap::{Args, ValueEnum};
use fairfit::fit::end_constraints::{EndConstraint, EndConstraints};
use fairfit::fit::{KnotRule, Parameterization};
use fairfit::prelude::{ClosedMode, EndCondition, Tolerance, Vec3};
use std::path::PathBuf;

/// The fitting method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Least squares with a tolerance-driven knot count (fast baseline).
    Lsq,
    /// Integrated fitting and fairing (knots by particle swarm optimisation).
    Integrated,
    /// Least squares, then fairing of the fitted curve.
    FitThenFair,
}

impl From<Method> for fairfit::fit::method::Method {
    fn from(m: Method) -> Self {
        match m {
            Method::Lsq => fairfit::fit::method::Method::Lsq,
            Method::Integrated => fairfit::fit::method::Method::Integrated,
            Method::FitThenFair => fairfit::fit::method::Method::FitThenFair,
        }
    }
}

/// `--outliers`: what to do with isolated spikes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OutliersArg {
    /// Keep every point; a fit that misses the tolerance names the spikes that keep it out of reach.
    Off,
    /// Exclude isolated points far beyond both the tolerance and the noise (listed in the report).
    Auto,
}

/// Parameterisation choices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ParamArg {
    /// Equal parameter steps.
    Uniform,
    /// Steps proportional to chord length.
    Chord,
    /// Steps proportional to the square root of chord length (default).
    Centripetal,
}

impl From<ParamArg> for Parameterization {
    fn from(p: ParamArg) -> Self {
        match p {
            ParamArg::Uniform => Parameterization::Uniform,
            ParamArg::Chord => Parameterization::ChordLength,
            ParamArg::Centripetal => Parameterization::Centripetal,
        }
    }
}

/// Knot placement choices of `--method lsq`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum KnotArg {
    /// Split spans where the error is largest, then remove unneeded knots (default, fewest points).
    Refine,
    /// Symmetric averaging rule; smallest count meeting the tolerance.
    Averaging,
    /// Curvature-adaptive rule (more knots where the data turn fast); smallest count meeting it.
    Adaptive,
}

impl From<KnotArg> for KnotRule {
    fn from(k: KnotArg) -> Self {
        match k {
            KnotArg::Refine => KnotRule::Refine,
            KnotArg::Averaging => KnotRule::Averaging,
            KnotArg::Adaptive => KnotRule::Adaptive,
        }
    }
}

/// `--ends`: the end condition of an open curve (integrated method).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EndsArg {
    /// The curve starts and ends exactly at the first and last points.
    Pinned,
    /// The curve's end points may move within the tolerance of the first and last points, like
    /// every other point (fairer curves where the data end at high curvature).
    Free,
}

impl From<EndsArg> for EndCondition {
    fn from(e: EndsArg) -> Self {
        match e {
            EndsArg::Pinned => Self::Pinned,
            EndsArg::Free => Self::Free,
        }
    }
}

/// `--chain`: the continuity of the joins of a chain of pieces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ChainArg {
    /// Position and tangent direction.
    G1,
    /// Position, tangent direction and curvature vector.
    G2,
}

impl From<ChainArg> for fairfit::optim::chain::JoinContinuity {
    fn from(c: ChainArg) -> Self {
        match c {
            ChainArg::G1 => Self::G1,
            ChainArg::G2 => Self::G2,
        }
    }
}

/// `--continuity`: the order of continuity with a `--start-from` / `--end-from` curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ContinuityArg {
    /// Position only.
    G0,
    /// Position and tangent direction.
    G1,
    /// Position, tangent direction and curvature vector.
    G2,
}

impl ContinuityArg {
    /// The order 0, 1 or 2.
    pub fn order(self) -> usize {
        match self {
            ContinuityArg::G0 => 0,
            ContinuityArg::G1 => 1,
            ContinuityArg::G2 => 2,
        }
    }
}

/// A `--start-from` / `--end-from` value `FILE[:start|:end]`: the file and which of its ends
/// (`default_end`: the one taken without a suffix).
pub fn split_from(s: &str, default_end: bool) -> (PathBuf, bool) {
    match s.rsplit_once(':') {
        Some((f, "end")) if !f.is_empty() => (PathBuf::from(f), true),
        Some((f, "start")) if !f.is_empty() => (PathBuf::from(f), false),
        _ => (PathBuf::from(s), default_end),
    }
}

/// `--degree`: a fixed degree, or `auto` (the integrated method's degree search).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DegreeArg {
    /// One degree.
    Fixed(usize),
    /// Every degree from 3 to [`AUTO_MAX_DEGREE`], one kept (the integrated method's degree search).
    Auto,
}

/// The highest degree `--degree auto` tries.
pub const AUTO_MAX_DEGREE: usize = 5;

impl DegreeArg {
    /// The fixed degree, or the lowest (reference) degree of the search.
    pub fn lowest(self) -> usize {
        match self {
            DegreeArg::Fixed(d) => d,
            DegreeArg::Auto => 3,
        }
    }
}

/// Parses `auto` or a degree from 1 to 15.
fn parse_degree(s: &str) -> Result<DegreeArg, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(DegreeArg::Auto);
    }
    match s.trim().parse::<usize>() {
        Ok(d) if (1..=15).contains(&d) => Ok(DegreeArg::Fixed(d)),
        _ => Err(format!(
            "expected `auto` or a degree from 1 to 15, got `{s}`"
        )),
    }
}

/// Parses `X,Y` or `X,Y,Z` into a vector.
fn parse_vector(s: &str) -> Result<Vec3, String> {
    fairfit::fit::end_constraints::parse_vector(s)
}

/// An end condition `point[:X,Y[,Z]]`, `tangent:X,Y[,Z]`, `curvature:X,Y[,Z]:KAPPA` (signed
/// curvature) or `curvature:X,Y,Z:KX,KY,KZ` (curvature vector): the library's text form.
fn parse_end_condition(s: &str) -> Result<EndConstraint, String> {
    s.parse()
}

/// [`parse_end_condition`] as a check: the text is kept (a parsed condition would make the
/// arguments much larger) and parsed again by [`CurveArgs::end_conditions`].
fn check_end_condition(s: &str) -> Result<String, String> {
    parse_end_condition(s).map(|_| s.to_string())
}

/// Arguments of `fairfit curve`.
#[derive(Args, Debug, Clone)]
pub struct CurveArgs {
    /// Point file: CSV/TSV/whitespace with 2 or 3 columns, or a Selig/Lednicer airfoil .dat file; or a
    /// STEP/IGES file whose B-spline curve is sampled densely and re-fitted (re-faired).
    /// With --chain, the first piece.
    #[arg(required = true)]
    pub input: PathBuf,
    /// The further pieces of a --chain, in order: each starts where the previous one ends (its
    /// first point within twice the tolerance of the previous file's last point).
    #[arg(value_name = "MORE")]
    pub more_inputs: Vec<PathBuf>,
    /// Fit INPUT MORE... as one fair chain of curves joined with this continuity: g1 (tangent) or
    /// g2 (and curvature). The joins are chosen within the tolerance of both pieces' end points
    /// (where the fairest single curve through every point passes); every piece is fitted by the
    /// integrated method under them, or is that curve's part between them when it is fairer.
    /// -o FILE.json writes the joined chain (one B-spline on [0, N], the joins knots of full
    /// multiplicity) and each piece to FILE_1.json, FILE_2.json, ...; --step,
    /// --iges, --mesh, --plot and --html show the joined chain; --report lists every piece and the
    /// continuity measured at every join. --start/--end (and --start-from/--end-from) hold the
    /// chain's own ends.
    #[arg(long, value_enum, value_name = "CONTINUITY")]
    pub chain: Option<ChainArg>,
    /// Airfoils: split the points at the leading edge (the point farthest from the trailing edge,
    /// the midpoint of the first and last points; both halves hold it), fit the halves as a G2
    /// chain (as --chain g2) and write the joined curve on [0, 1] with the leading edge at the
    /// parameter 0.5, a knot of full multiplicity: every section fitted so shares that knot.
    #[arg(long, conflicts_with = "chain")]
    pub split_at_le: bool,
    /// Entity choice for STEP/IGES input.
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// Fitting method.
    #[arg(long, value_enum, default_value_t = Method::Integrated)]
    pub method: Method,
    /// Absolute tolerance on the maximum orthogonal deviation.
    #[arg(long, conflicts_with = "rel_tol", allow_hyphen_values = true)]
    pub tol: Option<f64>,
    /// Tolerance relative to the largest side of the points' bounding box (default 1e-3).
    #[arg(long, allow_hyphen_values = true)]
    pub rel_tol: Option<f64>,
    /// Degree of the curve (1 to 15), or `auto` (integrated method, its default): the cubic's count
    /// search, then degrees 4 and 5 at the cubic's control points. The quartic also tries more
    /// points: up to the least-squares count (one above it where the cubic kept that count) when the
    /// cubic's fewest-extrema choice cost much F or its extra points still paid, and one above the
    /// least-squares count (at most a quarter of the points) when the cubic's curve has 6 or more
    /// curvature extrema. The fairest with no more curvature extrema than the cubic's is kept
    /// [default: auto for integrated, 3 for lsq and fit-then-fair]
    #[arg(long, value_parser = parse_degree, allow_hyphen_values = true)]
    pub degree: Option<DegreeArg>,
    /// Parameterisation of the points.
    #[arg(long = "param", value_enum, default_value_t = ParamArg::Centripetal)]
    pub param: ParamArg,
    /// Treat the points as a closed curve (otherwise closed when the last point repeats the first, or
    /// when the ends are a gap of at most the tolerance and a few spacings apart that the data continue
    /// smoothly through: the report's `closed_by_gap`).
    #[arg(long, conflicts_with = "open")]
    pub closed: bool,
    /// Treat the points as an open curve even when the last point repeats the first (or their ends
    /// are a gap apart that `--closed`'s detection would close): the curve
    /// starts and ends at that point, with ends of its own (which --start/--end can hold).
    #[arg(long)]
    pub open: bool,
    /// Turning angle (degrees) above which a point is a corner kept as a C0 knot.
    #[arg(long, default_value_t = fairfit::fit::shape::DEFAULT_CORNER_ANGLE_DEG, allow_hyphen_values = true)]
    pub corner_angle: f64,
    /// Do not detect corners.
    #[arg(long)]
    pub no_corners: bool,
    /// Spikes: `auto` excludes isolated points farther than 4 tolerances (and 8 noise σ) from the
    /// curve of their neighbours on both sides and lists them in the report (`outliers`); corners,
    /// thin trailing edges and short straight pieces are kept. It found none on any clean or noisy
    /// table tried, so it is the default.
    #[arg(long, value_enum, default_value_t = OutliersArg::Auto)]
    pub outliers: OutliersArg,
    /// Integrated method: skip the band fairing of the final control points (sequential convex
    /// programming inside the tolerance band).
    #[arg(long)]
    pub no_band_fairing: bool,
    /// Integrated method, open curves: whether the curve's end points stay on the first and last
    /// points (`pinned`) or, in a last fairing pass, may move within the tolerance of them (`free`);
    /// closed curves have no ends, and a curve with corners keeps its ends pinned (the report's
    /// "ends" says which was used).
    #[arg(long, value_enum, default_value_t = EndsArg::Pinned)]
    pub ends: EndsArg,
    /// Parameter-correction rounds per least-squares fit.
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub correction_rounds: usize,
    /// Scale-free smoothing weight λ (0 = plain least squares).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub smoothing: f64,
    /// Derivative order of the smoothing term: 2 for ∫|C''|², 3 for ∫|C'''|².
    #[arg(long, default_value_t = 2, allow_hyphen_values = true,
          value_parser = clap::value_parser!(u8).range(2..=3))]
    pub smoothing_order: u8,
    /// Knot placement (lsq and fit-then-fair methods).
    #[arg(long, value_enum, default_value_t = KnotArg::Refine)]
    pub knots: KnotArg,
    /// Tangent direction X,Y or X,Y,Z at the first point (open curves): `--start tangent:X,Y[,Z]`.
    #[arg(long, value_parser = parse_vector, allow_hyphen_values = true, conflicts_with = "start")]
    pub start_tangent: Option<Vec3>,
    /// Tangent direction X,Y or X,Y,Z at the last point (open curves): `--end tangent:X,Y[,Z]`.
    #[arg(long, value_parser = parse_vector, allow_hyphen_values = true, conflicts_with = "end")]
    pub end_tangent: Option<Vec3>,
    /// Condition at the first point (open curves): point[:X,Y[,Z]] (G0), tangent:X,Y[,Z] (G1,
    /// direction only) or curvature:X,Y[,Z]:KAPPA (G2, signed curvature; in 3-D also
    /// curvature:X,Y,Z:KX,KY,KZ). Every method holds it. Closed data have no ends: fit them with
    /// --open.
    #[arg(long, value_parser = check_end_condition, allow_hyphen_values = true)]
    pub start: Option<String>,
    /// Condition at the last point (as --start; the tangent is the direction the curve arrives in).
    #[arg(long, value_parser = check_end_condition, allow_hyphen_values = true)]
    pub end: Option<String>,
    /// Continue an existing curve (fairfit JSON, STEP or IGES): the curve starts where FILE's curve
    /// ends (`FILE:start`: where it starts), with the continuity of --continuity.
    #[arg(long, value_name = "FILE[:end]", conflicts_with_all = ["start", "start_tangent"])]
    pub start_from: Option<String>,
    /// Lead into an existing curve: the curve ends where FILE's curve starts (`FILE:end`: where it
    /// ends), with the continuity of --continuity.
    #[arg(long, value_name = "FILE[:start]", conflicts_with_all = ["end", "end_tangent"])]
    pub end_from: Option<String>,
    /// Continuity with the curves of --start-from / --end-from: g0 (position), g1 (and tangent),
    /// g2 (and curvature).
    #[arg(long, value_enum, default_value_t = ContinuityArg::G1)]
    pub continuity: ContinuityArg,
    /// The end conditions with --start-from/--end-from read (set by the command, not a flag).
    #[arg(skip)]
    pub resolved_ends: Option<EndConstraints>,
    /// The weights and points to interpolate of the points being fitted, for the integrated
    /// method's search (set by the command, not a flag; indices after screening and weight 0).
    #[arg(skip)]
    pub search_constraints: fairfit::fit::point_constraints::PointConstraints,
    /// One weight per point, a line each (`#` comments): point i is held to tol / w_i, weight 0
    /// ignores it. A point file may instead have a `w` (or `weight`) column named in its header.
    #[arg(long, value_name = "FILE")]
    pub weights: Option<PathBuf>,
    /// Points the curve passes through (within 1e-9 of the data's size): 0-based indices of the
    /// points as fitted, comma-separated. A point file may instead have an `i` column (0/1).
    #[arg(long, value_name = "I,J,...", value_delimiter = ',', value_parser = super::whole_number)]
    pub interpolate: Vec<usize>,
    /// Per-span fairness target F*: every knot span must reach F_j <= F* (integrated method).
    #[arg(long, allow_hyphen_values = true)]
    pub span_fairness: Option<f64>,
    /// Fixed number of control points instead of the fewest meeting the tolerance (integrated method).
    #[arg(long, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub control_points: Option<usize>,
    /// Write the Pareto front of (max deviation, F) as CSV (integrated method).
    #[arg(long)]
    pub pareto: Option<PathBuf>,
    /// Also write every Pareto front member as a curve JSON into this directory.
    #[arg(long)]
    pub pareto_curves: Option<PathBuf>,
    /// Random seed (methods with a stochastic search).
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number_u64)]
    pub seed: u64,
    /// Worker threads (0 = all cores; capped at 4 per core; results do not depend on it).
    #[arg(long, default_value_t = 0, allow_hyphen_values = true, value_parser = super::whole_number)]
    pub threads: usize,
    /// Output curve JSON file (stdout when absent).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Write a JSON report (deviation, fairness, timing) to this file.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// CAD, mesh, plot and HTML outputs.
    #[command(flatten)]
    pub outputs: OutputArgs,
}

impl CurveArgs {
    /// `--start`/`--end`, with `--start-tangent`/`--end-tangent` as `tangent:` conditions.
    pub fn end_conditions(&self) -> EndConstraints {
        if let Some(r) = self.resolved_ends {
            return r;
        }
        // the texts were checked by clap (`check_end_condition`)
        let parsed = |s: &Option<String>| s.as_deref().and_then(|s| parse_end_condition(s).ok());
        EndConstraints {
            start: parsed(&self.start)
                .or(self.start_tangent.map(EndConstraint::tangent))
                .unwrap_or_default(),
            end: parsed(&self.end)
                .or(self.end_tangent.map(EndConstraint::tangent))
                .unwrap_or_default(),
        }
    }

    /// `--tol` (absolute) or `--rel-tol`, else 1e-3 of the points' size.
    pub fn tolerance(&self) -> Tolerance {
        match (self.tol, self.rel_tol) {
            (Some(t), _) => Tolerance::Absolute(t),
            (None, Some(r)) => Tolerance::Relative(r),
            (None, None) => Tolerance::Relative(1e-3),
        }
    }

    /// `--closed`: always closed; `--open`: always open; otherwise detected (the last point repeats
    /// the first, or a gap closed at the tolerance's scale, `fairfit::fit::closure`).
    pub fn closed_mode(&self) -> ClosedMode {
        match (self.closed, self.open) {
            (true, _) => ClosedMode::Closed,
            (false, true) => ClosedMode::Open,
            (false, false) => ClosedMode::Auto,
        }
    }

    /// `--degree`, or the method's default: `auto` for the integrated method, 3 otherwise.
    pub fn degree(&self) -> DegreeArg {
        self.degree.unwrap_or(match self.method {
            Method::Integrated => DegreeArg::Auto,
            _ => DegreeArg::Fixed(3),
        })
    }
}
