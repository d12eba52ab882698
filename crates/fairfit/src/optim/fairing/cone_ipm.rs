//! A primal–dual interior-point solver for band fairing's subproblems ([`BandQp`]) that exploits
//! their shape: a few dozen step variables, hundreds of 3- or 4-row second-order cones and sign
//! rows that each touch only the 8–12 variables of one knot span's control points, and one
//! L1-penalised slack per soft row.
//!
//! The method is CVXOPT's `coneqp` (Vandenberghe, "The CVXOPT linear and quadratic cone program
//! solvers", 2010): Nesterov–Todd scaling, Mehrotra's predictor–corrector with the step-dependent
//! centring `σ = (1 − α + α² ds_aᵀdz_a / sᵀz)³`, steps of 0.99 of the way to the boundary. Each
//! Newton system is reduced to the dense normal matrix of the step variables,
//! `P + Σ_k (W_k⁻¹G_k)ᵀ(W_k⁻¹G_k) + Σ_j d_j g_j g_jᵀ`, assembled from every cone's small dense
//! block and every row's few entries (on windows of consecutive variables padded to a fixed
//! width, so the kernels have fixed sizes), with the slacks eliminated in closed form (each sits
//! in only its row and its own sign row), and factorised by a dense Cholesky, against a sparse
//! `LDLᵀ` of the whole KKT matrix (≈ 1400 rows with the sign targets) in a general solver:
//! about 15× fewer instructions per subproblem (measured in docs/optim.md).
//!
//! Start: not CVXOPT's least-squares point (it treats the sign rows as equations and lands tens
//! of band widths away) but the current curve (`x = 0`, feasible for the cones), each slack at
//! its row's violation plus one, `s` lifted to an eigenvalue of at least 0.5 and the perfectly
//! centred `z = μ₀ s⁻¹`; the iterations are infeasible-start ones as in CVXOPT.
//!
//! Scaling: the step variables are measured in units of the largest cone radius (the band's
//! width), every cone is divided by it, every linear row by the norm of its coefficients in those
//! units, and the objective by its largest curvature or gradient entry, so the stopping tests are
//! relative to the band. Deterministic and serial. `None` when it does not converge (for example
//! an infeasible subproblem): the caller falls back to [`BandQp::solve_clarabel`].

use super::band_qp::BandQp;
use super::cone_algebra::{arr, arr_mut, dot, jprod, nt_scaling};
use super::cone_newton::{factor, g_mul, gt_mul_add, max_step, newton, w_mul, Data, State, Window};

/// Most iterations before giving up.
const MAX_ITER: usize = 60;
/// Primal and dual residuals, relative to the scaled data.
const FEAS_TOL: f64 = 1e-8;
/// Duality gap, absolute (scaled objective) and relative to the objective. Tighter (1e-9, 1e-10)
/// costs 10 % more iterations for the same F to 6 digits on the benchmark's 200-point curves.
const GAP_ABS: f64 = 1e-8;
const GAP_REL: f64 = 1e-7;
/// Fraction of the way to the cone's boundary a step goes.
const STEP: f64 = 0.99;
/// The start's smallest eigenvalue of `s` (in units of the band width) and its `μ₀`: the
/// current curve is primal feasible up to the lift, `z = μ₀ s⁻¹` is perfectly centred, and the
/// scaled objective's curvature is at most 1. 15 % fewer iterations than CVXOPT's least-squares
/// start on the benchmark's 200-point curves (which pulls the step tens of band widths away
/// towards the sign rows' far side).
const START_MARGIN: f64 = 0.5;
const START_MU: f64 = 10.0;

/// Work arrays of [`solve`], reused between subproblems, and its answer.
#[derive(Default)]
pub struct IpmWork {
    data: Data,
    st: State,
    /// The solution in the caller's units.
    pub solution: Vec<f64>,
    /// Iterations of the last solve.
    pub iterations: usize,
    /// Why the last solve stopped.
    pub status: &'static str,
}

/// Solves `qp` into `w.solution` (the step variables, in the caller's units); `false` when it
/// does not converge or the cones are not all of dimension 3 or 4 (then nothing is solved).
pub fn solve(qp: &BandQp, w: &mut IpmWork) -> bool {
    w.iterations = 0;
    w.status = "unsupported";
    let nc = qp.cones();
    let d = if nc > 0 {
        qp.cone_row[1] - qp.cone_row[0]
    } else {
        3
    };
    if (0..nc).any(|k| qp.cone_row[k + 1] - qp.cone_row[k] != d) {
        return false;
    }
    match d {
        3 => solve_d::<3>(qp, w),
        4 => solve_d::<4>(qp, w),
        _ => false,
    }
}

