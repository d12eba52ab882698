//! Band fairing's model of one subproblem: the Gauss–Newton residuals of `F` at the Gauss nodes,
//! their Jacobian through the control map, the sign targets' rows and the data points' cones at
//! their current feet.
//!
//! Invariants: `Σ r_g² = F` exactly as the optimiser measures it (the residuals are normalised by
//! the current `F`, so the model's scale is `Σ r_g² = 1`); every cone holds at `δ = 0` (the current
//! curve is inside the band), and so does every hard sign row (hard rows are used only while every
//! target is met), so each subproblem is feasible.

use super::super::band_qp::BandQp;
use super::super::control_map::ControlMap;
use super::super::curvature_signs::target_signs;
use super::super::nodes::{basis_ders, gauss_nodes, node_derivatives, sign_changes, Node};
use super::options::BandOptions;
use crate::nurbs::knots::find_span;
use crate::nurbs::Vec3;
use crate::optim::search::objective::{speed_and_dkappa_du, CandidateEval, FitData};
use std::ops::Range;

/// Margin `m` of the sign targets, relative to the largest residual: `dκ/ds` is pushed slightly
/// past zero so that round-off cannot leave it on the wrong side of the hysteresis floor.
pub(super) const SIGN_MARGIN: f64 = 1e-4;

/// What stays fixed during a pass: sizes, the band, the node rules and the sign targets.
pub(super) struct Model {
    pub p: usize,
    pub n: usize,
    pub planar: bool,
    /// Coordinates per control point (2 for planar data).
    pub dims: usize,
    /// Step variables: movable points × `dims`.
    pub nv: usize,
    /// The data points whose deviation is constrained.
    pub free: Range<usize>,
    /// The largest deviation a step may leave (`tol`, or the starting curve's if larger).
    pub allowed: f64,
    /// The per-span cap on `max_j F_j`.
    pub span_cap: f64,
    /// The cones' radius `tol (1 − margin)`.
    pub radius: f64,
    pub nodes: Vec<Node>,
    /// The sign of `dκ/ds` every node should have (empty: no targets).
    pub targets: Vec<i8>,
    /// The edge sign nodes and their targets ([`BandOptions::edge_signs`]).
    pub edges: Vec<Node>,
    pub edge_targets: Vec<i8>,
}

/// The linearisation at the current control points (scalars; the rows are in [`Work`]).
pub(super) struct Linear {
    /// Residual scale `L³ / F`.
    pub c: f64,
    /// Largest residual magnitude.
    pub rmax: f64,
    /// The sign targets' margin `m`.
    pub sign_margin: f64,
    /// The current sign-target violation and merit `½ + w · violation`.
    pub cur_viol: f64,
    pub cur_merit: f64,
    /// Whether every target is met (sign rows hard, no slack variables).
    pub hard: bool,
    /// Largest diagonal entry of `JᵀJ`.
    pub max_diag: f64,
}

/// The buffers of the model, reused from one subproblem to the next.
#[derive(Default)]
pub(super) struct Work {
    /// Dense Jacobian rows (one per node) and the residuals.
    pub jac: Vec<f64>,
    pub res: Vec<f64>,
    /// The normal matrix `JᵀJ` and `Jᵀr`.
    pub jtj: Vec<f64>,
    pub jtr: Vec<f64>,
    pub node_ders: Vec<[Vec3; 4]>,
    pub edge_res: Vec<f64>,
    pub edge_row: Vec<f64>,
    /// Per point: its cone's index and its present deviation in the cone's frame.
    pub cone_of: Vec<usize>,
    pub now_dev: Vec<f64>,
    pub entries: Vec<(usize, usize, f64)>,
    pub qp: BandQp,
}

impl Model {
    /// The model of the curve in `ctrl` (knots `knots`) measured as `cur`, without sign targets.
    pub fn new(
        data: &FitData,
        knots: &[f64],
        n: usize,
        tol: f64,
        opts: &BandOptions,
        map: &ControlMap,
        cur: &CandidateEval,
    ) -> Model {
        let p = data.degree;
        let dims = if data.planar { 2 } else { 3 };
        let nv = map.vars() * dims;
        let free = map.free_points();
        let allowed = tol.max(cur.max_deviation);
        let span_cap = opts
            .span_cap
            .map_or(f64::INFINITY, |c| c.max(cur.max_span_fairness));
        let nodes = gauss_nodes(knots, p, n);
        Model {
            p,
            n,
            planar: data.planar,
            dims,
            nv,
            free,
            allowed,
            span_cap,
            radius: tol * (1.0 - opts.margin),
            nodes,
            targets: Vec::new(),
            edges: Vec::new(),
            edge_targets: Vec::new(),
        }
    }

