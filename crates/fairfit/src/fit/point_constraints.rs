//! Per-point weights and points to interpolate, around any fitting method (issue 26).
//!
//! **What holds.** With weights `w_i ≥ 0`, every point is held to `|d_i| ≤ tol / w_i` (`d_i` its
//! orthogonal distance, `tol` the absolute tolerance the method met; unweighted points have
//! `w_i = 1`); a point of weight 0 is removed before the fit, so the result is the fit of the data
//! without it, bit for bit. Every point to interpolate lies on the curve within
//! [`PointConstraintTuning::interpolation`] times the data's size (1e-9).
//!
//! **How.** [`fit_with_point_constraints`] wraps a method given as a closure (the least-squares
//! tolerance search, fit-then-fair, the integrated method; the closure also takes a tighter
//! tolerance). After the method's fit:
//!
//! 1. `reweight` (the least-squares method): the control points are solved again on the method's
//!    knots by weighted least squares, `min Σ w_i² |C(u_i) − Q_i|²` at the points' foot parameters,
//!    under the linear equalities `C(u_k) = Q_k` of the points to interpolate (a KKT system solved
//!    by its Schur complement, [`super::dense`]). The fair methods skip this step: a re-solve would
//!    undo their fairing.
//! 2. the minimum-norm move: the smallest change `ΔP` of the free control points (Euclidean norm)
//!    under the linear constraints `C(u_k) + Σ_j R_j(u_k) ΔP_j = Q_k` (each point to interpolate,
//!    at its foot parameter) and, for each point beyond its band, `n_i · Σ_j R_j(u_i) ΔP_j = d_i −
//!    m tol / w_i` (moved along its normal to the fraction `m` =
//!    [`PointConstraintTuning::band_margin`] of its band): `ΔP = Aᵀ (A Aᵀ)⁻¹ r`, by Cholesky of the
//!    Gram matrix `A Aᵀ`. The knot vector is kept, so the continuity at every knot, a periodic
//!    seam (shared control points move together) and the end conditions (their control points,
//!    [`Held`], are not moved) are kept exactly. The move is repeated while points are out of their
//!    band ([`PointConstraintTuning::move_rounds`]), each time measured again by orthogonal
//!    projection; a point once beyond its band keeps its row (at the margin) in later moves (an
//!    active set, so that one move does not push back out what the last brought in).
//! 3. when that cannot meet every band, or the constraints are dependent (more points to
//!    interpolate in a span than it has free control points), the method fits again at a tighter
//!    tolerance ([`PointConstraintTuning::tighten`], at most [`PointConstraintTuning::refits`]
//!    times), which gives it more control points; after the last one the error names the
//!    constraint (`weights` or `interpolate`).
//!
//! **Inside the search** ([`fit_with_point_constraints_inside`]): a method may honour the
//! constraints itself. The integrated method does (its option `point_constraints`, on open data
//! without corners that are not reduced): every least-squares solve of its knot, count and degree
//! searches is weighted and meets the points to interpolate exactly, every deviation it measures
//! is `w_i d_i`, and its band fairing and polish hold each point to `tol / w_i` and each point to
//! interpolate to a small fraction of the tolerance. The move above then only closes that last
//! gap, so it costs no control point. Elsewhere (closed data, corners, reduced dense data,
//! fit-then-fair's fairing) the method sees the points unweighted, and the move and the refits do
//! the work.
//!
//! Indices (of weights and points to interpolate) are those of the points passed in.

use super::cad_fit::Fitted;
use super::dense::{cholesky, cholesky_solve};
use super::deviation::{max_orthogonal_deviation, Deviation};
use super::points::bounding_box_extent;
use crate::errors::{Error, Result};
use crate::nurbs::basis::basis_funs_into;
use crate::nurbs::{NurbsCurve, Vec3};

/// Weights and points to interpolate of one fit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointConstraints {
    /// One weight per point (`None`: all 1). Finite, `≥ 0`, not all 0.
    pub weights: Option<Vec<f64>>,
    /// Indices of the points the curve must pass through.
    pub interpolate: Vec<usize>,
}

