//! Chains: several ordered point sets fitted as one fair chain of curves that join with G1 or G2
//! continuity ([`fit_chain`]).
//!
//! # The method
//!
//! Consecutive point sets share, or nearly share, their join point: the last point of piece `k` and
//! the first of piece `k + 1` lie within twice the tolerance of each other (else the chain is
//! refused: no curve passes within the tolerance of both). The joins are free within the tolerance
//! of both pieces' end points, and the chain is fitted in three steps:
//!
//! 1. **one curve through everything**: the integrated method on the union of the points (a join
//!    point shared by two pieces counted once), with the chain's own start and end conditions. It
//!    is the fairest single curve within the tolerance, so its position, unit tangent and curvature
//!    vector where it passes the join (its closest point to the midpoint of the two data end
//!    points) are a join that costs the pieces no fairness they would not pay anyway;
//! 2. **the pieces**: each piece by the integrated method, its ends held to those join conditions
//!    (G1: point and tangent; G2: also the curvature vector,
//!    [`crate::fit::end_constraints`]), the chain's ends to the chain's own conditions;
//! 3. **the fairer of two**: the single curve cut at the joins (exact, by knot insertion) meets
//!    the same join conditions where it is smooth there, so each piece keeps whichever of its own
//!    fit and its part of the single curve has the smaller `∫ (dκ/ds)² ds`, the part only when it
//!    meets the piece's end conditions to rounding and is within the tolerance of the piece's
//!    points ([`ChainResult::from_single`] says which).
//!
//! Every piece is fitted from the same joins, so the result does not depend on the order the pieces
//! are fitted in, and reversing the chain reverses the result. Both sides of a join carry the same
//! end condition, and the end conditions hold to rounding: the pieces meet at one point with the
//! same tangent (G1) and the same curvature vector (G2); [`ChainJoin`] measures it on the fitted
//! curves.
//!
//! # The chain's fairness
//!
//! [`ChainResult::fairness`] is the `F = L³ ∫ (dκ/ds)² ds` of the joined chain: `L` the total
//! length and the integral the sum of the pieces' (the joined curve's integral over its spans;
//! at a G2 join `κ` is continuous, so the join adds nothing). [`ChainResult::single`] is the
//! single curve of step 1 and [`ChainResult::single_fairness`] its `F` measured the same way, so
//! their ratio is the price of the joins.
//!
//! Invariants: every piece is open, without corners (the end conditions need both), and held to
//! the single curve's tolerance in the input's units (a relative tolerance is relative to the
//! whole chain's size).

use super::options::IntegratedOptions;
use super::pipeline::fit_integrated;
use super::result::IntegratedResult;
use crate::errors::{Error, Result};
use crate::fair::curve_fairness;
use crate::fit::end_constraints::{EndConstraint, EndCurvature};
use crate::fit::tolerance::ClosedMode;
use crate::nurbs::{NurbsCurve, Vec3};
use crate::tolerance::Tolerance;
use rayon::prelude::*;

/// The continuity of a chain's joins.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JoinContinuity {
    /// Position and tangent direction.
    G1,
    /// Position, tangent direction and curvature vector.
    G2,
}

impl JoinContinuity {
    /// The order: 1 or 2.
    pub fn order(self) -> usize {
        match self {
            JoinContinuity::G1 => 1,
            JoinContinuity::G2 => 2,
        }
    }

    /// The name front ends spell it with (`fairfit curve --chain g1|g2`, the report's `chain`).
    pub fn name(self) -> &'static str {
        match self {
            JoinContinuity::G1 => "g1",
            JoinContinuity::G2 => "g2",
        }
    }
}

impl std::fmt::Display for JoinContinuity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for JoinContinuity {
    type Err = String;

    /// `g1` or `g2` (the names of [`JoinContinuity::name`]); the error is the reason alone, for the
    /// caller to prefix with its own name of the option.
    fn from_str(text: &str) -> std::result::Result<Self, String> {
        match text {
            "g1" => Ok(JoinContinuity::G1),
            "g2" => Ok(JoinContinuity::G2),
            _ => Err(format!("expected `g1` or `g2`, got `{text}`")),
        }
    }
}

/// One join of a chain, measured on the fitted pieces: the end of piece `k` against the start of
/// piece `k + 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainJoin {
    /// The join point chosen (on the single curve, [`ChainResult::single`]).
    pub point: Vec3,
    /// Distance between the data's end points (the last point of piece `k`, the first of `k + 1`).
    pub data_gap: f64,
    /// Distance between the two pieces' curves at the join.
    pub position_gap: f64,
    /// Angle in radians between their tangents there.
    pub tangent_angle: f64,
    /// `|κ_k − κ_{k+1}| / max(|κ_k|, |κ_{k+1}|)` of their curvature vectors there (0 when both are
    /// straight).
    pub curvature_relative: f64,
    /// The curvature `|κ|` of piece `k` at the join.
    pub curvature: f64,
}

