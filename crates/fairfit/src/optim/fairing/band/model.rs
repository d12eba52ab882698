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
use super::super::nodes::{basis_ders, gauss_nodes, node_derivatives, Node};
use super::node_measures::{
    add_node_row, edge_nodes, local_frame, node_residuals, node_signals, residual,
    residual_gradient, violation,
};
use super::options::BandOptions;
use crate::nurbs::knots::find_span;
use crate::nurbs::Vec3;
use crate::optim::search::objective::{CandidateEval, FitData};
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
            let mut frame = local_frame(tan, data.planar, weight);
            if !data.bands.is_none() {
                // the point's cone in weighted distance: `‖w_i (C − Q_i)‖ ≤ ρ` (`PointBands`)
                let f = data.bands.factor(i);
                for v in frame.iter_mut() {
                    *v = *v * f;
                }
            }
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
