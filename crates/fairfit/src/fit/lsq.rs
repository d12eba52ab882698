//! Least-squares fitting of a curve with fixed knots and fixed weights (method reconstruction §6.1 and
//! §6.4): minimise `Σ_k |C(ū_k) − Q_k|² / (m + 1) + λ ∫ |C^(r)(u)|² du` over the control points, with
//! `r = 2` or `3`.
//!
//! - Open curves interpolate both end points (`P_0 = Q_0`, `P_n = Q_m`) and, optionally, given end
//!   derivatives, each on its own (which fix `P_1` and `P_{n−1}`).
//! - Closed curves use a periodic (unclamped) knot vector with the first `p` control points repeated at
//!   the end; every unknown is free and the seam is `C^(p−1)`.
//! - Rational curves: the basis is `R_i = N_i w_i / Σ_j N_j w_j`, still linear in the control points. The
//!   smoothing term uses the polynomial basis `N_i` (exact when all weights are 1).
//! - The normal equations `(NᵀN + λ' K) P = Nᵀ Q` are assembled straight from the `p + 1` non-zero basis
//!   values of each point into a band (an envelope for closed curves) and solved by Cholesky in O(n p²);
//!   `K` is exact by Gauss–Legendre with `p − r + 1` nodes inside each span.
//! - `λ` is scale-free: `λ' = λ (m + 1) D^{2r−1}` (`D` the domain length), so data term and smoothing term
//!   both scale like length², and `λ` means the same for any number of points and any domain.
//!
//! - Per-point weights and points to interpolate ([`LsqSolver::set_point_terms`], module
//!   `point_terms`): `Σ w_k² |C(ū_k) − Q_k|²` under `C(ū_k) = Q_k`, the equalities by the KKT
//!   system's Schur complement on the same factor.
//!
//! [`LsqSolver`] keeps every buffer, so a repeated solve of the same size allocates nothing.

mod point_terms;

use super::banded::EnvelopeCholesky;
use super::data_basis::DataBasis;
use super::end_constraints::{end_gaps, fixed_end, fixed_start, EndConstraints};
use crate::diffgeo::quadrature::GaussLegendre;
use crate::errors::{Error, Result};
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::knots::validate_knots;
use crate::nurbs::{NurbsCurve, Vec3};

/// Which derivative the smoothing term penalises.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SmoothingOrder {
    /// `∫|C''|²` (bending-like energy).
    #[default]
    Second,
    /// `∫|C'''|²` (penalises curvature variation more directly).
    Third,
}

impl SmoothingOrder {
    /// The derivative order `r`.
    pub fn order(self) -> usize {
        match self {
            SmoothingOrder::Second => 2,
            SmoothingOrder::Third => 3,
        }
    }
}

/// Options of one least-squares solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LsqOptions {
    /// `λ >= 0`, scale-free (see the module docs); 0 is plain least squares.
    pub smoothing: f64,
    /// The derivative order of the smoothing term.
    pub smoothing_order: SmoothingOrder,
    /// Derivatives `C'(a)` and `C'(b)` with respect to the curve parameter at the domain ends (open
    /// curves only).
    pub end_tangents: Option<(Vec3, Vec3)>,
    /// Periodic fit: the knot vector must be periodic (see [`periodic_knots`]) and the output holds the
    /// `n_u + p` control points whose last `p` repeat the first.
    pub closed: bool,
}

/// A least-squares solver for one degree, holding all working memory.
///
/// ```
/// use fairfit::fit::lsq::{LsqOptions, LsqSolver};
/// use fairfit::Vec3;
/// // points on the parabola y = x², fitted by a single cubic Bézier segment: exact
/// let q: Vec<Vec3> = (0..20).map(|k| { let x = k as f64 / 19.0; Vec3::new(x, x * x, 0.0) }).collect();
/// let u: Vec<f64> = (0..20).map(|k| k as f64 / 19.0).collect();
/// let knots = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
/// let mut solver = LsqSolver::new(3);
/// let mut ctrl = Vec::new();
/// solver.solve(&q, &u, &knots, None, &LsqOptions::default(), &mut ctrl).unwrap();
/// assert!((ctrl[1] - Vec3::new(1.0 / 3.0, 0.0, 0.0)).norm() < 1e-12);
/// assert!((ctrl[2] - Vec3::new(2.0 / 3.0, 1.0 / 3.0, 0.0)).norm() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct LsqSolver {
    degree: usize,
    mat: EnvelopeCholesky,
    rhs: Vec<Vec3>,
    /// basis values at the data parameters of the last solve
    basis: DataBasis,
    left: Vec<f64>,
    right: Vec<f64>,
    ndu: Vec<f64>,
    a: Vec<f64>,
    ders: Vec<f64>,
    /// Gauss–Legendre rules with 0..=p nodes (index = node count).
    gl: Vec<GaussLegendre>,
    /// The smoothing term's `r`-th basis derivatives at its Gauss nodes for `smooth_knots` (they
    /// depend on the knots only: a parameter correction solves again on the same knots).
    smooth: SmoothingDers,
    /// Per-point weights and points to interpolate ([`LsqSolver::set_point_terms`]).
    terms: point_terms::PointTerms,
}

/// `p + 1` values `N^(r)_{s−p+j}` per Gauss node of every non-empty span, in the order the
/// smoothing term visits them, for the knot vector `knots` and the order `r` (filled by the first
/// solve on these knots as it visits the nodes, read by the next ones).
#[derive(Clone, Debug, Default)]
struct SmoothingDers {
    knots: Vec<f64>,
    r: usize,
    ders: Vec<f64>,
}

