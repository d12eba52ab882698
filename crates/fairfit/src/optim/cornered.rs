//! The integrated method on data with corners: the pieces between corners ([`super::corners`]) are
//! fitted on their own (each with the whole curve's tolerance and its own seed stream) and joined C0.
//!
//! The pipeline sends open data here on every input point when they have corners: a corner is
//! judged on the points themselves, never on the reduced form's representatives (a centroid of a
//! tolerance-sized arc across a corner lies off it). A dense piece is then reduced on its own
//! ([`super::stages::reduce`]): its ends, the corner points, stay representatives and are
//! interpolated, and the fit is verified on every point of the piece. Its degree raise runs on the
//! representatives and is kept only when every point of the piece is within the tolerance.
//!
//! **A fixed control-point count** `N` ([`IntegratedOptions::control_points`]) is the joined curve's
//! count; neighbouring pieces share their corner control point, so the pieces get `N + k − 1`
//! between them (`k` pieces). The split:
//!
//! 1. every piece is first fitted freely (the fewest control points meeting the tolerance, as
//!    without `N`): its count `n_i*`;
//! 2. straight pieces (too few points for a cubic of their own) keep their `p + 1`; the others share
//!    the rest in proportion to `n_i*` (D'Hondt: one point at a time to the piece with the largest
//!    `n_i* / n_i`, or taken from the largest `n_i / n_i*`), each between `p + 1` and its points − 1;
//! 3. pieces whose share differs from `n_i*` are fitted again at that fixed count.
//!
//! So `N` equal to the free result's count reproduces the free curve exactly (within the
//! tolerance), a larger `N` spends the extra points where the data need most points, and a smaller
//! `N` takes them evenly (the tolerance may then be missed; the result says so). An `N` outside what
//! the pieces can take is an [`Error::InvalidSetting`] of `control_points` naming the range.

use super::condition_checks::{condition_error, held_at_corner_pieces, unmet_condition};
use super::context::{tolerance_of, Progress};
use super::corners::{corners_for_conditions, is_straight, join, pieces, straight_piece};
use super::fairing::EndCondition;
use super::kind::periodic::distinct_control_points;
use super::open;
use super::options::{validate, IntegratedOptions};
use super::result::{FitQuality, IntegratedResult, OptimStats};
use super::search::objective::PointBands;
use super::search::prepare::{prepare, Prepared};
use super::stages::degree_candidates::raise_open_piece;
use super::stages::degree_search::{keep_degree, Attempt};
use super::stages::reduce::{measured, verify, Dense};
use super::stages::warm_ends;
use super::tuning::Tuning;
use crate::errors::{Error, Result};
use crate::fit::end_constraints::{EndConstraint, EndConstraints};
use crate::fit::reduce::reduce;
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::tolerance::Tolerance;
use rayon::prelude::*;
use std::time::Instant;

/// Whether open data `points` have corners under `opts`: the detection [`fit`] makes, on the same
/// normalised points (so the pipeline can send data with corners here before any reduction).
pub(crate) fn has_corners(points: &[Vec3], opts: &IntegratedOptions) -> bool {
    let (Some(angle), Ok(prep)) = (opts.corner_angle_deg, prepare(points, opts.degree)) else {
        return false;
    };
    let tol = tolerance_of(opts, prep.scale);
    !crate::fit::corners::corners_at_tolerance(&prep.data.points, false, angle, tol).is_empty()
}

