//! Band fairing's step schedule: per linearisation up to `solves_per_subproblem` solves, each
//! followed by a line search along its solution, with the Levenberg–Marquardt multiplier `μ`
//! adapted between them.
//!
//! - A step is kept only when the true `F` (measured afresh, with the sign-target penalty: the
//!   merit) decreases, the maximum orthogonal deviation stays within the allowance, `max_j F_j`
//!   within the per-span cap and (with [`BandOptions::keep_extrema`]) the curvature extrema do not
//!   grow; else the step is halved.
//! - A full step that leaves the band draws in the cones of the points that left it; one that
//!   fails only by adding extrema hands its flipped samples to the sign guard and the subproblem
//!   is solved again; else `μ` grows. A step kept only at `t < 1` grows `μ` by `1/t²`.
//!
//! Invariant: the feasible set of a subproblem is convex and contains the current control points,
//! so every point of the segment to its solution is inside the cones.

use super::super::cone_ipm::{self, IpmWork};
use super::super::control_map::ControlMap;
use super::super::extrema::ExtremaCount;
use super::super::tuning::MIN_ACCEPTED_GAIN;
use super::model::{Linear, Model, Work};
use super::node_measures::{distance_at, node_fairness_residuals, node_residuals, violation};
use super::options::{BandFaired, BandOptions};
use super::sign_guard::SignGuard;
use crate::nurbs::Vec3;
use crate::optim::search::objective::{EvalWorkspace, FitData};

/// The state of a pass between subproblems.
pub(super) struct Pass<'a> {
    pub model: Model,
    pub work: Work,
    pub extrema: &'a mut ExtremaCount,
    /// Samples held on their side of `dκ/ds = 0`.
    pub guard: SignGuard,
    /// The current control points and feet.
    pub ctrl: Vec<Vec3>,
    pub feet: Vec<f64>,
    /// `F` and the extrema count of the current curve.
    pub cur_f: f64,
    pub cur_ext: usize,
    /// The Levenberg–Marquardt multiplier.
    pub mu: f64,
    /// Small accepted steps in a row.
    pub small_gains: usize,
    /// Per point: how far its cone is drawn in after a step left the band (second-order effects
    /// of the tangent-plane model).
    pub shrink: Vec<f64>,
    pub ipm: IpmWork,
    pub trial_res: Vec<f64>,
    pub trial_edge: Vec<f64>,
}

/// How a subproblem ended.
#[derive(Default)]
pub(super) struct Outcome {
    /// A step was kept.
    pub accepted: bool,
    /// A full step added extrema only; the guard holds more samples now.
    pub guarded: bool,
    /// The model predicted less than the smallest relative gain.
    pub converged: bool,
}

