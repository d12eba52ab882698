//! A primal–dual interior-point solver for band fairing's subproblems ([`BandQp`]) that exploits
//! their shape: a few dozen step variables, hundreds of 3- or 4-row second-order cones and sign
//! rows that each touch only the 8–12 variables of one knot span's control points, and one
//! L1-penalised slack per soft row.
//!
//! The method is CVXOPT's `coneqp` (Vandenberghe, "The CVXOPT linear and quadratic cone program
//! solvers", 2010): Nesterov–Todd scaling, Mehrotra's predictor–corrector with the step-dependent
//! centring `σ = (1 − α + α² ds_aᵀdz_a / sᵀz)³`, an infeasible start from the least-squares point
//! shifted into the cone's interior, steps of 0.99 of the way to the boundary. Each Newton system
//! is reduced to the dense normal matrix of the step variables,
//! `P + Σ_k (W_k⁻¹G_k)ᵀ(W_k⁻¹G_k) + Σ_j d_j g_j g_jᵀ`, assembled from every cone's small dense
//! block and every row's few entries, with the slacks eliminated in closed form (each sits in
//! only its row and its own sign row), and factorised by a dense Cholesky: an iteration costs
//! about what one cone's block costs times the number of cones, against a sparse `LDLᵀ` of the
//! whole KKT matrix (≈ 1400 rows with the sign targets) in a general solver, ~10× fewer
//! instructions per subproblem (docs/optim.md, "Speed, session 7").
//!
//! Scaling: the step variables are measured in units of the largest cone radius (the band's
//! width), every cone is divided by it, every linear row by the norm of its coefficients in those
//! units, and the objective by its largest curvature or gradient entry, so the stopping tests are
//! relative to the band. Deterministic and serial. `None` when it does not converge (for example
//! an infeasible subproblem): the caller falls back to [`BandQp::solve_clarabel`].

use super::band_qp::BandQp;

/// Most iterations before giving up.
const MAX_ITER: usize = 60;
/// Primal and dual residuals, relative to the scaled data.
const FEAS_TOL: f64 = 1e-9;
/// Duality gap, absolute (scaled objective) and relative to the objective.
const GAP_ABS: f64 = 1e-10;
const GAP_REL: f64 = 1e-9;
/// Fraction of the way to the cone's boundary a step goes.
const STEP: f64 = 0.99;

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
    /// Per cone, its first column (one more entry: the end).
    cstart: Vec<usize>,
    /// Per column, its variable, and `D` values (the column of `G_k`).
    ccols: Vec<usize>,
    cvals: Vec<f64>,
    /// Per linear row, its first entry (one more entry: the end), then variables and values.
    rstart: Vec<usize>,
    rcols: Vec<usize>,
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

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[inline]
fn arr<const D: usize>(s: &[f64]) -> &[f64; D] {
    s.try_into().expect("a cone block")
}

#[inline]
fn arr_mut<const D: usize>(s: &mut [f64]) -> &mut [f64; D] {
    s.try_into().expect("a cone block")
}

/// `s₀² − ‖s₁‖²`.
#[inline]
fn jnorm2<const D: usize>(s: &[f64; D]) -> f64 {
    let mut t = 0.0;
    for i in 1..D {
        t += s[i] * s[i];
    }
    s[0] * s[0] - t
}

/// `W⁻¹ x` (`INV`) or `W x` for the NT scaling `W = η (2 v vᵀ − J)` of one cone.
#[inline]
fn scale_cone<const D: usize, const INV: bool>(
    eta: f64,
    v: &[f64; D],
    x: &[f64; D],
    out: &mut [f64; D],
) {
    if INV {
        let mut a = v[0] * x[0];
        for i in 1..D {
            a -= v[i] * x[i];
        }
        let e = 1.0 / eta;
        out[0] = (2.0 * v[0] * a - x[0]) * e;
        for i in 1..D {
            out[i] = (x[i] - 2.0 * v[i] * a) * e;
        }
    } else {
        let mut a = 0.0;
        for i in 0..D {
            a += v[i] * x[i];
        }
        out[0] = eta * (2.0 * v[0] * a - x[0]);
        for i in 1..D {
            out[i] = eta * (2.0 * v[i] * a + x[i]);
        }
    }
}

