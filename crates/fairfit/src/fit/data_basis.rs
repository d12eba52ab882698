//! The non-vanishing basis functions at every data parameter of one least-squares solve, computed once
//! and kept: the solve assembles its normal equations from them, and the algebraic residuals
//! `|C(ū_k) − Q_k|` of the fitted curve (the first, cheap screen of the deviation measures) are then one
//! dot product per point instead of a span search and a basis recursion.
//!
//! Spans are found by walking from the previous point's span (the parameters of a fit are ordered, so
//! this is O(1) per point; any order stays correct). Degrees up to 5 use a recursion with fixed-size
//! arrays, unrolled by the compiler; its arithmetic is that of
//! [`crate::nurbs::basis::basis_funs_into`], so the values are bit-for-bit the same.

use crate::nurbs::basis::basis_funs_into;
use crate::nurbs::knots::find_span;
use crate::nurbs::Vec3;

/// Span index and `p + 1` basis values of every data parameter.
#[derive(Clone, Debug, Default)]
pub struct DataBasis {
    p: usize,
    /// knot span of each parameter
    spans: Vec<usize>,
    /// `p + 1` values per parameter: `N_{span−p+j}(ū_k)` at `k (p + 1) + j`
    values: Vec<f64>,
    /// the inputs of the last fill
    prev_knots: Vec<f64>,
    prev_params: Vec<f64>,
    /// the values are those of the last fill (no caller changed them)
    pristine: bool,
}

impl DataBasis {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Fills the cache for degree `p`, `knots` with `n + 1` control points, at `params`. With the
    /// parameters of the previous fill, values whose inputs (the `2p` knots around their span) are
    /// unchanged are kept, not recomputed, run by run of points sharing a span: a knot-removal trial
    /// changes the basis near the removed knot only.
    pub fn fill(&mut self, p: usize, n: usize, knots: &[f64], params: &[f64]) {
        let reuse = self.pristine
            && self.p == p
            && self.spans.len() == params.len()
            && self.prev_params == params;
        self.p = p;
        match p {
            1 => self.fill_const::<2>(n, knots, params, reuse),
            2 => self.fill_const::<3>(n, knots, params, reuse),
            3 => self.fill_const::<4>(n, knots, params, reuse),
            4 => self.fill_const::<5>(n, knots, params, reuse),
            5 => self.fill_const::<6>(n, knots, params, reuse),
            _ => {
                let p1 = p + 1;
                let (mut left, mut right) = (vec![0.0; p1], vec![0.0; p1]);
                self.spans.clear();
                self.values.clear();
                self.values.resize(params.len() * p1, 0.0);
                let mut span = p;
                for (k, &u) in params.iter().enumerate() {
                    span = span_from(n, p, u, knots, span);
                    self.spans.push(span);
                    let out = &mut self.values[k * p1..(k + 1) * p1];
                    basis_funs_into(span, u, p, knots, &mut left, &mut right, out);
                }
            }
        }
        self.prev_knots.clear();
        self.prev_knots.extend_from_slice(knots);
        if !reuse {
            self.prev_params.clear();
            self.prev_params.extend_from_slice(params);
        }
        self.pristine = true;
    }

    fn fill_const<const N: usize>(&mut self, n: usize, knots: &[f64], params: &[f64], reuse: bool) {
        let p = N - 1;
        let mut span = p;
        if !reuse {
            self.spans.clear();
            self.values.clear();
            self.values.reserve(params.len() * N);
            for &u in params {
                span = span_from(n, p, u, knots, span);
                self.spans.push(span);
                self.values
                    .extend_from_slice(&basis_const::<N>(span, u, knots));
            }
            return;
        }
        // the same parameters: walk the runs of points that shared a span in the last fill
        let m = params.len();
        let mut k = 0;
        while k < m {
            let old = self.spans[k];
            let end = k + self.spans[k..].iter().take_while(|&&s| s == old).count();
            span = span_from(n, p, params[k], knots, span);
            // the recursion reads u and knots[span + 1 - p ..= span + p]; equal windows also hold the
            // span's bounds, so every point of the run lies in the new span
            if self.prev_knots.get(old + 1 - p..=old + p) == knots.get(span + 1 - p..=span + p) {
                self.spans[k..end].fill(span);
                k = end;
                continue;
            }
            for (j, &u) in params.iter().enumerate().take(end).skip(k) {
                span = span_from(n, p, u, knots, span);
                self.spans[j] = span;
                self.values[j * N..(j + 1) * N].copy_from_slice(&basis_const::<N>(span, u, knots));
            }
            k = end;
        }
    }