/// [`solve`] with cones of dimension `D`.
fn solve_d<const D: usize>(qp: &BandQp, w: &mut IpmWork) -> bool {
    let dt = &mut w.data;
    let nv = qp.nv;
    let nc = qp.cones();
    let nr = qp.rows();
    let l0 = qp.cone_row[nc];
    dt.nv = nv;
    dt.nc = nc;
    dt.nr = nr;
    dt.slack_of.clear();
    dt.row_of.clear();
    for (j, &soft) in qp.soft.iter().enumerate() {
        if soft {
            dt.slack_of.push(dt.row_of.len());
            dt.row_of.push(j);
        } else {
            dt.slack_of.push(usize::MAX);
        }
    }
    dt.nt = dt.row_of.len();
    // scaling (module doc): x = sx y, cones / sx, rows / (sx ‖g‖), objective / kappa
    let sx = (0..nc)
        .map(|k| qp.h[qp.cone_row[k]].abs())
        .fold(0.0f64, f64::max);
    let sx = if sx > 0.0 && sx.is_finite() { sx } else { 1.0 };
    let ns = dt.ns::<D>();
    dt.h.clear();
    dt.h.resize(ns, 0.0);
    for (a, b) in dt.h[..l0].iter_mut().zip(&qp.h[..l0]) {
        *a = b / sx;
    }
    // cones and rows on windows of consecutive variables
    dt.cwin.clear();
    dt.cvals.clear();
    for k in 0..nc {
        let cols = &qp.cols[qp.cone_col[k]..qp.cone_col[k + 1]];
        let m = cols.len();
        let blk = &qp.block[qp.cone_block[k]..qp.cone_block[k + 1]];
        let win = Window::of(cols, dt.cvals.len());
        dt.cvals.resize(win.off + D * win.m, 0.0);
        for r in 0..D {
            for (a, &c) in cols.iter().enumerate() {
                dt.cvals[win.off + r * win.m + c - win.c0] = blk[r * m + a];
            }
        }
        dt.cwin.push(win);
    }
    dt.rwin.clear();
    dt.rvals.clear();
    let mut row_scale = Vec::with_capacity(nr);
    for j in 0..nr {
        let e = qp.row_start[j]..qp.row_start[j + 1];
        let (cols, vals) = (&qp.row_cols[e.clone()], &qp.row_vals[e]);
        let lo = cols.iter().copied().min().unwrap_or(0);
        let hi = cols.iter().copied().max().unwrap_or(0);
        let win = Window {
            c0: lo,
            m: if cols.is_empty() { 0 } else { hi - lo + 1 },
            off: dt.rvals.len(),
        };
        let norm = dot(vals, vals).sqrt() * sx;
        let n = if norm > 0.0 { norm } else { 1.0 };
        row_scale.push(n);
        dt.rvals.resize(win.off + win.m, 0.0);
        for (&c, &v) in cols.iter().zip(vals) {
            dt.rvals[win.off + c - lo] += v * sx / n;
        }
        dt.rwin.push(win);
        dt.h[nc * D + j] = qp.h[l0 + j] / n;
    }
    // windows up to 16 wide are padded to a common width M of 6, 8, 12 or 16 (zeros; 6: degree 2
    // or a planar curve of 5 control points), shifted to fit in 0..nv:
    // fixed-size kernels for them; wider ones (a periodic seam) keep their width
    let widest = dt
        .cwin
        .iter()
        .chain(&dt.rwin)
        .map(|w| w.m)
        .filter(|&m| m <= 16)
        .max()
        .unwrap_or(0);
    let mw = [6, 8, 12, 16]
        .into_iter()
        .find(|&m| m >= widest && m <= nv)
        .unwrap_or(0);
    if mw > 0 {
        pad(&mut dt.cwin, &mut dt.cvals, D, mw, nv);
        pad(&mut dt.rwin, &mut dt.rvals, 1, mw, nv);
    }
    // every cone's first row of G zero (as +0.0): the kernels skip it (cone_newton::Data)
    dt.head_zero = dt.cwin.iter().all(|w| {
        dt.cvals[w.off..w.off + w.m]
            .iter()
            .all(|v| v.to_bits() == 0)
    });
    let mut kappa = 0.0f64;
    for a in 0..nv {
        kappa = kappa
            .max(qp.p[a * nv + a] * sx * sx)
            .max((qp.q[a] * sx).abs());
    }
    let kappa = if kappa > 0.0 && kappa.is_finite() {
        kappa
    } else {
        1.0
    };
    dt.p.clear();
    dt.p.extend(qp.p.iter().map(|v| v * sx * sx / kappa));
    dt.q.clear();
    dt.q.extend(qp.q.iter().map(|v| v * sx / kappa));
    for &j in &dt.row_of {
        dt.q.push(qp.slack_weight * row_scale[j] / kappa);
    }
    let (dt, st, it, status) = (&w.data, &mut w.st, &mut w.iterations, &mut w.status);
    let ok = match mw {
        6 => iterate::<D, 6>(dt, st, it, status),
        8 => iterate::<D, 8>(dt, st, it, status),
        12 => iterate::<D, 12>(dt, st, it, status),
        16 => iterate::<D, 16>(dt, st, it, status),
        _ => iterate::<D, 0>(dt, st, it, status),
    };
    if ok {
        w.solution.clear();
        w.solution.extend(w.st.x[..nv].iter().map(|v| v * sx));
    }
    ok
}

