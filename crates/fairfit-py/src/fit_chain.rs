//! `fit_chain`: several point sets fitted as one fair chain of curves joining with G1 or G2
//! continuity, as `fairfit curve A B ... --chain g1|g2` fits them
//! (`crates/fairfit-cli/src/commands/curve_chain.rs`): the same checks in the same order, the same
//! library options (`options::chain_options`), the same library fit
//! (`fairfit::optim::chain::fit_chain`) and the joined curve and report made by the same library
//! calls (`fairfit::report::chain`), so the same points and seed give the CLI's bytes. Run without
//! the GIL in a local rayon pool.

use crate::convert::points_from_array;
use crate::curve::Curve;
use crate::options::{
    chain_options, parse_degree, parse_end, parse_outliers, CurveSettings, Method,
};
use fairfit::fit::points::drop_consecutive_duplicates;
use fairfit::fit::tolerance::KnotRule;
use fairfit::fit::Parameterization;
use fairfit::io::limits::{ReadLimits, DEFAULT_MAX_POINTS};
use fairfit::io::points::MIN_POINTS;
use fairfit::optim::chain::{fit_chain as lib_fit_chain, JoinContinuity};
use fairfit::report::chain::{chain_report, joined_curve, ChainReportInputs};
use fairfit::Vec3;
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;
use std::time::Instant;

/// The extension's `fit_chain` (the Python wrapper `fairfit.fit_chain` documents it): returns the
/// joined curve (its report the chain's), the pieces (each with its own report) and the warnings.
#[pyfunction]
#[pyo3(signature = (pieces, continuity, tol, rel_tol, degree, corner_angle, seed, threads,
    band_fairing, span_fairness, outliers, start, end, start_tangent, end_tangent, names,
    max_points=DEFAULT_MAX_POINTS))]
#[allow(clippy::too_many_arguments)] // one argument per keyword of the Python signature
pub fn fit_chain(
    py: Python<'_>,
    pieces: Vec<PyReadonlyArray2<'_, f64>>,
    continuity: &str,
    tol: Option<f64>,
    rel_tol: f64,
    degree: &str,
    corner_angle: Option<f64>,
    seed: u64,
    threads: Option<usize>,
    band_fairing: bool,
    span_fairness: Option<f64>,
    outliers: &str,
    start: Option<&str>,
    end: Option<&str>,
    start_tangent: Option<[f64; 3]>,
    end_tangent: Option<[f64; 3]>,
    names: Option<Vec<String>>,
    max_points: usize,
) -> PyResult<(Curve, Vec<Curve>, Vec<String>)> {
    let wall = Instant::now();
    let continuity: JoinContinuity = continuity
        .parse()
        .map_err(|e| crate::py_err(format!("continuity: {e}")))?;
    if pieces.len() < 2 {
        return Err(crate::py_err(format!(
            "fit_chain needs at least two point sets (the pieces, in order), got {}",
            pieces.len()
        )));
    }
    let settings = CurveSettings {
        method: Method::Integrated,
        tol,
        rel_tol,
        degree: parse_degree(degree).map_err(crate::py_err)?,
        control_points: None,
        closed: None,
        corner_angle,
        free_ends: false,
        seed,
        band_fairing,
        span_fairness,
        param: Parameterization::Centripetal,
        knots: KnotRule::Refine,
        knots_name: "refine".into(),
        correction_rounds: 0,
        smoothing: 0.0,
        smoothing_order: 2,
        start: parse_end("start", start, start_tangent).map_err(crate::py_err)?,
        end: parse_end("end", end, end_tangent).map_err(crate::py_err)?,
        outliers: parse_outliers(outliers).map_err(crate::py_err)?,
        pareto: false,
        search_constraints: Default::default(),
    };
    settings.check().map_err(crate::py_err)?;
    let names: Vec<String> = (0..pieces.len())
        .map(|k| {
            names
                .as_ref()
                .and_then(|n| n.get(k).cloned())
                .unwrap_or_else(|| format!("<piece {}>", k + 1))
        })
        .collect();
    let (sets, dim) = read_pieces(&pieces, &names, max_points)?;
    let fitted = crate::guarded(py, move || {
        fit(&settings, continuity, sets, names, wall, threads)
    })?;
    let piece_curves = fitted
        .pieces
        .into_iter()
        .enumerate()
        .map(|(k, c)| {
            let report = fitted.report["pieces"].get(k).cloned();
            Curve::new(c, dim, report)
        })
        .collect();
    Ok((
        Curve::new(fitted.joined, dim, Some(fitted.report)),
        piece_curves,
        fitted.warnings,
    ))
}