/// The fixed control points of an open solve: `start` = `P_0, P_1, …`, `end` = `P_n, P_{n−1}, …`
/// (each at least one point).
#[derive(Clone, Copy)]
struct FixedEnds<'a> {
    start: &'a [Vec3],
    end: &'a [Vec3],
}

/// How control-point columns map to unknowns.
#[derive(Clone, Copy)]
struct Layout {
    n_ctrl: usize,
    closed: bool,
    /// open: first free column (the fixed points at the start); closed: number of unique points
    lo: usize,
    /// open: fixed columns at the end
    hi: usize,
    n_unknown: usize,
}

impl Layout {
    #[inline]
    fn unknown(&self, col: usize) -> Option<usize> {
        if self.closed {
            Some(col % self.lo)
        } else if col >= self.lo && col + self.hi < self.n_ctrl {
            Some(col - self.lo)
        } else {
            None
        }
    }
}

impl LsqSolver {
    /// A solver for curves of `degree`.
    pub fn new(degree: usize) -> Self {
        let p1 = degree + 1;
        let gl = (0..=degree.max(1)).map(GaussLegendre::new).collect();
        LsqSolver {
            degree,
            mat: EnvelopeCholesky::new(),
            rhs: Vec::new(),
            basis: DataBasis::new(),
            left: vec![0.0; p1],
            right: vec![0.0; p1],
            ndu: vec![0.0; p1 * p1],
            a: vec![0.0; 2 * p1],
            ders: vec![0.0; 4 * p1],
            gl,
            smooth: SmoothingDers::default(),
            terms: Default::default(),
        }
    }

    /// Holds per-point weights (`weights`, one per data point; empty: all 1) and the indices of
    /// the points to interpolate (`equal`) for every later solve, until set again: the data term
    /// becomes `Σ_k w_k² |C(ū_k) − Q_k|²` and the solve meets `C(ū_k) = Q_k` for `k ∈ equal`
    /// (KKT by the Schur complement, module `point_terms`). Both empty: the plain solve, bit for
    /// bit.
    pub fn set_point_terms(&mut self, weights: &[f64], equal: &[usize]) {
        let t = &mut self.terms;
        t.weights2.clear();
        t.weights2.extend(weights.iter().map(|w| w * w));
        t.equal.clear();
        t.equal.extend_from_slice(equal);
    }

    /// The degree this solver fits.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Fits control points for `knots` (and fixed `weights`, one per control point, if given) to
    /// `points` at parameters `params`, writing them to `ctrl_out` (`knots.len() − p − 1` points).
    pub fn solve(
        &mut self,
        points: &[Vec3],
        params: &[f64],
        knots: &[f64],
        weights: Option<&[f64]>,
        opts: &LsqOptions,
        ctrl_out: &mut Vec<Vec3>,
    ) -> Result<()> {
        let ends = opts.end_tangents.map(|(a, b)| (Some(a), Some(b)));
        self.solve_with_ends(
            points,
            params,
            knots,
            weights,
            opts,
            ends.unwrap_or((None, None)),
            ctrl_out,
        )
    }

