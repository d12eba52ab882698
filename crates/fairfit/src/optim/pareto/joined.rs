//! `--pareto` for the curve the integrated method actually returned, corners and closed data
//! included.
//!
//! Without corners the front is [`super::front::pareto_front`] at the result's count, seeded with its
//! knots. With corners the joined curve is C0 at every corner, so its front is built from the
//! pieces' own fronts:
//!
//! 1. the result's knot vector is cut at its corner knots (multiplicity `p`); every piece gets the
//!    front of (maximum deviation, F) at its own count, seeded with its own knots (a straight piece
//!    has one member, the segment);
//! 2. the joined curve's maximum deviation is the largest of the pieces', and its energy
//!    `∫ (dκ/ds)² ds` is the sum of theirs (no span crosses a corner), so for every deviation level
//!    `d` (each member's deviation) the fairest joined curve within `d` takes, in every piece, the
//!    member within `d` with the least energy;
//! 3. those joined curves are measured (F of the whole curve by [`crate::fair::curve_fairness`]) and
//!    the dominated ones dropped: the front is sorted by increasing deviation with strictly
//!    decreasing F, and every member keeps every corner as a C0 knot.
//!
//! Closed data with corners are cut at the first corner as in the fit ([`crate::optim::closed`]); a periodic
//! closed curve (no corners) gets the periodic front of [`super::periodic`].

use super::front::{pareto_front, ParetoCurve};
use crate::errors::Result;
use crate::fair::curve_fairness;
use crate::fit::corners::corners_at_tolerance;
use crate::fit::shape::looks_closed;
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::tolerance_of;
use crate::optim::corners::{join, pieces, straight_piece};
use crate::optim::options::IntegratedOptions;
use crate::optim::result::{FitQuality, IntegratedResult};
use crate::optim::search::prepare::prepare;
use crate::tolerance::Tolerance;

