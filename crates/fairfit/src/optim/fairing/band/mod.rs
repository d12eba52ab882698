//! Band fairing: the control points (knots fixed) that minimise the true fairness `F` while every
//! data point stays inside the tolerance band, by sequential convex programming.
//!
//! The knot search only reaches curves of the form "least squares (with smoothing λ) on these
//! knots", and the polish ([`mod@super::polish`]) moves one control point at a time; both leave most
//! of the tolerance band unused. Here all movable control points move together:
//!
//! - **Variables**: the interior control points `P_1 … P_{n−2}` (x, y for planar data, else x, y, z).
//!   The end points stay fixed: the least-squares fit interpolates the data's end points, and the
//!   measurers count the ends as exact. With [`BandOptions::ends`] = [`EndCondition::Free`](super::control_map::EndCondition::Free) they
//!   move too, and the data's end points get the cones `‖P_0 − Q_0‖ ≤ ρ`, `‖P_{n−1} − Q_{m−1}‖ ≤ ρ`
//!   (feet held at the curve's ends, whole distance: [`ControlMap::end_point`]).
//! - **Constraints**: for every interior data point `Q_i` with its current foot parameter `u_i`,
//!   `‖C(u_i) − Q_i‖₂ ≤ ρ_i` with `ρ_i = max(tol (1 − margin), ‖C₀(u_i) − Q_i‖)` (a point outside
//!   the band, possible only at a fixed control-point count, may not get worse). `C(u_i)` is linear
//!   in the control points, so this is a second-order cone. The orthogonal distance is at most the
//!   distance at any parameter, so a curve meeting these cones meets the tolerance; after a step the
//!   feet are projected again (the distance can only shrink), so the next problem starts feasible.
//!   The feasible set is convex, so every point of the segment from the current control points to
//!   the step is feasible too: the line search never leaves the band.
//! - **Objective** (`model.rs`): Gauss–Newton on `F = L³ ∫ (dκ/ds)² ds` with the residuals
//!   `r_g = sqrt(L³ w_g / |C'(u_g)|) dκ/du(u_g)` at the 8 Gauss–Legendre nodes strictly inside every
//!   knot span (never at a knot, where `C'''` jumps), so `Σ r_g² = F` exactly as the optimiser
//!   measures it. The Jacobian is analytic in the basis functions and by central differences in
//!   the node's derivatives `C', C'', C'''` (`r_g` depends on the control points only through those);
//!   `L` is held at its current value in the model. A Levenberg–Marquardt term
//!   `μ δᵀ diag(JᵀJ) δ` keeps the step where the linearisation holds.
//! - **Solver**: each subproblem (a QP with second-order cones, [`super::band_qp`]) is solved by
//!   the dedicated interior-point solver [`super::cone_ipm`], by `clarabel` when that does not
//!   converge; sequential and deterministic.
//! - **Step schedule** (`schedule.rs`): a step is kept only when the merit (`F` measured afresh, plus
//!   the sign-target penalty) decreases, the maximum orthogonal deviation stays within the
//!   allowance, `max_j F_j` within the per-span cap `F*` and the curvature extrema do not grow;
//!   else it is halved, and after the last trial `μ` grows and the subproblem is solved again.
//! - **Sign guard** (`sign_guard.rs`): a full step that fails only because it adds curvature extrema
//!   is not halved: the extrema count's samples whose `dκ/ds` it flipped are held on their side by
//!   linearised rows in every later subproblem, and the subproblem is solved again, so the next
//!   step can be a full one (halved steps along a direction that crosses `dκ/ds = 0` stop the
//!   stage early at airfoil leading edges).
//! - **Sign targets** ([`super::curvature_signs`]): the persistence-simplified sign pattern of
//!   `dκ/ds` at the Gauss nodes, imposed by an exact penalty; with [`BandOptions::edge_signs`] also
//!   at two nodes 1e-6 of a span from each knot (the span's nearest Gauss node's target), because
//!   `dκ/ds` jumps at a knot and the minimiser of `F` likes a thin wrong-signed sliver there that
//!   no node sees: two real curvature extrema that only the exact count
//!   ([`crate::fair::exact_extrema`]) finds.
//! - **Later passes** ([`later_passes`]): after the polish, one more pass from the polished curve
//!   ([`refair`]), and a pass holding the extrema pattern when that one is kept.
//!
//! Minimising `F` also removes curvature wiggles (each costs `∫(dκ/ds)²`), so curvature extrema
//! usually fall with it. The policy numbers (budgets, step schedule) are in [`BandTuning`](super::tuning::BandTuning).

mod later_passes;
mod model;
mod node_measures;
mod options;
mod schedule;
mod sign_guard;