/// The result of [`fit_chain`].
#[derive(Clone, Debug)]
pub struct ChainResult {
    /// The pieces, in order, each the integrated method's result for its points.
    pub pieces: Vec<IntegratedResult>,
    /// Whether piece `k` is the single curve's part between its joins (else its own fit, module
    /// doc).
    pub from_single: Vec<bool>,
    /// The joins, `joins[k]` between `pieces[k]` and `pieces[k + 1]`.
    pub joins: Vec<ChainJoin>,
    /// The single curve through every point that chose the joins (module doc).
    pub single: IntegratedResult,
    /// The tolerance every piece was held to, in the input's units.
    pub tolerance: f64,
    /// Total length of the chain.
    pub length: f64,
    /// `F` of the joined chain (module doc).
    pub fairness: f64,
    /// `F` of the single curve, measured as [`Self::fairness`] is (`fairness / single_fairness` is
    /// the price of the joins).
    pub single_fairness: f64,
    /// Whether every piece met the tolerance.
    pub met: bool,
}

impl ChainResult {
    /// The warning a front end shows when a piece missed the tolerance (`None` when every piece met
    /// it): the pieces' reports say which.
    pub fn warning(&self) -> Option<&'static str> {
        (!self.met).then_some("a chain piece misses the tolerance (see the report's pieces)")
    }
}

/// Fits the point sets `pieces` (each ordered, consecutive ones meeting end to start) as one fair
/// chain of curves joining with `continuity`, by the integrated method with `opts` (module doc). The
/// chain's own start and end conditions are `opts`' (`opts.end_conditions`), held by the first
/// piece's start and the last piece's end.
///
/// Errors: fewer than two pieces ([`Error::InvalidOption`]); settings a chain cannot take —
/// closed curves, a fixed control-point count, free ends, per-point constraints
/// ([`Error::InvalidSetting`] naming it); consecutive pieces whose end points are more than twice
/// the tolerance apart ([`Error::InvalidData`]); a piece whose joins cannot be held within the
/// tolerance ([`Error::Fit`], naming the piece); and the integrated method's own errors.
///
/// ```
/// use fairfit::optim::chain::{fit_chain, JoinContinuity};
/// use fairfit::prelude::*;
/// // two arcs of the circle of radius 2, meeting at angle 1
/// let arc = |a0: f64, a1: f64| -> Vec<Vec3> {
///     (0..40)
///         .map(|i| {
///             let a = a0 + (a1 - a0) * i as f64 / 39.0;
///             Vec3::new(2.0 * a.cos(), 2.0 * a.sin(), 0.0)
///         })
///         .collect()
/// };
/// let opts = IntegratedOptions::new(Tolerance::Relative(1e-3));
/// let r = fit_chain(&[arc(0.0, 1.0), arc(1.0, 2.2)], JoinContinuity::G2, &opts)?;
/// assert!(r.met && r.pieces.len() == 2);
/// let j = r.joins[0];
/// assert!(j.tangent_angle < 1e-9 && j.curvature_relative < 1e-9);
/// assert!((j.curvature - 0.5).abs() < 0.02);
/// # Ok::<(), fairfit::Error>(())
/// ```
pub fn fit_chain<P: AsRef<[Vec3]> + Sync>(
    pieces: &[P],
    continuity: JoinContinuity,
    opts: &IntegratedOptions,
) -> Result<ChainResult> {
    check_options(pieces.len(), opts)?;
    let sets: Vec<&[Vec3]> = pieces.iter().map(|p| p.as_ref()).collect();
    let union = union_of(&sets);
    let tol = crate::fit::points::absolute_tolerance(opts.tolerance, &union);
    check_gaps(&sets, tol)?;
    // step 1: the single curve through every point, open and smooth
    let single_opts = IntegratedOptions {
        closed: ClosedMode::Open,
        ..opts.clone()
    };
    let single = fit_integrated(&union, &single_opts)?;
    // the tolerance the single curve held (a tolerance below the noise is raised by the screening)
    let tol = single.tolerance.max(tol);
    let (cuts, joins): (Vec<f64>, Vec<EndConstraint>) = sets
        .windows(2)
        .enumerate()
        .map(|(k, w)| join_condition(&single.curve, (k, w[0], w[1]), continuity.order()))
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .unzip();
    let split = split_at(&single.curve, &cuts)?;
    // step 2: every piece under its joins' conditions
    let piece_opts = IntegratedOptions {
        tolerance: Tolerance::Absolute(tol),
        closed: ClosedMode::Open,
        ..opts.clone()
    };
    let n = sets.len();
    let fitted: Vec<(IntegratedResult, bool)> = sets
        .par_iter()
        .enumerate()
        .map(|(k, pts)| {
            let mut o = piece_opts.clone();
            if k > 0 {
                o.end_conditions.start = joins[k - 1];
            }
            if k + 1 < n {
                o.end_conditions.end = joins[k];
            }
            let own = fit_integrated(pts, &o).map_err(|e| piece_error(e, k, n));
            fairer(own, &split[k], pts, tol, &single, &o.end_conditions)
        })
        .collect::<Result<Vec<_>>>()?;
    let (fitted, from_single): (Vec<IntegratedResult>, Vec<bool>) = fitted.into_iter().unzip();
    let measured: Vec<ChainJoin> = (0..n - 1)
        .map(|k| {
            let p = joins[k].point.unwrap_or(sets[k][sets[k].len() - 1]);
            measure_join(
                &fitted[k].curve,
                &fitted[k + 1].curve,
                p,
                sets[k],
                sets[k + 1],
            )
        })
        .collect();
    let (length, fairness) = chain_fairness(fitted.iter().map(|r| &r.curve));
    Ok(ChainResult {
        met: fitted.iter().all(|r| r.met),
        pieces: fitted,
        from_single,
        joins: measured,
        tolerance: tol,
        length,
        fairness,
        single_fairness: chain_fairness([&single.curve]).1,
        single,
    })
}