/// The Pareto front for the integrated result `r` of `points` under `opts` (see the module docs), at
/// the result's degree (the one a degree search kept).
pub fn pareto_front_of_result(
    points: &[Vec3],
    opts: &IntegratedOptions,
    r: &IntegratedResult,
) -> Result<Vec<ParetoCurve>> {
    let opts = &opts.at_degree(r.curve.degree());
    let p = opts.degree;
    let mut seq = points.to_vec();
    if r.closure.is_closed() {
        if looks_closed(&seq) {
            seq.pop();
        }
        let prep = prepare(&seq, p)?;
        let c0 = opts.corner_angle_deg.and_then(|a| {
            let tol = tolerance_of(opts, prep.scale);
            corners_at_tolerance(&prep.data.points, true, a, tol)
                .first()
                .copied()
        });
        let Some(c0) = c0 else {
            return super::periodic::pareto_front_periodic(&seq, opts, r);
        };
        seq = seq[c0..].iter().chain(&seq[..c0]).copied().collect();
        seq.push(seq[0]);
    }
    let open = IntegratedOptions {
        closed: ClosedMode::Open,
        ..opts.clone()
    };
    let prep = prepare(&seq, p)?;
    let corners = match opts.corner_angle_deg {
        Some(a) => {
            corners_at_tolerance(&prep.data.points, false, a, tolerance_of(opts, prep.scale))
        }
        None => Vec::new(),
    };
    let ranges = pieces(prep.data.points.len(), &corners);
    let segments = knot_segments(&r.curve);
    if ranges.len() == 1 || segments.len() != ranges.len() {
        let k = r.curve.knots();
        let interior = &k[p + 1..k.len() - p - 1];
        return pareto_front(
            &seq,
            &open,
            r.curve.n_control_points(),
            Some((interior, r.log_lambda)),
        );
    }
    // 1. every piece's own front (normalised coordinates)
    let tol = tolerance_of(opts, prep.scale);
    let mut fronts: Vec<Vec<Member>> = Vec::with_capacity(ranges.len());
    let mut shares = Vec::with_capacity(ranges.len());
    for (i, (&(a, b), knots)) in ranges.iter().zip(&segments).enumerate() {
        let piece = &prep.data.points[a..=b];
        shares.push(piece.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>());
        if piece.len() < (p + 1).max(3) {
            let curve = straight_piece(piece[0], piece[piece.len() - 1], p)?;
            let d = crate::fit::max_orthogonal_deviation(&curve, piece, &[]);
            fronts.push(vec![Member {
                curve,
                max_dev: d.max,
                sum2: d.rms * d.rms * piece.len() as f64,
                energy: 0.0,
            }]);
            continue;
        }
        let sub = IntegratedOptions {
            tolerance: Tolerance::Absolute(tol),
            corner_angle_deg: None,
            seed: opts.seed ^ (i as u64 + 1).wrapping_mul(0xD1B5_4A32_D192_ED03),
            ..open.clone()
        };
        let front = pareto_front(
            piece,
            &sub,
            knots.len() + p + 1,
            Some((knots, f64::NEG_INFINITY)),
        )?;
        fronts.push(
            front
                .into_iter()
                .map(|m| Member {
                    energy: curve_fairness(&m.curve).energy,
                    max_dev: m.quality.max_deviation,
                    sum2: m.quality.rms_deviation.powi(2) * piece.len() as f64,
                    curve: m.curve,
                })
                .collect(),
        );
    }
    if fronts.iter().any(|f| f.is_empty()) {
        return Ok(Vec::new());
    }
    // 2. per deviation level, the least-energy member within it in every piece
    let mut levels: Vec<f64> = fronts.iter().flatten().map(|m| m.max_dev).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    let n_points: usize = ranges.iter().map(|(a, b)| b - a + 1).sum();
    let mut picks: Vec<Vec<usize>> = Vec::new();
    for d in levels {
        let pick: Option<Vec<usize>> = fronts
            .iter()
            .map(|f| {
                (0..f.len())
                    .filter(|&j| f[j].max_dev <= d)
                    .min_by(|&x, &y| f[x].energy.total_cmp(&f[y].energy))
            })
            .collect();
        if let Some(pick) = pick {
            if picks.last() != Some(&pick) {
                picks.push(pick);
            }
        }
    }
    // 3. joined, measured, dominated ones dropped
    let mut out: Vec<ParetoCurve> = Vec::with_capacity(picks.len());
    for pick in picks {
        let chosen: Vec<&Member> = pick.iter().zip(&fronts).map(|(&j, f)| &f[j]).collect();
        let curves: Vec<NurbsCurve> = chosen.iter().map(|m| m.curve.clone()).collect();
        let joined = join(&curves, &shares)?;
        let ctrl: Vec<Vec3> = joined
            .control_points()
            .iter()
            .map(|&c| prep.denormalise(c))
            .collect();
        let curve = NurbsCurve::bspline(p, joined.knots().to_vec(), ctrl)?;
        let f = curve_fairness(&curve);
        let max_dev = chosen.iter().map(|m| m.max_dev).fold(0.0, f64::max);
        let sum2: f64 = chosen.iter().map(|m| m.sum2).sum();
        let quality = FitQuality {
            max_deviation: max_dev * prep.scale,
            rms_deviation: (sum2 / n_points as f64).sqrt() * prep.scale,
            fairness: f.fairness,
            max_span_fairness: f.max_span_fairness,
        };
        if out
            .last()
            .is_none_or(|l| quality.fairness < l.quality.fairness)
        {
            if out
                .last()
                .is_some_and(|l| l.quality.max_deviation >= quality.max_deviation)
            {
                out.pop();
            }
            out.push(ParetoCurve { curve, quality });
        }
    }
    Ok(out)
}

/// One member of a piece's front (normalised coordinates).
struct Member {
    curve: NurbsCurve,
    max_dev: f64,
    sum2: f64,
    energy: f64,
}

/// The interior knots of every C0 piece of a clamped curve (cut at interior knots of multiplicity
/// `p`), each mapped onto `[0, 1]`.
pub(crate) fn knot_segments(curve: &NurbsCurve) -> Vec<Vec<f64>> {
    let p = curve.degree();
    let k = curve.knots();
    let (lo, hi) = (k[p], k[k.len() - p - 1]);
    let inner = &k[p + 1..k.len() - p - 1];
    let mut cuts = vec![lo];
    let mut i = 0;
    let mut runs: Vec<(f64, usize)> = Vec::new();
    while i < inner.len() {
        let mut j = i;
        while j < inner.len() && inner[j] == inner[i] {
            j += 1;
        }
        runs.push((inner[i], j - i));
        i = j;
    }
    for &(t, mult) in &runs {
        if mult >= p {
            cuts.push(t);
        }
    }
    cuts.push(hi);
    cuts.windows(2)
        .map(|w| {
            runs.iter()
                .filter(|&&(t, mult)| mult < p && t > w[0] && t < w[1])
                .flat_map(|&(t, mult)| std::iter::repeat_n((t - w[0]) / (w[1] - w[0]), mult))
                .collect()
        })
        .collect()
}