/// The integrated fit of open data `points` (under `opts`, open): split at corners and fitted by
/// the pieces ([`fit_with_corners`]) when there are any, else by the open pipeline.
pub(crate) fn fit(
    points: &[Vec3],
    opts: &IntegratedOptions,
    progress: &Progress<'_>,
    start: Instant,
) -> Result<IntegratedResult> {
    let mut prep = prepare(points, opts.degree)?;
    let conditions = &opts.end_conditions;
    prep.data.ends = conditions.normalized(prep.origin, prep.scale);
    crate::fit::end_constraints::check_against_data(
        &prep.data.ends,
        &prep.data.points,
        tolerance_of(opts, prep.scale),
    )?;
    if let Some(angle) = opts.corner_angle_deg {
        let corners = crate::fit::corners::corners_at_tolerance(
            &prep.data.points,
            false,
            angle,
            tolerance_of(opts, prep.scale),
        );
        let n = prep.data.points.len();
        let corners = corners_for_conditions(n, &corners, opts.degree, conditions);
        let ranges = pieces(n, &corners);
        if ranges.len() > 1 {
            // the first piece holds the start condition, the last one the end condition
            let r = fit_with_corners(&prep, &ranges, opts, progress, start)?;
            if !r.met && !conditions.is_none() {
                return Err(unmet_condition(points, &r, conditions));
            }
            return held_at_corner_pieces(r, conditions);
        }
    }
    if !opts.point_constraints.is_none() {
        let pc = &opts.point_constraints;
        pc.validate(points.len())?;
        prep.data.bands = PointBands::new(
            points.len(),
            pc.weights.as_deref().unwrap_or(&[]),
            &pc.interpolate,
            Tuning::default().points.interpolation_band,
        );
    } else {
        prep.data.bands = PointBands::of_factors(&opts.tolerance_factors, prep.data.points.len());
    }
    let r = open::fit(&prep, opts, progress, start).map_err(|e| match conditions.is_none() {
        true => e,
        false => condition_error(&prep, opts.degree).unwrap_or(e),
    })?;
    let r = match conditions.is_none() || !opts.point_constraints.is_none() {
        true => r,
        false => with_warm_ends(&prep, opts, progress, start, r),
    };
    if !r.met && !conditions.is_none() {
        return Err(unmet_condition(points, &r, conditions));
    }
    Ok(r)
}

/// The fit under end conditions: the search's `searched`, or the unconstrained fit moved onto
/// the conditions and finished under them when that is fairer
/// ([`super::stages::warm_ends`]).
fn with_warm_ends(
    prep: &Prepared,
    opts: &IntegratedOptions,
    progress: &Progress<'_>,
    start: Instant,
    searched: IntegratedResult,
) -> IntegratedResult {
    let free_opts = IntegratedOptions {
        end_conditions: Default::default(),
        ..opts.clone()
    };
    let mut free_prep = prep.clone();
    free_prep.data.ends = Default::default();
    let rule = Tuning::default().count;
    match open::fit(&free_prep, &free_opts, progress, start)
        .ok()
        .and_then(|free| warm_ends::from_unconstrained(prep, &free, opts))
    {
        Some(warm) if warm_ends::prefer(&warm, &searched, &rule) => IntegratedResult {
            stats: searched.stats,
            baseline_control_points: searched.baseline_control_points,
            ..warm
        },
        _ => searched,
    }
}

/// One fitted piece (normalised coordinates).
#[derive(Clone)]
struct Piece {
    curve: NurbsCurve,
    max_dev: f64,
    /// Sum of squared deviations and number of points (its ends included as 0).
    sum2: f64,
    count: usize,
    met: bool,
    baseline: usize,
    stats: OptimStats,
    straight: bool,
}

/// The integrated method on the pieces between corners (`ranges` of the normalised points), joined
/// C0; with a fixed count, the budget is shared as described in the module docs.
fn fit_with_corners(
    prep: &Prepared,
    ranges: &[(usize, usize)],
    opts: &IntegratedOptions,
    progress: &Progress<'_>,
    start: Instant,
) -> Result<IntegratedResult> {
    let p = opts.degree;
    let tuning = Tuning::default();
    // the pieces share one degree: a degree search is made on the joined curve (below)
    let opts_in = opts;
    let opts = &opts.at_degree(p);
    let mut pieces: Vec<Piece> = (0..ranges.len())
        .map(|i| fit_piece(prep, ranges, i, opts, None, progress))
        .collect::<Result<_>>()?;
    let mut extra = OptimStats::default();
    if let Some(n) = opts.control_points {
        let free: Vec<usize> = pieces.iter().map(|q| q.curve.n_control_points()).collect();
        let lo: Vec<usize> = pieces
            .iter()
            .zip(&free)
            .map(|(q, &f)| if q.straight { f } else { p + 1 })
            .collect();
        let hi: Vec<usize> = pieces
            .iter()
            .zip(ranges)
            .zip(&free)
            .map(|((q, &(a, b)), &f)| if q.straight { f } else { (b - a).max(f) })
            .collect();
        let counts = share_budget(n, &free, &lo, &hi)?;
        for (i, (&c, &f)) in counts.iter().zip(&free).enumerate() {
            if c != f {
                accumulate(&mut extra, &pieces[i].stats);
                pieces[i] = fit_piece(prep, ranges, i, opts, Some(c), progress)?;
            }
        }
    }
    let reference = joined(prep, ranges, &pieces, extra, opts, start)?;
    // the raised pieces are fitted without the end conditions: under them the degree is kept
    if !opts_in.searches_degree() || !prep.data.ends.is_none() {
        return Ok(reference);
    }
    // staged degree search: every piece raised at its own count from its own knots
    let attempt = |d: usize| {
        let raised: Vec<(Option<Piece>, usize, usize)> = pieces
            .par_iter()
            .enumerate()
            .map(|(i, q)| raise_piece(prep, ranges, i, q, opts, d, &tuning))
            .collect();
        let evaluations = raised.iter().map(|r| r.1).sum();
        let iterations = raised.iter().map(|r| r.2).sum();
        let fit = raised
            .into_iter()
            .map(|r| r.0)
            .collect::<Option<Vec<Piece>>>()
            .and_then(|ps| {
                let o = opts.at_degree(d);
                joined(prep, ranges, &ps, OptimStats::default(), &o, start).ok()
            });
        Attempt {
            fit,
            evaluations,
            iterations,
        }
    };
    let highest = opts_in.max_degree.unwrap_or(p).max(p);
    keep_degree(reference, p + 1..=highest, &tuning, &attempt)
}