impl PointConstraints {
    /// True when nothing is asked (the fit is the method's own).
    pub fn is_none(&self) -> bool {
        self.weights.is_none() && self.interpolate.is_empty()
    }

    /// Refuses weights that are not one finite non-negative number per point, all zero, or an
    /// index to interpolate out of range or of weight 0 (`InvalidSetting` naming `weights` or
    /// `interpolate`).
    pub fn validate(&self, n_points: usize) -> Result<()> {
        let bad = |option, reason: String| Err(Error::InvalidSetting { option, reason });
        if let Some(w) = &self.weights {
            if w.len() != n_points {
                return bad(
                    "weights",
                    format!("{} weights for {n_points} points", w.len()),
                );
            }
            if let Some(i) = w.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
                return bad(
                    "weights",
                    format!("weight {i} is {}: weights must be finite and >= 0", w[i]),
                );
            }
            if w.iter().all(|&x| x == 0.0) {
                return bad("weights", "every weight is 0: nothing to fit".into());
            }
        }
        for &k in &self.interpolate {
            if k >= n_points {
                return bad(
                    "interpolate",
                    format!(
                        "point {k} is out of range (the data have {n_points} points, 0 to {})",
                        n_points.saturating_sub(1)
                    ),
                );
            }
            if self.weight(k) == 0.0 {
                return bad(
                    "interpolate",
                    format!("point {k} has weight 0: it cannot be both ignored and interpolated"),
                );
            }
        }
        Ok(())
    }

    /// The weight of point `i` (1 without weights).
    pub fn weight(&self, i: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[i])
    }
}

/// The thresholds of [`fit_with_point_constraints`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointConstraintTuning {
    /// Points to interpolate lie within this times the data's size (the bounding box's largest
    /// side).
    pub interpolation: f64,
    /// A point beyond its band is moved to this fraction of it (room for its neighbours' moves).
    pub band_margin: f64,
    /// Minimum-norm moves per fit.
    pub move_rounds: usize,
    /// Refits at a tighter tolerance when the moves cannot hold every constraint.
    pub refits: usize,
    /// Factor of the tolerance at each refit.
    pub tighten: f64,
}

impl Default for PointConstraintTuning {
    fn default() -> Self {
        PointConstraintTuning {
            interpolation: 1e-9,
            band_margin: 0.9,
            move_rounds: 6,
            refits: 5,
            tighten: 0.6,
        }
    }
}

/// Control points that the move keeps where they are: the first `start` and the last `end` of an
/// open curve (its end points, and the control points fixed by end conditions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Held {
    /// Held at the start.
    pub start: usize,
    /// Held at the end.
    pub end: usize,
}

impl Default for Held {
    fn default() -> Self {
        Held { start: 1, end: 1 }
    }
}

impl Held {
    /// The control points a fit holds at each end: the end point when `pinned_ends`, and the ones
    /// an end condition fixes (one more for a tangent, one more for a curvature).
    pub fn at_ends(pinned_ends: bool, conditions: &super::end_constraints::EndConstraints) -> Held {
        let held_at = |c: &super::end_constraints::EndConstraint| {
            usize::from(pinned_ends)
                + usize::from(c.tangent.is_some())
                + usize::from(c.curvature.is_some())
        };
        Held {
            start: held_at(&conditions.start),
            end: held_at(&conditions.end),
        }
    }
}

/// What the constraints achieved.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointConstraintReport {
    /// Each point to interpolate (index into the points passed in) and its orthogonal distance
    /// from the curve.
    pub interpolated: Vec<(usize, f64)>,
    /// The points of weight 0 (not fitted).
    pub ignored: Vec<usize>,
    /// `max_i w_i d_i / tol` over the fitted points (≤ 1).
    pub weighted_ratio: f64,
    /// The point with the largest `w_i d_i` (weighted fits): its index, distance and `tol / w_i`.
    pub tightest: Option<(usize, f64, f64)>,
    /// The absolute tolerance the check used.
    pub tolerance: f64,
    /// The tolerance the kept fit was made at (below `tolerance` after refits).
    pub fit_tolerance: f64,
    /// Refits at a tighter tolerance.
    pub refits: usize,
    /// Minimum-norm moves made on the kept fit.
    pub moves: usize,
    /// The largest deviation of the fitted points.
    pub max_deviation: f64,
    /// The RMS deviation of the fitted points.
    pub rms_deviation: f64,
}