pub use later_passes::{later_passes, refair};
pub use options::{BandFaired, BandOptions};

use super::control_map::ControlMap;
use super::extrema::ExtremaCount;
use crate::nurbs::Vec3;
use crate::optim::search::objective::{EvalWorkspace, FitData, MAX_DEGREE};
use model::Model;
use node_measures::node_fairness;
use schedule::Pass;

/// Fairs the control points in `ws.ctrl` (knots `ws.knots` fixed, and the end points unless
/// [`BandOptions::ends`] frees them) so that `F` decreases while every data point stays within
/// `tol` (or within its starting distance, if larger). `start` holds the data's parameters on the
/// current curve (projection seeds). On return `ws` holds the faired curve, its power form and foot parameters.
pub fn band_fair(
    data: &FitData,
    ws: &mut EvalWorkspace,
    start: &[f64],
    tol: f64,
    opts: &BandOptions,
) -> BandFaired {
    let map = ControlMap::open_for(ws.ctrl.len(), data, opts.ends);
    band_fair_mapped(data, ws, start, tol, opts, &map)
}

/// [`band_fair`] moving the movable points of `map` (for a periodic curve every distinct control
/// point, the seam kept `C^(p−1)`), with the data points and measure of `map`.
pub fn band_fair_mapped(
    data: &FitData,
    ws: &mut EvalWorkspace,
    start: &[f64],
    tol: f64,
    opts: &BandOptions,
    map: &ControlMap,
) -> BandFaired {
    band_fair_counted(data, ws, start, tol, opts, map, None)
}

/// [`band_fair_mapped`] with the extrema counter of the curve's knots, degree and count when the
/// caller has one ([`refair`]: one node rule instead of two).
fn band_fair_counted(
    data: &FitData,
    ws: &mut EvalWorkspace,
    start: &[f64],
    tol: f64,
    opts: &BandOptions,
    map: &ControlMap,
    counter: Option<&mut ExtremaCount>,
) -> BandFaired {
    let p = data.degree;
    let n = ws.ctrl.len();
    let m = data.points.len();
    let cur = map.measure(data, start, ws);
    let mut out = BandFaired {
        eval: cur,
        steps: 0,
        solves: 0,
        stalled: false,
    };
    if !cur.solved || !cur.fairness.is_finite() || n < 3 || m < 3 || !(3..=MAX_DEGREE).contains(&p)
    {
        return out;
    }
    let mut model = Model::new(data, &ws.knots, n, tol, opts, map, &cur);
    let (cur_f, start_fmax, _) = node_fairness(&model.nodes, &ws.ctrl, p, data.planar);
    let mut own;
    let extrema = match counter {
        Some(c) => c,
        None => {
            own = ExtremaCount::new(&ws.knots, p, n, data.planar);
            &mut own
        }
    };
    let cur_ext = extrema.count(&ws.ctrl);
    model.span_cap = model.span_cap.max(start_fmax);
    if !cur_f.is_finite() {
        return out;
    }
    model.set_targets(&ws.ctrl, &ws.knots, opts);
    let mut pass = Pass {
        work: model.work(m),
        trial_res: vec![0.0; model.nodes.len()],
        trial_edge: vec![0.0; model.edges.len()],
        model,
        extrema,
        guard: Default::default(),
        ctrl: ws.ctrl.clone(),
        feet: ws.foot_params.clone(),
        cur_f,
        cur_ext,
        mu: opts.step.mu_start,
        small_gains: 0,
        shrink: vec![0.0; m],
        ipm: Default::default(),
    };
    while out.solves < opts.max_solves {
        let st = &opts.step;
        let Some(lin) =
            pass.model
                .linearise(&pass.ctrl, pass.cur_f, map, st.sign_weight, &mut pass.work)
        else {
            break;
        };
        pass.model.push_cones_and_signs(
            data,
            &ws.knots,
            &pass.ctrl,
            &pass.feet,
            opts,
            map,
            &lin,
            &mut pass.work,
        );
        let o = pass.solve(data, ws, tol, opts, map, &lin, &mut out);
        if (!o.accepted && !o.guarded) || pass.small_gains >= st.small_gain_steps || o.converged {
            out.stalled = !o.accepted && !o.guarded && !o.converged;
            break;
        }
    }
    finish(data, ws, &pass.ctrl, &pass.feet, out, map)
}

