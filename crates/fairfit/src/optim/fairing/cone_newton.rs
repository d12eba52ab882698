//! The Newton system of [`super::cone_ipm`]'s interior-point iterations: the scaled problem's
//! layout ([`Data`], its cones' and rows' variable windows), the iterates ([`State`]), the
//! operators `G x`, `Gᵀ z` and the Nesterov–Todd scaling `W⁻¹`, and the reduced normal matrix
//! `P + Σ_k (W_k⁻¹G_k)ᵀ(W_k⁻¹G_k) + Σ_j d_j g_j g_jᵀ` with its assembly ([`factor`]: every cone's
//! small dense block and every row's few entries on windows of consecutive variables padded to a
//! fixed width `M`, the slacks eliminated in closed form), its dense Cholesky factor and the solve
//! of one Newton step ([`newton`]). The iterations themselves, the scaling of the problem and the
//! start are in [`super::cone_ipm`].

use super::cone_algebra::{arr, arr_mut, chol_solve, cholesky, cone_step, dot, jdiv, scale_cone};

/// The scaled problem (module doc) in the solver's layout: every cone has the same dimension `D`
/// and occupies rows `k D .. (k + 1) D` of the stacked `s`, `z`; then the linear rows, then one
/// sign row per slack.
#[derive(Default)]
pub(super) struct Data {
    pub(super) nv: usize,
    /// Linear rows, slacks, cones.
    pub(super) nr: usize,
    pub(super) nt: usize,
    pub(super) nc: usize,
    pub(super) p: Vec<f64>,
    pub(super) q: Vec<f64>,
    pub(super) h: Vec<f64>,
    /// Per cone, the window of consecutive variables its `G_k` touches: first variable, width,
    /// offset of its values in `cvals` (`G_k` restricted to the window, `D × width` row-major,
    /// zeros where it does not touch a variable of the window).
    pub(super) cwin: Vec<Window>,
    pub(super) cvals: Vec<f64>,
    /// The same per linear row (`g_j` on its window, in `rvals`).
    pub(super) rwin: Vec<Window>,
    pub(super) rvals: Vec<f64>,
    /// Per linear row, its slack (`usize::MAX`: hard); per slack, its row.
    pub(super) slack_of: Vec<usize>,
    pub(super) row_of: Vec<usize>,
    /// Whether every cone's first row of `G_k` is exactly `+0` (band fairing's cones: the radius
    /// is a constant, `‖C(u_i) − Q_i‖ ≤ ρ_i`): the kernels then skip that row. The sums they form
    /// are the same bit for bit: a product `+0 · x` (finite `x`) is `±0`, and `0.0 + (±0) = +0`
    /// or `a − (+0) = a` leave every partial sum as it was.
    pub(super) head_zero: bool,
}

impl Data {
    pub(super) fn nx(&self) -> usize {
        self.nv + self.nt
    }

    pub(super) fn ns<const D: usize>(&self) -> usize {
        self.nc * D + self.nr + self.nt
    }
}

/// Consecutive variables `c0 .. c0 + m` and where their values start.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Window {
    pub(super) c0: usize,
    pub(super) m: usize,
    pub(super) off: usize,
}

impl Window {
    /// The window of the sorted variables `cols` (empty: width 0).
    pub(super) fn of(cols: &[usize], off: usize) -> Window {
        match (cols.first(), cols.last()) {
            (Some(&a), Some(&b)) => Window {
                c0: a,
                m: b - a + 1,
                off,
            },
            _ => Window { c0: 0, m: 0, off },
        }
    }

    pub(super) fn vars(&self) -> std::ops::Range<usize> {
        self.c0..self.c0 + self.m
    }
}

/// The iterates and work arrays.
#[derive(Default)]
pub(super) struct State {
    pub(super) x: Vec<f64>,
    pub(super) s: Vec<f64>,
    pub(super) z: Vec<f64>,
    pub(super) lambda: Vec<f64>,
    pub(super) lsq: Vec<f64>,
    /// Per cone `η`; per cone row the scaling vector `v`; per linear and slack row `sqrt(s/z)`.
    pub(super) eta: Vec<f64>,
    pub(super) v: Vec<f64>,
    pub(super) dl: Vec<f64>,
    /// The normal matrix and its Cholesky factor.
    pub(super) chol: Vec<f64>,
    /// The first non-zero column of every row of `chol` (its envelope).
    pub(super) first: Vec<usize>,
    /// Per slack: the diagonal of the eliminated block and `1/d²` of its row.
    pub(super) htt: Vec<f64>,
    pub(super) arow: Vec<f64>,
    /// `W⁻¹ G_k`, column by column.
    pub(super) block: Vec<f64>,
    pub(super) rx: Vec<f64>,
    pub(super) rz: Vec<f64>,
    /// `W⁻¹ rz`, the same for the predictor and the corrector of one iteration.
    pub(super) wrz: Vec<f64>,
    pub(super) rc: Vec<f64>,
    pub(super) u: Vec<f64>,
    pub(super) t1: Vec<f64>,
    pub(super) t2: Vec<f64>,
    pub(super) gdx: Vec<f64>,
    pub(super) dx: Vec<f64>,
    pub(super) ds: Vec<f64>,
    pub(super) dz: Vec<f64>,
    pub(super) dsa: Vec<f64>,
    pub(super) dza: Vec<f64>,
}