/// The curve, the method's extra output and what the constraints achieved.
#[derive(Clone, Debug)]
pub struct ConstrainedFit<T> {
    /// The constrained curve.
    pub curve: NurbsCurve,
    /// The method's extra output of the kept fit.
    pub extra: T,
    /// What held.
    pub report: PointConstraintReport,
}

/// The points of non-zero weight, their weights, their indices among all points, and which of
/// them are to be interpolated.
struct Kept {
    points: Vec<Vec3>,
    weights: Vec<f64>,
    index: Vec<usize>,
    interpolate: Vec<bool>,
}

impl Kept {
    /// The constraints of the kept points (indices among them); none when every weight is 1
    /// and nothing is interpolated.
    fn constraints(&self) -> PointConstraints {
        PointConstraints {
            weights: self
                .weights
                .iter()
                .any(|&w| w != 1.0)
                .then(|| self.weights.clone()),
            interpolate: (0..self.points.len())
                .filter(|&j| self.interpolate[j])
                .collect(),
        }
    }
}

fn keep(points: &[Vec3], pc: &PointConstraints) -> Kept {
    let mut k = Kept {
        points: Vec::new(),
        weights: Vec::new(),
        index: Vec::new(),
        interpolate: Vec::new(),
    };
    for (i, &q) in points.iter().enumerate() {
        let w = pc.weight(i);
        if w > 0.0 {
            k.points.push(q);
            k.weights.push(w);
            k.index.push(i);
            k.interpolate.push(pc.interpolate.contains(&i));
        }
    }
    k
}

/// Fits `points` with `fit` (called with `None` first, then with tighter absolute tolerances) and
/// holds the weights and points to interpolate of `pc` (module docs). `held`: the control points
/// the move keeps; `reweight`: re-solve by weighted least squares first (the least-squares
/// method). Without constraints, exactly `fit(points, None)`.
pub fn fit_with_point_constraints<T, E: From<Error>>(
    points: &[Vec3],
    pc: &PointConstraints,
    held: Held,
    reweight: bool,
    tuning: &PointConstraintTuning,
    mut fit: impl FnMut(&[Vec3], Option<f64>) -> std::result::Result<Fitted<T>, E>,
) -> std::result::Result<ConstrainedFit<T>, E> {
    fit_with_point_constraints_inside(points, pc, held, reweight, tuning, |q, t, _| fit(q, t))
}