/// The pieces joined C0 into the curve of the whole data (input coordinates), measured.
fn joined(
    prep: &Prepared,
    ranges: &[(usize, usize)],
    pieces: &[Piece],
    extra: OptimStats,
    opts: &IntegratedOptions,
    start: Instant,
) -> Result<IntegratedResult> {
    let p = opts.degree;
    let pts = &prep.data.points;
    let tol = tolerance_of(opts, prep.scale);
    let mut shares = Vec::with_capacity(ranges.len());
    let mut stats = extra;
    let (mut max_dev, mut sum2, mut count) = (0.0f64, 0.0, 0usize);
    let (mut met, mut baseline) = (true, 0);
    for (i, (q, &(a, b))) in pieces.iter().zip(ranges).enumerate() {
        shares.push(
            pts[a..=b]
                .windows(2)
                .map(|w| (w[1] - w[0]).norm())
                .sum::<f64>(),
        );
        max_dev = max_dev.max(q.max_dev);
        sum2 += q.sum2;
        count += q.count;
        met &= q.met;
        baseline += q.baseline - usize::from(i > 0);
        accumulate(&mut stats, &q.stats);
    }
    let curves: Vec<NurbsCurve> = pieces.iter().map(|q| q.curve.clone()).collect();
    let joined = join(&curves, &shares)?;
    let ctrl: Vec<Vec3> = joined
        .control_points()
        .iter()
        .map(|&c| prep.denormalise(c))
        .collect();
    let curve = NurbsCurve::bspline(p, joined.knots().to_vec(), ctrl)?;
    let f = crate::fair::curve_fairness(&curve);
    let quality = FitQuality {
        max_deviation: max_dev * prep.scale,
        rms_deviation: (sum2 / count.max(1) as f64).sqrt() * prep.scale,
        fairness: f.fairness,
        max_span_fairness: f.max_span_fairness,
    };
    met &= max_dev <= tol
        && opts
            .span_fairness
            .is_none_or(|t| quality.max_span_fairness <= t);
    stats.seconds = start.elapsed().as_secs_f64();
    Ok(IntegratedResult {
        screening: Default::default(),
        closure: Default::default(),
        curve,
        quality,
        tolerance: tol * prep.scale,
        met,
        log_lambda: f64::NEG_INFINITY,
        baseline_control_points: baseline,
        stats,
    })
}

fn accumulate(stats: &mut OptimStats, s: &OptimStats) {
    stats.evaluations += s.evaluations;
    stats.iterations += s.iterations;
    stats.polish_moves += s.polish_moves;
    stats.counts_tried.extend(&s.counts_tried);
    stats.fairness_by_count.extend(&s.fairness_by_count);
}

