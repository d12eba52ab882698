//! `fairfit curve`'s per-point constraints: weights (`--weights FILE`, or a `w`/`weight` column) and
//! points to interpolate (`--interpolate I,J,...`, or an `i` column), read here and held by
//! `fairfit::fit::point_constraints` around whichever method fits.
//!
//! Layering: this module is below `curve.rs` (which calls it with its method as a closure) and
//! imports nothing of it, so the command's modules have no cycle. Without weights or points to
//! interpolate nothing here changes the fit.
//!
//! Exit codes: a bad weight (in a file or a column) is an input error (1); an `--interpolate`
//! index out of range, or points to interpolate the curve cannot take, a usage error (2) naming
//! `--interpolate`; an `i` column the curve cannot take, an input error (1).

use super::curve_args::{CurveArgs, Method};
use super::{CliError, CmdResult};
use fairfit::fit::cad_fit::Fitted;
use fairfit::fit::point_constraints::{
    fit_with_point_constraints_inside, Held, PointConstraintTuning, PointConstraints,
};
use fairfit::io::point_columns::read_point_columns;
use fairfit::io::PointSet;
use fairfit::prelude::Vec3;
use fairfit::report::point_constraints::add_point_constraints;
use serde_json::Value;
use std::path::Path;

/// The constraints of one input and where each part came from (for the messages).
#[derive(Clone, Debug, Default)]
pub struct InputConstraints {
    /// Weights and points to interpolate, indices into the points read.
    pub constraints: PointConstraints,
    /// Where the weights came from: `--weights FILE` or `the w column of FILE`.
    pub weights_source: String,
    /// Whether the points to interpolate came from `--interpolate` (else from the `i` column).
    pub interpolate_flag: bool,
    /// The index in the file of each point kept (points of weight 0 are dropped on reading, so
    /// that everything after, the screening included, sees the data without them).
    pub original: Vec<usize>,
    /// The points of weight 0 (indices in the file).
    pub ignored: Vec<usize>,
}

/// Usage checks of `--weights` / `--interpolate` before any input is read.
pub fn check_options(args: &CurveArgs) -> CmdResult {
    let asked = args.weights.is_some() || !args.interpolate.is_empty();
    if asked && fairfit::io::cad_read::CadFormat::from_path(&args.input).is_some() {
        return Err(CliError::usage(
            "--weights and --interpolate need a point file, not a STEP or IGES curve",
        ));
    }
    Ok(())
}

/// Reads `args.input` as `cad_input::read_curve_points` does, and its weight and flag columns
/// when the file names them (`fairfit::io::point_columns`), with `--weights` and `--interpolate`.
pub fn read_input(
    args: &CurveArgs,
) -> Result<
    (
        PointSet,
        Option<super::cad_input::CadCurve>,
        InputConstraints,
    ),
    CliError,
> {
    let is_cad = fairfit::io::cad_read::CadFormat::from_path(&args.input).is_some();
    let columns = match is_cad {
        true => None,
        false => read_point_columns(&args.input)?,
    };
    let mut ic = InputConstraints::default();
    let (set, cad) = match columns {
        None => super::cad_input::read_curve_points(&args.input, &args.cad)?,
        Some(c) => {
            if c.points.len() < fairfit::io::points::MIN_POINTS {
                return Err(CliError::new(format!(
                    "{}: at least 2 distinct points are needed, found {}",
                    args.input.display(),
                    c.points.len()
                )));
            }
            if c.weights.is_some() && args.weights.is_some() {
                return Err(CliError::usage(format!(
                    "--weights: {} has a weight column already; give one of them",
                    args.input.display()
                )));
            }
            ic.weights_source = format!("the weight column of {}", args.input.display());
            ic.constraints.weights = c.weights;
            ic.constraints.interpolate = c.interpolate;
            let set = PointSet {
                columns: if c.has_z { 3 } else { 2 },
                points: c.points,
                dropped_duplicates: c.dropped_duplicates,
                name: None,
                lednicer: false,
            };
            (set, None)
        }
    };
    if let Some(path) = &args.weights {
        ic.weights_source = format!("--weights {}", path.display());
        ic.constraints.weights = Some(read_weights(path)?);
    }
    if !args.interpolate.is_empty() {
        ic.interpolate_flag = true;
        ic.constraints.interpolate.extend(&args.interpolate);
    }
    ic.constraints.interpolate.sort_unstable();
    ic.constraints.interpolate.dedup();
    let mut set = set;
    ic.original = (0..set.points.len()).collect();
    if !ic.constraints.is_none() {
        let n = set.points.len();
        ic.constraints
            .validate(n)
            .map_err(|e| constraint_error(e, &ic))?;
        drop_ignored(&mut set, &mut ic);
    }
    Ok((set, cad, ic))
}