/// Pads every window of at most `mw` variables (`d` rows of values each) to exactly `mw`,
/// shifted left where it would end past `nv`; `vals` is rebuilt.
fn pad(wins: &mut [Window], vals: &mut Vec<f64>, d: usize, mw: usize, nv: usize) {
    let old = std::mem::take(vals);
    for w in wins.iter_mut() {
        let src = &old[w.off..w.off + d * w.m];
        let off = vals.len();
        if w.m > mw {
            vals.extend_from_slice(src);
            w.off = off;
            continue;
        }
        let c0 = w.c0.min(nv - mw);
        let shift = w.c0 - c0;
        vals.resize(off + d * mw, 0.0);
        for r in 0..d {
            for a in 0..w.m {
                vals[off + r * mw + shift + a] = src[r * w.m + a];
            }
        }
        *w = Window { c0, m: mw, off };
    }
}

/// Whether a point where the iterations cannot go on is accurate enough (looser tolerances, as a
/// general solver's "almost solved").
fn almost(pres: f64, dres: f64, gap: f64, pcost: f64) -> bool {
    pres <= 1e3 * FEAS_TOL
        && dres <= 1e3 * FEAS_TOL
        && (gap <= 1e3 * GAP_ABS || gap <= 1e3 * GAP_REL * pcost.abs())
}

fn resize(v: &mut Vec<f64>, n: usize) {
    v.clear();
    v.resize(n, 0.0);
}

/// The interior-point iterations on the scaled problem `dt`.
fn iterate<const D: usize, const M: usize>(
    dt: &Data,
    st: &mut State,
    iterations: &mut usize,
    status: &mut &'static str,
) -> bool {
    *status = "max iterations";
    size_buffers::<D>(dt, st);
    start_point::<D, M>(dt, st);
    let resx0 = dot(&dt.q, &dt.q).sqrt().max(1.0);
    let resz0 = dot(&dt.h, &dt.h).sqrt().max(1.0);
    let nu = (dt.nc + dt.nr + dt.nt) as f64;
    for it in 0..MAX_ITER {
        *iterations = it;
        let pcost = residuals::<D, M>(dt, st);
        let gap = dot(&st.s, &st.z);
        let pres = dot(&st.rz, &st.rz).sqrt() / resz0;
        let dres = dot(&st.rx, &st.rx).sqrt() / resx0;
        if !(gap.is_finite() && pres.is_finite() && dres.is_finite()) {
            *status = "not finite";
            return false;
        }
        if pres <= FEAS_TOL && dres <= FEAS_TOL && (gap <= GAP_ABS || gap <= GAP_REL * pcost.abs())
        {
            *status = "solved";
            return st.x.iter().all(|v| v.is_finite());
        }
        if let Err(e) = scaling::<D>(dt, st) {
            *status = e;
            return match e {
                "cone not interior" => {
                    almost(pres, dres, gap, pcost) && st.x.iter().all(|v| v.is_finite())
                }
                _ => false,
            };
        }
        if !factor::<D, M>(dt, st) {
            // the normal matrix lost definiteness to round-off near the optimum
            *status = "cholesky";
            return almost(pres, dres, gap, pcost) && st.x.iter().all(|v| v.is_finite());
        }
        lambda_squared::<D>(dt, st);
        let mu = gap / nu;
        let sigma = predictor::<D, M>(dt, st, gap);
        corrector::<D, M>(dt, st, sigma, mu);
        if !take_step::<D, M>(dt, st) {
            *status = "step";
            return false;
        }
    }
    false
}

