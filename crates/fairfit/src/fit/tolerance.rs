//! Tolerance-driven least-squares fitting: the fewest control points (found greedily) whose curve
//! stays within a tolerance of every point, measured orthogonally.
//!
//! Per piece of data (the whole curve, or the stretches between corners): start from one Bézier
//! segment (or `p + 1` periodic spans for a closed curve), fit with parameter correction, and while the
//! maximum orthogonal deviation exceeds the tolerance, split every knot span whose points miss it at
//! the median of its data parameters (so both halves keep data: Schoenberg–Whitney holds). A final pass
//! tries removing each interior knot and keeps the removal when the tolerance still holds. Pieces are
//! joined with knots of multiplicity `p` (C0 corners); a closed curve without corners is fitted
//! periodically (C^(p−1) at the seam).

use super::closure::{closure_at_tolerance, Closure};
use super::correction::{fit_corrected, CorrectedFit};
use super::deviation::{max_orthogonal_deviation, Deviation, Screen};
use super::end_constraints::{check_against_data, EndConstraints};
use super::hooks::{end_chord_index, end_hooks};
use super::knot_placement::{averaging_knots, curvature_adaptive_knots};
use super::lsq::{periodic_knots, LsqOptions, LsqSolver, SmoothingOrder};
use super::parameterize::{parameterize_into, Parameterization};
use super::shape::{looks_closed, DEFAULT_CORNER_ANGLE_DEG};
use crate::errors::{Error, Result};
use crate::fit::points::{bounding_box_extent, drop_consecutive_duplicates};
use crate::nurbs::scale::{normalising_factor, scaled_curve};
use crate::nurbs::{NurbsCurve, Vec3};
use std::time::Instant;

pub use crate::tolerance::Tolerance;

/// Parameter-correction rounds tried once when refinement gets stuck (no span left to split).
const RESCUE_ROUNDS: usize = 3;

/// Smoothings tried below the requested one (each a tenth of the previous) before `λ = 0`, when the
/// requested smoothing keeps the curve from reaching the tolerance.
pub const SMOOTHING_FALLBACK_TRIES: usize = 6;

/// Whether the data form a closed curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ClosedMode {
    /// Closed when the last point equals the first (see [`super::shape::looks_closed`]), or when the
    /// ends are a gap apart that the data continue smoothly through at the tolerance's scale
    /// ([`super::closure::closure_at_tolerance`]; not with end tangents or end conditions, which ask
    /// for ends).
    #[default]
    Auto,
    /// Always open.
    Open,
    /// Always closed (the closing chord from the last point to the first is part of the curve).
    Closed,
}

impl ClosedMode {
    /// How `points` are fitted under this mode. With [`ClosedMode::Auto`]: when `ends_asked` (end
    /// tangents or end conditions) only a repeated point closes them; otherwise
    /// [`closure_at_tolerance`] at the tolerance `tol()` (the points' units, computed only then)
    /// and the corner angle (the default one when corners are off).
    pub(crate) fn closure(
        self,
        points: &[Vec3],
        ends_asked: bool,
        tol: impl FnOnce() -> f64,
        corner_angle_deg: Option<f64>,
    ) -> Closure {
        match self {
            ClosedMode::Open => Closure::Open,
            ClosedMode::Closed => Closure::Closed,
            ClosedMode::Auto if ends_asked => {
                if looks_closed(points) {
                    Closure::Closed
                } else {
                    Closure::Open
                }
            }
            ClosedMode::Auto => closure_at_tolerance(
                points,
                tol(),
                corner_angle_deg.unwrap_or(DEFAULT_CORNER_ANGLE_DEG),
            ),
        }
    }
}

/// Options of [`fit_to_tolerance`].
#[derive(Clone, Debug, PartialEq)]
pub struct FitOptions {
    /// Degree `p` (default 3).
    pub degree: usize,
    /// Parameterisation (default centripetal).
    pub parameterization: Parameterization,
    /// Tolerance (default relative 1e-3).
    pub tolerance: Tolerance,
    /// Closed-curve handling.
    pub closed: ClosedMode,
    /// Corner threshold in degrees; `None` disables corner detection.
    pub corner_angle_deg: Option<f64>,
    /// Parameter-correction rounds per fit (default 0: on the benchmark airfoils, correcting inside the
    /// knot search gave more control points and wigglier curves, and it costs a projection per round).
    pub correction_rounds: usize,
    /// Scale-free smoothing `λ` (default 0; see [`super::lsq`]).
    pub smoothing: f64,
    /// Smoothing derivative order.
    pub smoothing_order: SmoothingOrder,
    /// Try removing knots once the tolerance is met (default true).
    pub knot_removal: bool,
    /// Upper bound on control points per piece; 0 means the number of points.
    pub max_control_points: usize,
    /// How knots are placed (default [`KnotRule::Refine`]).
    pub knot_rule: KnotRule,
    /// With [`KnotRule::Refine`] on open pieces, also try the curvature-adaptive rule below the refined
    /// count and keep it when it meets the tolerance with fewer control points (default true).
    pub try_adaptive: bool,
    /// Direction of the curve at the first point (open curves; the magnitude is taken from the data).
    pub start_tangent: Option<Vec3>,
    /// Direction of the curve at the last point (open curves).
    pub end_tangent: Option<Vec3>,
    /// G0/G1/G2 conditions at the data's ends (open curves; [`super::end_constraints`]): every
    /// least-squares solve holds them exactly (the fixed control points of
    /// [`LsqSolver::solve_constrained`]). Not together with `start_tangent`/`end_tangent`
    /// (a `tangent` condition says the same). Default: none.
    pub end_conditions: EndConstraints,
}

/// Knot placement of the tolerance search.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KnotRule {
    /// Start from one segment, split the spans whose points miss the tolerance at the median of their
    /// parameters, then remove knots that are not needed (the default: fewest control points).
    #[default]
    Refine,
    /// The symmetric averaging rule ([`super::knot_placement::averaging_knots`]) with the smallest
    /// control-point count found (by growth then bisection) that meets the tolerance.
    Averaging,
    /// Curvature-adaptive knots ([`super::knot_placement::curvature_adaptive_knots`]), count searched
    /// the same way. Closed periodic fits use equal cyclic index steps for both rules.
    Adaptive,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            degree: 3,
            parameterization: Parameterization::default(),
            tolerance: Tolerance::Relative(1e-3),
            closed: ClosedMode::Auto,
            corner_angle_deg: Some(DEFAULT_CORNER_ANGLE_DEG),
            correction_rounds: 0,
            smoothing: 0.0,
            smoothing_order: SmoothingOrder::Second,
            knot_removal: true,
            max_control_points: 0,
            knot_rule: KnotRule::Refine,
            try_adaptive: true,
            start_tangent: None,
            end_tangent: None,
            end_conditions: EndConstraints::default(),
        }
    }
}