/// [`fit_with_point_constraints`] with a method that honours the constraints itself (the
/// integrated method: [`crate::optim::IntegratedOptions::point_constraints`]): `fit` also gets
/// the constraints of the points it is given (the points of weight 0 gone; default when every
/// weight left is 1 and nothing is interpolated). The move and the refits then follow as there,
/// and have little or nothing left to do.
pub fn fit_with_point_constraints_inside<T, E: From<Error>>(
    points: &[Vec3],
    pc: &PointConstraints,
    held: Held,
    reweight: bool,
    tuning: &PointConstraintTuning,
    mut fit: impl FnMut(&[Vec3], Option<f64>, &PointConstraints) -> std::result::Result<Fitted<T>, E>,
) -> std::result::Result<ConstrainedFit<T>, E> {
    pc.validate(points.len())?;
    let kept = keep(points, pc);
    let inside = kept.constraints();
    let mut fit = |q: &[Vec3], t: Option<f64>| fit(q, t, &inside);
    let size = bounding_box_extent(points);
    let first = fit(&kept.points, None)?;
    let tol = first.tolerance;
    if pc.interpolate.is_empty()
        && pc
            .weights
            .as_ref()
            .is_none_or(|w| w.iter().all(|&x| x == 0.0 || x == 1.0))
    {
        // zero weights only: the fit of the remaining points is the answer
        let dev = max_orthogonal_deviation(&first.curve, &kept.points, &[]);
        let report = report_of(&kept, pc, &dev, tol, tol, 0, 0);
        return Ok(ConstrainedFit {
            curve: first.curve,
            extra: first.extra,
            report,
        });
    }
    let mut fitted = first;
    let mut fit_tol = tol;
    let mut last_miss = Miss::default();
    for refit in 0..=tuning.refits {
        if refit > 0 {
            fit_tol *= tuning.tighten;
            fitted = fit(&kept.points, Some(fit_tol))?;
        }
        let mut curve = fitted.curve.clone();
        let mut dev = max_orthogonal_deviation(&curve, &kept.points, &[]);
        if reweight {
            if let Some(c) = weighted_resolve(&curve, &kept, &dev.params, held) {
                curve = c;
                dev = max_orthogonal_deviation(&curve, &kept.points, &dev.params);
            }
        }
        match hold(curve, dev, &kept, tol, size, held, tuning) {
            Ok((curve, dev, moves)) => {
                let report = report_of(&kept, pc, &dev, tol, fit_tol, refit, moves);
                return Ok(ConstrainedFit {
                    curve,
                    extra: fitted.extra,
                    report,
                });
            }
            Err(m) => last_miss = m,
        }
    }
    let n_ctrl = fitted.curve.n_control_points();
    Err(E::from(last_miss.error(
        &kept,
        tol,
        tuning.interpolation * size,
        n_ctrl,
    )))
}

fn report_of(
    kept: &Kept,
    pc: &PointConstraints,
    dev: &Deviation,
    tol: f64,
    fit_tol: f64,
    refits: usize,
    moves: usize,
) -> PointConstraintReport {
    let mut r = PointConstraintReport {
        ignored: (0..pc.weights.as_ref().map_or(0, |w| w.len()))
            .filter(|&i| pc.weight(i) == 0.0)
            .collect(),
        tolerance: tol,
        fit_tolerance: fit_tol,
        refits,
        moves,
        max_deviation: dev.max,
        rms_deviation: dev.rms,
        ..Default::default()
    };
    for (j, &d) in dev.per_point.iter().enumerate() {
        if kept.interpolate[j] {
            r.interpolated.push((kept.index[j], d));
        }
        let ratio = d * kept.weights[j] / tol;
        if ratio > r.weighted_ratio || r.tightest.is_none() {
            r.weighted_ratio = r.weighted_ratio.max(ratio);
            r.tightest = Some((kept.index[j], d, tol / kept.weights[j]));
        }
    }
    if pc.weights.is_none() {
        r.tightest = None;
    }
    r
}

/// Why the constraints were not met on one fit.
#[derive(Clone, Copy, Debug, Default)]
struct Miss {
    /// The constraints' Gram matrix was singular (dependent constraints).
    singular: bool,
    /// Largest distance of a point to interpolate (index among the kept points).
    interpolation: Option<(usize, f64)>,
    /// Largest `w_i d_i / tol` of the other points, and its point.
    band: Option<(usize, f64)>,
}

impl Miss {
    fn error(&self, kept: &Kept, tol: f64, limit: f64, n_ctrl: usize) -> Error {
        let n_interp = kept.interpolate.iter().filter(|&&b| b).count();
        if self.singular || self.interpolation.is_some() {
            let how = match self.interpolation {
                Some((j, d)) if !self.singular => format!(
                    "point {} stays {d:.3e} off the curve (limit {limit:.1e})",
                    kept.index[j]
                ),
                _ => "the constraints are dependent (too many points to interpolate in too few knot spans)".into(),
            };
            return Error::InvalidSetting {
                option: "interpolate",
                reason: format!(
                    "{n_interp} points to interpolate cannot be held with the tolerance met: {how}, last fit {n_ctrl} control points"
                ),
            };
        }
        let (j, ratio) = self.band.unwrap_or((0, f64::NAN));
        Error::InvalidSetting {
            option: "weights",
            reason: format!(
                "point {} (weight {}) is {:.3e} from the curve, beyond its tolerance {:.3e} (tol / weight), last fit {n_ctrl} control points",
                kept.index[j],
                kept.weights[j],
                ratio * tol / kept.weights[j],
                tol / kept.weights[j]
            ),
        }
    }
}

