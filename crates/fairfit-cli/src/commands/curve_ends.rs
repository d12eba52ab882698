//! The end conditions of `fairfit curve` that are read from files (`--start-from FILE[:end]`,
//! `--end-from FILE[:start]` with `--continuity`); the report of a fit under end conditions
//! (`end_conditions`) is the library's (`fairfit::report::end_conditions`).
//!
//! A condition taken from a curve's end is its position, unit tangent and curvature vector there
//! (`EndConstraint::from_curve_end`), up to the order `--continuity` asks for. The tangent is
//! oriented along the new curve's travel: a curve that starts where FILE's curve ends continues in
//! its direction; one that starts where FILE's curve starts leaves it, in the opposite direction.

use super::curve_args::{split_from, CurveArgs};
use super::CliError;
use fairfit::fit::end_constraints::EndConstraint;
use fairfit::io::{read_geometry, Geometry};

/// `args` with `--start-from` / `--end-from` read into [`CurveArgs::resolved_ends`] (with the
/// other end's text condition), or `None` when neither is given. A file that cannot be read, or
/// holds no curve, is an input error (exit 1).
pub fn with_ends_from_files(args: &CurveArgs) -> Result<Option<CurveArgs>, CliError> {
    if args.start_from.is_none() && args.end_from.is_none() {
        return Ok(None);
    }
    let mut ends = args.end_conditions();
    let order = args.continuity.order();
    if let Some(s) = &args.start_from {
        ends.start = condition_from(s, true, false, order, "--start-from")?;
    }
    if let Some(s) = &args.end_from {
        ends.end = condition_from(s, false, true, order, "--end-from")?;
    }
    let mut out = args.clone();
    out.resolved_ends = Some(ends);
    Ok(Some(out))
}

/// The condition at the start (`at_new_end` false) or end of the new curve from the value `s`
/// (`FILE[:start|:end]`, `default_end` the end of FILE's curve taken without a suffix).
fn condition_from(
    s: &str,
    default_end: bool,
    at_new_end: bool,
    order: usize,
    flag: &str,
) -> Result<EndConstraint, CliError> {
    let (path, file_end) = split_from(s, default_end);
    let curve = match read_geometry(&path).map_err(|e| CliError::new(e.to_string()))? {
        Geometry::Curve(c) => c,
        Geometry::Surface(_) => {
            return Err(CliError::new(format!(
                "{flag} {}: holds a surface, not a curve",
                path.display()
            )))
        }
    };
    let mut c = EndConstraint::from_curve_end(&curve, file_end, order).ok_or_else(|| {
        CliError::new(format!(
            "{flag} {}: the curve has no tangent at its {} (zero derivative)",
            path.display(),
            if file_end { "end" } else { "start" }
        ))
    })?;
    // continuing (start at its end, or end at its start) keeps its direction; otherwise reversed
    if file_end == at_new_end {
        c.tangent = c.tangent.map(|t| -t);
    }
    Ok(c)
}

/// The `end_conditions` report of `--method lsq` and `fit-then-fair` (the library's).
pub use fairfit::report::end_conditions::lsq_end_conditions as lsq_end_conditions_report;