/// The result of [`fit_to_tolerance`].
#[derive(Clone, Debug)]
pub struct FitResult {
    /// The fitted curve (domain `[0, 1]`).
    pub curve: NurbsCurve,
    /// The points as fitted (duplicates removed; a closed curve with corners starts at its first
    /// corner; the repeated closing point of closed data is dropped).
    pub points: Vec<Vec3>,
    /// Parameter of each of [`FitResult::points`] (its foot point on the curve).
    pub params: Vec<f64>,
    /// Orthogonal deviation of the points from the curve.
    pub deviation: Deviation,
    /// Number of control points (for a closed periodic curve, the distinct ones).
    pub n_control_points: usize,
    /// The absolute tolerance that was met.
    pub tolerance: f64,
    /// True when the curve is closed.
    pub closed: bool,
    /// The distance from the last point to the first when the data were closed across it
    /// ([`ClosedMode::Auto`], [`crate::fit::closure`]); `None` for open data, a repeated point or
    /// [`ClosedMode::Closed`].
    pub closed_by_gap: Option<f64>,
    /// Indices in [`FitResult::points`] of the corners kept as C0 knots.
    pub corners: Vec<usize>,
    /// Least-squares solves performed.
    pub solves: usize,
    /// Wall time of the fit, seconds.
    pub fit_seconds: f64,
    /// The smoothing `λ` of the returned fit: the requested one, or a smaller one when the requested
    /// smoothing pulled the curve away from the points (tenths of it, then 0; see
    /// [`SMOOTHING_FALLBACK_TRIES`]).
    pub smoothing_used: f64,
}

/// Fits a curve within a tolerance of `points` with few control points.
///
/// ```
/// use fairfit::fit::tolerance::{fit_to_tolerance, FitOptions, Tolerance};
/// use fairfit::Vec3;
/// let q: Vec<Vec3> = (0..100).map(|k| { let t = 1.5707963 * k as f64 / 99.0;
///     Vec3::new(t.cos(), 0.5 * t.sin(), 0.0) }).collect();
/// let opts = FitOptions { tolerance: Tolerance::Absolute(1e-4), ..Default::default() };
/// let r = fit_to_tolerance(&q, &opts).unwrap();
/// assert!(r.deviation.max <= 1e-4);
/// assert!(r.n_control_points <= 10);
/// ```
///
/// When the smoothing keeps the tolerance out of reach, it is lowered by factors of 10 (at most
/// [`SMOOTHING_FALLBACK_TRIES`] times, then 0) until it is met; [`FitResult::smoothing_used`] says
/// which was used. The error of the unsmoothed fit is returned when even that misses.
pub fn fit_to_tolerance(points: &[Vec3], opts: &FitOptions) -> Result<FitResult> {
    let start = Instant::now();
    let first = fit_smoothed_as_given(points, opts);
    if !(matches!(first, Err(Error::Fit(_))) && opts.smoothing > 0.0) {
        return first;
    }
    let mut o = opts.clone();
    let mut last = first;
    for k in 1..=SMOOTHING_FALLBACK_TRIES + 1 {
        o.smoothing = if k > SMOOTHING_FALLBACK_TRIES {
            0.0
        } else {
            opts.smoothing / 10f64.powi(k as i32)
        };
        last = fit_smoothed_as_given(points, &o);
        if !matches!(last, Err(Error::Fit(_))) {
            break;
        }
    }
    last.map(|mut r| {
        r.fit_seconds = start.elapsed().as_secs_f64();
        r
    })
}

/// [`fit_to_tolerance`] at the requested smoothing.
fn fit_smoothed_as_given(points: &[Vec3], opts: &FitOptions) -> Result<FitResult> {
    // far from unit size (beyond 2^±64) chord lengths and squared distances overflow or underflow:
    // fit an exactly rescaled copy (a power of two) and scale the result back
    let f = normalising_factor(points);
    if f == 1.0 {
        return fit_at_scale(points, opts);
    }
    let start = Instant::now();
    let scaled: Vec<Vec3> = points.iter().map(|&q| q * f).collect();
    let mut o = opts.clone();
    if let Tolerance::Absolute(t) = o.tolerance {
        o.tolerance = Tolerance::Absolute(t * f);
    }
    o.end_conditions = o.end_conditions.normalized(Vec3::ZERO, 1.0 / f);
    let mut r = fit_at_scale(&scaled, &o)?;
    let back = 1.0 / f;
    r.curve = scaled_curve(&r.curve, back)?;
    for q in &mut r.points {
        *q = *q * back;
    }
    r.deviation.max *= back;
    r.deviation.rms *= back;
    for d in &mut r.deviation.per_point {
        *d *= back;
    }
    r.tolerance *= back;
    r.fit_seconds = start.elapsed().as_secs_f64();
    Ok(r)
}