    /// Sets the sign targets of the curve with control points `ctrl` ([`target_signs`]) and,
    /// with [`BandOptions::edge_signs`], the edge nodes.
    pub fn set_targets(&mut self, ctrl: &[Vec3], knots: &[f64], opts: &BandOptions) {
        let p = self.p;
        if opts.extrema_persistence > 0.0 {
            let (sig, inc) = node_signals(&self.nodes, ctrl, p, self.planar);
            target_signs(&sig, &inc, opts.extrema_persistence, &mut self.targets);
        }
        (self.edges, self.edge_targets) = if opts.edge_signs {
            edge_nodes(&self.nodes, &self.targets, knots, p)
        } else {
            (Vec::new(), Vec::new())
        };
    }

    /// Buffers sized for this model and `m` data points.
    pub fn work(&self, m: usize) -> Work {
        let nv = self.nv;
        Work {
            jac: vec![0.0; self.nodes.len() * nv],
            res: vec![0.0; self.nodes.len()],
            jtj: vec![0.0; nv * nv],
            jtr: vec![0.0; nv],
            node_ders: Vec::with_capacity(self.nodes.len()),
            edge_res: vec![0.0; self.edges.len()],
            edge_row: vec![0.0; nv],
            cone_of: vec![usize::MAX; m],
            now_dev: vec![0.0; m],
            entries: Vec::new(),
            qp: BandQp::default(),
        }
    }

    /// Linearises `F` at the control points `ctrl` (residuals normalised by `cur_f`: `Σ r² = 1`)
    /// into `w`; `None` when the normal equations are not finite or vanish.
    pub fn linearise(
        &self,
        ctrl: &[Vec3],
        cur_f: f64,
        map: &ControlMap,
        sign_weight: f64,
        w: &mut Work,
    ) -> Option<Linear> {
        let (p, nv, dims, planar) = (self.p, self.nv, self.dims, self.planar);
        let nodes = &self.nodes;
        let (jac, res, jtj, jtr) = (&mut w.jac, &mut w.res, &mut w.jtj, &mut w.jtr);
        w.node_ders.clear();
        w.node_ders
            .extend(nodes.iter().map(|nd| node_derivatives(nd, ctrl, p)));
        let length: f64 = nodes
            .iter()
            .zip(&w.node_ders)
            .map(|(nd, d)| nd.weight * d[1].norm())
            .sum();
        let c = length.powi(3) / cur_f.max(f64::MIN_POSITIVE);
        jac.fill(0.0);
        for (g, (nd, d)) in nodes.iter().zip(&w.node_ders).enumerate() {
            let d = *d;
            let cw = c * nd.weight;
            res[g] = residual(&d, cw, planar);
            let grad = residual_gradient(&d, cw, planar, p, dims);
            add_node_row(nd, &grad, p, dims, map, 1.0, &mut jac[g * nv..(g + 1) * nv]);
        }
        // the edge nodes' residuals (their Jacobian rows only where a row is set up below)
        node_residuals(&self.edges, ctrl, p, planar, c, &mut w.edge_res);
        jtj.fill(0.0);
        jtr.fill(0.0);
        for g in 0..nodes.len() {
            let row = &jac[g * nv..(g + 1) * nv];
            for (a, &ra) in row.iter().enumerate() {
                if ra == 0.0 {
                    continue;
                }
                jtr[a] += ra * res[g];
                for (b, &rb) in row.iter().enumerate().skip(a) {
                    if rb != 0.0 {
                        jtj[a * nv + b] += ra * rb;
                    }
                }
            }
        }
        if !jtr.iter().all(|v| v.is_finite()) || !jtj.iter().all(|v| v.is_finite()) {
            return None;
        }
        // sign targets: merit ½ F/F_cur + w Σ max(0, m − s_g r_g)
        let rmax = res.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let sign_margin = SIGN_MARGIN * rmax;
        let cur_viol = violation(res, &self.targets, sign_margin)
            + violation(&w.edge_res, &self.edge_targets, sign_margin);
        let cur_merit = 0.5 + sign_weight * cur_viol;
        // met targets (no violation, so `δ = 0` is feasible): hard rows, no slack variables
        let hard = cur_viol == 0.0;
        let max_diag = (0..nv).map(|a| jtj[a * nv + a]).fold(0.0f64, f64::max);
        if max_diag <= 0.0 {
            return None;
        }
        Some(Linear {
            c,
            rmax,
            sign_margin,
            cur_viol,
            cur_merit,
            hard,
            max_diag,
        })
    }

