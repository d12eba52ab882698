//! A bound on the work of the commands that analyse or sample a whole curve or surface (`info`,
//! `plot`, `export`): their cost grows with the number of knot spans (fairness integrals, exact
//! extrema, plot and mesh samples are all per span), so an input with more spans than `--max-spans`
//! (default [`DEFAULT_MAX_SPANS`]) is refused at once with one line, instead of running for minutes
//! or exhausting memory. A surface counts its u spans times its v spans.

use super::CliError;
use fairfit::io::Geometry;
use fairfit::nurbs::knots::distinct_breakpoints;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Default `--max-spans`: `info` on a 10^4-span curve takes a few seconds.
pub const DEFAULT_MAX_SPANS: usize = 10_000;

static MAX_SPANS: AtomicUsize = AtomicUsize::new(DEFAULT_MAX_SPANS);

/// Sets the limit for this run (from `--max-spans`).
pub fn set_max_spans(n: usize) {
    MAX_SPANS.store(n, Ordering::Relaxed);
}

/// The knot spans of `g` (u spans × v spans for a surface).
pub fn spans(g: &Geometry) -> usize {
    let count = |knots: &[f64], p: usize| distinct_breakpoints(knots, p).len().saturating_sub(1);
    match g {
        Geometry::Curve(c) => count(c.knots(), c.degree()),
        Geometry::Surface(s) => {
            count(s.knots_u(), s.degree_u()).saturating_mul(count(s.knots_v(), s.degree_v()))
        }
    }
}

/// Refuses `g`, read from `path`, when it has more spans than `--max-spans` allows.
pub fn check_spans(g: &Geometry, path: &Path) -> Result<(), CliError> {
    let limit = MAX_SPANS.load(Ordering::Relaxed);
    let n = spans(g);
    if n > limit {
        let what = match g {
            Geometry::Curve(_) => "knot spans",
            Geometry::Surface(_) => "knot spans (u × v)",
        };
        return Err(CliError::new(format!(
            "{}: {n} {what}, over the limit of {limit} for this command, whose work grows with the \
             spans (raise it with --max-spans N)",
            path.display()
        )));
    }
    Ok(())
}