/// [`fit_to_tolerance`] on points of moderate size.
fn fit_at_scale(points: &[Vec3], opts: &FitOptions) -> Result<FitResult> {
    let start = Instant::now();
    let p = opts.degree;
    if p == 0 || p > 15 {
        return Err(Error::InvalidDegree {
            degree: p,
            reason: "the degree must be between 1 and 15".into(),
        });
    }
    if let Some(i) = points.iter().position(|q| !q.is_finite()) {
        return Err(Error::InvalidData(format!("point {i} is not finite")));
    }
    let (mut pts, _) = drop_consecutive_duplicates(points);
    let extent = bounding_box_extent(&pts);
    if pts.len() < 2 || extent <= 0.0 {
        return Err(Error::InvalidData(
            "all points coincide: nothing to fit".into(),
        ));
    }
    let tol = match opts.tolerance {
        Tolerance::Absolute(t) => t,
        Tolerance::Relative(r) => r * extent,
    };
    if tol.is_nan() || tol <= 0.0 || tol.is_infinite() {
        return Err(Error::InvalidOption(format!(
            "the tolerance must be positive and finite, got {tol}"
        )));
    }
    let closure = closure_of(&pts, opts, tol);
    let closed = closure.is_closed();
    if closed && looks_closed(&pts) {
        pts.pop();
    }
    if closed && (opts.start_tangent.is_some() || opts.end_tangent.is_some()) {
        return Err(Error::InvalidOption(
            "end tangents apply to open curves only (these points form a closed curve)".into(),
        ));
    }
    if !opts.end_conditions.is_none() {
        opts.end_conditions.validate()?;
        if closed {
            return Err(Error::InvalidOption(
                "end conditions apply to open curves only (these points form a closed curve)"
                    .into(),
            ));
        }
        if opts.start_tangent.is_some() || opts.end_tangent.is_some() {
            return Err(Error::InvalidOption(
                "end conditions and end tangents together: give the tangent as a condition".into(),
            ));
        }
        check_against_data(&opts.end_conditions, &pts, tol)?;
    }
    if let Some(t) = opts
        .start_tangent
        .iter()
        .chain(&opts.end_tangent)
        .find(|t| !(t.is_finite() && t.norm() > 0.0))
    {
        return Err(Error::InvalidOption(format!(
            "an end tangent must be a finite non-zero vector, got {t:?}"
        )));
    }
    let needed = if closed { p + 2 } else { p + 1 };
    if pts.len() < needed {
        return Err(Error::InvalidData(format!(
            "a{} curve of degree {p} needs at least {needed} distinct points, got {}",
            if closed { " closed" } else { "n open" },
            pts.len()
        )));
    }
    let corners = match opts.corner_angle_deg {
        Some(a) => super::corners::corners_at_tolerance(&pts, closed, a, tol),
        None => Vec::new(),
    };
    let mut ctx = Ctx {
        solver: LsqSolver::new(p),
        opts,
        tol,
        ends: (None, None),
        conditions: None,
        planar: pts.iter().all(|q| q[2] == 0.0),
        pinned: (false, false),
        solves: 0,
    };
    let (curve, seq, params, corners_out, n_ctrl) = if closed && corners.is_empty() {
        let f = ctx.fit_piece(&pts, true, (false, false))?;
        let n = f.curve.n_control_points() - p;
        (f.curve, pts, f.params, Vec::new(), n)
    } else {
        // a sequence that starts and ends at corners (closed) or at the data ends (open)
        let (seq, cuts) = if closed {
            let c0 = corners[0];
            let mut seq: Vec<Vec3> = pts[c0..].iter().chain(&pts[..c0]).copied().collect();
            seq.push(pts[c0]);
            let mut cuts: Vec<usize> = corners.iter().map(|&c| c - c0).collect();
            cuts.push(seq.len() - 1);
            (seq, cuts)
        } else {
            let mut cuts = vec![0];
            cuts.extend(&corners);
            cuts.push(pts.len() - 1);
            (pts.clone(), cuts)
        };
        let mut pieces = Vec::with_capacity(cuts.len() - 1);
        let last = cuts.len() - 2;
        for (i, w) in cuts.windows(2).enumerate() {
            let ends = (!closed && i == 0, !closed && i == last);
            pieces.push(ctx.fit_piece(&seq[w[0]..=w[1]], false, ends)?);
        }
        let lengths: Vec<f64> = cuts
            .windows(2)
            .map(|w| {
                seq[w[0]..=w[1]]
                    .windows(2)
                    .map(|s| (s[1] - s[0]).norm())
                    .sum()
            })
            .collect();
        let (curve, params) = join_pieces(&pieces, &lengths, p)?;
        let inner: Vec<usize> = cuts[1..cuts.len() - 1].to_vec();
        let mut corners_out = if closed { vec![0] } else { Vec::new() };
        corners_out.extend(inner);
        let n = curve.n_control_points();
        (curve, seq, params, corners_out, n)
    };
    let deviation = max_orthogonal_deviation(&curve, &seq, &params);
    Ok(FitResult {
        params: deviation.params.clone(),
        curve,
        points: seq,
        deviation,
        n_control_points: n_ctrl,
        tolerance: tol,
        closed,
        closed_by_gap: closure.gap(),
        corners: corners_out,
        solves: ctx.solves,
        fit_seconds: start.elapsed().as_secs_f64(),
        smoothing_used: opts.smoothing,
    })
}

/// How the distinct points `pts` are fitted under `opts` at the absolute tolerance `tol`
/// ([`ClosedMode::closure`]; end tangents or conditions ask for ends).
fn closure_of(pts: &[Vec3], opts: &FitOptions, tol: f64) -> Closure {
    let wants_ends = opts.start_tangent.is_some()
        || opts.end_tangent.is_some()
        || !opts.end_conditions.is_none();
    opts.closed
        .closure(pts, wants_ends, || tol, opts.corner_angle_deg)
}

struct Ctx<'a> {
    solver: LsqSolver,
    opts: &'a FitOptions,
    tol: f64,
    /// end derivatives of the piece being fitted
    ends: (Option<Vec3>, Option<Vec3>),
    /// end conditions of the piece being fitted (`FitOptions::end_conditions` at its data ends)
    conditions: Option<EndConstraints>,
    /// the data lie in the xy plane (signed curvature conditions)
    planar: bool,
    /// ends of the piece whose derivative is pinned to the data's direction (after a hook there)
    pinned: (bool, bool),
    solves: usize,
}

/// The first breakpoints of an open piece under end conditions `c`: one Bézier segment has
/// `p + 1` control points, fewer than conditions at both ends may fix (G2 + G2 fix 6), so interior
/// breaks at data-parameter quantiles are added until one control point is left free.
fn conditioned_breaks(breaks: &mut Vec<f64>, params: &[f64], c: &EndConstraints, p: usize) {
    let (lo, hi) = c.fixed_points();
    let need = lo + hi + 1;
    if need <= p + 1 || params.len() < 3 {
        return;
    }
    let k = need - p - 1;
    let m = params.len() - 1;
    let mut b = vec![0.0];
    for j in 1..=k {
        let u = params[(m * j / (k + 1)).clamp(1, m - 1)];
        if u > b[b.len() - 1] && u < 1.0 {
            b.push(u);
        }
    }
    b.push(1.0);
    *breaks = b;
}

/// Knot vector from distinct breakpoints `0 = b_0 < … < b_k = 1`.
fn knots_from_breaks(breaks: &[f64], p: usize, closed: bool) -> Vec<f64> {
    if closed {
        return periodic_knots(breaks, p);
    }
    let mut k = Vec::with_capacity(breaks.len() + 2 * p);
    k.extend(std::iter::repeat_n(breaks[0], p + 1));
    k.extend_from_slice(&breaks[1..breaks.len() - 1]);
    k.extend(std::iter::repeat_n(breaks[breaks.len() - 1], p + 1));
    k
}