    /// The knot span of every parameter.
    pub fn spans(&self) -> &[usize] {
        &self.spans
    }

    /// The basis values of points `k..end`, `p + 1` per point.
    #[inline]
    pub fn values(&self, k: usize, end: usize) -> &[f64] {
        let p1 = self.p + 1;
        &self.values[k * p1..end * p1]
    }

    /// The basis values of point `k`, to change in place (a rational solve normalises them).
    #[inline]
    pub fn values_mut(&mut self, k: usize) -> &mut [f64] {
        // the values may change: the next fill recomputes every one
        self.pristine = false;
        let p1 = self.p + 1;
        &mut self.values[k * p1..(k + 1) * p1]
    }

    /// `|Σ_j N_j(ū_k) P_{span−p+j} − Q_k|` for every point into `out`: the algebraic distances of the
    /// curve with control points `ctrl` (the knots and parameters of the last [`DataBasis::fill`]).
    pub fn residual_norms_into(&self, points: &[Vec3], ctrl: &[Vec3], out: &mut Vec<f64>) {
        out.clear();
        if self.p == 3 {
            return self.residuals_const::<4>(points, ctrl, out);
        }
        let p1 = self.p + 1;
        out.extend(
            points
                .iter()
                .zip(&self.spans)
                .zip(self.values.chunks_exact(p1))
                .map(|((q, &span), nb)| {
                    let mut c = Vec3::ZERO;
                    for (j, &v) in nb.iter().enumerate() {
                        c += ctrl[span + j - self.p] * v;
                    }
                    (c - *q).norm()
                }),
        );
    }
}

impl DataBasis {
    /// [`DataBasis::residual_norms_into`] for degree `N − 1` (same arithmetic, unrolled).
    #[allow(clippy::needless_range_loop)] // j indexes the control points and the values alike
    fn residuals_const<const N: usize>(&self, points: &[Vec3], ctrl: &[Vec3], out: &mut Vec<f64>) {
        let spans = self.spans.iter();
        for ((q, &span), nb) in points.iter().zip(spans).zip(self.values.chunks_exact(N)) {
            let cp = &ctrl[span + 1 - N..=span];
            let mut c = Vec3::ZERO;
            for j in 0..N {
                c += cp[j] * nb[j];
            }
            out.push((c - *q).norm());
        }
    }
}

/// The span `s` with `knots[s] <= u < knots[s + 1]` as [`find_span`] returns it, walking from `hint`.
#[inline(always)]
fn span_from(n: usize, p: usize, u: f64, knots: &[f64], hint: usize) -> usize {
    if u >= knots[n + 1] || u <= knots[p] || !(p..=n).contains(&hint) {
        return find_span(n, p, u, knots);
    }
    let mut s = hint;
    // u < knots[n + 1] stops the walk up at n; u > knots[p] stops the walk down at p
    while u >= knots[s + 1] {
        s += 1;
    }
    while u < knots[s] {
        s -= 1;
    }
    s
}