    /// [`LsqSolver::solve`] with each end derivative optional on its own (`ends` = start, end);
    /// `opts.end_tangents` is ignored.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_with_ends(
        &mut self,
        points: &[Vec3],
        params: &[f64],
        knots: &[f64],
        weights: Option<&[f64]>,
        opts: &LsqOptions,
        ends: (Option<Vec3>, Option<Vec3>),
        ctrl_out: &mut Vec<Vec3>,
    ) -> Result<()> {
        if ends.0.iter().chain(ends.1.iter()).any(|d| !d.is_finite()) {
            return Err(Error::InvalidOption("end tangents must be finite".into()));
        }
        let p = self.degree;
        let (lo, hi) = (
            1 + usize::from(ends.0.is_some()),
            1 + usize::from(ends.1.is_some()),
        );
        let (mut start, mut end) = ([Vec3::ZERO; 3], [Vec3::ZERO; 3]);
        if let (Some(&q0), Some(&qm)) = (points.first(), points.last()) {
            start[0] = q0;
            end[0] = qm;
            if knots.len() >= 2 * (p + 1) {
                let n = knots.len() - p - 2;
                if let Some(d0) = ends.0 {
                    start[1] = q0 + d0 * ((knots[p + 1] - knots[1]) / p as f64);
                }
                if let Some(d1) = ends.1 {
                    end[1] = qm - d1 * ((knots[n + p] - knots[n]) / p as f64);
                }
            }
        }
        let fixed = FixedEnds {
            start: &start[..lo],
            end: &end[..hi],
        };
        self.solve_fixed(points, params, knots, weights, opts, fixed, ctrl_out)
    }

    /// [`LsqSolver::solve`] under the end conditions `ends`
    /// ([`crate::fit::end_constraints`]): the unconstrained solve on the same knots gives the legs,
    /// a second solve has the conditions' control points fixed. `planar`: the data lie in the xy
    /// plane (signed curvature). Without conditions, exactly [`LsqSolver::solve`] without end
    /// tangents.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_constrained(
        &mut self,
        points: &[Vec3],
        params: &[f64],
        knots: &[f64],
        weights: Option<&[f64]>,
        opts: &LsqOptions,
        ends: &EndConstraints,
        planar: bool,
        ctrl_out: &mut Vec<Vec3>,
    ) -> Result<()> {
        if ends.is_none() {
            return self.solve_with_ends(
                points,
                params,
                knots,
                weights,
                opts,
                (None, None),
                ctrl_out,
            );
        }
        let p = self.degree;
        let (Some(&q0), Some(&qm)) = (points.first(), points.last()) else {
            return Err(Error::InvalidData(
                "least squares needs at least 2 points, got 0".into(),
            ));
        };
        let n_ctrl = knots.len().saturating_sub(p + 1);
        ends.check_room(p, n_ctrl)?;
        let (Some(g0), Some(g1)) = (end_gaps(p, knots, false), end_gaps(p, knots, true)) else {
            return Err(Error::InvalidKnots(format!(
                "degree {p} needs at least {} knots",
                2 * (p + 1)
            )));
        };
        // the legs from the solve with the end points only (given or the data's)
        let start0 = [ends.start.point.unwrap_or(q0)];
        let end0 = [ends.end.point.unwrap_or(qm)];
        let plain = FixedEnds {
            start: &start0,
            end: &end0,
        };
        self.solve_fixed(points, params, knots, weights, opts, plain, ctrl_out)?;
        let (mut start, mut end) = ([Vec3::ZERO; 3], [Vec3::ZERO; 3]);
        let backwards = |option| Error::InvalidSetting {
            option,
            reason: "the tangent points backwards from the data's direction at that end".into(),
        };
        let lo = fixed_start(&ends.start, p, g0, q0, ctrl_out, planar, &mut start)
            .ok_or_else(|| backwards("start"))?;
        let hi = fixed_end(&ends.end, p, g1, qm, ctrl_out, planar, &mut end)
            .ok_or_else(|| backwards("end"))?;
        let fixed = FixedEnds {
            start: &start[..lo],
            end: &end[..hi],
        };
        self.solve_fixed(points, params, knots, weights, opts, fixed, ctrl_out)
    }

    /// The solve with the open curve's first control points `fixed.start` (`P_0, P_1, …`) and last
    /// ones `fixed.end` (`P_n, P_{n−1}, …`) given (closed curves: none).
    #[allow(clippy::too_many_arguments)]
    fn solve_fixed(
        &mut self,
        points: &[Vec3],
        params: &[f64],
        knots: &[f64],
        weights: Option<&[f64]>,
        opts: &LsqOptions,
        ends: FixedEnds<'_>,
        ctrl_out: &mut Vec<Vec3>,
    ) -> Result<()> {
        let p = self.degree;
        let layout = self.check(points, params, knots, weights, opts, ends)?;
        let n_ctrl = layout.n_ctrl;
        let n = n_ctrl - 1;
        let nu = layout.n_unknown;
        // fixed columns (open curves)
        let fixed = |col: usize| -> Vec3 {
            if col < ends.start.len() {
                ends.start[col]
            } else {
                ends.end[(n - col).min(ends.end.len() - 1)]
            }
        };
        ctrl_out.clear();
        // basis values once per point, kept for the residuals (also when nothing is free)
        self.basis.fill(p, n, knots, params);
        if nu == 0 {
            ctrl_out.extend((0..n_ctrl).map(fixed));
            return Ok(());
        }
        self.shape_matrix(layout);
        self.rhs.clear();
        self.rhs.resize(nu, Vec3::ZERO);
        self.add_data_term(points, weights, layout, &fixed);
        self.add_smoothing_term(knots, points.len(), opts, layout, &fixed);
        self.mat.factor()?;
        self.mat.solve_vec3(&mut self.rhs);
        if !self.terms.equal.is_empty() {
            self.hold_equalities(points, layout, &fixed)?;
        }
        for c in 0..n_ctrl {
            ctrl_out.push(match layout.unknown(c) {
                Some(u) => self.rhs[u],
                None => fixed(c),
            });
        }
        Ok(())
    }

    /// Sets the normal matrix's shape and zeroes it: a band of width `p` on open curves; on closed
    /// ones the envelope of the wrapped spans (each row's first non-zero column).
    fn shape_matrix(&mut self, layout: Layout) {
        let p = self.degree;
        let nu = layout.n_unknown;
        if layout.closed {
            let first = self.mat.first_mut(nu);
            for s in p..layout.lo + p {
                for a in 0..=p {
                    for b in 0..=p {
                        let (ua, ub) = ((s - p + a) % layout.lo, (s - p + b) % layout.lo);
                        if ub <= ua && ub < first[ua] {
                            first[ua] = ub;
                        }
                    }
                }
            }
            self.mat.reshape();
        } else {
            self.mat.reset_band(nu, p);
        }
    }

    /// Adds the data term `Σ_k (Σ_j N_j(ū_k) P_j − Q_k)²` to the normal equations, point by point in
    /// order; open unweighted cubics take each span's run of points at once.
    fn add_data_term(
        &mut self,
        points: &[Vec3],
        weights: Option<&[f64]>,
        layout: Layout,
        fixed: &impl Fn(usize) -> Vec3,
    ) {
        let p = self.degree;
        let m = points.len();
        let mut k = 0;
        let plain = self.terms.weights2.is_empty();
        while k < m {
            k = if !layout.closed && weights.is_none() && p == 3 && plain {
                self.add_cubic_run(k, points, layout, fixed)
            } else {
                self.add_point(k, points, weights, layout, fixed)
            };
        }
    }

    /// Moves the solution in `self.rhs` onto the equalities `C(ū_k) = Q_k` of the points to
    /// interpolate (module `point_terms`); `Err` naming `interpolate` when they are dependent.
    fn hold_equalities(
        &mut self,
        points: &[Vec3],
        layout: Layout,
        fixed: &impl Fn(usize) -> Vec3,
    ) -> Result<()> {
        let p = self.degree;
        let scale = points.iter().map(|q| q.max_abs()).fold(0.0f64, f64::max);
        self.terms.clear_rows();
        for i in 0..self.terms.equal.len() {
            let k = self.terms.equal[i];
            if k >= points.len() {
                continue;
            }
            let span = self.basis.spans()[k];
            let nb = self.basis.values(k, k + 1);
            let mut target = points[k];
            for (j, &v) in nb.iter().enumerate() {
                if layout.unknown(span - p + j).is_none() {
                    target -= fixed(span - p + j) * v;
                }
            }
            let entries = nb
                .iter()
                .enumerate()
                .filter_map(|(j, &v)| layout.unknown(span - p + j).map(|u| (u, v)));
            // a row on fixed columns only holds when they already pass through the point (to
            // rounding of the data's size)
            self.terms.push_row(k, entries, target, 1e-12 * scale)?;
        }
        self.terms.apply(&self.mat, &mut self.rhs)
    }

    /// The run of points from `k` in `k`'s span (open unweighted cubic), summed in registers as
    /// one span block; returns the index after the run.
    fn add_cubic_run(
        &mut self,
        k: usize,
        points: &[Vec3],
        layout: Layout,
        fixed: &impl Fn(usize) -> Vec3,
    ) -> usize {
        let p = self.degree;
        let n_ctrl = layout.n_ctrl;
        let span = self.basis.spans()[k];
        let run = self.basis.spans()[k..].iter().take_while(|&&s| s == span);
        let end = k + run.count();
        // unknown columns a0..a1 of the span's p + 1, the others fixed
        let first_col = span - p;
        let a0 = layout.lo.saturating_sub(first_col).min(p + 1);
        let a1 = (n_ctrl - layout.hi).saturating_sub(first_col).min(p + 1);
        let mut fixed_cols = [None; 4];
        for (a, f) in fixed_cols.iter_mut().enumerate() {
            if a < a0 || a >= a1 {
                *f = Some(fixed(first_col + a));
            }
        }
        let block = SpanBlock {
            base: first_col + a0,
            unknown: a0..a1.max(a0),
            fixed: fixed_cols,
        };
        let values = self.basis.values(k, end);
        block.add_to(
            &mut self.mat,
            &mut self.rhs,
            layout.lo,
            &points[k..end],
            values,
        );
        end
    }

    /// Point `k`'s contribution (rational basis when `weights` are given, normalised in place;
    /// fixed columns moved to the right-hand side); returns `k + 1`.
    fn add_point(
        &mut self,
        k: usize,
        points: &[Vec3],
        weights: Option<&[f64]>,
        layout: Layout,
        fixed: &impl Fn(usize) -> Vec3,
    ) -> usize {
        let p = self.degree;
        let n_ctrl = layout.n_ctrl;
        let span = self.basis.spans()[k];
        let interior = !layout.closed && span >= p + layout.lo && span + layout.hi < n_ctrl;
        let q = &points[k];
        if let Some(w) = weights {
            let nb = self.basis.values_mut(k);
            let mut sum = 0.0;
            for (v, wj) in nb.iter_mut().zip(&w[span - p..]) {
                *v *= wj;
                sum += *v;
            }
            for v in nb.iter_mut() {
                *v /= sum;
            }
        }
        let nb = self.basis.values(k, k + 1);
        // the point's weight² (1 unweighted: every product below is then exact as before)
        let w2 = self.terms.weight2(k);
        if interior {
            // every column of the span is an unknown: no fixed columns, no wrapping
            let base = span - p - layout.lo;
            for (a, &ra) in nb.iter().enumerate() {
                self.rhs[base + a] += *q * (ra * w2);
                for (b, &rb) in nb[..=a].iter().enumerate() {
                    self.mat.add(base + a, base + b, ra * rb * w2);
                }
            }
            return k + 1;
        }
        let mut target = *q;
        for (j, &v) in nb.iter().enumerate() {
            let c = span - p + j;
            if layout.unknown(c).is_none() {
                target -= fixed(c) * v;
            }
        }
        for (a, &ra) in nb.iter().enumerate() {
            let Some(ua) = layout.unknown(span - p + a) else {
                continue;
            };
            self.rhs[ua] += target * (ra * w2);
            for (b, &rb) in nb.iter().enumerate() {
                if let Some(ub) = layout.unknown(span - p + b) {
                    if ub <= ua {
                        self.mat.add(ua, ub, ra * rb * w2);
                    }
                }
            }
        }
        k + 1
    }

    /// Adds the smoothing term `λ ∫ (C^(r))²` (Gauss–Legendre per non-empty span, `λ` scaled by the
    /// point count and the parameter range so it is invariant to both) when `opts.smoothing > 0`
    /// and `r ≤ p`. The nodes' basis derivatives are cached across solves on the same knots.
    fn add_smoothing_term(
        &mut self,
        knots: &[f64],
        n_points: usize,
        opts: &LsqOptions,
        layout: Layout,
        fixed: &impl Fn(usize) -> Vec3,
    ) {
        let p = self.degree;
        let n = layout.n_ctrl - 1;
        let r = opts.smoothing_order.order();
        if !(opts.smoothing > 0.0 && r <= p) {
            return;
        }
        let (da, db) = (knots[p], knots[n + 1]);
        let lam = opts.smoothing * n_points as f64 * (db - da).powi(2 * r as i32 - 1);
        let ng = (p - r + 1).min(self.gl.len() - 1);
        let p1 = p + 1;
        let same = |a: &[f64], b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        };
        // one walk over the nodes: on new knots (or a new order) each node's derivatives are
        // computed and cached as it is reached, otherwise read from the cache
        let refill = self.smooth.r != r || !same(&self.smooth.knots, knots);
        if refill {
            self.smooth.r = r;
            self.smooth.knots.clear();
            self.smooth.knots.extend_from_slice(knots);
            self.smooth.ders.clear();
        }
        let rule = &self.gl[ng];
        let mut node = 0;
        for s in p..=n {
            let (u0, u1) = (knots[s], knots[s + 1]);
            if u1 <= u0 {
                continue;
            }
            let half = 0.5 * (u1 - u0);
            for (&x, &w) in rule.nodes().iter().zip(rule.weights()) {
                if refill {
                    ders_basis_funs_into(
                        s,
                        u0 + half * (x + 1.0),
                        p,
                        r,
                        knots,
                        &mut self.left,
                        &mut self.right,
                        &mut self.ndu,
                        &mut self.a,
                        &mut self.ders,
                    );
                    self.smooth
                        .ders
                        .extend_from_slice(&self.ders[r * p1..(r + 1) * p1]);
                }
                let d = &self.smooth.ders[node * p1..(node + 1) * p1];
                node += 1;
                let wg = w * half * lam;
                for a in 0..=p {
                    let Some(ua) = layout.unknown(s - p + a) else {
                        continue;
                    };
                    for b in 0..=p {
                        let v = wg * d[a] * d[b];
                        match layout.unknown(s - p + b) {
                            Some(ub) if ub <= ua => self.mat.add(ua, ub, v),
                            Some(_) => {}
                            None => self.rhs[ua] -= fixed(s - p + b) * v,
                        }
                    }
                }
            }
        }
    }

    /// The algebraic distances `|C(ū_k) − Q_k|` of the curve with control points `ctrl` (the output of
    /// the last solve, on its knots and parameters) from `points` (the solve's points), into `out`:
    /// the basis values of the solve are reused, no curve evaluation.
    pub fn residual_norms_into(&self, points: &[Vec3], ctrl: &[Vec3], out: &mut Vec<f64>) {
        self.basis.residual_norms_into(points, ctrl, out);
    }

    /// The knot span of every data point of the last solve.
    pub fn data_spans(&self) -> &[usize] {
        self.basis.spans()
    }

    fn check(
        &self,
        points: &[Vec3],
        params: &[f64],
        knots: &[f64],
        weights: Option<&[f64]>,
        opts: &LsqOptions,
        ends: FixedEnds<'_>,
    ) -> Result<Layout> {
        let p = self.degree;
        if points.len() != params.len() {
            return Err(Error::InvalidOption(format!(
                "{} points but {} parameters",
                points.len(),
                params.len()
            )));
        }
        if points.len() < 2 {
            return Err(Error::InvalidData(format!(
                "least squares needs at least 2 points, got {}",
                points.len()
            )));
        }
        if knots.len() < 2 * (p + 1) {
            return Err(Error::InvalidKnots(format!(
                "degree {p} needs at least {} knots, got {}",
                2 * (p + 1),
                knots.len()
            )));
        }
        let n_ctrl = knots.len() - p - 1;
        validate_knots(knots, p, n_ctrl, "least-squares fit")?;
        if let Some(w) = weights {
            if w.len() != n_ctrl || w.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
                return Err(Error::InvalidWeights(format!(
                    "{n_ctrl} finite positive weights expected, got {} values",
                    w.len()
                )));
            }
        }
        if !(opts.smoothing >= 0.0 && opts.smoothing.is_finite()) {
            return Err(Error::InvalidOption(format!(
                "smoothing must be finite and >= 0, got {}",
                opts.smoothing
            )));
        }
        if opts.closed {
            let n_u = n_ctrl - p;
            if n_u < p + 1 {
                return Err(Error::InvalidOption(format!(
                    "a closed curve of degree {p} needs at least {} distinct control points, got {n_u}",
                    p + 1
                )));
            }
            return Ok(Layout {
                n_ctrl,
                closed: true,
                lo: n_u,
                hi: 0,
                n_unknown: n_u,
            });
        }
        if ends.start.iter().chain(ends.end).any(|d| !d.is_finite()) {
            return Err(Error::InvalidOption("end conditions must be finite".into()));
        }
        let (lo, hi) = (ends.start.len(), ends.end.len());
        if n_ctrl < lo + hi {
            return Err(Error::InvalidOption(format!(
                "end tangents need at least {} control points, got {n_ctrl}",
                lo + hi
            )));
        }
        Ok(Layout {
            n_ctrl,
            closed: false,
            lo,
            hi,
            n_unknown: n_ctrl - lo - hi,
        })
    }
}