/// The `D × M` values of a full-width window, row by row.
#[inline]
pub(super) fn rows_of<const D: usize, const M: usize>(v: &[f64]) -> [&[f64; M]; D] {
    std::array::from_fn(|r| arr(&v[r * M..(r + 1) * M]))
}

/// `out = G x` (`x` of length `nx`).
pub(super) fn g_mul<const D: usize, const M: usize>(dt: &Data, x: &[f64], out: &mut [f64]) {
    let l0 = dt.nc * D;
    for (o, win) in out[..l0].chunks_exact_mut(D).zip(&dt.cwin) {
        let g = &dt.cvals[win.off..win.off + D * win.m];
        if M > 0 && win.m == M {
            let xw: &[f64; M] = arr(&x[win.vars()]);
            let g = rows_of::<D, M>(g);
            let r0 = usize::from(dt.head_zero);
            o[0] = 0.0;
            for r in r0..D {
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
        let mut v = dot_win::<M>(g, x, win);
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
pub(super) fn axpy(f: f64, x: &[f64], y: &mut [f64]) {
    for (a, &b) in y.iter_mut().zip(x) {
        *a += f * b;
    }
}

/// `x[c0 .. c0 + M] += f g` for a full-width window (`axpy` otherwise).
#[inline]
pub(super) fn axpy_win<const M: usize>(f: f64, g: &[f64], x: &mut [f64], win: &Window) {
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
pub(super) fn dot_win<const M: usize>(g: &[f64], x: &[f64], win: &Window) -> f64 {
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
pub(super) fn gt_mul_add<const D: usize, const M: usize>(dt: &Data, z: &[f64], x: &mut [f64]) {
    let l0 = dt.nc * D;
    for (zk, win) in z[..l0].chunks_exact(D).zip(&dt.cwin) {
        let g = &dt.cvals[win.off..win.off + D * win.m];
        if M > 0 && win.m == M {
            let g = rows_of::<D, M>(g);
            let xw: &mut [f64; M] = arr_mut(&mut x[win.vars()]);
            if dt.head_zero {
                for b in 0..M {
                    let mut t = 0.0;
                    for r in 1..D {
                        t += g[r][b] * zk[r];
                    }
                    xw[b] += t;
                }
            } else {
                for b in 0..M {
                    let mut t = 0.0;
                    for r in 0..D {
                        t += g[r][b] * zk[r];
                    }
                    xw[b] += t;
                }
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
pub(super) fn w_mul<const D: usize, const INV: bool>(
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
pub(super) fn max_step<const D: usize, const M: usize>(dt: &Data, u: &[f64], du: &[f64]) -> f64 {
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
pub(super) fn factor<const D: usize, const M: usize>(dt: &Data, st: &mut State) -> bool {
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
            if dt.head_zero {
                for c in 0..M {
                    let mut a = 0.0;
                    for r in 1..D {
                        a -= v[r] * g[r][c];
                    }
                    bm[0][c] = 2.0 * v[0] * a * e;
                    for r in 1..D {
                        bm[r][c] = (g[r][c] - 2.0 * v[r] * a) * e;
                    }
                }
            } else {
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
    cholesky(h, nv, &mut st.first)
}

/// Solves the reduced system for the right-hand side `r` (length `nx`) in place.
pub(super) fn solve_reduced<const M: usize>(dt: &Data, st: &State, r: &mut [f64]) {
    let nv = dt.nv;
    let (rv, rt) = r.split_at_mut(nv);
    for (t, &j) in dt.row_of.iter().enumerate() {
        let win = &dt.rwin[j];
        let f = st.arow[t] * rt[t] / st.htt[t];
        axpy_win::<M>(f, &dt.rvals[win.off..win.off + win.m], rv, win);
    }
    chol_solve(&st.chol, nv, &st.first, rv);
    for (t, &j) in dt.row_of.iter().enumerate() {
        let win = &dt.rwin[j];
        let gd = dot_win::<M>(&dt.rvals[win.off..win.off + win.m], rv, win);
        rt[t] = (rt[t] + st.arow[t] * gd) / st.htt[t];
    }
}

/// One Newton solve for the complementarity right-hand side `st.rc` (residuals `st.rx`,
/// `st.rz`, and `st.wrz = W⁻¹ rz` of the current scaling): `st.dx`, `st.ds`, `st.dz`.
pub(super) fn newton<const D: usize, const M: usize>(dt: &Data, st: &mut State) {
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
    for ((t, &w), &u) in st.t1.iter_mut().zip(&st.wrz).zip(&st.u) {
        *t = -(w + u);
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
