//! Band fairing's sign guard: samples of the extrema count held on their side of `dκ/ds = 0`.
//!
//! The extrema guard of the line search is nonlinear and only sees a step after the fact. When a
//! full step is good in every respect but adds curvature extrema, the samples whose sign it flipped
//! get a linearised row in every later subproblem, so the next step can be a full one instead of a
//! half step along a direction that crosses. Invariant: a row is emitted only while the current
//! curve meets it (the sample is still on its side), so the subproblem stays feasible.

use super::super::control_map::ControlMap;
use super::super::extrema::ExtremaCount;
use super::super::nodes::node_derivatives;
use super::model::SIGN_MARGIN;
use super::node_measures::{add_node_row, residual, residual_gradient};
use crate::nurbs::Vec3;

/// Samples of [`ExtremaCount`] held on their side of `dκ/ds = 0`: when a full step is good in
/// every respect but adds curvature extrema, the samples whose sign it flipped get the linearised
/// row `s_k (r_k + J_k δ) ≥ m_k` in every later subproblem (the current curve meets it, so the
/// subproblem stays feasible). The extrema guard of the line search is nonlinear and only sees
/// the step after the fact; the rows put the sign changes the step must not make into the model,
/// so the next step can be a full one instead of a half step along a direction that crosses.
#[derive(Default)]
pub(super) struct SignGuard {
    /// `(sample, sign)` pairs.
    held: Vec<(usize, i8)>,
    now: Vec<i8>,
    trial: Vec<i8>,
}

impl SignGuard {
    /// Adds the samples whose sign `dκ/ds` differs between `ctrl` (nonzero there) and `trial`;
    /// whether any was new.
    pub(super) fn hold(
        &mut self,
        counter: &mut ExtremaCount,
        ctrl: &[Vec3],
        trial: &[Vec3],
    ) -> bool {
        counter.signs(ctrl, &mut self.now);
        counter.signs(trial, &mut self.trial);
        let mut added = false;
        for (k, (&a, &b)) in self.now.iter().zip(&self.trial).enumerate() {
            if a != 0 && b != a && !self.held.iter().any(|h| h.0 == k) {
                self.held.push((k, a));
                added = true;
            }
        }
        added
    }

    /// The rows `(b_k, −s_k J_k)` at the control points `ctrl` (residual scale `c`, model
    /// residuals of largest magnitude `rmax`) of the held samples still on their side.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rows(
        &self,
        counter: &ExtremaCount,
        ctrl: &[Vec3],
        p: usize,
        planar: bool,
        map: &ControlMap,
        dims: usize,
        c: f64,
        rmax: f64,
    ) -> Vec<(f64, Vec<f64>)> {
        let nv = map.vars() * dims;
        let mut rows = Vec::new();
        for &(k, sign) in &self.held {
            let nd = &counter.nodes[k];
            let d = node_derivatives(nd, ctrl, p);
            // the scale of a Gauss node of this span (the edge samples have weight 0)
            let cw = c * counter.nodes[k.saturating_sub(1).max(1)]
                .weight
                .max(nd.weight);
            let sg = f64::from(sign);
            let r = residual(&d, cw, planar);
            if sg * r <= 0.0 {
                continue;
            }
            let grad = residual_gradient(&d, cw, planar, p, dims);
            let mut row = vec![0.0; nv];
            add_node_row(nd, &grad, p, dims, map, -sg, &mut row);
            rows.push((sg * r - (SIGN_MARGIN * rmax).min(0.5 * sg * r), row));
        }
        rows
    }
}