/// Refuses a chain of fewer than two pieces and the settings a chain cannot take.
fn check_options(n: usize, opts: &IntegratedOptions) -> Result<()> {
    if n < 2 {
        return Err(Error::InvalidOption(format!(
            "a chain needs at least two point sets, got {n}"
        )));
    }
    let refuse = |option: &'static str, reason: &str| {
        Err(Error::InvalidSetting {
            option,
            reason: reason.into(),
        })
    };
    if opts.closed == ClosedMode::Closed {
        return refuse("closed", "a chain's pieces are open curves");
    }
    if opts.control_points.is_some() {
        return refuse(
            "control_points",
            "a chain chooses each piece's count (a fixed count cannot apply to every piece)",
        );
    }
    if opts.ends == super::EndCondition::Free {
        return refuse(
            "ends",
            "a chain's pieces carry join conditions, which fix their end points",
        );
    }
    if !opts.point_constraints.is_none() {
        return refuse(
            "point_constraints",
            "weights and points to interpolate index one point set, not a chain",
        );
    }
    Ok(())
}

/// The points of every piece in order, a join point the next piece repeats counted once.
fn union_of(sets: &[&[Vec3]]) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::with_capacity(sets.iter().map(|s| s.len()).sum());
    for s in sets {
        let skip = match (out.last(), s.first()) {
            (Some(a), Some(b)) => usize::from(a == b),
            _ => 0,
        };
        out.extend_from_slice(&s[skip.min(s.len())..]);
    }
    out
}

/// Refuses (data error) consecutive pieces whose end points are more than `2 tol` apart, and empty
/// pieces.
fn check_gaps(sets: &[&[Vec3]], tol: f64) -> Result<()> {
    for (k, s) in sets.iter().enumerate() {
        if s.len() < 2 {
            return Err(Error::InvalidData(format!(
                "chain piece {} has {} point(s); at least 2 are needed",
                k + 1,
                s.len()
            )));
        }
    }
    for (k, w) in sets.windows(2).enumerate() {
        let gap = (w[0][w[0].len() - 1] - w[1][0]).norm();
        if gap.is_nan() || gap > 2.0 * tol {
            return Err(Error::InvalidData(format!(
                "chain pieces {} and {} do not meet: the last point of piece {} is {gap:.3e} from the first point of piece {} (more than twice the tolerance {tol:.3e}); check their order and direction",
                k + 1,
                k + 2,
                k + 1,
                k + 2
            )));
        }
    }
    Ok(())
}