/// [`basis_funs_into`] for degree `N − 1` with fixed-size arrays (same arithmetic, same values).
#[inline(always)]
fn basis_const<const N: usize>(span: usize, u: f64, knots: &[f64]) -> [f64; N] {
    let mut out = [0.0; N];
    let (mut left, mut right) = ([0.0; N], [0.0; N]);
    // the 2p knots the recursion reads, `knots[span + 1 − p ..= span + p]` (one bounds check)
    let kw = &knots[span + 2 - N..span + N];
    out[0] = 1.0;
    for j in 1..N {
        left[j] = u - kw[N - 1 - j];
        right[j] = kw[N - 2 + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

    #[test]
    fn matches_span_search_basis_and_curve_points_bit_for_bit() {
        for p in 1..=7 {
            let n_ctrl = p + 6;
            let mut knots = vec![0.0; p + 1];
            let inner = [0.1, 0.3, 0.3, 0.55, 0.7, 0.9];
            knots.extend_from_slice(&inner[..n_ctrl - p - 1]);
            knots.extend(std::iter::repeat_n(1.0, p + 1));
            let ctrl: Vec<Vec3> = (0..n_ctrl)
                .map(|i| Vec3::new(i as f64, (i as f64).sin(), 0.5))
                .collect();
            let c = NurbsCurve::bspline(p, knots.clone(), ctrl.clone()).unwrap();
            // ordered, then shuffled parameters, knots and ends included
            let mut us: Vec<f64> = (0..=40).map(|k| k as f64 / 40.0).collect();
            us.extend([0.3, 0.0, 0.95, 0.1, 1.0, 0.31]);
            let mut db = DataBasis::new();
            db.fill(p, n_ctrl - 1, &knots, &us);
            let (mut l, mut r, mut want) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
            let q: Vec<Vec3> = us.iter().map(|&u| Vec3::new(u, 1.0, 0.0)).collect();
            let mut res = Vec::new();
            db.residual_norms_into(&q, &ctrl, &mut res);
            for (k, &u) in us.iter().enumerate() {
                let s = find_span(n_ctrl - 1, p, u, &knots);
                assert_eq!(db.spans()[k], s, "p={p} u={u}");
                basis_funs_into(s, u, p, &knots, &mut l, &mut r, &mut want);
                assert_eq!(db.values(k, k + 1), &want[..], "p={p} u={u}");
                assert_eq!(res[k], (c.point(u) - q[k]).norm(), "p={p} u={u}");
            }
        }
    }

    #[test]
    fn a_refill_after_knot_removal_equals_a_fresh_fill() {
        let us: Vec<f64> = (0..=80).map(|k| (k as f64 / 80.0).powf(1.2)).collect();
        let with = [
            0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.35, 0.5, 0.6, 0.8, 1.0, 1.0, 1.0, 1.0,
        ];
        let without = [
            0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.5, 0.6, 0.8, 1.0, 1.0, 1.0, 1.0,
        ];
        let mut reused = DataBasis::new();
        reused.fill(3, 9, &with, &us);
        reused.fill(3, 8, &without, &us);
        let mut fresh = DataBasis::new();
        fresh.fill(3, 8, &without, &us);
        assert_eq!(reused.spans(), fresh.spans());
        assert_eq!(reused.values(0, us.len()), fresh.values(0, us.len()));
        // values changed in place by a caller are never reused
        reused.values_mut(40)[0] = 7.0;
        reused.fill(3, 8, &without, &us);
        assert_eq!(reused.values(0, us.len()), fresh.values(0, us.len()));
        // an inserted knot, a moved one and shuffled parameters (runs of one point) likewise
        let other = [
            0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.5, 0.65, 0.8, 1.0, 1.0, 1.0, 1.0,
        ];
        let shuffled: Vec<f64> = (0..=80).map(|k| us[(k * 37) % 81]).collect();
        for (n, knots, params) in [
            (9, &other[..], &us),
            (9, &other[..], &shuffled),
            (8, &without[..], &shuffled),
        ] {
            reused.fill(3, n, knots, params);
            let mut fresh = DataBasis::new();
            fresh.fill(3, n, knots, params);
            assert_eq!(reused.spans(), fresh.spans());
            assert_eq!(reused.values(0, us.len()), fresh.values(0, us.len()));
        }
    }
}