impl Ctx<'_> {
    /// The fewest control points the piece's end conditions leave room for (one free).
    fn conditioned_min(&self) -> usize {
        self.conditions.map_or(0, |c| {
            let (lo, hi) = c.fixed_points();
            lo + hi + 1
        })
    }

    fn fit(
        &mut self,
        pts: &[Vec3],
        params: &[f64],
        breaks: &[f64],
        lsq: &LsqOptions,
    ) -> Result<CorrectedFit> {
        let rounds = self.opts.correction_rounds;
        self.fit_rounds(pts, params, breaks, lsq, rounds, Screen::SpanMiss)
    }

    fn fit_rounds(
        &mut self,
        pts: &[Vec3],
        params: &[f64],
        breaks: &[f64],
        lsq: &LsqOptions,
        rounds: usize,
        screen: Screen,
    ) -> Result<CorrectedFit> {
        let knots = knots_from_breaks(breaks, self.opts.degree, lsq.closed);
        let f = fit_corrected(
            &mut self.solver,
            pts,
            params,
            &knots,
            lsq,
            self.ends,
            self.conditions.as_ref().map(|c| (c, self.planar)),
            rounds,
            self.tol,
            screen,
        );
        self.solves += 1 + f.as_ref().map(|f| f.rounds_kept).unwrap_or(0);
        f
    }

    /// Fits one piece on `[0, 1]`; `at_ends` says whether it starts / ends where the data do (the end
    /// tangents apply there). When the requested parameterisation fails (a degenerate parameter
    /// sequence, or the tolerance cannot be reached with it), the others are tried in the order
    /// centripetal, chord length, uniform, and the first success is kept.
    fn fit_piece(
        &mut self,
        pts: &[Vec3],
        closed: bool,
        at_ends: (bool, bool),
    ) -> Result<CorrectedFit> {
        self.pinned = (false, false);
        let (first, method) = self.fit_piece_any(pts, closed, at_ends);
        let f = first?;
        // end conditions are held as asked (a tangent against the data was refused up front)
        if closed || pts.len() < self.opts.degree + 1 || self.conditions.is_some() {
            return Ok(f);
        }
        // an end derivative pointing against the data is a hook (a near-cusp folded inside the
        // tolerance, F ~ 1e15 and up): refit with that end's direction pinned to the data's
        let user = (
            at_ends.0 && self.opts.start_tangent.is_some(),
            at_ends.1 && self.opts.end_tangent.is_some(),
        );
        let mut best = f;
        let mut pinned = (false, false);
        // a pinned refit can show a hook at the other end: pin that one too (at most twice)
        for _ in 0..2 {
            let hooks = end_hooks(&best.curve, pts, &best.params, self.tol);
            let pin = (
                pinned.0 || (hooks.0 && !user.0),
                pinned.1 || (hooks.1 && !user.1),
            );
            if pin == pinned {
                break;
            }
            self.pinned = pin;
            let again = self.fit_piece_with(pts, closed, at_ends, method);
            self.pinned = (false, false);
            match again {
                Ok(g) => {
                    best = g;
                    pinned = pin;
                }
                Err(_) => break,
            }
        }
        Ok(best)
    }

    /// [`Self::fit_piece`] without the hook check; also returns the parameterisation used.
    fn fit_piece_any(
        &mut self,
        pts: &[Vec3],
        closed: bool,
        at_ends: (bool, bool),
    ) -> (Result<CorrectedFit>, Parameterization) {
        let asked = self.opts.parameterization;
        let first = self.fit_piece_with(pts, closed, at_ends, asked);
        if first.is_ok() {
            return (first, asked);
        }
        for alt in [
            Parameterization::Centripetal,
            Parameterization::ChordLength,
            Parameterization::Uniform,
        ] {
            if alt != asked {
                if let Ok(f) = self.fit_piece_with(pts, closed, at_ends, alt) {
                    return (Ok(f), alt);
                }
            }
        }
        (first, asked)
    }

    fn fit_piece_with(
        &mut self,
        pts: &[Vec3],
        closed: bool,
        at_ends: (bool, bool),
        method: Parameterization,
    ) -> Result<CorrectedFit> {
        let p = self.opts.degree;
        let mut params = Vec::with_capacity(pts.len());
        parameterize_into(pts, method, closed, &mut params)?;
        self.conditions = Some(self.opts.end_conditions.at_ends(at_ends)).filter(|c| !c.is_none());
        // a direction scaled to the data's speed dQ/dū at that end
        let m = pts.len() - 1;
        let speed = |a: usize, b: usize| (pts[b] - pts[a]).norm() / (params[b] - params[a]).abs();
        let scaled = |t: Vec3, s: f64| t * (s / t.norm());
        self.ends = (
            self.opts
                .start_tangent
                .filter(|_| at_ends.0 && m >= 1)
                .map(|t| scaled(t, speed(0, 1))),
            self.opts
                .end_tangent
                .filter(|_| at_ends.1 && m >= 1)
                .map(|t| scaled(t, speed(m - 1, m))),
        );
        // a pinned end takes the direction and the speed of the chord above the noise: the first
        // segment's speed can be far lower (centripetal steps shrink only as √ of a short segment), and
        // a slow pinned end folds a curvature spike into its first span (rae2822 at smoothing 1e-8:
        // 0.14 of the chord's speed, F_j of the end spans ~1e7 times the others')
        if self.pinned.0 && self.ends.0.is_none() {
            let k = end_chord_index(pts, false, self.tol);
            self.ends.0 = Some(scaled(pts[k] - pts[0], speed(0, k)));
        }
        if self.pinned.1 && self.ends.1.is_none() {
            let k = end_chord_index(pts, true, self.tol);
            self.ends.1 = Some(scaled(pts[m] - pts[k], speed(k, m)));
        }
        let mut lsq = LsqOptions {
            smoothing: self.opts.smoothing,
            smoothing_order: self.opts.smoothing_order,
            end_tangents: None,
            closed,
        };
        if !closed && pts.len() < p + 1 {
            // a short stretch between corners: one Bézier segment, regularised toward a line
            lsq.smoothing = lsq.smoothing.max(1e-8);
            lsq.smoothing_order = SmoothingOrder::Second;
            self.ends = (None, None);
            return self.fit(pts, &params, &[0.0, 1.0], &lsq);
        }
        if self.opts.knot_rule != KnotRule::Refine {
            return self.fit_by_rule(pts, &params, &lsq, closed);
        }
        let mut breaks = if closed {
            initial_periodic_breaks(&params, p + 1)
        } else {
            vec![0.0, 1.0]
        };
        if let Some(c) = &self.conditions {
            conditioned_breaks(&mut breaks, &params, c, p);
        }
        let max_ctrl = match self.opts.max_control_points {
            0 => pts.len(),
            m => m.min(pts.len()),
        };
        let ctrl_count = |b: &[f64]| if closed { b.len() - 1 } else { b.len() + p - 1 };
        let first_params = params.clone();
        let mut best = self.fit(pts, &params, &breaks, &lsq)?;
        let mut rescued = false;
        while best.deviation.max > self.tol {
            params.clone_from(&best.params);
            let mut trial = breaks.clone();
            let added = split_bad_spans(&mut trial, &best.deviation.per_point, &params, self.tol);
            if added == 0 || ctrl_count(&trial) > max_ctrl {
                if !rescued {
                    // stuck with these parameters: correct them (project the points onto the curve
                    // and refit) on the current knots, then carry on refining with the feet
                    rescued = true;
                    let rounds = self.opts.correction_rounds.max(RESCUE_ROUNDS);
                    best = self.fit_rounds(pts, &params, &breaks, &lsq, rounds, Screen::All)?;
                    continue;
                }
                // with smoothing, more knots do not bring the curve closer: say which knob to turn
                let why = if lsq.smoothing > 0.0 {
                    format!(
                        "the smoothing {:e} pulls the curve away from the points; lower --smoothing \
                         (e.g. {:e}) or raise the tolerance",
                        lsq.smoothing,
                        lsq.smoothing / 10.0
                    )
                } else {
                    "too few points per knot span to refine further; noisy data need a larger \
                     tolerance"
                        .to_string()
                };
                return Err(Error::Fit(format!(
                    "tolerance {:.3e} not reached: max deviation {:.3e} with {} control points ({why})",
                    self.tol,
                    best.deviation.max,
                    best.curve.n_control_points()
                )));
            }
            breaks = trial;
            best = self.fit(pts, &params, &breaks, &lsq)?;
        }
        if self.opts.knot_removal {
            self.remove_knots(pts, &mut breaks, &mut best, &lsq, closed);
        }
        if !closed && self.opts.try_adaptive {
            // the adaptive rule beats refinement on some curves (naca4412: 14 vs 17): keep it when it
            // needs fewer control points
            let upper = best.curve.n_control_points();
            if let Some(f) = self.adaptive_below(pts, &first_params, &lsq, upper) {
                best = f;
            }
        }
        Ok(best)
    }
}

