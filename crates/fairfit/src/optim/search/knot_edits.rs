//! The knot-vector edits the open and periodic curve kinds ([`crate::optim::kind`]) share, on
//! interior knots (or breakpoints) in `(0, 1)`:
//!
//! - [`lsq_method_fit`], [`map_knots`]: the least-squares method's own fit of the data and its knots
//!   mapped piecewise linearly onto the search's parameters (the baseline's start);
//! - [`removal_candidates`]: every single-knot removal refitted and ranked by its maximum
//!   deviation;
//! - [`insertion_spans`]: the spans an inserted knot may split.
//!
//! Only the candidate evaluation differs between open and periodic curves; it is passed in.

use super::encoding::KnotEncoding;
use super::objective::CandidateEval;
use crate::fit::tolerance::{fit_to_tolerance, ClosedMode, FitOptions, FitResult, Tolerance};
use crate::nurbs::Vec3;
use rayon::prelude::*;

/// The least-squares method's fit (`fit::tolerance`: centripetal as the search, corners off) of
/// the normalised `points` at degree `p` within the absolute tolerance `tol`; `None` when it fails.
pub(crate) fn lsq_method_fit(
    points: &[Vec3],
    p: usize,
    tol: f64,
    closed: ClosedMode,
) -> Option<FitResult> {
    fit_to_tolerance(
        points,
        &FitOptions {
            degree: p,
            tolerance: Tolerance::Absolute(tol),
            closed,
            corner_angle_deg: None,
            parameterization: crate::fit::Parameterization::Centripetal,
            ..FitOptions::default()
        },
    )
    .ok()
}

/// The knots `interior` of a fit with data parameters `from` mapped onto the parameters `onto`
/// of the same points, piecewise linearly between consecutive points.
pub(crate) fn map_knots(interior: &[f64], from: &[f64], onto: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(interior.len());
    for &t in interior {
        let i = from.partition_point(|&u| u <= t).clamp(1, from.len() - 1) - 1;
        let w = from[i + 1] - from[i];
        let a = if w > 0.0 {
            ((t - from[i]) / w).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(onto[i] + a * (onto[i + 1] - onto[i]));
    }
    out
}

/// Every way to remove one interior knot of `knots` (repaired on `params`), evaluated by `eval`
/// without smoothing, sorted by the resulting maximum deviation (ties by knot index):
/// `(deviation, knots)`. Evaluated in parallel (one `W::default()` workspace per worker),
/// collected in order.
pub(crate) fn removal_candidates<W, E>(
    knots: &[f64],
    params: &[f64],
    eval: E,
) -> Vec<(f64, Vec<f64>)>
where
    W: Default + Send,
    E: Fn(&mut W, &[f64]) -> CandidateEval + Sync + Send,
{
    let enc = KnotEncoding::new(knots.len().saturating_sub(1), 0.0, false);
    let mut out: Vec<(usize, f64, Vec<f64>)> = (0..knots.len())
        .into_par_iter()
        .map_init(W::default, |ws, j| {
            let mut k: Vec<f64> = knots.to_vec();
            k.remove(j);
            if !enc.repair(&mut k, params) {
                return (j, f64::INFINITY, k);
            }
            let e = eval(ws, &k);
            let dev = if e.solved {
                e.max_deviation
            } else {
                f64::INFINITY
            };
            (j, dev, k)
        })
        .collect();
    out.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    out.into_iter().map(|(_, d, k)| (d, k)).collect()
}

/// The interior knots with `0` and `1` added (the span edges), and the spans holding at least
/// two of `params` strictly inside: those an inserted knot may split.
pub(crate) fn insertion_spans(knots: &[f64], params: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut edges = Vec::with_capacity(knots.len() + 2);
    edges.push(0.0);
    edges.extend_from_slice(knots);
    edges.push(1.0);
    let spans: Vec<usize> = (0..edges.len() - 1)
        .filter(|&j| {
            params
                .iter()
                .filter(|&&u| u > edges[j] && u < edges[j + 1])
                .count()
                >= 2
        })
        .collect();
    (edges, spans)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knots_map_linearly_between_the_points() {
        // points at 0, 0.5, 1 in one parameterisation and 0, 0.2, 1 in the other: 0.25 is halfway
        // through the first interval (0.1), 0.75 halfway through the second (0.6)
        let m = map_knots(&[0.25, 0.5, 0.75], &[0.0, 0.5, 1.0], &[0.0, 0.2, 1.0]);
        let expect = [0.1, 0.2, 0.6];
        for (a, b) in m.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{m:?}");
        }
    }

    #[test]
    fn only_spans_with_two_inner_parameters_may_be_split() {
        let params = [0.05, 0.1, 0.3, 0.6, 0.7, 0.8];
        let (edges, spans) = insertion_spans(&[0.2, 0.5], &params);
        assert_eq!(edges, vec![0.0, 0.2, 0.5, 1.0]);
        // (0, 0.2) holds 0.05 and 0.1, (0.2, 0.5) only 0.3, (0.5, 1) holds three
        assert_eq!(spans, vec![0, 2]);
    }
}
