//! The options of `fit_curve`, checked and mapped to the library exactly as the CLI's `fairfit curve`
//! maps its flags (`crates/fairfit-cli/src/commands/curve.rs` and `curve_optim.rs`): the same defaults,
//! the same checks with the same messages (named by their Python keywords), the same library options.
//! `integrated_options` (with `chain_options` on top of it) and `fit_options` are the only places
//! that build library options.

use fairfit::fit::end_constraints::{EndConstraint, EndConstraints};
pub use fairfit::fit::method::Method;
use fairfit::fit::method::MethodOption;
use fairfit::fit::screening::OutlierMode;
use fairfit::fit::tolerance::{ClosedMode, FitOptions, KnotRule, Tolerance};
use fairfit::fit::{Parameterization, SmoothingOrder};
use fairfit::optim::{EndCondition, IntegratedOptions};
use fairfit::Vec3;

/// The highest degree `degree="auto"` tries (the CLI's `AUTO_MAX_DEGREE`).
pub const AUTO_MAX_DEGREE: usize = 5;

/// Every setting of one curve fit, as the Python keywords give them.
#[derive(Clone, Debug)]
pub struct CurveSettings {
    /// `method`.
    pub method: Method,
    /// `tol` (absolute; takes precedence over `rel_tol`).
    pub tol: Option<f64>,
    /// `rel_tol` (relative to the largest side of the points' bounding box).
    pub rel_tol: f64,
    /// `degree`: `None` for `"auto"`.
    pub degree: Option<usize>,
    /// `control_points`.
    pub control_points: Option<usize>,
    /// `closed`: `None` detects a repeated first point or a gap closed at the tolerance's scale
    /// (`fairfit::fit::closure`), `True` forces a closed curve, `False` an open one.
    pub closed: Option<bool>,
    /// `corner_angle` in degrees; `None` detects no corners (`--no-corners`).
    pub corner_angle: Option<f64>,
    /// `ends`: free end points (`"free"`), else pinned.
    pub free_ends: bool,
    /// `seed`.
    pub seed: u64,
    /// `band_fairing` (`--no-band-fairing` when false).
    pub band_fairing: bool,
    /// `span_fairness` (the per-span target F*).
    pub span_fairness: Option<f64>,
    /// `param`.
    pub param: Parameterization,
    /// `knots` (the knot rule of `lsq` and `fit-then-fair`).
    pub knots: KnotRule,
    /// `knots` as given (the lsq report names it).
    pub knots_name: String,
    /// `correction_rounds`.
    pub correction_rounds: usize,
    /// `smoothing` λ.
    pub smoothing: f64,
    /// `smoothing_order` (2 or 3).
    pub smoothing_order: u8,
    /// `start` (`--start`), or `start_tangent` as a `tangent:` condition; `None` for neither.
    pub start: Option<EndConstraint>,
    /// `end` (`--end`), or `end_tangent` as a `tangent:` condition.
    pub end: Option<EndConstraint>,
    /// `outliers` (`--outliers`).
    pub outliers: OutlierMode,
    /// `pareto` (`--pareto`).
    pub pareto: bool,
    /// The weights and points to interpolate the integrated method holds inside its search (set
    /// by the constrained fit, `constrained.rs`, for the points it passes; default otherwise).
    pub search_constraints: fairfit::fit::point_constraints::PointConstraints,
}

/// `"auto"` or a degree from 1 to 15 (the CLI's `--degree`); `None` is `auto`.
pub fn parse_degree(text: &str) -> Result<Option<usize>, String> {
    if text.eq_ignore_ascii_case("auto") {
        return Ok(None);
    }
    match text.trim().parse::<usize>() {
        Ok(d) if (1..=15).contains(&d) => Ok(Some(d)),
        _ => Err(format!(
            "degree: expected `auto` or a degree from 1 to 15, got `{text}`"
        )),
    }
}

/// `method=`.
pub fn parse_method(text: &str) -> Result<Method, String> {
    text.parse().map_err(|e| format!("method: {e}"))
}

/// `param=`.
pub fn parse_param(text: &str) -> Result<Parameterization, String> {
    match text {
        "centripetal" => Ok(Parameterization::Centripetal),
        "chord" => Ok(Parameterization::ChordLength),
        "uniform" => Ok(Parameterization::Uniform),
        _ => Err(format!(
            "param: expected `centripetal`, `chord` or `uniform`, got `{text}`"
        )),
    }
}