impl Ctx<'_> {
    /// Breakpoints of the knot rule for `n` control points (distinct ones when closed).
    fn rule_breaks(
        &self,
        pts: &[Vec3],
        params: &[f64],
        n: usize,
        closed: bool,
        rule: KnotRule,
    ) -> Result<Vec<f64>> {
        let p = self.opts.degree;
        if closed {
            return Ok(initial_periodic_breaks(params, n));
        }
        let knots = match rule {
            KnotRule::Adaptive => curvature_adaptive_knots(pts, params, p, n, 0.5, 0.5)?,
            _ => averaging_knots(params, p, n)?,
        };
        Ok(knots[p..knots.len() - p].to_vec())
    }

    /// The fit with `n` control points placed by `rule`, if it meets the tolerance.
    fn rule_fit(
        &mut self,
        pts: &[Vec3],
        params: &[f64],
        lsq: &LsqOptions,
        n: usize,
        closed: bool,
        rule: KnotRule,
    ) -> Option<CorrectedFit> {
        let breaks = self.rule_breaks(pts, params, n, closed, rule).ok()?;
        self.fit(pts, params, &breaks, lsq)
            .ok()
            .filter(|f| f.deviation.max <= self.tol)
    }

    /// The smallest control-point count (growth by half, then bisection) whose rule knots meet the
    /// tolerance.
    fn fit_by_rule(
        &mut self,
        pts: &[Vec3],
        params: &[f64],
        lsq: &LsqOptions,
        closed: bool,
    ) -> Result<CorrectedFit> {
        let p = self.opts.degree;
        let max_n = match self.opts.max_control_points {
            0 => pts.len(),
            m => m.min(pts.len()),
        };
        let min_n =
            (p + 1 + usize::from(self.ends.0.is_some()) + usize::from(self.ends.1.is_some()))
                .max(self.conditioned_min());
        let rule = self.opts.knot_rule;
        let try_n = |ctx: &mut Self, n: usize| ctx.rule_fit(pts, params, lsq, n, closed, rule);
        let (mut fail, mut n) = (min_n.saturating_sub(1), min_n.min(max_n));
        let mut pass = None;
        let mut last_err = None;
        while n <= max_n {
            if let Some(f) = try_n(self, n) {
                pass = Some((n, f));
                break;
            }
            last_err = Some(n);
            fail = n;
            if n == max_n {
                break;
            }
            n = (n + n.div_ceil(2)).min(max_n);
        }
        let Some((good, best)) = pass else {
            return Err(Error::Fit(format!(
                "tolerance {:.3e} not reached with {} control points placed by the {:?} knot rule",
                self.tol,
                last_err.unwrap_or(max_n),
                self.opts.knot_rule
            )));
        };
        Ok(bisect_fewest(self, fail, good, best, try_n))
    }

    /// The curvature-adaptive rule's fit with the fewest control points below `upper` (the refine
    /// rule's count) that meets the tolerance, or `None`. One trial at `upper - 1` decides whether
    /// to search at all (bisection below it), so this costs one solve when refine wins.
    fn adaptive_below(
        &mut self,
        pts: &[Vec3],
        params: &[f64],
        lsq: &LsqOptions,
        upper: usize,
    ) -> Option<CorrectedFit> {
        let p = self.opts.degree;
        let min_n =
            (p + 1 + usize::from(self.ends.0.is_some()) + usize::from(self.ends.1.is_some()))
                .max(self.conditioned_min());
        let try_n =
            |ctx: &mut Self, n: usize| ctx.rule_fit(pts, params, lsq, n, false, KnotRule::Adaptive);
        if upper <= min_n {
            return None;
        }
        let good = upper - 1;
        let best = try_n(self, good)?;
        let fail = min_n - 1;
        Some(bisect_fewest(self, fail, good, best, try_n))
    }

    /// Knot removal from both ends inward, pairwise (outermost left with outermost right, ...), so that
    /// reversed data make the same decisions mirrored: a pair goes when both can go; otherwise the one
    /// whose removal leaves the smaller deviation goes if it keeps the tolerance.
    fn remove_knots(
        &mut self,
        pts: &[Vec3],
        breaks: &mut Vec<f64>,
        best: &mut CorrectedFit,
        lsq: &LsqOptions,
        closed: bool,
    ) {
        let min_breaks = if closed { self.opts.degree + 2 } else { 2 };
        let (mut lo, mut hi) = (1usize, breaks.len().saturating_sub(2));
        // knot sets already found to miss: the pairwise walk meets some twice (without correction
        // rounds the parameters stay those of `best`, so a miss stays a miss)
        let mut missed: Vec<Vec<f64>> = Vec::new();
        let rounds = self.opts.correction_rounds;
        while lo <= hi && hi + 1 < breaks.len() && lo >= 1 {
            let mut try_remove = |ctx: &mut Self,
                                  idx: &[usize]|
             -> Option<(Vec<f64>, CorrectedFit)> {
                if breaks.len() - idx.len() < min_breaks {
                    return None;
                }
                let mut trial = Vec::with_capacity(breaks.len());
                trial.extend(
                    breaks
                        .iter()
                        .enumerate()
                        .filter(|(i, _)| !idx.contains(i))
                        .map(|(_, &b)| b),
                );
                if missed.contains(&trial) {
                    return None;
                }
                match ctx.fit_rounds(pts, &best.params, &trial, lsq, rounds, Screen::FirstMiss) {
                    Ok(f) if f.deviation.max <= ctx.tol => Some((trial, f)),
                    _ => {
                        if rounds == 0 {
                            missed.push(trial);
                        }
                        None
                    }
                }
            };
            if lo == hi {
                if let Some((t, f)) = try_remove(self, &[lo]) {
                    *breaks = t;
                    *best = f;
                }
                break;
            }
            if let Some((t, f)) = try_remove(self, &[lo, hi]) {
                *breaks = t;
                *best = f;
                hi -= 2;
                continue;
            }
            let left = try_remove(self, &[lo]);
            let right = try_remove(self, &[hi]);
            match (left, right) {
                (Some(l), Some(r)) if l.1.deviation.max <= r.1.deviation.max => {
                    (*breaks, *best) = l;
                    hi -= 1;
                }
                (_, Some(r)) => {
                    (*breaks, *best) = r;
                    hi -= 1;
                }
                (Some(l), None) => {
                    (*breaks, *best) = l;
                    hi -= 1;
                }
                (None, None) => {
                    lo += 1;
                    hi -= 1;
                }
            }
        }
    }
}