/// Fits piece `i` (freely, or with `count` control points).
fn fit_piece(
    prep: &Prepared,
    ranges: &[(usize, usize)],
    i: usize,
    opts: &IntegratedOptions,
    count: Option<usize>,
    progress: &Progress<'_>,
) -> Result<Piece> {
    let p = opts.degree;
    let (a, b) = ranges[i];
    let piece = &prep.data.points[a..=b];
    if is_straight(piece.len(), p) {
        // too few points for a cubic of its own: the straight segment
        let (mut max_dev, mut sum2) = (0.0f64, 0.0);
        for q in &piece[1..piece.len() - 1] {
            let d = point_segment_distance(*q, piece[0], piece[piece.len() - 1]);
            max_dev = max_dev.max(d);
            sum2 += d * d;
        }
        return Ok(Piece {
            curve: straight_piece(piece[0], piece[piece.len() - 1], p)?,
            max_dev,
            sum2,
            count: piece.len(),
            met: true,
            baseline: p + 1,
            stats: OptimStats::default(),
            straight: true,
        });
    }
    let sub = piece_options(prep, (i, ranges.len()), opts, count);
    // the piece is open data without corners: the open pipeline on its own points
    validate(&sub)?;
    let reduce_tuning = Tuning::default().reduce;
    let tol = tolerance_of(opts, prep.scale);
    let dense = reduced_piece(piece, tol, p, &reduce_tuning)
        .and_then(|_| Dense::of(piece, &sub, &reduce_tuning));
    if let Some(dense) = dense {
        // dense: its reduced form fitted, verified and repaired on every point of the piece
        let fit = |pts: &[Vec3], o: &IntegratedOptions| -> Result<IntegratedResult> {
            let mut q = prepare(pts, o.degree)?;
            q.data.bands = PointBands::of_factors(&o.tolerance_factors, q.data.points.len());
            q.data.ends = o.end_conditions.normalized(q.origin, q.scale);
            open::fit(&q, o, progress, Instant::now())
        };
        let r = dense.fit(&sub, &reduce_tuning, &fit)?;
        return Ok(piece_of(r, piece.len()));
    }
    let mut piece_prep = prepare(piece, sub.degree)?;
    piece_prep.data.ends = sub
        .end_conditions
        .normalized(piece_prep.origin, piece_prep.scale);
    let r = open::fit(&piece_prep, &sub, progress, Instant::now())?;
    Ok(piece_of(r, piece.len()))
}

/// The options of piece `i`'s own fit (its seed stream, the whole curve's tolerance).
fn piece_options(
    prep: &Prepared,
    (i, pieces): (usize, usize),
    opts: &IntegratedOptions,
    count: Option<usize>,
) -> IntegratedOptions {
    IntegratedOptions {
        tolerance: Tolerance::Absolute(tolerance_of(opts, prep.scale)),
        corner_angle_deg: None,
        closed: ClosedMode::Open,
        control_points: count,
        seed: opts.seed ^ (i as u64 + 1).wrapping_mul(0xD1B5_4A32_D192_ED03),
        // the pieces are joined at their ends
        ends: EndCondition::Pinned,
        // the whole curve's per-point factors index other points
        tolerance_factors: Vec::new(),
        // the first piece holds the curve's start condition, the last its end condition, in the
        // normalised coordinates the pieces' points are in
        end_conditions: EndConstraints {
            start: if i == 0 {
                prep.data.ends.start
            } else {
                EndConstraint::default()
            },
            end: if i + 1 == pieces {
                prep.data.ends.end
            } else {
                EndConstraint::default()
            },
        },
        ..opts.clone()
    }
}

/// A piece of `len` points from its integrated fit.
fn piece_of(r: IntegratedResult, len: usize) -> Piece {
    Piece {
        max_dev: r.quality.max_deviation,
        // the piece's RMS is over all its points (its interpolated ends count as 0)
        sum2: r.quality.rms_deviation.powi(2) * len as f64,
        count: len,
        met: r.met,
        baseline: r.baseline_control_points,
        stats: r.stats,
        straight: false,
        curve: r.curve,
    }
}

/// The reduced form of a piece's points (`tol` in their units), when the piece is dense and its
/// representatives are enough for a curve of degree `p` of its own (at least `2 (p + 1)`: a short
/// piece of dense data, such as a spike cut out by corners with `--outliers off`, is fitted on its
/// points).
fn reduced_piece(
    piece: &[Vec3],
    tol: f64,
    p: usize,
    tuning: &crate::fit::reduce::ReduceTuning,
) -> Option<crate::fit::reduce::Reduced> {
    reduce(piece, tol, tuning).filter(|r| r.bins.len() >= 2 * (p + 1))
}