    /// Starts the subproblem in `w.qp`: the cones of the data points at the feet `feet` of the
    /// curve with control points `ctrl`, then the sign rows (one group). The nodes near or past
    /// the wrong side get a penalised constraint `s_g (r_g + J_g δ) + t_g ≥ m`, `t_g ≥ 0`, or,
    /// while every target is met, the hard constraint `s_g (r_g + J_g δ) ≥ m` for the nodes within
    /// `sign_near_met` of the wrong side.
    #[allow(clippy::too_many_arguments)]
    pub fn push_cones_and_signs(
        &self,
        data: &FitData,
        knots: &[f64],
        ctrl: &[Vec3],
        feet: &[f64],
        opts: &BandOptions,
        map: &ControlMap,
        lin: &Linear,
        w: &mut Work,
    ) {
        let (p, n, nv, dims) = (self.p, self.n, self.nv, self.dims);
        let var = |v: usize, k: usize| v * dims + k;
        let (targets, edge_targets) = (&self.targets, &self.edge_targets);
        let (res, edge_res) = (&w.res, &w.edge_res);
        let sign_margin = lin.sign_margin;
        let hard = lin.hard;
        let step = &opts.step;
        let near = if hard {
            step.sign_near_met
        } else {
            step.sign_near
        } * lin.rmax;
        let signed: Vec<usize> = (0..targets.len())
            .filter(|&g| targets[g] != 0 && f64::from(targets[g]) * res[g] < near)
            .collect();
        let edge_signed: Vec<usize> = (0..self.edges.len())
            .filter(|&g| f64::from(edge_targets[g]) * edge_res[g] < near)
            .collect();
        let qp = &mut w.qp;
        qp.reset(nv);
        qp.slack_weight = step.sign_weight;
        for i in self.free.clone() {
            let u = feet[i];
            let s = find_span(n - 1, p, u, knots);
            let basis = basis_ders(knots, p, s, u, 1);
            let (mut ci, mut tan) = (-data.points[i], Vec3::ZERO);
            for j in 0..=p {
                ci += ctrl[s - p + j] * basis[j];
                tan += ctrl[s - p + j] * basis[p + 1 + j];
            }
            let weight = if map.end_point(i) {
                1.0
            } else {
                opts.tangent_weight
            };
            let frame = local_frame(tan, data.planar, weight);
            w.now_dev[i] = frame.iter().map(|f| f.dot(ci).powi(2)).sum::<f64>().sqrt();
            w.cone_of[i] = qp.cones();
            let mut h = [0.0; 4];
            w.entries.clear();
            for (r, f) in frame.iter().enumerate().take(dims) {
                h[1 + r] = f.dot(ci);
                for j in 0..=p {
                    let cj = s - p + j;
                    if basis[j] == 0.0 {
                        continue;
                    }
                    for &(z, c) in map.row(cj) {
                        for k in 0..dims {
                            if f[k] != 0.0 {
                                w.entries.push((1 + r, var(z, k), -(c * basis[j]) * f[k]));
                            }
                        }
                    }
                }
            }
            qp.push_cone(&h[..dims + 1], &w.entries);
        }
        for &g in &signed {
            let sg = f64::from(targets[g]);
            let row = &w.jac[g * nv..(g + 1) * nv];
            qp.push_row(
                sg * res[g] - sign_margin,
                row.iter()
                    .enumerate()
                    .filter(|(_, &v)| v != 0.0)
                    .map(|(a, &v)| (a, -sg * v)),
                !hard,
            );
        }
        for &g in &edge_signed {
            let sg = f64::from(edge_targets[g]);
            let nd = &self.edges[g];
            let d = node_derivatives(nd, ctrl, p);
            let grad = residual_gradient(&d, lin.c * nd.weight, data.planar, p, dims);
            w.edge_row.fill(0.0);
            add_node_row(nd, &grad, p, dims, map, 1.0, &mut w.edge_row);
            let row = &w.edge_row;
            qp.push_row(
                sg * edge_res[g] - sign_margin,
                row.iter()
                    .enumerate()
                    .filter(|(_, &v)| v != 0.0)
                    .map(|(a, &v)| (a, -sg * v)),
                !hard,
            );
        }
        qp.end_group();
    }
}

/// Offset of the edge sign nodes from their knot, relative to the span ([`BandOptions::edge_signs`]):
/// the span's own polynomial next to the knot, never the third derivative at the knot itself.
const EDGE_OFFSET: f64 = 1e-6;