/// `knots=`.
pub fn parse_knots(text: &str) -> Result<KnotRule, String> {
    match text {
        "refine" => Ok(KnotRule::Refine),
        "averaging" => Ok(KnotRule::Averaging),
        "adaptive" => Ok(KnotRule::Adaptive),
        _ => Err(format!(
            "knots: expected `refine`, `averaging` or `adaptive`, got `{text}`"
        )),
    }
}

/// `outliers=`.
pub fn parse_outliers(text: &str) -> Result<OutlierMode, String> {
    match text {
        "auto" => Ok(OutlierMode::Auto),
        "off" => Ok(OutlierMode::Off),
        _ => Err(format!("outliers: expected `auto` or `off`, got `{text}`")),
    }
}

/// One end's condition from `start=`/`end=` (the text of `--start`/`--end`) or
/// `start_tangent=`/`end_tangent=` (a direction), which exclude each other (`which` is `"start"`
/// or `"end"`).
pub fn parse_end(
    which: &str,
    text: Option<&str>,
    tangent: Option<[f64; 3]>,
) -> Result<Option<EndConstraint>, String> {
    match (text, tangent) {
        (Some(_), Some(_)) => Err(format!(
            "{which} and {which}_tangent cannot be used together"
        )),
        (Some(t), None) => t
            .parse::<EndConstraint>()
            .map(Some)
            .map_err(|e| format!("{which}: {e}, got `{t}`")),
        (None, Some([x, y, z])) => Ok(Some(EndConstraint::tangent(Vec3::new(x, y, z)))),
        (None, None) => Ok(None),
    }
}

/// `ends=`: true for free ends.
pub fn parse_ends(text: &str) -> Result<bool, String> {
    match text {
        "pinned" => Ok(false),
        "free" => Ok(true),
        _ => Err(format!("ends: expected `pinned` or `free`, got `{text}`")),
    }
}

/// The library's check of `corner_angle` (`None`: no corners), its message led by the keyword:
/// `corner_angle must be in (0, 180] degrees, got 200`.
pub fn check_corner_angle(degrees: Option<f64>) -> Result<(), String> {
    match degrees.map(fairfit::fit::shape::check_corner_angle) {
        Some(Err(fairfit::Error::InvalidSetting { option, reason })) => {
            Err(format!("{option} {reason}"))
        }
        Some(Err(e)) => Err(e.to_string()),
        _ => Ok(()),
    }
}

impl CurveSettings {
    /// `degree`, or the method's default: `auto` for the integrated method, 3 otherwise.
    pub fn degree(&self) -> Option<usize> {
        match (self.degree, self.method) {
            (Some(d), _) => Some(d),
            (None, Method::Integrated) => None,
            (None, _) => Some(3),
        }
    }

    /// The fixed degree, or the lowest (reference) degree of the search.
    pub fn lowest_degree(&self) -> usize {
        self.degree().unwrap_or(3)
    }

    /// The tolerance: `tol` when given, else `rel_tol`.
    pub fn tolerance(&self) -> Tolerance {
        match self.tol {
            Some(t) => Tolerance::Absolute(t),
            None => Tolerance::Relative(self.rel_tol),
        }
    }

    fn closed_mode(&self) -> ClosedMode {
        match self.closed {
            None => ClosedMode::Auto,
            Some(true) => ClosedMode::Closed,
            Some(false) => ClosedMode::Open,
        }
    }

    /// The checks `fairfit curve` makes before it reads its input, with the same messages.
    pub fn check(&self) -> Result<(), String> {
        self.check_method_options()?;
        check_corner_angle(self.corner_angle)?;
        if !(self.smoothing.is_finite() && self.smoothing >= 0.0) {
            return Err(format!(
                "smoothing must be a finite number >= 0, got {}",
                self.smoothing
            ));
        }
        if !(2..=3).contains(&self.smoothing_order) {
            return Err(format!(
                "smoothing_order must be 2 or 3, got {}",
                self.smoothing_order
            ));
        }
        let integrated = self.method == Method::Integrated;
        if self.degree().is_none() && !integrated {
            return Err("degree='auto' needs method='integrated'".into());
        }
        if self.control_points.is_some() && !integrated {
            return Err("control_points needs method='integrated'".into());
        }
        if self.free_ends && !integrated {
            return Err("ends='free' needs method='integrated'".into());
        }
        Ok(())
    }

