//! What a chain fit ([`crate::optim::chain::fit_chain`]) gives out: the joined curve
//! ([`joined_curve`]) and the report ([`chain_report`]), made here once so that `fairfit curve A B
//! --chain g1|g2` and the Python package's `fit_chain` write the same bytes and keys.
//!
//! The joined curve is one B-spline on `[0, N]` for `N` pieces, piece `k` (0-based) mapped onto
//! `[k, k + 1]`: every join lies at a whole number and is a knot of full multiplicity
//! ([`crate::io::cad_chain::join_segments`]: exact, G1/G2 there as the pieces are).
//!
//! Key names of the report are a public contract (scripts read them); a new key may be added, none
//! renamed.

use super::curve::{integrated_report, shape_report, with_method};
use crate::errors::Result;
use crate::io::cad_chain::join_segments;
use crate::nurbs::NurbsCurve;
use crate::optim::chain::{ChainResult, JoinContinuity};
use serde_json::{json, Value};

/// `c` with its knots mapped affinely onto `[0, 1]` (the same curve): `(k − a) / (b − a)` for its
/// domain `[a, b]`, the arithmetic every written chain was made with (so the bytes stay the same).
pub fn unit_domain(c: &NurbsCurve) -> Result<NurbsCurve> {
    let (a, b) = c.domain();
    let knots: Vec<f64> = c.knots().iter().map(|&k| (k - a) / (b - a)).collect();
    let weights = c.is_rational().then(|| c.weights().to_vec());
    NurbsCurve::new(c.degree(), knots, c.control_points().to_vec(), weights)
}

/// The pieces of `r` joined as one curve on `[0, N]` (module doc), each piece first mapped onto
/// `[0, 1]` ([`unit_domain`]).
///
/// ```
/// use fairfit::optim::chain::{fit_chain, JoinContinuity};
/// use fairfit::prelude::*;
/// use fairfit::report::chain::joined_curve;
/// let arc = |a0: f64, a1: f64| -> Vec<Vec3> {
///     (0..30)
///         .map(|i| {
///             let a = a0 + (a1 - a0) * i as f64 / 29.0;
///             Vec3::new(a.cos(), a.sin(), 0.0)
///         })
///         .collect()
/// };
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
/// let r = fit_chain(&[arc(0.0, 1.0), arc(1.0, 2.0)], JoinContinuity::G2, &opts)?;
/// let joined = joined_curve(&r)?;
/// assert_eq!(joined.domain(), (0.0, 2.0));
/// assert!((joined.point(1.0) - r.pieces[1].curve.point(r.pieces[1].curve.domain().0)).norm() < 1e-12);
/// # Ok::<(), fairfit::Error>(())
/// ```
pub fn joined_curve(r: &ChainResult) -> Result<NurbsCurve> {
    let unit: Vec<NurbsCurve> = r
        .pieces
        .iter()
        .map(|p| unit_domain(&p.curve))
        .collect::<Result<_>>()?;
    join_segments(&unit)
}

/// What a chain's report says beyond its result: how it was asked for and what it was fitted from.
#[derive(Clone, Copy, Debug)]
pub struct ChainReportInputs<'a> {
    /// The continuity asked for (the report's `chain`).
    pub continuity: JoinContinuity,
    /// What each piece's report calls its points (`input`), one per piece.
    pub names: &'a [String],
    /// Where each piece was written (its report's `output`), when it was written on its own.
    pub outputs: Option<&'a [String]>,
    /// The number of points each piece was given (its report's `points`).
    pub points: &'a [usize],
    /// The per-span fairness target asked for (as in a single fit's report).
    pub span_fairness: Option<f64>,
    /// The swarm's seed.
    pub seed: u64,
    /// The wall time of the whole run so far, in seconds.
    pub wall_seconds: f64,
}

/// The report of a chain (`fairfit curve ... --chain --report`): the chain's measures, every piece's
/// own report (the keys of a single integrated fit's, with `from_single_curve` and, when written
/// on its own, `output`) and every join's continuity measured on the fitted pieces (`tangent_angle`
/// in radians, `curvature_relative` the relative difference of the curvature vectors).
pub fn chain_report(r: &ChainResult, inputs: &ChainReportInputs<'_>) -> Value {
    let seconds = inputs.wall_seconds;
    let piece_reports: Vec<Value> = r
        .pieces
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let name = inputs.names.get(k).map_or("", String::as_str);
            let points = inputs.points.get(k).copied().unwrap_or(0);
            let mut v = with_method(
                shape_report(&p.curve, name, points, seconds),
                &integrated_report(p, false, inputs.span_fairness, inputs.seed),
            );
            if let Some(o) = inputs.outputs.and_then(|o| o.get(k)) {
                v["output"] = json!(o);
            }
            // the single curve's part between the joins, or the piece's own fit under them
            v["from_single_curve"] = json!(r.from_single.get(k).copied().unwrap_or(false));
            v
        })
        .collect();
    let joins: Vec<Value> = r
        .joins
        .iter()
        .enumerate()
        .map(|(k, j)| {
            json!({
                "pieces": [k + 1, k + 2],
                "point": j.point.0,
                "data_gap": j.data_gap,
                "position_gap": j.position_gap,
                "tangent_angle": j.tangent_angle,
                "curvature_relative": j.curvature_relative,
                "curvature": j.curvature,
            })
        })
        .collect();
    let single = r.single_fairness;
    json!({
        "chain": inputs.continuity.name(),
        "pieces": piece_reports,
        "joins": joins,
        "tolerance": r.tolerance,
        "tolerance_met": r.met,
        "max_deviation": r.pieces.iter().map(|p| p.quality.max_deviation).fold(0.0, f64::max),
        "length": r.length,
        "fairness": r.fairness,
        "single_curve_fairness": single,
        "fairness_ratio": (single > 0.0).then(|| r.fairness / single),
        "wall_seconds": seconds,
    })
}