/// The span of a run of points in an open fit: its `N` columns, of which `unknown` (a range of
/// column offsets) are unknowns, the others have the given fixed values.
struct SpanBlock<const N: usize> {
    /// column of the first unknown offset
    base: usize,
    unknown: std::ops::Range<usize>,
    fixed: [Option<Vec3>; N],
}

impl<const N: usize> SpanBlock<N> {
    /// Adds the data term of `points` (with `N` basis values each, all in this span): the span's block
    /// of the normal equations is loaded, the points' products are summed onto it in their order and it
    /// is stored back, so every entry receives the same additions in the same order as one
    /// [`EnvelopeCholesky::add`] per point (bit-identical), without index arithmetic per point.
    /// `lo` is the layout's first free column.
    #[inline]
    #[allow(clippy::needless_range_loop)] // (a, b) index the block and the matrix alike
    fn add_to(
        &self,
        mat: &mut EnvelopeCholesky,
        rhs: &mut [Vec3],
        lo: usize,
        points: &[Vec3],
        values: &[f64],
    ) {
        let (a0, a1) = (self.unknown.start, self.unknown.end);
        if a0 == a1 {
            return;
        }
        let u0 = self.base - lo; // unknown index of column offset a0
        let mut blk = [[0.0; N]; N];
        let mut r = [Vec3::ZERO; N];
        for a in a0..a1 {
            r[a] = rhs[u0 + a - a0];
            for b in a0..=a {
                blk[a][b] = *mat.entry_mut(u0 + a - a0, u0 + b - a0);
            }
        }
        if a0 == 0 && a1 == N {
            // all columns unknown: constant bounds, so the block stays in registers
            for (q, nb) in points.iter().zip(values.chunks_exact(N)) {
                for a in 0..N {
                    let ra = nb[a];
                    r[a] += *q * ra;
                    for b in 0..=a {
                        blk[a][b] += ra * nb[b];
                    }
                }
            }
        } else {
            for (q, nb) in points.iter().zip(values.chunks_exact(N)) {
                let mut target = *q;
                for j in 0..N {
                    if let Some(f) = self.fixed[j] {
                        target -= f * nb[j];
                    }
                }
                for a in a0..a1 {
                    let ra = nb[a];
                    r[a] += target * ra;
                    for b in a0..=a {
                        blk[a][b] += ra * nb[b];
                    }
                }
            }
        }
        for a in a0..a1 {
            rhs[u0 + a - a0] = r[a];
            for b in a0..=a {
                *mat.entry_mut(u0 + a - a0, u0 + b - a0) = blk[a][b];
            }
        }
    }
}