    /// Refuses a keyword the chosen method would ignore (`fairfit curve`'s usage error), naming
    /// the method that uses it.
    fn check_method_options(&self) -> Result<(), String> {
        let given = |option: MethodOption, set: bool| set.then_some(option);
        let ignored = self.method.first_ignored(
            [
                given(MethodOption::Knots, self.knots != KnotRule::Refine),
                given(
                    MethodOption::Param,
                    self.param != Parameterization::Centripetal,
                ),
                given(MethodOption::CorrectionRounds, self.correction_rounds != 0),
                given(MethodOption::Smoothing, self.smoothing != 0.0),
                given(MethodOption::SmoothingOrder, self.smoothing_order != 2),
                given(MethodOption::SpanFairness, self.span_fairness.is_some()),
                given(MethodOption::Pareto, self.pareto),
                given(MethodOption::BandFairing, !self.band_fairing),
            ]
            .into_iter()
            .flatten(),
        );
        let Some(option) = ignored else {
            return Ok(());
        };
        let uses: Vec<String> = option
            .methods()
            .iter()
            .map(|m| format!("method='{m}'"))
            .collect();
        Err(format!(
            "{} has no effect with method='{}'; it needs {}",
            keyword(option),
            self.method,
            uses.join(" or ")
        ))
    }

    /// The end conditions (`start`, `end`; none where not given).
    pub fn end_conditions(&self) -> EndConstraints {
        EndConstraints {
            start: self.start.unwrap_or_default(),
            end: self.end.unwrap_or_default(),
        }
    }

    /// The check `fairfit curve` makes once the points are known.
    pub fn check_points(&self, distinct: usize) -> Result<(), String> {
        match self.control_points {
            Some(n) if n > distinct => Err(format!(
                "control_points {n} exceeds the {distinct} distinct input points"
            )),
            _ => Ok(()),
        }
    }
}

/// The least-squares options (`method="lsq"` and `"fit-then-fair"`), as `fairfit curve` builds them,
/// fitted to `tolerance` (the screening's, [`fairfit::fit::screening::ScreenedInput::fit_tolerance`]).
/// A tangent alone keeps the least-squares pipeline's end derivative (its length from the data's
/// speed); a point or a curvature makes every condition exact.
pub fn fit_options(s: &CurveSettings, tolerance: Tolerance) -> FitOptions {
    let conditions = s.end_conditions();
    let exact = [&conditions.start, &conditions.end]
        .iter()
        .any(|c| c.point.is_some() || c.curvature.is_some());
    FitOptions {
        degree: s.lowest_degree(),
        parameterization: s.param,
        tolerance,
        closed: s.closed_mode(),
        corner_angle_deg: s.corner_angle,
        correction_rounds: s.correction_rounds,
        smoothing: s.smoothing,
        smoothing_order: if s.smoothing_order == 3 {
            SmoothingOrder::Third
        } else {
            SmoothingOrder::Second
        },
        knot_rule: s.knots,
        start_tangent: conditions.start.tangent.filter(|_| !exact),
        end_tangent: conditions.end.tangent.filter(|_| !exact),
        end_conditions: if exact {
            conditions
        } else {
            Default::default()
        },
        ..FitOptions::default()
    }
}

/// The integrated method's options, as `fairfit curve` builds them (its `integrated_options`).
pub fn integrated_options(s: &CurveSettings) -> IntegratedOptions {
    let conditions = s.end_conditions();
    IntegratedOptions::new(s.tolerance())
        .degree(s.lowest_degree())
        .degree_search(s.degree().is_none().then_some(AUTO_MAX_DEGREE))
        .span_fairness(s.span_fairness)
        .seed(s.seed)
        .control_points(s.control_points)
        .corner_angle(s.corner_angle)
        .closed(s.closed_mode())
        .band_fairing(s.band_fairing)
        .ends(if s.free_ends {
            EndCondition::Free
        } else {
            EndCondition::Pinned
        })
        .start(conditions.start)
        .end(conditions.end)
        .point_constraints(s.search_constraints.clone())
}

/// The options of every piece of a chain (`fit_chain`), as `fairfit curve --chain` builds them (its
/// `fit_pieces`): the integrated method's options with the screening of `outliers`, which the chain
/// fit runs itself (on the union of the pieces) instead of the single fit's screening stage.
pub fn chain_options(s: &CurveSettings) -> IntegratedOptions {
    integrated_options(s).outliers(s.outliers)
}

/// The Python keyword of a method-specific option.
fn keyword(option: MethodOption) -> &'static str {
    match option {
        MethodOption::Knots => "knots",
        MethodOption::Param => "param",
        MethodOption::CorrectionRounds => "correction_rounds",
        MethodOption::Smoothing => "smoothing",
        MethodOption::SmoothingOrder => "smoothing_order",
        MethodOption::SpanFairness => "span_fairness",
        MethodOption::Pareto | MethodOption::ParetoCurves => "pareto",
        MethodOption::BandFairing => "band_fairing",
    }
}