/// Sizes every work vector of `st` for `dt` (zeroed): `x`-sized, cone-and-row-sized, one `η` per
/// cone and one `d` per row. Reuses the allocations across calls.
fn size_buffers<const D: usize>(dt: &Data, st: &mut State) {
    let (nx, ns) = (dt.nx(), dt.ns::<D>());
    let nl = dt.nr + dt.nt;
    for v in [&mut st.x, &mut st.rx, &mut st.dx] {
        resize(v, nx);
    }
    for v in [
        &mut st.s,
        &mut st.z,
        &mut st.lambda,
        &mut st.lsq,
        &mut st.v,
        &mut st.rz,
        &mut st.wrz,
        &mut st.rc,
        &mut st.u,
        &mut st.t1,
        &mut st.t2,
        &mut st.gdx,
        &mut st.ds,
        &mut st.dz,
        &mut st.dsa,
        &mut st.dza,
    ] {
        resize(v, ns);
    }
    resize(&mut st.eta, dt.nc);
    resize(&mut st.dl, nl);
}

/// The starting point (module doc): the current curve, slacks at their rows' violation plus one,
/// `s` lifted strictly into the cone, `z = μ₀ s⁻¹`. On return `s` and `z` are interior.
fn start_point<const D: usize, const M: usize>(dt: &Data, st: &mut State) {
    let (nv, ns) = (dt.nv, dt.ns::<D>());
    let l0 = dt.nc * D;
    st.x.fill(0.0);
    for (t, &j) in dt.row_of.iter().enumerate() {
        st.x[nv + t] = (-dt.h[l0 + j]).max(0.0) + 1.0;
    }
    g_mul::<D, M>(dt, &st.x, &mut st.gdx);
    for i in 0..ns {
        st.s[i] = dt.h[i] - st.gdx[i];
    }
    for (sk, zk) in st.s[..l0]
        .chunks_exact_mut(D)
        .zip(st.z[..l0].chunks_exact_mut(D))
    {
        let norm = dot(&sk[1..], &sk[1..]).sqrt();
        sk[0] = sk[0].max(norm + START_MARGIN);
        let det = sk[0] * sk[0] - norm * norm;
        zk[0] = START_MU * sk[0] / det;
        for r in 1..D {
            zk[r] = -START_MU * sk[r] / det;
        }
    }
    for (si, zi) in st.s[l0..].iter_mut().zip(&mut st.z[l0..]) {
        *si = si.max(START_MARGIN);
        *zi = START_MU / *si;
    }
}

/// The residuals `rx = P x + q + Gᵀ z` and `rz = G x + s − h` at the current point; returns the
/// primal cost `½ xᵀP x + qᵀx` (summed in `x` order, in the same pass as `rx`).
fn residuals<const D: usize, const M: usize>(dt: &Data, st: &mut State) -> f64 {
    let (nv, nx, ns) = (dt.nv, dt.nx(), dt.ns::<D>());
    let mut pcost = 0.0;
    for i in 0..nx {
        let px = if i < nv {
            dot(&dt.p[i * nv..(i + 1) * nv], &st.x[..nv])
        } else {
            0.0
        };
        pcost += st.x[i] * (0.5 * px + dt.q[i]);
        st.rx[i] = px + dt.q[i];
    }
    gt_mul_add::<D, M>(dt, &st.z, &mut st.rx);
    g_mul::<D, M>(dt, &st.x, &mut st.gdx);
    for i in 0..ns {
        st.rz[i] = st.gdx[i] + st.s[i] - dt.h[i];
    }
    pcost
}

