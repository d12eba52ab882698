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
//! ~15× fewer instructions per subproblem (docs/optim.md, "Speed, session 7").
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
use super::cone_algebra::{
    arr, arr_mut, chol_solve, cholesky, cone_step, dot, jdiv, jprod, nt_scaling, scale_cone,
};

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

/// The scaled problem (module doc) in the solver's layout: every cone has the same dimension `D`
/// and occupies rows `k D .. (k + 1) D` of the stacked `s`, `z`; then the linear rows, then one
/// sign row per slack.
#[derive(Default)]
struct Data {
    nv: usize,
    /// Linear rows, slacks, cones.
    nr: usize,
    nt: usize,
    nc: usize,
    p: Vec<f64>,
    q: Vec<f64>,
    h: Vec<f64>,
    /// Per cone, the window of consecutive variables its `G_k` touches: first variable, width,
    /// offset of its values in `cvals` (`G_k` restricted to the window, `D × width` row-major,
    /// zeros where it does not touch a variable of the window).
    cwin: Vec<Window>,
    cvals: Vec<f64>,
    /// The same per linear row (`g_j` on its window, in `rvals`).
    rwin: Vec<Window>,
    rvals: Vec<f64>,
    /// Per linear row, its slack (`usize::MAX`: hard); per slack, its row.
    slack_of: Vec<usize>,
    row_of: Vec<usize>,
}

impl Data {
    fn nx(&self) -> usize {
        self.nv + self.nt
    }

    fn ns<const D: usize>(&self) -> usize {
        self.nc * D + self.nr + self.nt
    }
}

/// Consecutive variables `c0 .. c0 + m` and where their values start.
#[derive(Clone, Copy, Debug, Default)]
struct Window {
    c0: usize,
    m: usize,
    off: usize,
}

impl Window {
    /// The window of the sorted variables `cols` (empty: width 0).
    fn of(cols: &[usize], off: usize) -> Window {
        match (cols.first(), cols.last()) {
            (Some(&a), Some(&b)) => Window {
                c0: a,
                m: b - a + 1,
                off,
            },
            _ => Window { c0: 0, m: 0, off },
        }
    }

    fn vars(&self) -> std::ops::Range<usize> {
        self.c0..self.c0 + self.m
    }
}

/// The iterates and work arrays.
#[derive(Default)]
struct State {
    x: Vec<f64>,
    s: Vec<f64>,
    z: Vec<f64>,
    lambda: Vec<f64>,
    lsq: Vec<f64>,
    /// Per cone `η`; per cone row the scaling vector `v`; per linear and slack row `sqrt(s/z)`.
    eta: Vec<f64>,
    v: Vec<f64>,
    dl: Vec<f64>,
    /// The normal matrix and its Cholesky factor.
    chol: Vec<f64>,
    /// Per slack: the diagonal of the eliminated block and `1/d²` of its row.
    htt: Vec<f64>,
    arow: Vec<f64>,
    /// `W⁻¹ G_k`, column by column.
    block: Vec<f64>,
    rx: Vec<f64>,
    rz: Vec<f64>,
    rc: Vec<f64>,
    u: Vec<f64>,
    t1: Vec<f64>,
    t2: Vec<f64>,
    gdx: Vec<f64>,
    dx: Vec<f64>,
    ds: Vec<f64>,
    dz: Vec<f64>,
    dsa: Vec<f64>,
    dza: Vec<f64>,
}

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

