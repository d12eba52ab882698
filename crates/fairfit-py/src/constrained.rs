//! `fit_curve(..., weights=..., interpolate=...)`: the fit under per-point weights and points to
//! interpolate, as `fairfit curve --weights FILE --interpolate I,J` makes it
//! (`fairfit::fit::point_constraints`): the points of weight 0 dropped, the screening run on the
//! rest, its spikes dropped except the points to interpolate, and the method held to the
//! constraints (the integrated method inside its search too), with the same report keys.
//!
//! Indices (of `interpolate`, and in the report) are rows of the array passed in. A run of
//! consecutive duplicate rows is one point: it gets the largest weight of the run (every row of the
//! run is then held to its own tolerance), and is interpolated when any row of the run is.

use crate::fit_curve::{fit_points, Fitted};
use crate::options::{CurveSettings, Method};
use fairfit::fit::cad_fit::Fitted as MethodFit;
use fairfit::fit::constrained_points::{kept_after_screening, without_ignored};
use fairfit::fit::point_constraints::{
    fit_with_point_constraints_inside, Held, PointConstraintTuning, PointConstraints,
};
use fairfit::fit::screening::screen_input;
use fairfit::fit::tolerance::FitOptions;
use fairfit::report::curve::add_screening;
use fairfit::report::point_constraints::add_point_constraints;
use fairfit::{Tolerance, Vec3};
use std::time::Instant;

/// The constraints of the array's `rows` rows, checked, carried over to the points left after
/// consecutive duplicates were dropped (`kept[r]`: the point of row `r`).
pub fn constraints_of_points(
    weights: Option<Vec<f64>>,
    interpolate: Option<Vec<usize>>,
    rows: usize,
    kept: &[usize],
) -> Result<PointConstraints, String> {
    let mut interpolate = interpolate.unwrap_or_default();
    interpolate.sort_unstable();
    interpolate.dedup();
    let by_row = PointConstraints {
        weights,
        interpolate,
    };
    by_row.validate(rows).map_err(constraint_message)?;
    let n = kept.last().map_or(0, |&k| k + 1);
    let weights = by_row.weights.as_ref().map(|w| {
        let mut out = vec![0.0f64; n];
        for (r, &k) in kept.iter().enumerate() {
            out[k] = out[k].max(w[r]);
        }
        out
    });
    let mut interpolate: Vec<usize> = by_row.interpolate.iter().map(|&r| kept[r]).collect();
    interpolate.dedup();
    Ok(PointConstraints {
        weights,
        interpolate,
    })
}

/// A constraint error as the package raises it: `weights: ...` or `interpolate: ...`.
fn constraint_message(e: fairfit::Error) -> String {
    match e {
        fairfit::Error::InvalidSetting { option, reason } => format!("{option}: {reason}"),
        e => e.to_string(),
    }
}

/// Why a constrained fit failed: the method's own error, or the constraints'.
enum Failure {
    Method(String),
    Constraint(fairfit::Error),
}

impl From<fairfit::Error> for Failure {
    fn from(e: fairfit::Error) -> Self {
        Failure::Constraint(e)
    }
}

/// The fit of `points` (duplicates dropped; `rows[i]`: the first array row of point `i`) under
/// `pc` (module doc), with the report and warnings of `fit_screened`.
pub fn fit_constrained(
    s: &CurveSettings,
    input: &str,
    points: &[Vec3],
    pc: &PointConstraints,
    rows: &[usize],
    wall: Instant,
    threads: Option<usize>,
) -> Result<Fitted, String> {
    let w = without_ignored(points, pc);
    let screened = screen_input(w.points.clone(), s.tolerance(), s.outliers);
    let mut warnings: Vec<String> = screened
        .warning()
        .map(|w| w.trim_start_matches("warning: ").to_string())
        .into_iter()
        .collect();
    let opts = crate::options::fit_options(s, screened.fit_tolerance());
    let outliers: Vec<usize> = screened
        .screening
        .as_ref()
        .map(|sc| sc.outliers.iter().map(|o| o.index).collect())
        .unwrap_or_default();
    let (kept, kc, index) = kept_after_screening(&w.points, &outliers, &w.constraints);
    let held = Held::at_ends(!s.free_ends, &s.end_conditions());
    let reweight = s.method == Method::Lsq && s.smoothing == 0.0;
    let tuning = PointConstraintTuning::default();
    let fit = |pts: &[Vec3], tol: Option<f64>, inside: &PointConstraints| {
        let mut s2 = s.clone();
        if s.method == Method::Integrated {
            s2.search_constraints = inside.clone();
        }
        let opts2 = match tol {
            Some(t) => {
                s2.tol = Some(t);
                FitOptions {
                    tolerance: Tolerance::Absolute(t),
                    ..opts.clone()
                }
            }
            None => opts.clone(),
        };
        let f = fit_points(&s2, input, &opts2, pts, wall, threads).map_err(Failure::Method)?;
        let field = |k: &str| f.report[k].as_f64().unwrap_or(f64::NAN);
        Ok(MethodFit {
            curve: f.curve.clone(),
            tolerance: field("tolerance"),
            max_deviation: field("max_deviation"),
            extra: f,
        })
    };
    let r = fit_with_point_constraints_inside(&kept, &kc, held, reweight, &tuning, fit);
    let r = match r {
        Ok(r) => r,
        Err(Failure::Method(e)) => return Err(e),
        Err(Failure::Constraint(e)) => return Err(constraint_message(e)),
    };
    let mut fitted = r.extra;
    let row = |i: usize| rows[w.original[index[i]]];
    let index_rows: Vec<usize> = (0..index.len()).map(row).collect();
    let ignored_rows: Vec<usize> = w.ignored.iter().map(|&i| rows[i]).collect();
    add_point_constraints(
        &mut fitted.report,
        input,
        &r.curve,
        &r.report,
        &index_rows,
        &ignored_rows,
    );
    if let Some(sc) = &screened.screening {
        add_screening(&mut fitted.report, s.outliers, sc);
    }
    warnings.append(&mut fitted.warnings);
    fitted.warnings = warnings;
    fitted.curve = r.curve;
    Ok(fitted)
}