/// Drops the points of weight 0 from `set` and `ic` (validated: not all, none to interpolate).
fn drop_ignored(set: &mut PointSet, ic: &mut InputConstraints) {
    let w = fairfit::fit::constrained_points::without_ignored(&set.points, &ic.constraints);
    set.points = w.points;
    ic.constraints = w.constraints;
    ic.original = w.original;
    ic.ignored = w.ignored;
}

/// One weight per line (`#` comments and blank lines skipped), each finite and `>= 0`.
fn read_weights(path: &Path) -> Result<Vec<f64>, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::new(fairfit::Error::io(path, &e).to_string()))?;
    let mut w = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        match line.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= 0.0 => w.push(v),
            _ => {
                let shown: String = line.chars().take(40).collect();
                return Err(CliError::new(format!(
                    "--weights {}:{}: expected a finite weight >= 0, found '{shown}'",
                    path.display(),
                    k + 1
                )));
            }
        }
    }
    Ok(w)
}

/// A constraint error of the library as the command prints it (module docs for the exit codes).
fn constraint_error(e: fairfit::Error, ic: &InputConstraints) -> CliError {
    match e {
        fairfit::Error::InvalidSetting {
            option: "weights",
            reason,
        } => CliError::new(format!("{}: {reason}", ic.weights_source)),
        fairfit::Error::InvalidSetting {
            option: "interpolate",
            reason,
        } if ic.interpolate_flag => {
            CliError::usage(format!("invalid option --interpolate: {reason}"))
        }
        fairfit::Error::InvalidSetting {
            option: "interpolate",
            reason,
        } => CliError::new(format!("the interpolation column: {reason}")),
        e => CliError::from(e),
    }
}

/// A fit's failure: the method's own (as it printed it) or the constraints'.
pub enum Failure {
    /// The method's error.
    Method(CliError),
    /// The constraint layer's error.
    Constraint(fairfit::Error),
}

impl From<fairfit::Error> for Failure {
    fn from(e: fairfit::Error) -> Self {
        Failure::Constraint(e)
    }
}

/// Which of `points` the screening kept (`fairfit::fit::constrained_points::kept_after_screening`),
/// with the constraints of the kept points and their indices among `points`.
pub fn kept_after_screening(
    points: &[Vec3],
    outliers: &[usize],
    ic: &InputConstraints,
) -> (Vec<Vec3>, InputConstraints, Vec<usize>) {
    let (kept, constraints, index) =
        fairfit::fit::constrained_points::kept_after_screening(points, outliers, &ic.constraints);
    let mut out = ic.clone();
    out.constraints = constraints;
    (kept, out, index)
}

/// Fits `points` with `fit` (the method; `Some(t)`: at the absolute tolerance `t`) under the
/// constraints `ic`; `index` maps the points back to `ic`'s (and `ic.original` to the file's) for
/// the report. The report, when
/// the method made one, gets the constrained curve's shape and deviation, `point_constraints` and
/// `point_constraint_fit`.
pub fn fit_constrained<R>(
    args: &CurveArgs,
    points: &[Vec3],
    ic: &InputConstraints,
    index: &[usize],
    fit: impl FnMut(
        &[Vec3],
        Option<f64>,
        &PointConstraints,
    ) -> Result<Fitted<(Option<Value>, R)>, Failure>,
) -> Result<Fitted<(Option<Value>, R)>, CliError> {
    let conditions = args.end_conditions();
    // free ends may move (within the tolerance, as the method left them); pinned ends and the
    // control points of end conditions are held
    let held = Held::at_ends(args.ends != super::curve_args::EndsArg::Free, &conditions);
    let reweight = args.method == Method::Lsq && args.smoothing == 0.0;
    let tuning = PointConstraintTuning::default();
    let r =
        fit_with_point_constraints_inside(points, &ic.constraints, held, reweight, &tuning, fit);
    let r = match r {
        Ok(r) => r,
        Err(Failure::Method(e)) => return Err(e),
        Err(Failure::Constraint(e)) => return Err(constraint_error(e, ic)),
    };
    let (mut report, files) = r.extra;
    let index: Vec<usize> = index.iter().map(|&i| ic.original[i]).collect();
    if let Some(rep) = report.as_mut() {
        let input = args.input.display().to_string();
        add_point_constraints(rep, &input, &r.curve, &r.report, &index, &ic.ignored);
    }
    Ok(Fitted {
        tolerance: r.report.tolerance,
        max_deviation: r.report.max_deviation,
        curve: r.curve,
        extra: (report, files),
    })
}