/// Moves `curve` by minimum-norm steps until every point is in its band and every point to
/// interpolate is on it: the curve, its deviation and the moves made, or why not.
fn hold(
    mut curve: NurbsCurve,
    mut dev: Deviation,
    kept: &Kept,
    tol: f64,
    size: f64,
    held: Held,
    tuning: &PointConstraintTuning,
) -> std::result::Result<(NurbsCurve, Deviation, usize), Miss> {
    let limit = tuning.interpolation * size;
    // the points once beyond their band stay constrained (held at the margin) in later moves: an
    // active set, so that a move does not push back out the points the last one brought in
    let mut active = vec![false; kept.points.len()];
    for round in 0..=tuning.move_rounds {
        let miss = measure(&dev, kept, tol, limit);
        if miss.interpolation.is_none() && miss.band.is_none() {
            return Ok((curve, dev, round));
        }
        if round == tuning.move_rounds {
            return Err(miss);
        }
        for (j, a) in active.iter_mut().enumerate() {
            *a |= !kept.interpolate[j] && dev.per_point[j] * kept.weights[j] > tol;
        }
        let rows = move_rows(&curve, &dev, kept, &active, tol, tuning.band_margin);
        match minimum_norm_move(&curve, &rows, held) {
            Some(c) => curve = c,
            None => {
                return Err(Miss {
                    singular: true,
                    ..miss
                })
            }
        }
        dev = max_orthogonal_deviation(&curve, &kept.points, &dev.params);
    }
    Err(Miss::default())
}

/// The constraints `dev` misses: points to interpolate farther than `limit`, points beyond
/// `tol / w_i`.
fn measure(dev: &Deviation, kept: &Kept, tol: f64, limit: f64) -> Miss {
    let mut miss = Miss::default();
    for (j, &d) in dev.per_point.iter().enumerate() {
        if kept.interpolate[j] {
            if d > limit && miss.interpolation.is_none_or(|(_, w)| d > w) {
                miss.interpolation = Some((j, d));
            }
        } else {
            let ratio = d * kept.weights[j] / tol;
            if ratio > 1.0 && miss.band.is_none_or(|(_, r)| ratio > r) {
                miss.band = Some((j, ratio));
            }
        }
    }
    miss
}

/// One linear constraint on the control-point move: `Σ_j R_j(u) (dir · ΔP_j) = rhs`.
struct Row {
    u: f64,
    dir: Vec3,
    rhs: f64,
}

/// The rows of one move: three per point to interpolate (onto it), one per `active` point (along
/// its normal, to `margin` of its band).
fn move_rows(
    curve: &NurbsCurve,
    dev: &Deviation,
    kept: &Kept,
    active: &[bool],
    tol: f64,
    margin: f64,
) -> Vec<Row> {
    let mut rows = Vec::new();
    for (j, (&d, &u)) in dev.per_point.iter().zip(&dev.params).enumerate() {
        let gap = kept.points[j] - curve.point(u);
        if kept.interpolate[j] {
            for a in 0..3 {
                let mut e = [0.0; 3];
                e[a] = 1.0;
                rows.push(Row {
                    u,
                    dir: Vec3(e),
                    rhs: gap.0[a],
                });
            }
        } else if active[j] && d > 0.0 {
            let n = gap * (1.0 / gap.norm());
            rows.push(Row {
                u,
                dir: n,
                rhs: d - margin * tol / kept.weights[j],
            });
        }
    }
    rows
}