impl Pass<'_> {
    /// Completes the subproblem the model started in `work.qp` (the guard rows, `q`) and solves
    /// it up to `solves_per_subproblem` times, each solution followed by a line search.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        data: &FitData,
        ws: &mut EvalWorkspace,
        tol: f64,
        opts: &BandOptions,
        map: &ControlMap,
        lin: &Linear,
        out: &mut BandFaired,
    ) -> Outcome {
        let (p, nv, dims) = (self.model.p, self.model.nv, self.model.dims);
        let st = &opts.step;
        let guard_rows = self.guard.rows(
            self.extrema,
            &self.ctrl,
            p,
            data.planar,
            map,
            dims,
            lin.c,
            lin.rmax,
        );
        let qp = &mut self.work.qp;
        for (bj, coef) in &guard_rows {
            qp.push_row(
                *bj,
                coef.iter()
                    .enumerate()
                    .filter(|(_, &v)| v != 0.0)
                    .map(|(a, &v)| (a, v)),
                false,
            );
        }
        qp.end_group();
        qp.q.copy_from_slice(&self.work.jtr);
        let mut outcome = Outcome::default();
        for _ in 0..st.solves_per_subproblem {
            if out.solves >= opts.max_solves {
                break;
            }
            let (jtj, qp) = (&self.work.jtj, &mut self.work.qp);
            // P = JᵀJ + μ (diag(JᵀJ) + 1e-6 max diag)
            qp.p.copy_from_slice(jtj);
            for a in 0..nv {
                for b in 0..a {
                    qp.p[a * nv + b] = jtj[b * nv + a];
                }
                let v = &mut qp.p[a * nv + a];
                *v += self.mu * (*v + 1e-6 * lin.max_diag);
            }
            for i in self.model.free.clone() {
                // a point outside the band (only at a fixed count) may not get worse
                let r = (self.model.radius - self.shrink[i]).max(0.5 * tol);
                let now = self.work.now_dev[i];
                qp.cone_h_mut(self.work.cone_of[i])[0] = if now > tol { r.max(now) } else { r };
            }
            out.solves += 1;
            // the dedicated interior-point solver, clarabel when it does not converge
            let x = if cone_ipm::solve(qp, &mut self.ipm) {
                Some(self.ipm.solution.clone())
            } else {
                qp.solve_clarabel()
            };
            let Some(x) = x else {
                self.mu *= st.mu_failed_solve_growth;
                continue;
            };
            // the model's own merit gain (½ F/F_k is ½ + the model value): a step it predicts to
            // gain less than `min_rel_gain` ends the stage
            if (lin.cur_merit - 0.5 - qp.model_value(&x)) < opts.min_rel_gain * lin.cur_merit {
                outcome.converged = true;
                break;
            }
            let left_band = self.line_search(data, ws, tol, opts, map, lin, &x, out, &mut outcome);
            if outcome.accepted || outcome.guarded {
                break;
            }
            if !left_band {
                self.mu *= st.mu_no_step_growth;
            }
        }
        outcome
    }

    /// The line search along the solution `x`: trial steps `t = 1, ½, ¼, …`; sets
    /// `outcome.accepted` (the step kept, `μ` updated) or `outcome.guarded`. Whether a full step
    /// left the band (its points' cones are drawn in).
    #[allow(clippy::too_many_arguments)]
    fn line_search(
        &mut self,
        data: &FitData,
        ws: &mut EvalWorkspace,
        tol: f64,
        opts: &BandOptions,
        map: &ControlMap,
        lin: &Linear,
        x: &[f64],
        out: &mut BandFaired,
        outcome: &mut Outcome,
    ) -> bool {
        let (p, n, dims) = (self.model.p, self.model.n, self.model.dims);
        let var = |v: usize, k: usize| v * dims + k;
        let st = &opts.step;
        let model = &self.model;
        let (targets, edge_targets) = (&model.targets, &model.edge_targets);
        let (allowed, span_cap, radius) = (model.allowed, model.span_cap, model.radius);
        let (c, sign_margin, cur_merit, cur_viol) =
            (lin.c, lin.sign_margin, lin.cur_merit, lin.cur_viol);
        let mut t = 1.0;
        let mut left_band = false;
        for _ in 0..st.line_search_steps {
            for j in 0..n {
                let terms = map.row(j);
                if terms.is_empty() {
                    continue;
                }
                ws.ctrl[j] = self.ctrl[j];
                for k in 0..dims {
                    let mut step = terms[0].1 * x[var(terms[0].0, k)];
                    for &(z, c) in &terms[1..] {
                        step += c * x[var(z, k)];
                    }
                    ws.ctrl[j][k] += t * step;
                }
            }
            let e = map.measure(data, &self.feet, ws);
            let trial = if targets.is_empty() {
                &mut self.trial_res[..0]
            } else {
                &mut self.trial_res[..]
            };
            let (f, fmax) =
                node_fairness_residuals(&model.nodes, &ws.ctrl, p, data.planar, c, trial);
            let mut merit = 0.5 * f / self.cur_f;
            let mut viol = 0.0;
            if !targets.is_empty() {
                viol = violation(&self.trial_res, targets, sign_margin);
                if !model.edges.is_empty() {
                    node_residuals(
                        &model.edges,
                        &ws.ctrl,
                        p,
                        data.planar,
                        c,
                        &mut self.trial_edge,
                    );
                    viol += violation(&self.trial_edge, edge_targets, sign_margin);
                }
                merit += st.sign_weight * viol;
            }
            if t == 1.0 && e.solved && e.max_deviation > allowed {
                // draw in the cones of the points that left the band
                left_band = true;
                for i in model.free.clone() {
                    let d = distance_at(&ws.knots, &ws.ctrl, p, ws.foot_params[i], data.points[i])
                        * data.bands.factor(i);
                    if d > radius - self.shrink[i] {
                        self.shrink[i] += d - (radius - self.shrink[i]) + opts.margin * tol;
                    }
                }
            }
            let mut ext = self.cur_ext;
            if e.solved
                && e.max_deviation <= allowed
                && fmax <= span_cap
                && merit < cur_merit * (1.0 - MIN_ACCEPTED_GAIN)
                && (!opts.keep_extrema || {
                    ext = self.extrema.count(&ws.ctrl);
                    ext <= self.cur_ext
                })
            {
                let gain = 1.0 - merit / cur_merit;
                // a step that cuts the sign violation enough is progress too
                self.small_gains =
                    if gain < opts.min_rel_gain && viol >= st.violation_progress * cur_viol {
                        self.small_gains + 1
                    } else {
                        0
                    };
                self.ctrl.copy_from_slice(&ws.ctrl);
                self.feet.copy_from_slice(&ws.foot_params);
                self.cur_f = f;
                self.cur_ext = ext;
                out.steps += 1;
                outcome.accepted = true;
                if t == 1.0 {
                    self.mu = (self.mu / st.mu_full_step_divisor).max(st.mu_min);
                } else {
                    // the model overreached: a shorter step next time
                    self.mu /= t.powi(st.mu_short_step_power);
                }
                break;
            }
            if t == 1.0
                && opts.keep_extrema
                && e.solved
                && e.max_deviation <= allowed
                && fmax <= span_cap
                && merit < cur_merit * (1.0 - MIN_ACCEPTED_GAIN)
                && self.guard.hold(self.extrema, &self.ctrl, &ws.ctrl)
            {
                // only new extrema spoilt the full step: solve again with the flipped samples
                // held on their side
                outcome.guarded = true;
                break;
            }
            t *= 0.5;
        }
        left_band
    }
}