/// Bisection for the fewest control points: `fail` control points miss the tolerance, `good` meet it
/// with the fit `best`; `try_n` fits `n` and returns it when it meets the tolerance. Returns the fit at
/// the smallest count found.
fn bisect_fewest<C, T>(
    ctx: &mut C,
    mut fail: usize,
    mut good: usize,
    mut best: T,
    mut try_n: impl FnMut(&mut C, usize) -> Option<T>,
) -> T {
    while good - fail > 1 {
        let mid = fail + (good - fail) / 2;
        match try_n(ctx, mid) {
            Some(f) => {
                good = mid;
                best = f;
            }
            None => fail = mid,
        }
    }
    best
}

/// `count` periodic spans at equal steps of the cyclic data index.
fn initial_periodic_breaks(params: &[f64], count: usize) -> Vec<f64> {
    let m = params.len();
    let mut b = Vec::with_capacity(count + 1);
    b.push(0.0);
    for j in 1..count {
        let t = (j * m) as f64 / count as f64;
        let i = t.floor() as usize;
        let a = t - i as f64;
        let next = if i + 1 < m { params[i + 1] } else { 1.0 };
        b.push((1.0 - a) * params[i] + a * next);
    }
    b.push(1.0);
    b
}

/// Splits every span whose points exceed `tol` at the median of its parameters; returns the number of
/// knots added. A bad span holding fewer than two parameters cannot be split with data on both sides:
/// its neighbours are split instead (on both sides, which keeps reversal symmetric), giving the basis
/// more freedom there. This is what lets noisy data with a sharp leading edge reach the tolerance.
fn split_bad_spans(breaks: &mut Vec<f64>, err: &[f64], params: &[f64], tol: f64) -> usize {
    let nspan = breaks.len() - 1;
    let span_of = |u: f64| -> usize {
        match breaks.binary_search_by(|b| b.total_cmp(&u)) {
            Ok(i) => i.min(nspan - 1),
            Err(i) => i.saturating_sub(1).min(nspan - 1),
        }
    };
    let mut bad = vec![false; nspan];
    for (e, &u) in err.iter().zip(params) {
        if *e > tol {
            let s = span_of(u);
            bad[s] = true;
            // a point exactly on a knot belongs to both spans (keeps reversal symmetric)
            if s > 0 && u == breaks[s] {
                bad[s - 1] = true;
            }
        }
    }
    // parameters of each span, both ends included (a point on a knot counts for both spans, which
    // keeps reversal symmetric)
    let mut inside: Vec<Vec<f64>> = vec![Vec::new(); nspan];
    for &u in params {
        let s = span_of(u);
        inside[s].push(u);
        if s > 0 && u == breaks[s] {
            inside[s - 1].push(u);
        }
    }
    let split_at = |s: usize, us: &mut Vec<f64>| -> Option<f64> {
        if us.len() < 2 {
            return None;
        }
        us.sort_by(f64::total_cmp);
        // the median, placed symmetrically: reversed data split at the mirrored value
        let c = us.len();
        let h = c / 2;
        let (k, lo, hi) = if c % 2 == 0 {
            (0.5 * (us[h - 1] + us[h]), us[h - 1], us[h])
        } else {
            (
                0.25 * (us[h - 1] + 2.0 * us[h] + us[h + 1]),
                us[h - 1],
                us[h + 1],
            )
        };
        (k > lo && k < hi && k > breaks[s] && k < breaks[s + 1]).then_some(k)
    };
    let mut want = vec![false; nspan];
    let mut new_knots = Vec::new();
    for s in 0..nspan {
        if !bad[s] {
            continue;
        }
        if let Some(k) = split_at(s, &mut inside[s]) {
            want[s] = true;
            new_knots.push(k);
        }
    }
    // unsplittable bad spans: split their neighbours
    for s in 0..nspan {
        if !bad[s] || want[s] {
            continue;
        }
        for t in [s.wrapping_sub(1), s + 1] {
            if t < nspan && !want[t] {
                if let Some(k) = split_at(t, &mut inside[t]) {
                    want[t] = true;
                    new_knots.push(k);
                }
            }
        }
    }
    let added = new_knots.len();
    breaks.extend(new_knots);
    breaks.sort_by(f64::total_cmp);
    added
}