/// Which unknown (free control point) each control point is: `None` when held; a periodic curve's
/// repeated control points share their unknown.
struct Columns {
    of: Vec<Option<usize>>,
    n_free: usize,
}

fn columns(curve: &NurbsCurve, held: Held) -> Columns {
    let p = curve.degree();
    let (k, c) = (curve.knots(), curve.control_points());
    let n = c.len();
    let clamped = n > p && k[0] == k[p] && k[n] == k[n + p];
    let periodic = !clamped && n > 2 * p && (0..p).all(|j| c[j] == c[n - p + j]);
    if periodic {
        let unique = n - p;
        return Columns {
            of: (0..n).map(|i| Some(i % unique)).collect(),
            n_free: unique,
        };
    }
    let (lo, hi) = if clamped {
        (held.start, held.end)
    } else {
        (0, 0)
    };
    let mut next = 0;
    let of = (0..n)
        .map(|i| {
            (i >= lo && i + hi < n).then(|| {
                next += 1;
                next - 1
            })
        })
        .collect();
    Columns { of, n_free: next }
}

/// The `p + 1` basis values `R_j(u)` of `curve` (rational when weighted) and the first index `j`.
fn basis_at(curve: &NurbsCurve, u: f64, out: &mut [f64]) -> usize {
    let p = curve.degree();
    let span = curve.find_span(u);
    let (mut left, mut right) = (vec![0.0; p + 1], vec![0.0; p + 1]);
    basis_funs_into(span, u, p, curve.knots(), &mut left, &mut right, out);
    if curve.is_rational() {
        let w = &curve.weights()[span - p..=span];
        let sum: f64 = out.iter().zip(w).map(|(a, b)| a * b).sum();
        for (v, wj) in out.iter_mut().zip(w) {
            *v *= wj / sum;
        }
    }
    span - p
}

/// The smallest move of the free control points (Euclidean norm) that satisfies `rows`, or `None`
/// when the rows are dependent.
fn minimum_norm_move(curve: &NurbsCurve, rows: &[Row], held: Held) -> Option<NurbsCurve> {
    let cols = columns(curve, held);
    let p = curve.degree();
    let nu = 3 * cols.n_free;
    let r = rows.len();
    // A (r × 3 n_free), dense: a row has at most 3 (p + 1) non-zeros
    let mut a = vec![0.0; r * nu];
    let mut nb = vec![0.0; p + 1];
    for (i, row) in rows.iter().enumerate() {
        let first = basis_at(curve, row.u, &mut nb);
        for (j, &v) in nb.iter().enumerate() {
            if let Some(f) = cols.of[first + j] {
                for ax in 0..3 {
                    a[i * nu + 3 * f + ax] += v * row.dir.0[ax];
                }
            }
        }
    }
    let mut g = vec![0.0; r * r];
    for i in 0..r {
        for j in 0..=i {
            let s: f64 = (0..nu).map(|c| a[i * nu + c] * a[j * nu + c]).sum();
            g[i * r + j] = s;
            g[j * r + i] = s;
        }
    }
    let mut y: Vec<f64> = rows.iter().map(|row| row.rhs).collect();
    // a row on held control points only (a point to interpolate at a held end) cannot move:
    // it takes no part (y_i = 0), and the measure says whether it holds
    for i in 0..r {
        if g[i * r + i] == 0.0 {
            g[i * r + i] = 1.0;
            y[i] = 0.0;
        }
    }
    if !cholesky(&mut g, r) {
        return None;
    }
    cholesky_solve(&g, r, &mut y);
    let mut delta = vec![0.0; nu];
    for i in 0..r {
        for c in 0..nu {
            delta[c] += a[i * nu + c] * y[i];
        }
    }
    let moved: Vec<Vec3> = curve
        .control_points()
        .iter()
        .zip(&cols.of)
        .map(|(&c, f)| match f {
            Some(f) => c + Vec3::new(delta[3 * f], delta[3 * f + 1], delta[3 * f + 2]),
            None => c,
        })
        .collect();
    rebuilt(curve, moved)
}