/// The `D × M` values of a full-width window, row by row.
#[inline]
fn rows_of<const D: usize, const M: usize>(v: &[f64]) -> [&[f64; M]; D] {
    std::array::from_fn(|r| arr(&v[r * M..(r + 1) * M]))
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

/// `out = G x` (`x` of length `nx`).
fn g_mul<const D: usize, const M: usize>(dt: &Data, x: &[f64], out: &mut [f64]) {
    let l0 = dt.nc * D;
    for (o, win) in out[..l0].chunks_exact_mut(D).zip(&dt.cwin) {
        let g = &dt.cvals[win.off..win.off + D * win.m];
        if M > 0 && win.m == M {
            let xw: &[f64; M] = arr(&x[win.vars()]);
            let g = rows_of::<D, M>(g);
            for r in 0..D {
                let mut t = 0.0;
                for b in 0..M {
                    t += g[r][b] * xw[b];
                }
                o[r] = t;
            }
        } else {
            o.fill(0.0);
            for (or, gr) in o.iter_mut().zip(g.chunks_exact(win.m.max(1))) {
                *or = dot(gr, &x[win.vars()]);
            }
        }
    }
    let (lin, slk) = out[l0..].split_at_mut(dt.nr);
    for (j, win) in dt.rwin.iter().enumerate() {
        let g = &dt.rvals[win.off..win.off + win.m];
        let mut v = if M > 0 && win.m == M {
            let (g, xw): (&[f64; M], &[f64; M]) = (arr(g), arr(&x[win.vars()]));
            let mut t = 0.0;
            for b in 0..M {
                t += g[b] * xw[b];
            }
            t
        } else {
            dot(g, &x[win.vars()])
        };
        let t = dt.slack_of[j];
        if t != usize::MAX {
            let xt = x[dt.nv + t];
            v -= xt;
            slk[t] = -xt;
        }
        lin[j] = v;
    }
}

/// `y += f x`.
#[inline]
fn axpy(f: f64, x: &[f64], y: &mut [f64]) {
    for (a, &b) in y.iter_mut().zip(x) {
        *a += f * b;
    }
}

/// `x[c0 .. c0 + M] += f g` for a full-width window (`axpy` otherwise).
#[inline]
fn axpy_win<const M: usize>(f: f64, g: &[f64], x: &mut [f64], win: &Window) {
    if M > 0 && win.m == M {
        let (g, xw): (&[f64; M], &mut [f64; M]) = (arr(g), arr_mut(&mut x[win.vars()]));
        for b in 0..M {
            xw[b] += f * g[b];
        }
    } else {
        axpy(f, g, &mut x[win.vars()]);
    }
}

/// `gᵀ x[c0 ..]` of a window.
#[inline]
fn dot_win<const M: usize>(g: &[f64], x: &[f64], win: &Window) -> f64 {
    if M > 0 && win.m == M {
        let (g, xw): (&[f64; M], &[f64; M]) = (arr(g), arr(&x[win.vars()]));
        let mut t = 0.0;
        for b in 0..M {
            t += g[b] * xw[b];
        }
        t
    } else {
        dot(g, &x[win.vars()])
    }
}

/// `x += Gᵀ z`.
fn gt_mul_add<const D: usize, const M: usize>(dt: &Data, z: &[f64], x: &mut [f64]) {
    let l0 = dt.nc * D;
    for (zk, win) in z[..l0].chunks_exact(D).zip(&dt.cwin) {
        let g = &dt.cvals[win.off..win.off + D * win.m];
        if M > 0 && win.m == M {
            let g = rows_of::<D, M>(g);
            let xw: &mut [f64; M] = arr_mut(&mut x[win.vars()]);
            for b in 0..M {
                let mut t = 0.0;
                for r in 0..D {
                    t += g[r][b] * zk[r];
                }
                xw[b] += t;
            }
        } else {
            for (&zr, gr) in zk.iter().zip(g.chunks_exact(win.m.max(1))) {
                axpy(zr, gr, &mut x[win.vars()]);
            }
        }
    }
    let (lin, slk) = z[l0..].split_at(dt.nr);
    for (j, win) in dt.rwin.iter().enumerate() {
        let zj = lin[j];
        axpy_win::<M>(zj, &dt.rvals[win.off..win.off + win.m], x, win);
        let t = dt.slack_of[j];
        if t != usize::MAX {
            x[dt.nv + t] -= zj + slk[t];
        }
    }
}

/// `W⁻¹ x` (`INV`) or `W x` into `out`, blockwise.
fn w_mul<const D: usize, const INV: bool>(
    dt: &Data,
    st_eta: &[f64],
    st_v: &[f64],
    dl: &[f64],
    x: &[f64],
    out: &mut [f64],
) {
    let l0 = dt.nc * D;
    for (((o, xk), vk), &eta) in out[..l0]
        .chunks_exact_mut(D)
        .zip(x[..l0].chunks_exact(D))
        .zip(st_v.chunks_exact(D))
        .zip(st_eta)
    {
        scale_cone::<D, INV>(eta, arr(vk), arr(xk), arr_mut(o));
    }
    for ((o, &xi), &d) in out[l0..].iter_mut().zip(&x[l0..]).zip(dl) {
        *o = if INV { xi / d } else { xi * d };
    }
}

/// Largest step (possibly `∞`) keeping `u + α du` in the cone.
fn max_step<const D: usize, const M: usize>(dt: &Data, u: &[f64], du: &[f64]) -> f64 {
    let l0 = dt.nc * D;
    let mut best = f64::INFINITY;
    for (uk, dk) in u[..l0].chunks_exact(D).zip(du[..l0].chunks_exact(D)) {
        best = best.min(cone_step::<D>(arr(uk), arr(dk)));
    }
    for (&ui, &di) in u[l0..].iter().zip(&du[l0..]) {
        if di < 0.0 {
            best = best.min(-ui / di);
        }
    }
    best
}

/// Assembles and factorises the reduced normal matrix for the current scaling.
fn factor<const D: usize, const M: usize>(dt: &Data, st: &mut State) -> bool {
    let nv = dt.nv;
    let h = &mut st.chol;
    h.clear();
    h.extend_from_slice(&dt.p);
    for (k, win) in dt.cwin.iter().enumerate() {
        let m = win.m;
        if m == 0 {
            continue;
        }
        let g = &dt.cvals[win.off..win.off + D * m];
        let v: &[f64; D] = arr(&st.v[k * D..(k + 1) * D]);
        let e = 1.0 / st.eta[k];
        if M > 0 && m == M {
            // B = W⁻¹ G_k, W⁻¹ = (2 J v vᵀ J − J) / η; H[c0 + a, c0 + b] += (BᵀB)_ab, b ≥ a
            let g = rows_of::<D, M>(g);
            let mut bm: [[f64; M]; D] = [[0.0; M]; D];
            for c in 0..M {
                let mut a = v[0] * g[0][c];
                for r in 1..D {
                    a -= v[r] * g[r][c];
                }
                bm[0][c] = (2.0 * v[0] * a - g[0][c]) * e;
                for r in 1..D {
                    bm[r][c] = (g[r][c] - 2.0 * v[r] * a) * e;
                }
            }
            for a in 0..M {
                let base = (win.c0 + a) * nv + win.c0;
                let row: &mut [f64; M] = arr_mut(&mut h[base..base + M]);
                for c in a..M {
                    let mut t = 0.0;
                    for r in 0..D {
                        t += bm[r][a] * bm[r][c];
                    }
                    row[c] += t;
                }
            }
            continue;
        }
        st.block.clear();
        st.block.resize(D * m, 0.0);
        let b = &mut st.block[..D * m];
        for c in 0..m {
            let mut a = v[0] * g[c];
            for r in 1..D {
                a -= v[r] * g[r * m + c];
            }
            b[c] = (2.0 * v[0] * a - g[c]) * e;
            for r in 1..D {
                b[r * m + c] = (g[r * m + c] - 2.0 * v[r] * a) * e;
            }
        }
        let b = &st.block[..D * m];
        for a in 0..m {
            let row = &mut h[(win.c0 + a) * nv + win.c0 + a..(win.c0 + a) * nv + win.c0 + m];
            for br in b.chunks_exact(m) {
                axpy(br[a], &br[a..], row);
            }
        }
    }
    st.htt.clear();
    st.arow.clear();
    let nr = dt.nr;
    for (j, win) in dt.rwin.iter().enumerate() {
        let t = dt.slack_of[j];
        let a = 1.0 / (st.dl[j] * st.dl[j]);
        let coef = if t == usize::MAX {
            a
        } else {
            let b = 1.0 / (st.dl[nr + t] * st.dl[nr + t]);
            st.htt.push(a + b);
            st.arow.push(a);
            a * b / (a + b)
        };
        let g = &dt.rvals[win.off..win.off + win.m];
        if M > 0 && win.m == M {
            let g: &[f64; M] = arr(g);
            for a in 0..M {
                let f = coef * g[a];
                let base = (win.c0 + a) * nv + win.c0;
                let row: &mut [f64; M] = arr_mut(&mut h[base..base + M]);
                for c in a..M {
                    row[c] += f * g[c];
                }
            }
        } else {
            for (a, &ga) in g.iter().enumerate() {
                let r0 = (win.c0 + a) * nv + win.c0;
                axpy(coef * ga, &g[a..], &mut h[r0 + a..r0 + win.m]);
            }
        }
    }
    // the upper triangle holds the sums: mirror, factorise
    for a in 0..nv {
        for b in 0..a {
            h[a * nv + b] = h[b * nv + a];
        }
    }
    cholesky(h, nv)
}

/// Solves the reduced system for the right-hand side `r` (length `nx`) in place.
fn solve_reduced<const M: usize>(dt: &Data, st: &State, r: &mut [f64]) {
    let nv = dt.nv;
    let (rv, rt) = r.split_at_mut(nv);
    for (t, &j) in dt.row_of.iter().enumerate() {
        let win = &dt.rwin[j];
        let f = st.arow[t] * rt[t] / st.htt[t];
        axpy_win::<M>(f, &dt.rvals[win.off..win.off + win.m], rv, win);
    }
    chol_solve(&st.chol, nv, rv);
    for (t, &j) in dt.row_of.iter().enumerate() {
        let win = &dt.rwin[j];
        let gd = dot_win::<M>(&dt.rvals[win.off..win.off + win.m], rv, win);
        rt[t] = (rt[t] + st.arow[t] * gd) / st.htt[t];
    }
}

/// One Newton solve for the complementarity right-hand side `st.rc` (residuals `st.rx`,
/// `st.rz`): `st.dx`, `st.ds`, `st.dz`.
fn newton<const D: usize, const M: usize>(dt: &Data, st: &mut State) {
    let l0 = dt.nc * D;
    // u = λ⁻¹ ∘ rc
    for ((l, rc), u) in st.lambda[..l0]
        .chunks_exact(D)
        .zip(st.rc[..l0].chunks_exact(D))
        .zip(st.u[..l0].chunks_exact_mut(D))
    {
        jdiv::<D>(arr(l), arr(rc), arr_mut(u));
    }
    for ((u, &rc), &l) in st.u[l0..]
        .iter_mut()
        .zip(&st.rc[l0..])
        .zip(&st.lambda[l0..])
    {
        *u = rc / l;
    }
    // t2 = −W⁻¹ (W⁻¹ rz + u)
    w_mul::<D, true>(dt, &st.eta, &st.v, &st.dl, &st.rz, &mut st.t1);
    for (t, &u) in st.t1.iter_mut().zip(&st.u) {
        *t = -(*t + u);
    }
    w_mul::<D, true>(dt, &st.eta, &st.v, &st.dl, &st.t1, &mut st.t2);
    // (P + Gᵀ W⁻² G) dx = −rx + Gᵀ t2
    for (d, &r) in st.dx.iter_mut().zip(&st.rx) {
        *d = -r;
    }
    gt_mul_add::<D, M>(dt, &st.t2, &mut st.dx);
    let mut dx = std::mem::take(&mut st.dx);
    solve_reduced::<M>(dt, st, &mut dx);
    st.dx = dx;
    // ds = −rz − G dx; dz = W⁻¹ (W⁻¹ (G dx + rz) + u)
    g_mul::<D, M>(dt, &st.dx, &mut st.gdx);
    for ((g, ds), &rz) in st.gdx.iter_mut().zip(st.ds.iter_mut()).zip(&st.rz) {
        *g += rz;
        *ds = -*g;
    }
    w_mul::<D, true>(dt, &st.eta, &st.v, &st.dl, &st.gdx, &mut st.t1);
    for (t, &u) in st.t1.iter_mut().zip(&st.u) {
        *t += u;
    }
    w_mul::<D, true>(dt, &st.eta, &st.v, &st.dl, &st.t1, &mut st.dz);
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
    let (nv, nx, ns) = (dt.nv, dt.nx(), dt.ns::<D>());
    let l0 = dt.nc * D;
    let nl = dt.nr + dt.nt;
    *status = "max iterations";
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
    // starting point (module doc): the current curve, slacks at their rows' violation plus one,
    // s lifted into the cone, z = μ₀ s⁻¹
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
    let resx0 = dot(&dt.q, &dt.q).sqrt().max(1.0);
    let resz0 = dot(&dt.h, &dt.h).sqrt().max(1.0);
    let nu = (dt.nc + nl) as f64;
    for it in 0..MAX_ITER {
        *iterations = it;
        // residuals rx = P x + q + Gᵀ z, rz = G x + s − h
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
        // scaling and λ = W z
        for (((sk, zk), vk), eta) in st.s[..l0]
            .chunks_exact(D)
            .zip(st.z[..l0].chunks_exact(D))
            .zip(st.v[..l0].chunks_exact_mut(D))
            .zip(st.eta.iter_mut())
        {
            match nt_scaling::<D>(arr(sk), arr(zk), arr_mut(vk)) {
                Some(e) => *eta = e,
                None => {
                    *status = "cone not interior";
                    return almost(pres, dres, gap, pcost) && st.x.iter().all(|v| v.is_finite());
                }
            }
        }
        for i in 0..nl {
            let (si, zi) = (st.s[l0 + i], st.z[l0 + i]);
            if !(si > 0.0 && zi > 0.0) {
                *status = "row not interior";
                return false;
            }
            st.dl[i] = (si / zi).sqrt();
        }
        w_mul::<D, false>(dt, &st.eta, &st.v, &st.dl, &st.z, &mut st.lambda);
        if !factor::<D, M>(dt, st) {
            // the normal matrix lost definiteness to round-off near the optimum
            *status = "cholesky";
            return almost(pres, dres, gap, pcost) && st.x.iter().all(|v| v.is_finite());
        }
        for (l, o) in st.lambda[..l0]
            .chunks_exact(D)
            .zip(st.lsq[..l0].chunks_exact_mut(D))
        {
            jprod::<D>(arr(l), arr(l), arr_mut(o));
        }
        for i in l0..ns {
            st.lsq[i] = st.lambda[i] * st.lambda[i];
        }
        let mu = gap / nu;
        // predictor
        for (r, &l) in st.rc.iter_mut().zip(&st.lsq) {
            *r = -l;
        }
        newton::<D, M>(dt, st);
        let step = max_step::<D, M>(dt, &st.s, &st.ds)
            .min(max_step::<D, M>(dt, &st.z, &st.dz))
            .min(1.0);
        let dsdz = dot(&st.ds, &st.dz);
        let sigma = (1.0 - step + dsdz / gap * step * step)
            .clamp(0.0, 1.0)
            .powi(3);
        // corrector: −λ∘λ − (W⁻¹ ds_a) ∘ (W dz_a) + σ μ e
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
        let alpha = (STEP
            * max_step::<D, M>(dt, &st.s, &st.ds).min(max_step::<D, M>(dt, &st.z, &st.dz)))
        .min(1.0);
        if !(alpha > 0.0 && alpha.is_finite()) {
            *status = "step";
            return false;
        }
        for (x, &d) in st.x.iter_mut().zip(&st.dx) {
            *x += alpha * d;
        }
        for i in 0..ns {
            st.s[i] += alpha * st.ds[i];
            st.z[i] += alpha * st.dz[i];
        }
    }
    false
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