/// Every piece's points (consecutive duplicates kept, for the fit to drop) and the dimension of
/// the chain (3 when any piece has three columns), checked as the CLI reads its point files: the
/// size limit, finite numbers.
fn read_pieces(
    pieces: &[PyReadonlyArray2<'_, f64>],
    names: &[String],
    max_points: usize,
) -> PyResult<(Vec<Vec<Vec3>>, usize)> {
    let limits = ReadLimits {
        max_points,
        ..ReadLimits::current()
    };
    let mut dim = 2;
    let mut sets = Vec::with_capacity(pieces.len());
    for (a, name) in pieces.iter().zip(names) {
        limits
            .check_points(name, a.as_array().nrows(), "points")
            .map_err(|e| crate::py_err(e.to_string().replace("--max-points N", "max_points=N")))?;
        let (pts, d) = points_from_array(a, name)?;
        dim = dim.max(d);
        sets.push(pts);
    }
    Ok((sets, dim))
}

/// A fitted chain: the joined curve, the pieces, the report and the CLI's warnings.
struct FittedChain {
    joined: fairfit::NurbsCurve,
    pieces: Vec<fairfit::NurbsCurve>,
    report: serde_json::Value,
    warnings: Vec<String>,
}

/// The chain of `sets` as `fairfit curve --chain` fits it (its `read_piece` and `fit_pieces`):
/// consecutive duplicates dropped with a warning, too few points refused, the library's chain fit
/// with the CLI's options in a pool of `threads`, the joined curve and the report.
fn fit(
    s: &CurveSettings,
    continuity: JoinContinuity,
    sets: Vec<Vec<Vec3>>,
    names: Vec<String>,
    wall: Instant,
    threads: Option<usize>,
) -> Result<FittedChain, String> {
    let mut warnings = Vec::new();
    let mut pieces = Vec::with_capacity(sets.len());
    for (raw, name) in sets.iter().zip(&names) {
        let (points, dropped) = drop_consecutive_duplicates(raw);
        if points.len() < MIN_POINTS {
            return Err(fairfit::Error::InvalidData(format!(
                "{name}: at least {MIN_POINTS} distinct points are needed, found {}",
                points.len()
            ))
            .to_string());
        }
        if dropped > 0 {
            warnings.push(format!(
                "{name}: dropped {dropped} consecutive duplicate point(s)"
            ));
        }
        pieces.push(points);
    }
    let opts = chain_options(s);
    let r = crate::with_pool(threads, || {
        lib_fit_chain(&pieces, continuity, &opts).map_err(|e| e.to_string())
    })?;
    warnings.extend(r.warning().map(String::from));
    let joined = joined_curve(&r).map_err(|e| e.to_string())?;
    let points: Vec<usize> = pieces.iter().map(Vec::len).collect();
    let report = chain_report(
        &r,
        &ChainReportInputs {
            continuity,
            names: &names,
            outputs: None,
            points: &points,
            span_fairness: s.span_fairness,
            seed: s.seed,
            wall_seconds: wall.elapsed().as_secs_f64(),
        },
    );
    Ok(FittedChain {
        joined,
        pieces: r.pieces.into_iter().map(|p| p.curve).collect(),
        report,
        warnings,
    })
}