fn rebuilt(curve: &NurbsCurve, ctrl: Vec<Vec3>) -> Option<NurbsCurve> {
    let w = curve.is_rational().then(|| curve.weights().to_vec());
    NurbsCurve::new(curve.degree(), curve.knots().to_vec(), ctrl, w).ok()
}

/// The control points solved again on `curve`'s knots by weighted least squares at the foot
/// parameters `params`, under the equalities `C(u_k) = Q_k` of the points to interpolate; the held
/// control points stay. `None` when a system is singular (then the curve is kept as it was).
fn weighted_resolve(
    curve: &NurbsCurve,
    kept: &Kept,
    params: &[f64],
    held: Held,
) -> Option<NurbsCurve> {
    let cols = columns(curve, held);
    let n = cols.n_free;
    let p = curve.degree();
    let ctrl = curve.control_points();
    let mut m = vec![0.0; n * n];
    let mut b = vec![[0.0; 3]; n];
    let mut nb = vec![0.0; p + 1];
    // equality rows: (free coefficients, target minus held part)
    let mut eq: Vec<(Vec<(usize, f64)>, Vec3)> = Vec::new();
    for (k, &u) in params.iter().enumerate() {
        let first = basis_at(curve, u, &mut nb);
        let mut target = kept.points[k];
        let mut free = Vec::with_capacity(p + 1);
        for (j, &v) in nb.iter().enumerate() {
            match cols.of[first + j] {
                Some(f) => free.push((f, v)),
                None => target -= ctrl[first + j] * v,
            }
        }
        let w2 = kept.weights[k] * kept.weights[k];
        for &(fa, va) in &free {
            for (bx, tx) in b[fa].iter_mut().zip(target.0) {
                *bx += w2 * va * tx;
            }
            for &(fb, vb) in &free {
                m[fa * n + fb] += w2 * va * vb;
            }
        }
        if kept.interpolate[k] && !free.is_empty() {
            eq.push((free, target));
        }
    }
    if !cholesky(&mut m, n) {
        return None;
    }
    // x0 = M⁻¹ b per axis
    let mut x: Vec<Vec<f64>> = (0..3)
        .map(|ax| {
            let mut v: Vec<f64> = b.iter().map(|r| r[ax]).collect();
            cholesky_solve(&m, n, &mut v);
            v
        })
        .collect();
    if !eq.is_empty() {
        // Schur complement S = A M⁻¹ Aᵀ (the same A for every axis)
        let r = eq.len();
        let minv_at: Vec<Vec<f64>> = eq
            .iter()
            .map(|(row, _)| {
                let mut v = vec![0.0; n];
                for &(f, c) in row {
                    v[f] = c;
                }
                cholesky_solve(&m, n, &mut v);
                v
            })
            .collect();
        let mut s = vec![0.0; r * r];
        for i in 0..r {
            for j in 0..r {
                s[i * r + j] = eq[i].0.iter().map(|&(f, c)| c * minv_at[j][f]).sum();
            }
        }
        if !cholesky(&mut s, r) {
            return None;
        }
        for (ax, xa) in x.iter_mut().enumerate() {
            let mut lam: Vec<f64> = eq
                .iter()
                .map(|(row, t)| row.iter().map(|&(f, c)| c * xa[f]).sum::<f64>() - t.0[ax])
                .collect();
            cholesky_solve(&s, r, &mut lam);
            for (i, l) in lam.iter().enumerate() {
                for (xf, mv) in xa.iter_mut().zip(&minv_at[i]) {
                    *xf -= l * mv;
                }
            }
        }
    }
    let moved: Vec<Vec3> = ctrl
        .iter()
        .zip(&cols.of)
        .map(|(&c, f)| match f {
            Some(f) => Vec3::new(x[0][*f], x[1][*f], x[2][*f]),
            None => c,
        })
        .collect();
    rebuilt(curve, moved)
}