/// The Nesterov–Todd scaling `W` at the current point (`η`, `v` per cone, `d` per row), then
/// `λ = W z` and `W⁻¹ rz`. Errs with the status when a cone or a row has left the interior (the
/// cones are checked first, and nothing after the failing one is computed).
fn scaling<const D: usize>(dt: &Data, st: &mut State) -> Result<(), &'static str> {
    let l0 = dt.nc * D;
    let nl = dt.nr + dt.nt;
    for (((sk, zk), vk), eta) in st.s[..l0]
        .chunks_exact(D)
        .zip(st.z[..l0].chunks_exact(D))
        .zip(st.v[..l0].chunks_exact_mut(D))
        .zip(st.eta.iter_mut())
    {
        match nt_scaling::<D>(arr(sk), arr(zk), arr_mut(vk)) {
            Some(e) => *eta = e,
            None => return Err("cone not interior"),
        }
    }
    for i in 0..nl {
        let (si, zi) = (st.s[l0 + i], st.z[l0 + i]);
        if !(si > 0.0 && zi > 0.0) {
            return Err("row not interior");
        }
        st.dl[i] = (si / zi).sqrt();
    }
    w_mul::<D, false>(dt, &st.eta, &st.v, &st.dl, &st.z, &mut st.lambda);
    w_mul::<D, true>(dt, &st.eta, &st.v, &st.dl, &st.rz, &mut st.wrz);
    Ok(())
}

/// `λ ∘ λ` into `st.lsq`: the Jordan product per cone, the plain square per row.
fn lambda_squared<const D: usize>(dt: &Data, st: &mut State) {
    let l0 = dt.nc * D;
    let ns = dt.ns::<D>();
    for (l, o) in st.lambda[..l0]
        .chunks_exact(D)
        .zip(st.lsq[..l0].chunks_exact_mut(D))
    {
        jprod::<D>(arr(l), arr(l), arr_mut(o));
    }
    for i in l0..ns {
        st.lsq[i] = st.lambda[i] * st.lambda[i];
    }
}

/// The affine (predictor) Newton direction for the right-hand side `−λ∘λ`, left in `st.ds`/`st.dz`;
/// returns the centring weight `σ = (1 − α + α² ds·dz / gap)³`, clamped to `[0, 1]` before the cube.
fn predictor<const D: usize, const M: usize>(dt: &Data, st: &mut State, gap: f64) -> f64 {
    for (r, &l) in st.rc.iter_mut().zip(&st.lsq) {
        *r = -l;
    }
    newton::<D, M>(dt, st);
    let step = max_step::<D, M>(dt, &st.s, &st.ds)
        .min(max_step::<D, M>(dt, &st.z, &st.dz))
        .min(1.0);
    let dsdz = dot(&st.ds, &st.dz);
    (1.0 - step + dsdz / gap * step * step)
        .clamp(0.0, 1.0)
        .powi(3)
}

/// The combined (corrector) Newton direction for `−λ∘λ − (W⁻¹ ds_a) ∘ (W dz_a) + σ μ e`, where
/// `ds_a`, `dz_a` are the predictor's direction in `st.ds`/`st.dz`; overwrites them.
fn corrector<const D: usize, const M: usize>(dt: &Data, st: &mut State, sigma: f64, mu: f64) {
    let l0 = dt.nc * D;
    let ns = dt.ns::<D>();
    w_mul::<D, true>(dt, &st.eta, &st.v, &st.dl, &st.ds, &mut st.dsa);
    w_mul::<D, false>(dt, &st.eta, &st.v, &st.dl, &st.dz, &mut st.dza);
    for (((a, b), r), l) in st.dsa[..l0]
        .chunks_exact(D)
        .zip(st.dza[..l0].chunks_exact(D))
        .zip(st.rc[..l0].chunks_exact_mut(D))
        .zip(st.lsq[..l0].chunks_exact(D))
    {
        let mut prod = [0.0; D];
        jprod::<D>(arr(a), arr(b), &mut prod);
        for i in 0..D {
            r[i] = -l[i] - prod[i];
        }
        r[0] += sigma * mu;
    }
    for i in l0..ns {
        st.rc[i] = -st.lsq[i] - st.dsa[i] * st.dza[i] + sigma * mu;
    }
    newton::<D, M>(dt, st);
}