/// The edge sign nodes of [`BandOptions::edge_signs`]: two per knot span, with the weight (for the
/// residual's scale only; they are not part of `F`) and the target of the span's first and last
/// Gauss node. Empty without targets.
pub(super) fn edge_nodes(
    nodes: &[Node],
    targets: &[i8],
    knots: &[f64],
    p: usize,
) -> (Vec<Node>, Vec<i8>) {
    let (mut out, mut signs) = (Vec::new(), Vec::new());
    if targets.is_empty() {
        return (out, signs);
    }
    let mut g = 0;
    while g < nodes.len() {
        let s = nodes[g].span;
        let end = g + nodes[g..].iter().take_while(|nd| nd.span == s).count();
        let (a, b) = (knots[s], knots[s + 1]);
        for (u, k) in [
            (a + EDGE_OFFSET * (b - a), g),
            (b - EDGE_OFFSET * (b - a), end - 1),
        ] {
            if targets[k] != 0 {
                out.push(Node {
                    span: s,
                    weight: nodes[k].weight,
                    ders: basis_ders(knots, p, s, u, 3.min(p)),
                });
                signs.push(targets[k]);
            }
        }
        g = end;
    }
    (out, signs)
}

/// `(F, max_j F_j, curvature extrema)` of the curve with control points `ctrl` by the rule of
/// `nodes`; the extrema are the sign changes of `dκ/ds` at the nodes with a hysteresis floor of
/// `1e-6 max|dκ/ds| L² + 1e-9` (as the benchmark's measurer counts them on its samples).
pub(super) fn node_fairness(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
) -> (f64, f64, usize) {
    let (mut length, mut total, mut fmax) = (0.0, 0.0, 0.0f64);
    let (mut span, mut part) = (usize::MAX, 0.0);
    let mut dkds = Vec::with_capacity(nodes.len());
    for nd in nodes {
        if nd.span != span {
            fmax = fmax.max(part);
            (span, part) = (nd.span, 0.0);
        }
        let d = node_derivatives(nd, ctrl, p);
        let (v, dk) = speed_and_dkappa_du(&d, planar);
        length += nd.weight * v;
        dkds.push(if v > 0.0 { dk / v } else { 0.0 });
        if v > 0.0 {
            let e = nd.weight * dk * dk / v;
            total += e;
            part += e;
        }
    }
    fmax = fmax.max(part);
    let l3 = length * length * length;
    let f = l3 * total;
    let extrema = sign_changes(&dkds, length * length);
    if f.is_finite() {
        (f, l3 * fmax, extrema)
    } else {
        (f64::INFINITY, f64::INFINITY, usize::MAX)
    }
}

/// `(F, max_j F_j)` of [`node_fairness`] (the same sums) without the extrema count, and, when
/// `res` is not empty, the residuals of [`node_residuals`] (scale `c`) into it, from the same
/// node derivatives: the line search's measure of a trial step.
pub(super) fn node_fairness_residuals(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
    c: f64,
    res: &mut [f64],
) -> (f64, f64) {
    let (mut length, mut total, mut fmax) = (0.0, 0.0, 0.0f64);
    let (mut span, mut part) = (usize::MAX, 0.0);
    let with_res = !res.is_empty();
    for (g, nd) in nodes.iter().enumerate() {
        if nd.span != span {
            fmax = fmax.max(part);
            (span, part) = (nd.span, 0.0);
        }
        let d = node_derivatives(nd, ctrl, p);
        let (v, dk) = speed_and_dkappa_du(&d, planar);
        length += nd.weight * v;
        if v > 0.0 {
            let e = nd.weight * dk * dk / v;
            total += e;
            part += e;
        }
        if with_res {
            // as `residual` with `c_w = c w_g`
            res[g] = if v > 0.0 {
                (c * nd.weight / v).sqrt() * dk
            } else {
                0.0
            };
        }
    }
    fmax = fmax.max(part);
    let l3 = length * length * length;
    let f = l3 * total;
    if f.is_finite() {
        (f, l3 * fmax)
    } else {
        (f64::INFINITY, f64::INFINITY)
    }
}

/// Per node, `dκ/ds` (any positive scaling: here `dκ/du / |C'|`) and the curvature change
/// `w_g dκ/du` it carries: the inputs of [`target_signs`].
pub(super) fn node_signals(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
) -> (Vec<f64>, Vec<f64>) {
    nodes
        .iter()
        .map(|nd| {
            let (v, dk) = speed_and_dkappa_du(&node_derivatives(nd, ctrl, p), planar);
            (if v > 0.0 { dk / v } else { 0.0 }, nd.weight * dk)
        })
        .unzip()
}

