//! Univariate polynomials in Bernstein form on `[0, 1]`: arithmetic and robust isolation of the
//! parameters where a polynomial changes sign.
//!
//! A polynomial of degree `n` is the slice `c` of its `n + 1` Bernstein coefficients,
//! `f(t) = Σ c_i C(n, i) tⁱ (1 − t)ⁿ⁻ⁱ`. The form is the natural one for a Bézier piece of a
//! B-spline (its control points are the coefficients), products and derivatives stay in it, and
//! it is numerically stable on `[0, 1]`: evaluation and subdivision are de Casteljau's convex
//! combinations, so no value is ever larger than the largest coefficient.
//!
//! [`sign_changes`] isolates the sign changes by subdivision with Descartes' rule of signs for the
//! Bernstein basis: the number of roots in `(0, 1)` is at most the number of sign variations of
//! the coefficients and has the same parity. A piece without variations has no root, a piece with
//! one variation exactly one simple root (found by bisection on the piece's own coefficients),
//! otherwise the piece is halved. Pieces whose coefficients are all below the caller's `zero`
//! (rounding noise of a polynomial that vanishes identically, e.g. on a line or an exact circle)
//! are treated as zero and have no sign change; a cluster of roots closer than [`MIN_WIDTH`]
//! counts as one sign change when the signs at its ends differ, else as none (an even number of
//! crossings within 1e-13 of the span is not a visible feature). Near a multiple root, rounding
//! can report a sign change where `|f|` is at the noise level: callers that need the sign on each
//! side evaluate it away from the reported parameters (see [`super::exact_extrema`]).

/// Pieces narrower than this (in the `[0, 1]` parameter) are not split further.
pub const MIN_WIDTH: f64 = 1e-13;

/// Binomial coefficient `C(n, k)` as a float (exact for the degrees used here).
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut b = 1.0;
    for i in 0..k {
        b = b * (n - i) as f64 / (i + 1) as f64;
    }
    b.round()
}

/// `f(t)` by de Casteljau's algorithm (`c` non-empty).
pub fn eval(c: &[f64], t: f64) -> f64 {
    let mut w: Vec<f64> = c.to_vec();
    let n = w.len();
    for r in 1..n {
        for i in 0..n - r {
            w[i] = (1.0 - t) * w[i] + t * w[i + 1];
        }
    }
    w[0]
}

/// The derivative `f'` (degree `n − 1`; a constant's derivative is the zero constant).
pub fn derivative(c: &[f64]) -> Vec<f64> {
    let n = c.len() - 1;
    if n == 0 {
        return vec![0.0];
    }
    c.windows(2).map(|w| n as f64 * (w[1] - w[0])).collect()
}

/// The product `f g` (degree `m + n`).
pub fn mul(a: &[f64], b: &[f64]) -> Vec<f64> {
    let (m, n) = (a.len() - 1, b.len() - 1);
    let mut out = vec![0.0; m + n + 1];
    for (i, &ai) in a.iter().enumerate() {
        let ci = binomial(m, i);
        for (j, &bj) in b.iter().enumerate() {
            out[i + j] += ci * binomial(n, j) * ai * bj;
        }
    }
    for (k, o) in out.iter_mut().enumerate() {
        *o /= binomial(m + n, k);
    }
    out
}

/// `f` written with degree `n ≥` its own (repeated degree elevation).
pub(crate) fn elevate_to(c: &[f64], n: usize) -> Vec<f64> {
    let mut w = c.to_vec();
    while w.len() - 1 < n {
        let m = w.len(); // new degree
        let mut e = vec![0.0; m + 1];
        e[0] = w[0];
        e[m] = w[m - 1];
        for i in 1..m {
            let a = i as f64 / m as f64;
            e[i] = a * w[i - 1] + (1.0 - a) * w[i];
        }
        w = e;
    }
    w
}

/// `α f + β g` (degree the larger of the two).
pub(crate) fn combine(alpha: f64, a: &[f64], beta: f64, b: &[f64]) -> Vec<f64> {
    let n = (a.len().max(b.len())) - 1;
    let (a, b) = (elevate_to(a, n), elevate_to(b, n));
    a.iter()
        .zip(&b)
        .map(|(x, y)| alpha * x + beta * y)
        .collect()
}

/// The coefficients of `f` on `[0, ½]` and on `[½, 1]` (each reparametrised to `[0, 1]`).
pub fn halves(c: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = c.len();
    let mut w = c.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = vec![0.0; n];
    left.push(w[0]);
    right[n - 1] = w[n - 1];
    for r in 1..n {
        for i in 0..n - r {
            w[i] = 0.5 * (w[i] + w[i + 1]);
        }
        left.push(w[0]);
        right[n - 1 - r] = w[n - 1 - r];
    }
    (left, right)
}

/// Sign variations of the coefficients (exact zeros skipped).
pub fn variations(c: &[f64]) -> usize {
    let mut last = 0.0f64;
    let mut v = 0;
    for &x in c {
        if x == 0.0 {
            continue;
        }
        if last != 0.0 && (x > 0.0) != (last > 0.0) {
            v += 1;
        }
        last = x;
    }
    v
}

/// The parameters in `(0, 1)` where `f` changes sign, ascending, appended to `out` (see the module
/// documentation); coefficients of magnitude at most `zero` count as rounding noise.
pub fn sign_changes(c: &[f64], zero: f64, out: &mut Vec<f64>) {
    isolate(c, 0.0, 1.0, zero, false, out);
}