/// The NT scaling of one cone at interior `s`, `z`: `η`, and `v` into `v`; `None` when not
/// interior.
fn nt_scaling<const D: usize>(s: &[f64; D], z: &[f64; D], v: &mut [f64; D]) -> Option<f64> {
    let (a, b) = (jnorm2(s), jnorm2(z));
    if !(a > 0.0 && b > 0.0 && s[0] > 0.0 && z[0] > 0.0) {
        return None;
    }
    let (a, b) = (a.sqrt(), b.sqrt());
    let mut sz = 0.0;
    for i in 0..D {
        sz += s[i] * z[i];
    }
    let gamma = ((1.0 + sz / (a * b)) / 2.0).sqrt();
    let w0 = (s[0] / a + z[0] / b) / (2.0 * gamma);
    let c = (2.0 * (w0 + 1.0)).sqrt();
    v[0] = (w0 + 1.0) / c;
    for i in 1..D {
        v[i] = (s[i] / a - z[i] / b) / (2.0 * gamma * c);
    }
    Some((a / b).sqrt())
}

/// Jordan product `u ∘ w` of one cone.
#[inline]
fn jprod<const D: usize>(u: &[f64; D], w: &[f64; D], out: &mut [f64; D]) {
    let mut t = 0.0;
    for i in 0..D {
        t += u[i] * w[i];
    }
    out[0] = t;
    for i in 1..D {
        out[i] = u[0] * w[i] + w[0] * u[i];
    }
}

/// `x` with `l ∘ x = d` (one cone, `l` interior).
#[inline]
fn jdiv<const D: usize>(l: &[f64; D], d: &[f64; D], out: &mut [f64; D]) {
    let mut t = l[0] * d[0];
    for i in 1..D {
        t -= l[i] * d[i];
    }
    let x0 = t / jnorm2(l);
    out[0] = x0;
    for i in 1..D {
        out[i] = (d[i] - x0 * l[i]) / l[0];
    }
}

/// Largest `α` (possibly `∞`) with `u + α du` in the cone (`u` interior).
fn cone_step<const D: usize>(u: &[f64; D], du: &[f64; D]) -> f64 {
    let c = jnorm2(u);
    let mut b = u[0] * du[0];
    for i in 1..D {
        b -= u[i] * du[i];
    }
    let a = jnorm2(du);
    let mut best = f64::INFINITY;
    if du[0] < 0.0 {
        best = -u[0] / du[0];
    }
    // roots of a α² + 2 b α + c
    if a == 0.0 {
        if b < 0.0 {
            best = best.min(-c / (2.0 * b));
        }
    } else {
        let disc = b * b - a * c;
        if disc >= 0.0 {
            let qq = if b >= 0.0 {
                -(b + disc.sqrt())
            } else {
                -b + disc.sqrt()
            };
            for r in [qq / a, if qq != 0.0 { c / qq } else { f64::INFINITY }] {
                if r > 0.0 {
                    best = best.min(r);
                }
            }
        }
    }
    best
}