/// Joins open pieces (each on `[0, 1]`, clamped, sharing end points) into one curve with knots of
/// multiplicity `p` at the joins; piece `i` gets a share of `[0, 1]` proportional to `lengths[i]`.
fn join_pieces(
    pieces: &[CorrectedFit],
    lengths: &[f64],
    p: usize,
) -> Result<(NurbsCurve, Vec<f64>)> {
    let total: f64 = lengths.iter().sum();
    let mut a = vec![0.0];
    let mut acc = 0.0;
    for l in lengths {
        acc += l;
        a.push(acc / total);
    }
    let last = a.len() - 1;
    a[last] = 1.0;
    let mut knots = vec![0.0; p + 1];
    let mut ctrl: Vec<Vec3> = Vec::new();
    let mut params: Vec<f64> = Vec::new();
    for (i, f) in pieces.iter().enumerate() {
        let (lo, hi) = (a[i], a[i + 1]);
        let k = f.curve.knots();
        let cps = f.curve.control_points();
        let skip = usize::from(i > 0);
        ctrl.extend_from_slice(&cps[skip..]);
        knots.extend(k[p + 1..k.len() - p - 1].iter().map(|u| lo + (hi - lo) * u));
        if i + 1 < pieces.len() {
            knots.extend(std::iter::repeat_n(hi, p));
        }
        params.extend(f.params[skip..].iter().map(|u| lo + (hi - lo) * u));
    }
    knots.extend(std::iter::repeat_n(1.0, p + 1));
    Ok((NurbsCurve::bspline(p, knots, ctrl)?, params))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(name: &str) -> Vec<Vec3> {
        let p = format!("{}/../../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
        crate::io::read_points(p).unwrap().points
    }

    /// Largest distance from `q` to the polyline through `n + 1` equally spaced curve points.
    fn polyline_distance(c: &NurbsCurve, q: &[Vec3], n: usize) -> f64 {
        let us: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
        let poly = c.points(&us);
        q.iter()
            .map(|&p| {
                poly.windows(2)
                    .map(|w| {
                        let d = w[1] - w[0];
                        let t = ((p - w[0]).dot(d) / d.norm_squared()).clamp(0.0, 1.0);
                        (w[0] + d * t - p).norm()
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn quarter_ellipse_meets_rel_tol_measured_by_global_projection() {
        let q = read("quarter_ellipse_200.csv");
        let r = fit_to_tolerance(&q, &FitOptions::default()).unwrap();
        let tol = 1e-3 * 1.0; // extent of the quarter ellipse is 1 (x from 0 to 1)
        assert!((r.tolerance - tol).abs() < 1e-12);
        // independent measure: dense global projection with a fresh projector
        let proj = crate::diffgeo::CurveProjector::new(&r.curve, 64);
        let worst = q
            .iter()
            .map(|&p| proj.project(p).distance)
            .fold(0.0, f64::max);
        assert!(worst <= tol, "{worst}");
        assert!(r.n_control_points <= 8, "{}", r.n_control_points);
    }

    #[test]
    fn reversed_input_gives_the_mirrored_curve() {
        let q = read("quarter_ellipse_200.csv");
        let rev: Vec<Vec3> = q.iter().rev().copied().collect();
        for knot_rule in [KnotRule::Refine, KnotRule::Averaging, KnotRule::Adaptive] {
            let opts = FitOptions {
                tolerance: Tolerance::Absolute(1e-5),
                knot_rule,
                ..Default::default()
            };
            let a = fit_to_tolerance(&q, &opts).unwrap();
            let b = fit_to_tolerance(&rev, &opts).unwrap();
            assert_eq!(a.n_control_points, b.n_control_points, "{knot_rule:?}");
            assert!(a.deviation.max <= 1e-5, "{knot_rule:?}");
            for (x, y) in a
                .curve
                .control_points()
                .iter()
                .zip(b.curve.control_points().iter().rev())
            {
                assert!((*x - *y).norm() < 1e-9, "{knot_rule:?}: {x:?} vs {y:?}");
            }
        }
    }

    #[test]
    fn closed_circle_is_periodic_with_matching_seam_derivatives() {
        let mut q: Vec<Vec3> = (0..100)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 100.0;
                Vec3::new(2.0 * a.cos(), 2.0 * a.sin(), 0.0)
            })
            .collect();
        q.push(q[0]);
        let r = fit_to_tolerance(&q, &FitOptions::default()).unwrap();
        assert!(r.closed && r.corners.is_empty());
        let d0 = r.curve.derivatives(0.0, 2);
        let d1 = r.curve.derivatives(1.0, 2);
        for j in 0..3 {
            assert!(
                (d0[j] - d1[j]).norm() <= 1e-10 * (1.0 + d0[j].norm()),
                "order {j}: {:?} vs {:?}",
                d0[j],
                d1[j]
            );
        }
        assert!(r.deviation.max <= 4e-3, "{}", r.deviation.max);
        // and the curve is round: radius 2 within the tolerance along a dense sampling
        for k in 0..400 {
            let p = r.curve.point(k as f64 / 400.0);
            assert!((p.norm() - 2.0).abs() <= 4e-3 + 1e-12);
        }
    }

    #[test]
    fn blunt_trailing_edge_keeps_its_corners_when_closed() {
        let q = read("fx77w343.csv");
        let opts = FitOptions {
            closed: ClosedMode::Closed,
            ..Default::default()
        };
        let r = fit_to_tolerance(&q, &opts).unwrap();
        let tol = r.tolerance;
        let worst = r
            .deviation
            .per_point
            .iter()
            .enumerate()
            .fold((0, 0.0), |a, (i, &e)| if e > a.1 { (i, e) } else { a });
        assert!(
            r.deviation.max <= tol,
            "{} > {tol} at {worst:?} of {}, corners {:?}",
            r.deviation.max,
            r.points.len(),
            r.corners
        );
        // two corners: the first and the last data points (the TE base is the closing chord)
        assert_eq!(r.corners.len(), 2, "{:?}", r.corners);
        let k = r.curve.knots();
        let p = 3;
        let c0_knots: Vec<f64> = k
            .iter()
            .enumerate()
            .filter(|&(i, &u)| {
                i > p
                    && i < k.len() - p - 1
                    && k[i - 1] != u
                    && crate::nurbs::knots::multiplicity(k, u) == p
            })
            .map(|(_, &u)| u)
            .collect();
        assert_eq!(
            c0_knots.len(),
            1,
            "one interior C0 knot besides the seam: {k:?}"
        );
        // the TE base between the two corners stays straight: no overshoot beyond tol
        let (a, b) = (q[q.len() - 1], q[0]);
        let u0 = c0_knots[0];
        for j in 0..=50 {
            let u = u0 + (1.0 - u0) * j as f64 / 50.0;
            let c = r.curve.point(u);
            let d = (c - a).cross(b - a).norm() / (b - a).norm();
            assert!(d <= tol, "{d} at u={u}");
            let t = (c - a).dot(b - a) / (b - a).norm_squared();
            assert!((-1e-9..=1.0 + 1e-9).contains(&t), "overshoot t={t}");
        }
    }

    #[test]
    fn open_airfoil_interpolates_its_trailing_edge_points() {
        let q = read("fx77w343.csv");
        let r = fit_to_tolerance(&q, &FitOptions::default()).unwrap();
        assert!(!r.closed);
        assert!((r.curve.point(0.0) - q[0]).norm() < 1e-14);
        assert!((r.curve.point(1.0) - q[q.len() - 1]).norm() < 1e-14);
        assert!(r.deviation.max <= r.tolerance);
    }

    #[test]
    fn noisy_sharp_leading_edge_meets_the_tolerance_with_any_correction_rounds() {
        // du84132v with noise 1e-4 chord: refinement used to get stuck at the leading edge ("too few
        // points per knot span") and correction rounds used to fold the curve (2e-2 deviation)
        let q = read("du84132v_noise1e-4.csv");
        for rounds in [0, 1, 2, 3] {
            let opts = FitOptions {
                correction_rounds: rounds,
                ..Default::default()
            };
            let r = fit_to_tolerance(&q, &opts).unwrap();
            assert!((r.tolerance - 1e-3).abs() < 1e-5, "{}", r.tolerance);
            // independent measure: distance to a dense polyline of the curve (chord error < 1e-8
            // here). The sampled projector is not used: at this thin trailing edge its best sample can
            // lie on the other surface (it reported 5.3e-3 for a point 6.5e-4 away).
            let worst = polyline_distance(&r.curve, &q, 100_000);
            assert!(
                worst <= r.tolerance * (1.0 + 1e-6),
                "rounds {rounds}: {worst}"
            );
            // the clean airfoil needs 15 (closed, sharp TE); noise must not blow the count up
            assert!(
                r.n_control_points <= 20,
                "rounds {rounds}: {}",
                r.n_control_points
            );
        }
    }

    #[test]
    fn collinear_points_fit_a_line_with_few_control_points() {
        let q: Vec<Vec3> = (0..30)
            .map(|k| Vec3::new(k as f64, 2.0 * k as f64, -1.0))
            .collect();
        let r = fit_to_tolerance(&q, &FitOptions::default()).unwrap();
        assert_eq!(r.n_control_points, 4);
        assert!(r.deviation.max < 1e-9);
    }

    #[test]
    fn too_much_smoothing_falls_back_to_a_tenth_until_the_tolerance_is_met() {
        let q = read("e387.csv");
        let at = |smoothing: f64, max_control_points: usize| FitOptions {
            smoothing,
            max_control_points,
            ..Default::default()
        };
        // as given, 1e-5 and 1e-6 miss the tolerance (docs/fit.md), 1e-7 meets it
        for l in [1e-5, 1e-6] {
            let e = fit_smoothed_as_given(&q, &at(l, 0))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("not reached") && e.contains("lower --smoothing"),
                "{e}"
            );
        }
        let direct = fit_smoothed_as_given(&q, &at(1e-7, 0)).unwrap();
        let r = fit_to_tolerance(&q, &at(1e-5, 0)).unwrap();
        assert_eq!(r.smoothing_used, 1e-5 / 100.0);
        assert!(r.deviation.max <= r.tolerance, "{}", r.deviation.max);
        assert_eq!(r.curve.control_points(), direct.curve.control_points());
        // a fit that meets the tolerance as asked keeps its smoothing
        assert_eq!(
            fit_to_tolerance(&q, &at(1e-8, 0)).unwrap().smoothing_used,
            1e-8
        );
        // 5 control points miss the tolerance even unsmoothed: the error stays
        let e = fit_to_tolerance(&q, &at(1e-5, 5)).unwrap_err().to_string();
        assert!(e.contains("not reached"), "{e}");
    }

    #[test]
    fn points_far_from_unit_size_fit_like_unit_points() {
        // at 2^500 and 2^-1000 (about 3e150 and 9e-302) chord lengths and squared distances would
        // overflow or underflow; scaled by an exact power of two the fit must be the same, scaled
        let unit: Vec<Vec3> = (0..60)
            .map(|i| {
                let t = i as f64 / 59.0;
                Vec3::new(t, 0.3 * (4.0 * t).sin() + 0.1 * t * t, 0.0)
            })
            .collect();
        let opts = FitOptions {
            tolerance: Tolerance::Relative(1e-3),
            ..FitOptions::default()
        };
        let base = fit_to_tolerance(&unit, &opts).unwrap();
        for e in [500, -1000] {
            let s = 2f64.powi(e);
            let pts: Vec<Vec3> = unit.iter().map(|&q| q * s).collect();
            let r = fit_to_tolerance(&pts, &opts).unwrap();
            assert_eq!(r.n_control_points, base.n_control_points, "2^{e}");
            assert_eq!(r.deviation.max, base.deviation.max * s, "2^{e}");
            assert_eq!(r.tolerance, base.tolerance * s, "2^{e}");
            for (a, b) in r
                .curve
                .control_points()
                .iter()
                .zip(base.curve.control_points())
            {
                assert_eq!(*a, *b * s, "2^{e}");
            }
            // an absolute tolerance scales with the data too
            let abs = FitOptions {
                tolerance: Tolerance::Absolute(base.tolerance * s),
                ..opts.clone()
            };
            let r = fit_to_tolerance(&pts, &abs).unwrap();
            assert_eq!(r.n_control_points, base.n_control_points, "2^{e} absolute");
        }
    }

    #[test]
    fn ill_posed_inputs_are_errors() {
        let two = [Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)];
        assert!(fit_to_tolerance(&two, &FitOptions::default())
            .unwrap_err()
            .to_string()
            .contains("at least 4"));
        let same = [Vec3::new(1.0, 1.0, 1.0); 10];
        assert!(fit_to_tolerance(&same, &FitOptions::default())
            .unwrap_err()
            .to_string()
            .contains("coincide"));
    }
}