/// As [`sign_changes`], and also the parameters where the subdivision meets an exact zero of `f` (a
/// root at a dyadic parameter such as ½, which [`sign_changes`] passes over: neither half then has
/// ends of opposite signs), ascending: the candidates of a search that checks each one itself.
pub fn sign_changes_and_zeros(c: &[f64], zero: f64, out: &mut Vec<f64>) {
    isolate(c, 0.0, 1.0, zero, true, out);
}

fn isolate(c: &[f64], lo: f64, hi: f64, zero: f64, zeros: bool, out: &mut Vec<f64>) {
    if c.iter().all(|x| x.abs() <= zero) || c.iter().any(|x| !x.is_finite()) {
        return;
    }
    let v = variations(c);
    if v == 0 {
        return;
    }
    let (first, last) = (c[0], c[c.len() - 1]);
    let opposite = first != 0.0 && last != 0.0 && (first > 0.0) != (last > 0.0);
    if v == 1 && opposite {
        out.push(lo + (hi - lo) * bisect(c));
        return;
    }
    if hi - lo <= MIN_WIDTH {
        if opposite {
            out.push(0.5 * (lo + hi));
        }
        return;
    }
    let mid = 0.5 * (lo + hi);
    let (l, r) = halves(c);
    isolate(&l, lo, mid, zero, zeros, out);
    if zeros && l.last() == Some(&0.0) {
        out.push(mid);
    }
    isolate(&r, mid, hi, zero, zeros, out);
}

/// The root in `(0, 1)` of `f` with `f(0) f(1) < 0`, by bisection to rounding.
fn bisect(c: &[f64]) -> f64 {
    let (mut a, mut b) = (0.0f64, 1.0f64);
    let neg_at_a = c[0] < 0.0;
    for _ in 0..64 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if (eval(c, m) < 0.0) == neg_at_a {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bernstein coefficients of `(t − r₁)(t − r₂)…` by products of linear factors.
    fn from_roots(roots: &[f64]) -> Vec<f64> {
        roots
            .iter()
            .fold(vec![1.0], |acc, &r| mul(&acc, &[-r, 1.0 - r]))
    }

    #[test]
    fn products_derivatives_and_elevation_agree_with_power_form() {
        // f = (t − 0.2)(t − 0.7) = t² − 0.9 t + 0.14; f' = 2t − 0.9
        let f = from_roots(&[0.2, 0.7]);
        for &t in &[0.0, 0.13, 0.5, 0.91, 1.0] {
            let want = t * t - 0.9 * t + 0.14;
            assert!((eval(&f, t) - want).abs() < 1e-15);
            assert!((eval(&derivative(&f), t) - (2.0 * t - 0.9)).abs() < 1e-15);
            assert!((eval(&elevate_to(&f, 6), t) - want).abs() < 1e-15);
            let (l, r) = halves(&f);
            let (tl, tr) = (0.5 * t, 0.5 + 0.5 * t);
            assert!((eval(&l, t) - (tl * tl - 0.9 * tl + 0.14)).abs() < 1e-15);
            assert!((eval(&r, t) - (tr * tr - 0.9 * tr + 0.14)).abs() < 1e-15);
        }
        assert_eq!(binomial(6, 3), 20.0);
    }

    #[test]
    fn sign_changes_are_the_odd_roots() {
        // simple roots at 0.1, 0.1 + 1e-6, 0.5 and a double root at 0.8, which rounding may
        // turn into sign changes within 1e-7 of it, where |f| is at the noise level
        let f = from_roots(&[0.1, 0.1 + 1e-6, 0.5, 0.8, 0.8]);
        let zero = 1e-15 * f.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let mut out = Vec::new();
        sign_changes(&f, zero, &mut out);
        assert!(out.len() >= 3, "{out:?}");
        assert!((out[0] - 0.1).abs() < 1e-11 && (out[1] - 0.1 - 1e-6).abs() < 1e-11);
        assert!((out[2] - 0.5).abs() < 1e-12);
        for &t in &out[3..] {
            assert!(
                (t - 0.8).abs() < 1e-7 && eval(&f, t).abs() < 10.0 * zero,
                "{out:?}"
            );
        }
        // a root 1e-5 from the end of the interval
        out.clear();
        sign_changes(&from_roots(&[0.3, 1.0 - 1e-5]), 0.0, &mut out);
        assert_eq!(out.len(), 2);
        assert!((out[1] - (1.0 - 1e-5)).abs() < 1e-14);
        // noise below `zero` has none
        out.clear();
        sign_changes(&[1e-17, -1e-17, 1e-17, -1e-17], 1e-15, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn a_root_at_a_dyadic_split_is_a_zero_not_a_sign_change_of_either_half() {
        // -18 (1 - 2t)(2 (1 - 2t)² + 1): D·E of the cusped cubic (0,0) (1,1) (0,1) (1,0), root ½
        let f = [-54.0, 30.0, -30.0, 54.0];
        assert_eq!(eval(&f, 0.5), 0.0);
        let mut out = Vec::new();
        sign_changes(&f, 0.0, &mut out);
        assert_eq!(out, Vec::<f64>::new());
        sign_changes_and_zeros(&f, 0.0, &mut out);
        assert_eq!(out, vec![0.5]);
        // a root off the splits is found by both, once
        let g = from_roots(&[0.3, 0.5, 0.9]);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        sign_changes(&g, 0.0, &mut a);
        sign_changes_and_zeros(&g, 0.0, &mut b);
        assert_eq!(b.len(), 3, "{b:?}");
        assert!((b[0] - 0.3).abs() < 1e-15 && b[1] == 0.5 && (b[2] - 0.9).abs() < 1e-15);
        assert_eq!(a.len(), 2, "{a:?}");
    }
}