/// The parameter of `curve` at the join of the point sets `a` (before) and `b` (after), its closest
/// point to the midpoint of `a`'s last and `b`'s first point, and the condition there: position,
/// unit tangent (`order` ≥ 1) and curvature vector (`order` 2) of `curve`. The tangent is the
/// curve's direction of travel, right for the end of `a`'s piece and the start of `b`'s.
fn join_condition(
    curve: &NurbsCurve,
    (k, a, b): (usize, &[Vec3], &[Vec3]),
    order: usize,
) -> Result<(f64, EndConstraint)> {
    let mid = (a[a.len() - 1] + b[0]) * 0.5;
    let u = crate::diffgeo::project_point(curve, mid).u;
    let turn = turn_at(curve, u);
    if turn > CORNER_TURN {
        return Err(Error::InvalidData(format!(
            "chain pieces {} and {} meet at a corner (the curve through every point turns by {:.1} degrees there): a G1/G2 chain needs a smooth join; fit them as one curve, which keeps the corner, or separately",
            k + 1,
            k + 2,
            turn.to_degrees()
        )));
    }
    let d = curve.derivatives(u, 2);
    let speed = d[1].norm();
    if !(speed > 0.0 && speed.is_finite()) {
        return Err(Error::Fit(
            "the single curve has no tangent at a join (zero derivative)".into(),
        ));
    }
    let mut c = EndConstraint::point(d[0]);
    c.tangent = Some(d[1] / speed);
    if order >= 2 {
        let k = d[1].cross(d[2]).cross(d[1]) / speed.powi(4);
        if !k.is_finite() {
            return Err(Error::Fit(
                "the single curve's curvature at a join is not a finite number".into(),
            ));
        }
        c.curvature = Some(EndCurvature::Vector(k));
    }
    Ok((u, c))
}

/// The turn of a join (radians) above which the single curve has a corner there: its tangents
/// `1e-9` of the domain either side of a smooth join differ by about `1e-8` rad, across a corner
/// (a C0 knot) by the corner's angle.
const CORNER_TURN: f64 = 1e-3;

/// The angle between `curve`'s unit tangents just before and just after `u`.
fn turn_at(curve: &NurbsCurve, u: f64) -> f64 {
    let (a, b) = curve.domain();
    let h = 1e-9 * (b - a);
    let tangent = |x: f64| {
        let d = curve.derivatives(x.clamp(a, b), 1);
        d[1] / d[1].norm()
    };
    let (l, r) = (tangent(u - h), tangent(u + h));
    l.cross(r).norm().atan2(l.dot(r))
}

/// `curve` cut at the increasing interior parameters `cuts` into `cuts.len() + 1` clamped pieces,
/// each on `[0, 1]` (exact: knot insertion to multiplicity `p` at every cut). A cut outside the
/// open domain, or cuts out of order, are an error.
fn split_at(curve: &NurbsCurve, cuts: &[f64]) -> Result<Vec<NurbsCurve>> {
    let p = curve.degree();
    let (a, b) = curve.domain();
    let lost = |u: f64| Error::KnotOperation(format!("cannot cut the curve at {u}"));
    let mut c = curve.clone();
    let mut last = a;
    for &u in cuts {
        if !(u > last && u < b) {
            return Err(lost(u));
        }
        last = u;
        let m = c.knots().iter().filter(|&&k| k == u).count();
        if m < p {
            c = c.insert_knot(u, p - m)?;
        }
    }
    let (k, pts, w) = (c.knots(), c.control_points(), c.weights());
    let bounds: Vec<f64> = std::iter::once(a)
        .chain(cuts.iter().copied())
        .chain(std::iter::once(b))
        .collect();
    let mut out = Vec::with_capacity(cuts.len() + 1);
    for (j, ends) in bounds.windows(2).enumerate() {
        let (s, e) = (ends[0], ends[1]);
        // an interior cut of multiplicity p at knots i..i+p: the curve there is P_{i-1}
        let first = match j {
            0 => 0,
            _ => k
                .iter()
                .position(|&x| x == s)
                .and_then(|i| i.checked_sub(1))
                .ok_or_else(|| lost(s))?,
        };
        let end = match j + 1 == cuts.len() + 1 {
            true => pts.len() - 1,
            false => k
                .iter()
                .position(|&x| x == e)
                .and_then(|i| i.checked_sub(1))
                .ok_or_else(|| lost(e))?,
        };
        let map = |x: f64| (x - s) / (e - s);
        let mut knots = vec![0.0; p + 1];
        knots.extend(k.iter().filter(|&&x| x > s && x < e).map(|&x| map(x)));
        knots.extend(std::iter::repeat_n(1.0, p + 1));
        let weights = c.is_rational().then(|| w[first..=end].to_vec());
        out.push(NurbsCurve::new(
            p,
            knots,
            pts[first..=end].to_vec(),
            weights,
        )?);
    }
    Ok(out)
}