/// The Gauss–Newton residuals `r_g` (scale `c = L³ / F` of the current linearisation) into `out`.
pub(super) fn node_residuals(
    nodes: &[Node],
    ctrl: &[Vec3],
    p: usize,
    planar: bool,
    c: f64,
    out: &mut [f64],
) {
    for (r, nd) in out.iter_mut().zip(nodes) {
        *r = residual(&node_derivatives(nd, ctrl, p), c * nd.weight, planar);
    }
}

/// `Σ max(0, m − s_g r_g)` over the nodes with a sign target.
pub(super) fn violation(res: &[f64], targets: &[i8], margin: f64) -> f64 {
    res.iter()
        .zip(targets)
        .filter(|(_, &t)| t != 0)
        .map(|(&r, &t)| (margin - f64::from(t) * r).max(0.0))
        .sum()
}

/// `∂r/∂C^(o)_k` of a node's [`residual`] by central differences in its derivatives `d` (orders
/// `1..=min(p, 3)`, coordinates `0..dims`; the other entries stay 0).
pub(super) fn residual_gradient(
    d: &[Vec3; 4],
    c_w: f64,
    planar: bool,
    p: usize,
    dims: usize,
) -> [[f64; 3]; 4] {
    let mut grad = [[0.0; 3]; 4];
    for o in 1..=3.min(p) {
        let h = 1e-6 * (d[o].norm() + 1e-3 * d[1].norm()).max(1e-300);
        for k in 0..dims {
            let mut dp = *d;
            dp[o][k] += h;
            let rp = residual(&dp, c_w, planar);
            dp[o][k] -= 2.0 * h;
            let rm = residual(&dp, c_w, planar);
            grad[o][k] = (rp - rm) / (2.0 * h);
        }
    }
    grad
}

/// Adds `scale ·` the node's residual gradient with respect to the free variables to `row`: the
/// chain rule from `grad` ([`residual_gradient`], by derivative order and coordinate) through the
/// node's basis derivatives and the control map (variable `z`, coordinate `k` at `z · dims + k`).
pub(super) fn add_node_row(
    nd: &Node,
    grad: &[[f64; 3]; 4],
    p: usize,
    dims: usize,
    map: &ControlMap,
    scale: f64,
    row: &mut [f64],
) {
    for j in 0..=p {
        let cj = nd.span - p + j;
        for k in 0..dims {
            let mut v = 0.0;
            for o in 1..=3.min(p) {
                v += grad[o][k] * nd.ders[o * (p + 1) + j];
            }
            for &(z, c) in map.row(cj) {
                row[z * dims + k] += scale * c * v;
            }
        }
    }
}

/// The residual `sqrt(c w / |C'|) dκ/du` of a node with derivatives `d`.
pub(super) fn residual(d: &[Vec3; 4], c_w: f64, planar: bool) -> f64 {
    let (v, dk) = speed_and_dkappa_du(d, planar);
    if v > 0.0 {
        (c_w / v).sqrt() * dk
    } else {
        0.0
    }
}

/// `‖C(u) − q‖` for the B-spline (`knots`, `ctrl`, degree `p`).
pub(super) fn distance_at(knots: &[f64], ctrl: &[Vec3], p: usize, u: f64, q: Vec3) -> f64 {
    let s = find_span(ctrl.len() - 1, p, u, knots);
    let basis = basis_ders(knots, p, s, u, 0);
    let mut c = -q;
    for j in 0..=p {
        c += ctrl[s - p + j] * basis[j];
    }
    c.norm()
}

/// The rows measuring a deviation `e` at a foot with tangent `tan`: the normal directions, then the
/// tangent scaled by `tangent_weight` (1: the full distance; a unit tangent of zero length falls
/// back to the coordinate axes).
pub(super) fn local_frame(tan: Vec3, planar: bool, tangent_weight: f64) -> [Vec3; 3] {
    let len = tan.norm();
    if !(len > 0.0 && len.is_finite()) {
        return [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
    }
    let t = tan / len;
    if planar {
        return [Vec3::new(-t[1], t[0], 0.0), t * tangent_weight, Vec3::ZERO];
    }
    // the coordinate axis least aligned with t, made orthogonal to it
    let mut k = 0;
    for i in 1..3 {
        if t[i].abs() < t[k].abs() {
            k = i;
        }
    }
    let mut a = Vec3::ZERO;
    a[k] = 1.0;
    let n1 = a - t * t.dot(a);
    let n1 = n1 / n1.norm();
    let n2 = t.cross(n1);
    [n1, n2, t * tangent_weight]
}