/// Moves `(x, s, z)` along the corrector's direction by `STEP` times the largest step that keeps
/// `s` and `z` interior (at most 1). False, with nothing moved, when that step is not positive
/// and finite.
fn take_step<const D: usize, const M: usize>(dt: &Data, st: &mut State) -> bool {
    let ns = dt.ns::<D>();
    let alpha = (STEP
        * max_step::<D, M>(dt, &st.s, &st.ds).min(max_step::<D, M>(dt, &st.z, &st.dz)))
    .min(1.0);
    if !(alpha > 0.0 && alpha.is_finite()) {
        return false;
    }
    for (x, &d) in st.x.iter_mut().zip(&st.dx) {
        *x += alpha * d;
    }
    for i in 0..ns {
        st.s[i] += alpha * st.ds[i];
        st.z[i] += alpha * st.dz[i];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `min ½‖x − a‖²` over the unit disc (a cone `(1, x) ∈ Q`), with `x₀ ≥ 0.2` as a hard row
    /// (`soft`: an L1-penalised row of weight 0.5).
    fn disc_problem(a: [f64; 2], soft: bool) -> BandQp {
        let mut qp = BandQp::default();
        qp.reset(2);
        qp.p.copy_from_slice(&[1.0, 0.0, 0.0, 1.0]);
        qp.q.copy_from_slice(&[-a[0], -a[1]]);
        qp.slack_weight = 0.5;
        qp.push_cone(&[1.0, 0.0, 0.0], &[(1, 0, -1.0), (2, 1, -1.0)]);
        // −0.2 − (−1) x₀ ≥ 0
        qp.push_row(-0.2, [(0, -1.0)], soft);
        qp.end_group();
        qp
    }

    /// Asserts that this solver and clarabel both reach the known minimiser `best` of `qp`: the
    /// objective within 1e-7 of its optimum (both stop at relative duality gaps of ~1e-7), the
    /// constraints met to 1e-8, and the point within `tol` (where the active constraint is curved,
    /// as a disc's edge, the gap bounds the distance only by its square root: ~1e-4).
    fn assert_solves(qp: &BandQp, best: &[f64], tol: f64) {
        let mut w = IpmWork::default();
        assert!(solve(qp, &mut w), "{}", w.status);
        let (optimum, _) = qp.evaluate(best);
        for x in [w.solution.clone(), qp.solve_clarabel().expect("clarabel")] {
            let (obj, viol) = qp.evaluate(&x);
            assert!(
                obj - optimum < 1e-7 * optimum.abs().max(1.0) && viol < 1e-8,
                "{obj} {optimum} {viol}"
            );
            for (a, b) in x.iter().zip(best) {
                assert!((a - b).abs() < tol, "{x:?} {best:?}");
            }
        }
    }

    #[test]
    fn a_projection_onto_a_disc_with_a_half_plane_is_exact() {
        // for a = (−1, 2) the half-plane is active: (0.2, sqrt(1 − 0.04)) on the circle (the
        // corner: the point is pinned by two constraints)
        assert_solves(
            &disc_problem([-1.0, 2.0], false),
            &[0.2, 0.96f64.sqrt()],
            1e-6,
        );
        // with the row soft (weight 0.5) it gives way: ½‖x − a‖² − 0.5 x₀ + const is
        // ½‖x − a'‖² with a' = (−0.5, 2), projected onto the disc
        let n = 4.25f64.sqrt();
        assert_solves(&disc_problem([-1.0, 2.0], true), &[-0.5 / n, 2.0 / n], 2e-4);
        // a point inside the disc and the half-plane is its own projection
        assert_solves(&disc_problem([0.3, -0.4], false), &[0.3, -0.4], 1e-6);
    }

    #[test]
    fn a_projection_onto_a_ball_in_three_dimensions_is_exact() {
        // min ½‖x − a‖² over ‖x − c‖ ≤ 0.5 (a cone of dimension 4): c + 0.5 (a − c)/‖a − c‖
        let (a, c) = ([1.0, 2.0, -2.0], [0.1, 0.2, 0.3]);
        let mut qp = BandQp::default();
        qp.reset(3);
        for i in 0..3 {
            qp.p[i * 3 + i] = 1.0;
            qp.q[i] = -a[i];
        }
        // (0.5, x − c) = h − G x with h = (0.5, −c), G = (0; −I)
        qp.push_cone(
            &[0.5, -c[0], -c[1], -c[2]],
            &[(1, 0, -1.0), (2, 1, -1.0), (3, 2, -1.0)],
        );
        let d: Vec<f64> = (0..3).map(|i| a[i] - c[i]).collect();
        let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        let best: Vec<f64> = (0..3).map(|i| c[i] + 0.5 * d[i] / norm).collect();
        assert_solves(&qp, &best, 2e-4);
    }

    #[test]
    fn an_infeasible_problem_is_not_solved() {
        // x₀ ≥ 2 as a hard row, but the cone keeps ‖x‖ ≤ 1
        let mut qp = disc_problem([0.0, 0.0], false);
        qp.h[qp.cone_row[1]] = -2.0;
        let mut w = IpmWork::default();
        assert!(!solve(&qp, &mut w));
        assert!(qp.solve_clarabel().is_none());
    }
}