/// The periodic knot vector of degree `p` for the breakpoints `b_0 < … < b_{n_u}` (one period): the
/// spans repeat with period `b_{n_u} − b_0` beyond both ends (`n_u + 2p + 1` knots, `n_u + p` control
/// points of which the last `p` repeat the first). Empty for fewer than two breakpoints (no period).
pub fn periodic_knots(breaks: &[f64], degree: usize) -> Vec<f64> {
    if breaks.len() < 2 {
        return Vec::new();
    }
    let nu = breaks.len() - 1;
    let period = breaks[nu] - breaks[0];
    let mut k = Vec::with_capacity(nu + 2 * degree + 1);
    for s in (1..=degree).rev() {
        k.push(breaks[nu - s % nu] - period * (1 + s / nu) as f64);
    }
    k.extend_from_slice(breaks);
    for s in 1..=degree {
        k.push(breaks[s % nu] + period * (1 + s / nu) as f64);
    }
    k
}

/// Fits a non-rational curve with fixed knots (see [`LsqSolver`]); a one-off convenience.
pub fn fit_fixed_knots(
    points: &[Vec3],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    opts: &LsqOptions,
) -> Result<NurbsCurve> {
    let mut solver = LsqSolver::new(degree);
    let mut ctrl = Vec::new();
    solver.solve(points, params, knots, None, opts, &mut ctrl)?;
    NurbsCurve::bspline(degree, knots.to_vec(), ctrl)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::knots::uniform_clamped;

    fn known_curve() -> NurbsCurve {
        let ctrl: Vec<Vec3> = [
            (0.0, 0.0),
            (1.0, 2.0),
            (2.0, 3.0),
            (3.0, 1.0),
            (4.0, 0.0),
            (5.0, 2.0),
            (6.0, 1.0),
            (7.0, -1.0),
        ]
        .iter()
        .map(|&(x, y)| Vec3::new(x, y, 0.3 * x))
        .collect();
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.35, 0.5, 0.8, 1.0, 1.0, 1.0, 1.0];
        NurbsCurve::bspline(3, knots, ctrl).unwrap()
    }

    /// `known_curve` at `u`, each point moved by `0.01 ((7 k) mod 5)` in y.
    fn noisy_samples(c: &NurbsCurve, u: &[f64]) -> Vec<Vec3> {
        c.points(u)
            .iter()
            .enumerate()
            .map(|(k, p)| *p + Vec3::new(0.0, 0.01 * ((k * 7) % 5) as f64, 0.0))
            .collect()
    }

    #[test]
    fn refit_of_a_known_bspline_with_its_knots_is_exact() {
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| (k as f64 / 59.0).powf(1.3)).collect();
        let q = c.points(&u);
        let f = fit_fixed_knots(&q, &u, 3, c.knots(), &LsqOptions::default()).unwrap();
        for (a, b) in f.control_points().iter().zip(c.control_points()) {
            assert!((*a - *b).norm() < 1e-10, "{a:?} vs {b:?}");
        }
        let dense: Vec<f64> = (0..500).map(|k| k as f64 / 499.0).collect();
        let dev = f
            .points(&dense)
            .iter()
            .zip(c.points(&dense))
            .map(|(a, b)| (*a - b).norm())
            .fold(0.0, f64::max);
        assert!(dev <= 1e-10, "{dev}");
    }

    #[test]
    fn rational_refit_with_known_weights_is_exact() {
        // a quarter circle as a rational quadratic, refitted with its weights
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            Some(vec![1.0, s, 1.0]),
        )
        .unwrap();
        let u: Vec<f64> = (0..15).map(|k| k as f64 / 14.0).collect();
        let q = c.points(&u);
        let mut solver = LsqSolver::new(2);
        let mut ctrl = Vec::new();
        solver
            .solve(
                &q,
                &u,
                c.knots(),
                Some(c.weights()),
                &LsqOptions::default(),
                &mut ctrl,
            )
            .unwrap();
        assert!(
            (ctrl[1] - Vec3::new(1.0, 1.0, 0.0)).norm() < 1e-12,
            "{:?}",
            ctrl[1]
        );
        // and every point is on the unit circle
        assert!(q.iter().all(|p| (p.norm() - 1.0).abs() < 1e-14));
    }

    #[test]
    fn point_order_does_not_matter() {
        // the span-by-span assembly must also be right when the parameters are not sorted
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| (k as f64 / 59.0).powf(1.3)).collect();
        let q = noisy_samples(&c, &u);
        // the end points stay first and last: they are interpolated
        let mut order = vec![0];
        order.extend((1..59).map(|k| 1 + (k * 37) % 58));
        order.push(59);
        let (us, qs): (Vec<f64>, Vec<Vec3>) = order.iter().map(|&k| (u[k], q[k])).unzip();
        let o = LsqOptions::default();
        let a = fit_fixed_knots(&q, &u, 3, c.knots(), &o).unwrap();
        let b = fit_fixed_knots(&qs, &us, 3, c.knots(), &o).unwrap();
        for (x, y) in a.control_points().iter().zip(b.control_points()) {
            assert!((*x - *y).norm() < 1e-12, "{x:?} vs {y:?}");
        }
        assert!((a.control_points()[3] - c.control_points()[3]).norm() > 1e-4);
    }

    #[test]
    fn residuals_follow_a_solve_without_unknowns() {
        // a Bézier segment with both end tangents has no free control point: the residuals must still
        // be those of this solve, not of the previous (larger) one
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| k as f64 / 59.0).collect();
        let q = c.points(&u);
        let mut s = LsqSolver::new(3);
        let mut ctrl = Vec::new();
        let o = LsqOptions::default();
        s.solve(&q, &u, c.knots(), None, &o, &mut ctrl).unwrap();
        let bezier = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let ends = (
            Some(Vec3::new(3.0, 0.0, 0.0)),
            Some(Vec3::new(3.0, 1.0, 0.0)),
        );
        s.solve_with_ends(&q, &u, &bezier, None, &o, ends, &mut ctrl)
            .unwrap();
        assert_eq!(ctrl.len(), 4);
        let mut res = Vec::new();
        s.residual_norms_into(&q, &ctrl, &mut res);
        let f = NurbsCurve::bspline(3, bezier.to_vec(), ctrl).unwrap();
        for (k, r) in res.iter().enumerate() {
            assert_eq!(*r, (f.point(u[k]) - q[k]).norm(), "point {k}");
        }
    }

    #[test]
    fn end_tangents_are_honoured() {
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| k as f64 / 59.0).collect();
        let q = c.points(&u);
        let (d0, d1) = (Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, -2.0, 0.0));
        let opts = LsqOptions {
            end_tangents: Some((d0, d1)),
            ..Default::default()
        };
        let f = fit_fixed_knots(&q, &u, 3, &uniform_clamped(3, 9), &opts).unwrap();
        assert!((f.derivatives(0.0, 1)[1] - d0).norm() < 1e-12);
        assert!((f.derivatives(1.0, 1)[1] - d1).norm() < 1e-12);
        assert!((f.point(0.0) - q[0]).norm() < 1e-14 && (f.point(1.0) - q[59]).norm() < 1e-14);
    }

    #[test]
    fn one_end_tangent_alone_is_honoured() {
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| k as f64 / 59.0).collect();
        let q = c.points(&u);
        let mut s = LsqSolver::new(3);
        let mut ctrl = Vec::new();
        let o = LsqOptions::default();
        // an arbitrary end derivative is met exactly, the start stays free
        let d1 = Vec3::new(0.5, -2.0, 1.0);
        let knots = uniform_clamped(3, 9);
        s.solve_with_ends(&q, &u, &knots, None, &o, (None, Some(d1)), &mut ctrl)
            .unwrap();
        let f = NurbsCurve::bspline(3, knots, ctrl.clone()).unwrap();
        assert!((f.derivatives(1.0, 1)[1] - d1).norm() < 1e-12);
        assert!((f.point(0.0) - q[0]).norm() < 1e-14 && (f.point(1.0) - q[59]).norm() < 1e-14);
        // the true start derivative of the sampled curve, alone, with its knots: the exact curve back
        let d0 = c.derivatives(0.0, 1)[1];
        s.solve_with_ends(&q, &u, c.knots(), None, &o, (Some(d0), None), &mut ctrl)
            .unwrap();
        for (a, b) in ctrl.iter().zip(c.control_points()) {
            assert!((*a - *b).norm() < 1e-10, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn smoothing_drives_the_fit_toward_a_straight_line() {
        // noisy-ish zigzag: with huge λ (second order) the interior control points become collinear
        let q: Vec<Vec3> = (0..40)
            .map(|k| Vec3::new(k as f64, if k % 2 == 0 { 0.0 } else { 1.0 }, 0.0))
            .collect();
        let u: Vec<f64> = (0..40).map(|k| k as f64 / 39.0).collect();
        let knots = uniform_clamped(3, 12);
        let e = |lam: f64, order| {
            let o = LsqOptions {
                smoothing: lam,
                smoothing_order: order,
                ..Default::default()
            };
            let f = fit_fixed_knots(&q, &u, 3, &knots, &o).unwrap();
            let line = |p: Vec3| {
                let a = q[0];
                let d = q[39] - a;
                (p - a).cross(d).norm() / d.norm()
            };
            f.control_points()
                .iter()
                .map(|&p| line(p))
                .fold(0.0, f64::max)
        };
        let (e0, e1, e2) = (
            e(0.0, SmoothingOrder::Second),
            e(1e-3, SmoothingOrder::Second),
            e(1e6, SmoothingOrder::Second),
        );
        assert!(e2 < 1e-4 && e1 < e0, "{e0} {e1} {e2}");
        // third order with huge λ: the curve tends to a parabola, not a line; still bounded
        assert!(e(1e6, SmoothingOrder::Third).is_finite());
    }

    #[test]
    fn smoothing_is_scale_free_in_the_number_of_points() {
        // same curve sampled at 50 and 400 points: same λ gives nearly the same fit
        let c = known_curve();
        let fit = |m: usize| {
            let u: Vec<f64> = (0..m).map(|k| k as f64 / (m - 1) as f64).collect();
            let q = c.points(&u);
            let o = LsqOptions {
                smoothing: 1e-4,
                ..Default::default()
            };
            fit_fixed_knots(&q, &u, 3, c.knots(), &o).unwrap()
        };
        let (a, b) = (fit(50), fit(400));
        let d = a
            .control_points()
            .iter()
            .zip(b.control_points())
            .map(|(x, y)| (*x - *y).norm())
            .fold(0.0, f64::max);
        let exact = fit(50)
            .control_points()
            .iter()
            .zip(c.control_points())
            .map(|(x, y)| (*x - *y).norm())
            .fold(0.0, f64::max);
        assert!(exact > 1e-3, "smoothing must act: {exact}");
        assert!(d < 0.1 * exact, "{d} vs {exact}");
    }

    #[test]
    fn repeated_solves_reuse_buffers() {
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| k as f64 / 59.0).collect();
        let q = c.points(&u);
        let mut s = LsqSolver::new(3);
        let mut out = Vec::new();
        let o = LsqOptions {
            smoothing: 1e-6,
            ..Default::default()
        };
        s.solve(&q, &u, c.knots(), None, &o, &mut out).unwrap();
        let ptrs = (s.rhs.as_ptr(), out.as_ptr(), s.mat.n());
        for _ in 0..5 {
            s.solve(&q, &u, c.knots(), None, &o, &mut out).unwrap();
        }
        assert_eq!(ptrs, (s.rhs.as_ptr(), out.as_ptr(), s.mat.n()));
    }

    #[test]
    fn the_cached_smoothing_term_equals_a_fresh_one() {
        // one solver alternating knot vectors and smoothing orders (each change refills the cache
        // of node derivatives on its walk, a repeat reads it): every result is bit for bit that of
        // a new solver, and the smoothing changes the fit (the term is really applied)
        let c = known_curve();
        let u: Vec<f64> = (0..60).map(|k| k as f64 / 59.0).collect();
        let q = noisy_samples(&c, &u);
        let other = vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.6, 1.0, 1.0, 1.0, 1.0];
        let mut s = LsqSolver::new(3);
        let mut out = Vec::new();
        for (knots, order) in [
            (c.knots(), SmoothingOrder::Third),
            (c.knots(), SmoothingOrder::Third),
            (&other[..], SmoothingOrder::Third),
            (&other[..], SmoothingOrder::Second),
            (c.knots(), SmoothingOrder::Second),
            (c.knots(), SmoothingOrder::Second),
        ] {
            let o = LsqOptions {
                smoothing: 1e-3,
                smoothing_order: order,
                ..Default::default()
            };
            s.solve(&q, &u, knots, None, &o, &mut out).unwrap();
            let mut fresh = Vec::new();
            let mut plain = Vec::new();
            LsqSolver::new(3)
                .solve(&q, &u, knots, None, &o, &mut fresh)
                .unwrap();
            LsqSolver::new(3)
                .solve(&q, &u, knots, None, &LsqOptions::default(), &mut plain)
                .unwrap();
            let bits = |v: &[Vec3]| {
                v.iter()
                    .flat_map(|p| p.0.map(f64::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&out), bits(&fresh));
            let moved = out.iter().zip(&plain).map(|(a, b)| (*a - *b).norm());
            assert!(moved.fold(0.0f64, f64::max) > 1e-4);
        }
    }

    #[test]
    fn periodic_knots_and_closed_fit_of_a_circle() {
        let breaks: Vec<f64> = (0..=8).map(|k| k as f64 / 8.0).collect();
        let k = periodic_knots(&breaks, 3);
        assert_eq!(k.len(), 8 + 7);
        // no period without two breakpoints: empty, never an index out of bounds
        assert!(periodic_knots(&[], 3).is_empty() && periodic_knots(&[0.5], 3).is_empty());
        assert!((k[0] + 3.0 / 8.0).abs() < 1e-15 && (k[14] - 11.0 / 8.0).abs() < 1e-15);
        let m = 100;
        let u: Vec<f64> = (0..m).map(|i| i as f64 / m as f64).collect();
        let q: Vec<Vec3> = u
            .iter()
            .map(|t| {
                let a = std::f64::consts::TAU * t;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let o = LsqOptions {
            closed: true,
            ..Default::default()
        };
        let f = fit_fixed_knots(&q, &u, 3, &k, &o).unwrap();
        assert_eq!(f.n_control_points(), 11);
        let d0 = f.derivatives(0.0, 2);
        let d1 = f.derivatives(1.0, 2);
        for j in 0..3 {
            assert!(
                (d0[j] - d1[j]).norm() < 1e-12 * (1.0 + d0[j].norm()),
                "order {j}"
            );
        }
        let err = q
            .iter()
            .zip(&u)
            .map(|(p, &t)| (f.point(t) - *p).norm())
            .fold(0.0, f64::max);
        assert!(err < 2e-3, "{err}");
    }

    #[test]
    fn empty_span_is_a_clear_error() {
        let u: Vec<f64> = (0..10).map(|k| 0.5 * k as f64 / 9.0).collect();
        let q: Vec<Vec3> = u.iter().map(|&x| Vec3::new(x, x * x, 0.0)).collect();
        let e = fit_fixed_knots(&q, &u, 3, &uniform_clamped(3, 8), &LsqOptions::default());
        assert!(e.unwrap_err().to_string().contains("singular"));
    }
}