/// Leaves the curve with control points `ctrl` measured in `ws` (feet from `feet`).
fn finish(
    data: &FitData,
    ws: &mut EvalWorkspace,
    ctrl: &[Vec3],
    feet: &[f64],
    mut out: BandFaired,
    map: &ControlMap,
) -> BandFaired {
    ws.ctrl.copy_from_slice(ctrl);
    out.eval = map.measure(data, feet, ws);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;
    use crate::optim::search::objective::{evaluate_candidate, set_knots};

    /// Largest distance from the points to the curve, by brute force on `samples + 1` curve points
    /// (independent of the projection used inside).
    fn brute_force_deviation(curve: &NurbsCurve, points: &[Vec3], samples: usize) -> f64 {
        let pts: Vec<Vec3> = (0..=samples)
            .map(|i| curve.point(i as f64 / samples as f64))
            .collect();
        points
            .iter()
            .map(|q| {
                pts.iter()
                    .map(|s| (*s - *q).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0f64, f64::max)
    }

    /// `L³ ∫ (dκ/ds)² ds` of a planar curve by finite differences of the curvature on a dense
    /// uniform grid (independent of the Gauss rules used inside).
    fn dense_fairness(curve: &NurbsCurve, samples: usize) -> f64 {
        let h = 1.0 / samples as f64;
        let (mut length, mut kappa, mut speed) = (0.0, Vec::new(), Vec::new());
        for i in 0..samples {
            let u = (i as f64 + 0.5) * h;
            let d = curve.derivatives(u, 2);
            let v = d[1].norm();
            kappa.push((d[1][0] * d[2][1] - d[1][1] * d[2][0]) / (v * v * v));
            speed.push(v);
            length += v * h;
        }
        let mut integral = 0.0;
        for i in 1..samples {
            let ds = 0.5 * (speed[i] + speed[i - 1]) * h;
            let dk = kappa[i] - kappa[i - 1];
            integral += dk * dk / ds;
        }
        length.powi(3) * integral
    }
    #[test]
    fn a_noisy_circle_arc_is_faired_to_nearly_constant_curvature_within_the_band() {
        // 120 points of a 120° arc of radius 1 with ±0.4 tol of radial noise: the exact arc lies
        // inside the band and has F = 0; the least-squares fit with 12 control points follows the
        // noise (F ≈ 0.09). Band fairing must bring F close to 0 with every point still within tol
        // (brute force on 400 001 curve samples, F by finite differences of κ on 20 000 cells).
        let (m, tol) = (120, 2e-3);
        let points: Vec<Vec3> = (0..m)
            .map(|i| {
                let t = 2.0 * std::f64::consts::FRAC_PI_3 * i as f64 / (m - 1) as f64;
                let noise = if i == 0 || i == m - 1 {
                    0.0
                } else {
                    0.4 * tol * (1.7 * i as f64).sin()
                };
                Vec3([(1.0 + noise) * t.cos(), (1.0 + noise) * t.sin(), 0.0])
            })
            .collect();
        let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
        let data = FitData {
            points: points.clone(),
            params,
            degree: 3,
            planar: true,
            corrections: 1,
            ends: Default::default(),
            bands: Default::default(),
        };
        let mut ws = EvalWorkspace::default();
        let interior: Vec<f64> = (1..9).map(|i| i as f64 / 9.0).collect();
        set_knots(3, &interior, &mut ws);
        let lsq = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
        assert!(
            lsq.solved && lsq.max_deviation < tol,
            "{}",
            lsq.max_deviation
        );
        let before = NurbsCurve::bspline(3, ws.knots.clone(), ws.ctrl.clone()).unwrap();
        let f_before = dense_fairness(&before, 20_000);
        let start = ws.foot_params.clone();
        // F alone (on an arc dκ/ds is nearly 0 everywhere, so the extrema guard would only count
        // sign changes of round-off-sized ripples)
        let bo = BandOptions {
            keep_extrema: false,
            extrema_persistence: 0.0,
            ..BandOptions::default()
        };
        let r = band_fair(&data, &mut ws, &start, tol, &bo);
        let after = NurbsCurve::bspline(3, ws.knots.clone(), ws.ctrl.clone()).unwrap();
        let f_after = dense_fairness(&after, 20_000);
        eprintln!("F {f_before:.4e} -> {f_after:.4e} in {} steps", r.steps);
        assert!(r.steps > 0);
        // (measured: 0.094 -> 7.3e-4)
        assert!(f_before > 0.05, "{f_before}");
        assert!(f_after < 0.02 * f_before && f_after < 2e-3, "{f_after}");
        let dev = brute_force_deviation(&after, &points, 400_000);
        assert!(dev <= tol, "{dev} > {tol}");
        // the end points stay where the data end
        assert!((after.point(0.0) - points[0]).norm() < 1e-12);
        assert!((after.point(1.0) - points[m - 1]).norm() < 1e-12);
    }
}