/// In-place Cholesky factor (lower, row-major) of the symmetric `n × n` matrix `a`; `false`
/// when it is not positive definite.
fn cholesky(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let rj = &a[j * n..j * n + j];
        let d = a[j * n + j] - dot(rj, rj);
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let (lo, hi) = a.split_at_mut(i * n);
            let rj = &lo[j * n..j * n + j];
            let ri = &mut hi[..=j];
            ri[j] = (ri[j] - dot(&ri[..j], rj)) / d;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place (`l` from [`cholesky`]).
fn chol_solve(l: &[f64], n: usize, x: &mut [f64]) {
    for i in 0..n {
        let v = x[i] - dot(&l[i * n..i * n + i], &x[..i]);
        x[i] = v / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut v = x[i];
        for k in i + 1..n {
            v -= l[k * n + i] * x[k];
        }
        x[i] = v / l[i * n + i];
    }
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
    // cone columns (all-zero ones dropped)
    dt.cstart.clear();
    dt.ccols.clear();
    dt.cvals.clear();
    dt.cstart.push(0);
    for k in 0..nc {
        let cols = &qp.cols[qp.cone_col[k]..qp.cone_col[k + 1]];
        let m = cols.len();
        let blk = &qp.block[qp.cone_block[k]..qp.cone_block[k + 1]];
        for (a, &c) in cols.iter().enumerate() {
            if (0..D).all(|r| blk[r * m + a] == 0.0) {
                continue;
            }
            dt.ccols.push(c);
            dt.cvals.extend((0..D).map(|r| blk[r * m + a]));
        }
        dt.cstart.push(dt.ccols.len());
    }
    dt.rstart.clear();
    dt.rstart.extend_from_slice(&qp.row_start);
    dt.rcols.clear();
    dt.rcols.extend_from_slice(&qp.row_cols);
    dt.rvals.clear();
    dt.rvals.extend_from_slice(&qp.row_vals);
    let mut row_scale = Vec::with_capacity(nr);
    for j in 0..nr {
        let e = qp.row_start[j]..qp.row_start[j + 1];
        let norm = dot(&qp.row_vals[e.clone()], &qp.row_vals[e.clone()]).sqrt() * sx;
        let n = if norm > 0.0 { norm } else { 1.0 };
        row_scale.push(n);
        for v in &mut dt.rvals[e] {
            *v *= sx / n;
        }
        dt.h[nc * D + j] = qp.h[l0 + j] / n;
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
    let ok = iterate::<D>(&w.data, &mut w.st, &mut w.iterations, &mut w.status);
    if ok {
        w.solution.clear();
        w.solution.extend(w.st.x[..nv].iter().map(|v| v * sx));
    }
    ok
}

/// `out = G x` (`x` of length `nx`).
fn g_mul<const D: usize>(dt: &Data, x: &[f64], out: &mut [f64]) {
    let l0 = dt.nc * D;
    for (k, o) in out[..l0].chunks_exact_mut(D).enumerate() {
        let (a0, a1) = (dt.cstart[k], dt.cstart[k + 1]);
        let mut acc = [0.0; D];
        for (col, &c) in dt.cvals[a0 * D..a1 * D]
            .chunks_exact(D)
            .zip(&dt.ccols[a0..a1])
        {
            let xv = x[c];
            for r in 0..D {
                acc[r] += col[r] * xv;
            }
        }
        o.copy_from_slice(&acc);
    }
    let (lin, slk) = out[l0..].split_at_mut(dt.nr);
    for j in 0..dt.nr {
        let e = dt.rstart[j]..dt.rstart[j + 1];
        let mut v = 0.0;
        for (&c, &g) in dt.rcols[e.clone()].iter().zip(&dt.rvals[e]) {
            v += g * x[c];
        }
        let t = dt.slack_of[j];
        if t != usize::MAX {
            let xt = x[dt.nv + t];
            v -= xt;
            slk[t] = -xt;
        }
        lin[j] = v;
    }
}

/// `x += Gᵀ z`.
fn gt_mul_add<const D: usize>(dt: &Data, z: &[f64], x: &mut [f64]) {
    let l0 = dt.nc * D;
    for (k, zk) in z[..l0].chunks_exact(D).enumerate() {
        let (a0, a1) = (dt.cstart[k], dt.cstart[k + 1]);
        for (col, &c) in dt.cvals[a0 * D..a1 * D]
            .chunks_exact(D)
            .zip(&dt.ccols[a0..a1])
        {
            let mut v = 0.0;
            for r in 0..D {
                v += col[r] * zk[r];
            }
            x[c] += v;
        }
    }
    let (lin, slk) = z[l0..].split_at(dt.nr);
    for j in 0..dt.nr {
        let zj = lin[j];
        let e = dt.rstart[j]..dt.rstart[j + 1];
        for (&c, &g) in dt.rcols[e.clone()].iter().zip(&dt.rvals[e]) {
            x[c] += g * zj;
        }
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
fn max_step<const D: usize>(dt: &Data, u: &[f64], du: &[f64]) -> f64 {
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

/// Assembles and factorises the reduced normal matrix for the current scaling (`identity`: the
/// scaling `W = I` of the starting point).
fn factor<const D: usize>(dt: &Data, st: &mut State, identity: bool) -> bool {
    let nv = dt.nv;
    let h = &mut st.chol;
    h.clear();
    h.extend_from_slice(&dt.p);
    for k in 0..dt.nc {
        let (a0, a1) = (dt.cstart[k], dt.cstart[k + 1]);
        let cols = &dt.ccols[a0..a1];
        let m = cols.len();
        // B = W⁻¹ G_k, column by column
        st.block.resize(m * D, 0.0);
        let vk: &[f64; D] = arr(&st.v[k * D..(k + 1) * D]);
        for (b, g) in st.block[..m * D]
            .chunks_exact_mut(D)
            .zip(dt.cvals[a0 * D..a1 * D].chunks_exact(D))
        {
            if identity {
                b.copy_from_slice(g);
            } else {
                scale_cone::<D, true>(st.eta[k], vk, arr(g), arr_mut(b));
            }
        }
        for (a, ba) in st.block[..m * D].chunks_exact(D).enumerate() {
            let ba: &[f64; D] = arr(ba);
            let row = &mut h[cols[a] * nv..(cols[a] + 1) * nv];
            for (bb, &cb) in st.block[a * D..m * D].chunks_exact(D).zip(&cols[a..]) {
                let mut s = 0.0;
                for r in 0..D {
                    s += ba[r] * bb[r];
                }
                row[cb] += s;
            }
        }
    }
    st.htt.clear();
    st.arow.clear();
    let nr = dt.nr;
    for j in 0..nr {
        let t = dt.slack_of[j];
        let a = if identity {
            1.0
        } else {
            1.0 / (st.dl[j] * st.dl[j])
        };
        let coef = if t == usize::MAX {
            a
        } else {
            let b = if identity {
                1.0
            } else {
                1.0 / (st.dl[nr + t] * st.dl[nr + t])
            };
            st.htt.push(a + b);
            st.arow.push(a);
            a * b / (a + b)
        };
        let e = dt.rstart[j]..dt.rstart[j + 1];
        let (cs, gs) = (&dt.rcols[e.clone()], &dt.rvals[e]);
        for (i1, (&c1, &g1)) in cs.iter().zip(gs).enumerate() {
            let v1 = coef * g1;
            for (&c2, &g2) in cs[i1..].iter().zip(&gs[i1..]) {
                let (lo, hi) = if c1 <= c2 { (c1, c2) } else { (c2, c1) };
                h[lo * nv + hi] += v1 * g2;
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
fn solve_reduced(dt: &Data, st: &State, r: &mut [f64]) {
    let nv = dt.nv;
    let (rv, rt) = r.split_at_mut(nv);
    for (t, &j) in dt.row_of.iter().enumerate() {
        let f = st.arow[t] * rt[t] / st.htt[t];
        let e = dt.rstart[j]..dt.rstart[j + 1];
        for (&c, &g) in dt.rcols[e.clone()].iter().zip(&dt.rvals[e]) {
            rv[c] += g * f;
        }
    }
    chol_solve(&st.chol, nv, rv);
    for (t, &j) in dt.row_of.iter().enumerate() {
        let e = dt.rstart[j]..dt.rstart[j + 1];
        let mut gd = 0.0;
        for (&c, &g) in dt.rcols[e.clone()].iter().zip(&dt.rvals[e]) {
            gd += g * rv[c];
        }
        rt[t] = (rt[t] + st.arow[t] * gd) / st.htt[t];
    }
}

/// One Newton solve for the complementarity right-hand side `st.rc` (residuals `st.rx`,
/// `st.rz`): `st.dx`, `st.ds`, `st.dz`.
fn newton<const D: usize>(dt: &Data, st: &mut State) {
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
    gt_mul_add::<D>(dt, &st.t2, &mut st.dx);
    let mut dx = std::mem::take(&mut st.dx);
    solve_reduced(dt, st, &mut dx);
    st.dx = dx;
    // ds = −rz − G dx; dz = W⁻¹ (W⁻¹ (G dx + rz) + u)
    g_mul::<D>(dt, &st.dx, &mut st.gdx);
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

/// Shifts `u` into the interior of the cone when its smallest eigenvalue is below `1e-8`.
fn shift_interior<const D: usize>(dt: &Data, u: &mut [f64]) {
    let l0 = dt.nc * D;
    let mut worst = f64::INFINITY;
    for uk in u[..l0].chunks_exact(D) {
        worst = worst.min(uk[0] - dot(&uk[1..], &uk[1..]).sqrt());
    }
    for &x in &u[l0..] {
        worst = worst.min(x);
    }
    if worst <= 1e-8 {
        let shift = 1.0 - worst;
        for uk in u[..l0].chunks_exact_mut(D) {
            uk[0] += shift;
        }
        for x in &mut u[l0..] {
            *x += shift;
        }
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
fn iterate<const D: usize>(
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
    // starting point: (P + GᵀG) x = −q + Gᵀh, s = h − G x, z = −s, both shifted into the cone
    if !factor::<D>(dt, st, true) {
        *status = "cholesky at the start";
        return false;
    }
    for (x, &q) in st.x.iter_mut().zip(&dt.q) {
        *x = -q;
    }
    gt_mul_add::<D>(dt, &dt.h, &mut st.x);
    let mut x = std::mem::take(&mut st.x);
    solve_reduced(dt, st, &mut x);
    st.x = x;
    g_mul::<D>(dt, &st.x, &mut st.gdx);
    for i in 0..ns {
        st.s[i] = dt.h[i] - st.gdx[i];
        st.z[i] = -st.s[i];
    }
    shift_interior::<D>(dt, &mut st.s);
    shift_interior::<D>(dt, &mut st.z);
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
        gt_mul_add::<D>(dt, &st.z, &mut st.rx);
        g_mul::<D>(dt, &st.x, &mut st.gdx);
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
        if !factor::<D>(dt, st, false) {
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
        newton::<D>(dt, st);
        let step = max_step::<D>(dt, &st.s, &st.ds)
            .min(max_step::<D>(dt, &st.z, &st.dz))
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
        newton::<D>(dt, st);
        let alpha = (STEP * max_step::<D>(dt, &st.s, &st.ds).min(max_step::<D>(dt, &st.z, &st.dz)))
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

    fn both(qp: &BandQp) -> [Vec<f64>; 2] {
        let mut w = IpmWork::default();
        assert!(solve(qp, &mut w), "{}", w.status);
        [w.solution.clone(), qp.solve_clarabel().expect("clarabel")]
    }

    #[test]
    fn a_projection_onto_a_disc_with_a_half_plane_is_exact() {
        // for a = (−1, 2) the half-plane is active: (0.2, sqrt(1 − 0.04)) on the circle
        for x in both(&disc_problem([-1.0, 2.0], false)) {
            assert!((x[0] - 0.2).abs() < 1e-7, "{x:?}");
            assert!((x[1] - 0.96f64.sqrt()).abs() < 1e-7, "{x:?}");
        }
        // with the row soft (weight 0.5) it gives way: ½‖x − a‖² − 0.5 x₀ + const is
        // ½‖x − a'‖² with a' = (−0.5, 2), projected onto the disc. Along the circle the objective
        // changes only to second order, so the solvers' duality gaps (this one's ~1e-9, clarabel's
        // ~1e-7 at band fairing's settings) leave the point off by up to ~1e-4 while the
        // objective is optimal to about the gap
        let n = 4.25f64.sqrt();
        let qp = disc_problem([-1.0, 2.0], true);
        let (best, _) = qp.evaluate(&[-0.5 / n, 2.0 / n]);
        for x in both(&qp) {
            assert!((x[0] + 0.5 / n).abs() < 2e-4, "{x:?}");
            assert!((x[1] - 2.0 / n).abs() < 2e-4, "{x:?}");
            let (obj, viol) = qp.evaluate(&x);
            assert!(obj - best < 1e-7 && viol < 1e-8, "{obj} {best} {viol}");
        }
        // a point inside the disc and the half-plane is its own projection
        for x in both(&disc_problem([0.3, -0.4], false)) {
            assert!(
                (x[0] - 0.3).abs() < 1e-7 && (x[1] + 0.4).abs() < 1e-7,
                "{x:?}"
            );
        }
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
        for x in both(&qp) {
            for i in 0..3 {
                assert!((x[i] - (c[i] + 0.5 * d[i] / norm)).abs() < 1e-7, "{x:?}");
            }
        }
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