/// Piece `i` (fitted at `opts.degree` as `q`) at degree `d`, at its count from its knots
/// ([`raise_open_piece`]); a straight piece is the same segment at degree `d`. `None` when the piece
/// cannot be fitted within the tolerance at its count; with the evaluations and iterations spent.
fn raise_piece(
    prep: &Prepared,
    ranges: &[(usize, usize)],
    i: usize,
    q: &Piece,
    opts: &IntegratedOptions,
    d: usize,
    tuning: &Tuning,
) -> (Option<Piece>, usize, usize) {
    let (a, b) = ranges[i];
    let piece = &prep.data.points[a..=b];
    if q.straight {
        let curve = straight_piece(piece[0], piece[piece.len() - 1], d).ok();
        return (curve.map(|curve| Piece { curve, ..q.clone() }), 0, 0);
    }
    let count = Some(distinct_control_points(&q.curve));
    let sub = piece_options(prep, (i, ranges.len()), opts, count);
    let tol = tolerance_of(opts, prep.scale);
    if let Some(red) = reduced_piece(piece, tol, d, &tuning.reduce) {
        // dense: raised on its representatives within the tolerance less their spread, kept only
        // when every point of the piece is within the tolerance
        let span = sub.span_fairness;
        let inner = IntegratedOptions {
            tolerance: Tolerance::Absolute((tol - red.spread()).max(0.25 * tol)),
            ..sub
        };
        let at = raise_open_piece(&red.points(), &q.curve, &inner, d, tuning);
        let r = at.fit.and_then(|r| {
            let (max, rms, _) = verify(&r.curve, piece, &red, tol);
            (max <= tol).then(|| piece_of(measured(r, max, rms, tol, span), piece.len()))
        });
        return (r, at.evaluations, at.iterations);
    }
    let at = raise_open_piece(piece, &q.curve, &sub, d, tuning);
    let r = at.fit.map(|r| piece_of(r, piece.len()));
    (r, at.evaluations, at.iterations)
}

/// Shares the joined count `n` among pieces with free counts `free` and bounds `lo..=hi` (see the
/// module docs); the counts sum to `n + pieces − 1`.
pub fn share_budget(n: usize, free: &[usize], lo: &[usize], hi: &[usize]) -> Result<Vec<usize>> {
    let k = free.len();
    if k == 0 || lo.len() != k || hi.len() != k {
        return Err(Error::InvalidData(format!(
            "control-point budget: {k} free counts, {} lower and {} upper bounds (one each per piece, \
             at least one piece)",
            lo.len(),
            hi.len()
        )));
    }
    let total = n + k - 1;
    let (min, max) = (lo.iter().sum::<usize>(), hi.iter().sum::<usize>());
    if total < min || total > max {
        return Err(Error::InvalidSetting {
            option: "control_points",
            reason: format!(
                "{n} control points cannot be shared among the {k} pieces between corners: give \
                 between {} and {} (or fit without corner detection)",
                min + 1 - k,
                max + 1 - k
            ),
        });
    }
    let mut c = free.to_vec();
    let mut sum: usize = c.iter().sum();
    while sum < total {
        // the piece most below its proportional share (largest free / count)
        let i = (0..k)
            .filter(|&i| c[i] < hi[i])
            .max_by(|&a, &b| {
                (free[a] as f64 / c[a] as f64)
                    .total_cmp(&(free[b] as f64 / c[b] as f64))
                    .then(b.cmp(&a))
            })
            .unwrap_or(0);
        c[i] += 1;
        sum += 1;
    }
    while sum > total {
        // the piece most above its proportional share (largest count / free), larger first
        let i = (0..k)
            .filter(|&i| c[i] > lo[i])
            .max_by(|&a, &b| {
                (c[a] as f64 / free[a] as f64)
                    .total_cmp(&(c[b] as f64 / free[b] as f64))
                    .then(c[a].cmp(&c[b]))
                    .then(b.cmp(&a))
            })
            .unwrap_or(0);
        c[i] -= 1;
        sum -= 1;
    }
    Ok(c)
}

/// Distance from `q` to the segment `[a, b]`.
fn point_segment_distance(q: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((q - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - q).norm()
}

#[cfg(test)]
mod tests {
    use super::share_budget;

    #[test]
    fn budget_is_shared_in_proportion_to_the_free_counts() {
        let (lo, hi) = ([4, 4, 4], [50, 4, 60]);
        let share = |n: usize| share_budget(n, &[10, 4, 20], &lo, &hi);
        // free counts 10, 4 (straight), 20; joined 32 = sum - 2 shared corners: unchanged
        assert_eq!(share(32).unwrap(), [10, 4, 20]);
        // 6 more: D'Hondt on 10 : 20 gives 2 and 4
        assert_eq!(share(38).unwrap(), [12, 4, 24]);
        // 6 fewer: taken from the larger piece first, in proportion (8 : 16 after 2 and 4)
        assert_eq!(share(26).unwrap(), [8, 4, 16]);
        // bounds: at least 4 + 4 + 4 - 2 = 10, at most 50 + 4 + 60 - 2 = 112
        let e = share(9).unwrap_err();
        let named = matches!(&e, crate::Error::InvalidSetting { option, .. } if *option == "control_points");
        assert!(named && e.to_string().contains("between 10 and 112"), "{e}");
        assert!(share(112).is_ok() && share(113).is_err());
    }
}