/// The fairer of a piece's own fit under its end conditions `ends` (`own`) and the single curve's
/// part between the same joins (`part`): the part when it meets `ends` to rounding (it does where
/// the single curve is smooth at the cuts; not at a corner of it), is within the tolerance `tol`
/// of the piece's `points` and its `∫ (dκ/ds)² ds` is no larger (or the own fit failed), else the
/// own fit (or its error); with whether the part was kept.
fn fairer(
    own: Result<IntegratedResult>,
    part: &NurbsCurve,
    points: &[Vec3],
    tol: f64,
    single: &IntegratedResult,
    ends: &crate::fit::end_constraints::EndConstraints,
) -> Result<(IntegratedResult, bool)> {
    let meets = |at_end: bool, c: &EndConstraint| {
        let a = crate::fit::end_constraints::achieved(part, at_end, c);
        a.point_distance <= 1e-9 * tol && a.tangent_angle <= 1e-10 && a.curvature_relative <= 1e-10
    };
    if !(meets(false, &ends.start) && meets(true, &ends.end)) {
        return own.map(|r| (r, false));
    }
    let dev = crate::fit::max_orthogonal_deviation(part, points, &[]);
    if dev.max.is_nan() || dev.max > tol * (1.0 + 1e-9) {
        return own.map(|r| (r, false));
    }
    let f = curve_fairness(part);
    if let Ok(r) = &own {
        let e_own = r.quality.fairness / curve_fairness(&r.curve).length.powi(3);
        if r.met && e_own < f.energy {
            return own.map(|r| (r, false));
        }
    }
    let kept = IntegratedResult {
        curve: part.clone(),
        quality: super::result::FitQuality {
            max_deviation: dev.max,
            rms_deviation: dev.rms,
            fairness: f.fairness,
            max_span_fairness: f.max_span_fairness,
        },
        tolerance: tol,
        met: true,
        log_lambda: single.log_lambda,
        baseline_control_points: single.baseline_control_points,
        stats: Default::default(),
        screening: Default::default(),
        closure: Default::default(),
    };
    Ok((kept, true))
}

/// A piece's error, naming the piece (`k` of `n`) and, for a refused join condition, the join.
fn piece_error(e: Error, k: usize, n: usize) -> Error {
    match e {
        Error::InvalidSetting { option, reason } if option == "start" && k > 0 => {
            Error::Fit(format!(
                "chain piece {} (its join with piece {}): {reason}",
                k + 1,
                k
            ))
        }
        Error::InvalidSetting { option, reason } if option == "end" && k + 1 < n => {
            Error::Fit(format!(
                "chain piece {} (its join with piece {}): {reason}",
                k + 1,
                k + 2
            ))
        }
        Error::InvalidSetting { option, reason } => Error::InvalidSetting { option, reason },
        Error::Fit(m) => Error::Fit(format!("chain piece {}: {m}", k + 1)),
        other => other,
    }
}

/// Position, unit tangent and curvature vector of `c` at its start (`at_end` false) or end.
fn end_frame(c: &NurbsCurve, at_end: bool) -> (Vec3, Vec3, Vec3) {
    let (a, b) = c.domain();
    let d = c.derivatives(if at_end { b } else { a }, 2);
    let speed = d[1].norm();
    let k = d[1].cross(d[2]).cross(d[1]) / speed.powi(4);
    (d[0], d[1] / speed, k)
}

/// The join of `before`'s end and `after`'s start at the chosen `point`, measured.
fn measure_join(
    before: &NurbsCurve,
    after: &NurbsCurve,
    point: Vec3,
    a: &[Vec3],
    b: &[Vec3],
) -> ChainJoin {
    let (p0, t0, k0) = end_frame(before, true);
    let (p1, t1, k1) = end_frame(after, false);
    let sin = t0.cross(t1).norm();
    let cos = t0.dot(t1);
    let scale = k0.norm().max(k1.norm());
    ChainJoin {
        point,
        data_gap: (a[a.len() - 1] - b[0]).norm(),
        position_gap: (p0 - p1).norm(),
        tangent_angle: sin.atan2(cos),
        curvature_relative: if scale > 0.0 {
            (k0 - k1).norm() / scale
        } else {
            0.0
        },
        curvature: k0.norm(),
    }
}

/// Total length and `F` of the joined chain of `curves` (module doc): `L = Σ L_k`,
/// `F = L³ Σ E_k` with `E_k = ∫ (dκ/ds)² ds` over piece `k`.
pub fn chain_fairness<'a>(curves: impl IntoIterator<Item = &'a NurbsCurve>) -> (f64, f64) {
    let (mut length, mut energy) = (0.0, 0.0);
    for c in curves {
        let f = curve_fairness(c);
        length += f.length;
        energy += f.energy;
    }
    (length, length.powi(3) * energy)
}
