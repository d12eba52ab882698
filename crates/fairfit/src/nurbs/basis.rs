//! B-spline basis functions and their derivatives (NURBS Book A2.2 and A2.3).
//!
//! The functions write into caller-provided slices so batched evaluation allocates nothing per point.
//! The private `Scratch` supplies stack buffers for degrees up to [`STACK_DEGREE`] and falls back to the heap
//! (once per batch, not per point) above that.

/// Degrees up to this value evaluate entirely on the stack.
pub const STACK_DEGREE: usize = 15;

/// Working memory for [`basis_funs`] and [`ders_basis_funs`]: reuse one per thread or per batch.
#[derive(Clone, Debug)]
pub struct BasisWorkspace {
    degree: usize,
    left: Vec<f64>,
    right: Vec<f64>,
    ndu: Vec<f64>,
    a: Vec<f64>,
}

impl BasisWorkspace {
    /// A workspace for basis functions of `degree`.
    pub fn new(degree: usize) -> Self {
        let p1 = degree + 1;
        BasisWorkspace {
            degree,
            left: vec![0.0; p1],
            right: vec![0.0; p1],
            ndu: vec![0.0; p1 * p1],
            a: vec![0.0; 2 * p1],
        }
    }
    /// The degree this workspace was sized for.
    pub fn degree(&self) -> usize {
        self.degree
    }
}

/// Fixed-size stack scratch (knot differences) used by the point evaluators for low degrees.
pub(crate) struct Scratch {
    pub left: [f64; STACK_DEGREE + 1],
    pub right: [f64; STACK_DEGREE + 1],
}

impl Scratch {
    #[inline]
    pub fn new() -> Self {
        Scratch {
            left: [0.0; STACK_DEGREE + 1],
            right: [0.0; STACK_DEGREE + 1],
        }
    }
}

/// Runs `f` with the three buffers a curve point evaluation at degree `p` needs (knot differences
/// left and right, basis values), each of at least `p + 1` entries: on the stack up to
/// [`STACK_DEGREE`], else in one heap allocation for the whole call.
#[inline]
pub(crate) fn with_basis_buffers<R>(
    p: usize,
    f: impl FnOnce(&mut [f64], &mut [f64], &mut [f64]) -> R,
) -> R {
    if p <= STACK_DEGREE {
        let mut left = [0.0; STACK_DEGREE + 1];
        let mut right = [0.0; STACK_DEGREE + 1];
        let mut n = [0.0; STACK_DEGREE + 1];
        f(&mut left, &mut right, &mut n)
    } else {
        let mut heap = vec![0.0; 3 * (p + 1)];
        let (left, rest) = heap.split_at_mut(p + 1);
        let (right, n) = rest.split_at_mut(p + 1);
        f(left, right, n)
    }
}

/// The non-vanishing basis functions `N[span-p..=span]` at `u` (NURBS Book A2.2).
///
/// `out`, `left` and `right` need at least `p + 1` entries.
#[inline]
pub fn basis_funs_into(
    span: usize,
    u: f64,
    p: usize,
    knots: &[f64],
    left: &mut [f64],
    right: &mut [f64],
    out: &mut [f64],
) {
    out[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
}

/// Convenience form of [`basis_funs_into`] using a [`BasisWorkspace`].
pub fn basis_funs(span: usize, u: f64, knots: &[f64], ws: &mut BasisWorkspace, out: &mut [f64]) {
    let p = ws.degree;
    basis_funs_into(span, u, p, knots, &mut ws.left, &mut ws.right, out);
}

/// Basis functions and their derivatives up to order `nd` at `u` (NURBS Book A2.3).
///
/// `ders` is row-major `(nd + 1) x (p + 1)`: `ders[k * (p + 1) + j]` is the k-th derivative of
/// `N[span - p + j]`. Derivative orders above `p` are zero. Scratch slices: `left`, `right` of length
/// `p + 1`, `ndu` of length `(p + 1)^2`, `a` of length `2 (p + 1)`.
///
/// Degrees 3 to 5 run with a constant degree (unrolled loops, the same arithmetic, so the same
/// values).
#[allow(clippy::too_many_arguments)]
pub fn ders_basis_funs_into(
    span: usize,
    u: f64,
    p: usize,
    nd: usize,
    knots: &[f64],
    left: &mut [f64],
    right: &mut [f64],
    ndu: &mut [f64],
    a: &mut [f64],
    ders: &mut [f64],
) {
    match p {
        3 => {
            // the cubic on local arrays of known length (no bounds checks in the unrolled
            // recursion; the same arithmetic): the scratch slices are not needed
            let _ = (left, right, ndu, a);
            let (mut l, mut r) = ([0.0; 4], [0.0; 4]);
            let (mut n, mut aa) = ([0.0; 16], [0.0; 8]);
            ders_basis_funs_any(span, u, 3, nd, knots, &mut l, &mut r, &mut n, &mut aa, ders)
        }
        4 => ders_basis_funs_any(span, u, 4, nd, knots, left, right, ndu, a, ders),
        5 => ders_basis_funs_any(span, u, 5, nd, knots, left, right, ndu, a, ders),
        _ => ders_basis_funs_any(span, u, p, nd, knots, left, right, ndu, a, ders),
    }
}

/// [`ders_basis_funs_into`] for any degree (always inlined so a constant `p` unrolls the loops).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn ders_basis_funs_any(
    span: usize,
    u: f64,
    p: usize,
    nd: usize,
    knots: &[f64],
    left: &mut [f64],
    right: &mut [f64],
    ndu: &mut [f64],
    a: &mut [f64],
    ders: &mut [f64],
) {
    let p1 = p + 1;
    // ndu[j][r] stored at j * p1 + r: upper triangle basis, lower triangle knot differences
    ndu[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j * p1 + r] = right[r + 1] + left[j - r];
            let temp = ndu[r * p1 + (j - 1)] / ndu[j * p1 + r];
            ndu[r * p1 + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * p1 + j] = saved;
    }
    for j in 0..=p {
        ders[j] = ndu[j * p1 + p];
    }
    let nmax = nd.min(p);
    for k in nmax + 1..=nd {
        for j in 0..=p {
            ders[k * p1 + j] = 0.0;
        }
    }
    // a is two rows of length p1
    for r in 0..=p as isize {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0] = 1.0;
        for k in 1..=nmax as isize {
            let mut d = 0.0;
            let rk = r - k;
            let pk = p as isize - k;
            if r >= k {
                let i = s2 * p1;
                a[i] = a[s1 * p1] / ndu[(pk as usize + 1) * p1 + rk as usize];
                d = a[i] * ndu[(rk as usize) * p1 + pk as usize];
            }
            let j1 = if rk >= -1 { 1 } else { -rk };
            let j2 = if r - 1 <= pk { k - 1 } else { p as isize - r };
            let mut j = j1;
            while j <= j2 {
                let idx = (j) as usize;
                a[s2 * p1 + idx] = (a[s1 * p1 + idx] - a[s1 * p1 + idx - 1])
                    / ndu[(pk as usize + 1) * p1 + (rk + j) as usize];
                d += a[s2 * p1 + idx] * ndu[((rk + j) as usize) * p1 + pk as usize];
                j += 1;
            }
            if r <= pk {
                a[s2 * p1 + k as usize] =
                    -a[s1 * p1 + (k - 1) as usize] / ndu[(pk as usize + 1) * p1 + r as usize];
                d += a[s2 * p1 + k as usize] * ndu[(r as usize) * p1 + pk as usize];
            }
            ders[k as usize * p1 + r as usize] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut r = p as f64;
    for k in 1..=nmax {
        for j in 0..=p {
            ders[k * p1 + j] *= r;
        }
        r *= (p - k) as f64;
    }
}

/// Convenience form of [`ders_basis_funs_into`] using a [`BasisWorkspace`].
pub fn ders_basis_funs(
    span: usize,
    u: f64,
    nd: usize,
    knots: &[f64],
    ws: &mut BasisWorkspace,
    ders: &mut [f64],
) {
    let p = ws.degree;
    ders_basis_funs_into(
        span,
        u,
        p,
        nd,
        knots,
        &mut ws.left,
        &mut ws.right,
        &mut ws.ndu,
        &mut ws.a,
        ders,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::knots::find_span;

    #[test]
    fn nurbs_book_example_2_3() {
        // U = {0,0,0,1,2,3,4,4,5,5,5}, p = 2, u = 5/2: N = 1/8, 6/8, 1/8 (NURBS Book Ex. 2.3)
        let knots = [0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0, 5.0, 5.0, 5.0];
        let span = find_span(7, 2, 2.5, &knots);
        assert_eq!(span, 4);
        let mut ws = BasisWorkspace::new(2);
        let mut n = [0.0; 3];
        basis_funs(span, 2.5, &knots, &mut ws, &mut n);
        assert!(
            (n[0] - 0.125).abs() < 1e-15
                && (n[1] - 0.75).abs() < 1e-15
                && (n[2] - 0.125).abs() < 1e-15
        );
        let mut d = [0.0; 9];
        ders_basis_funs(span, 2.5, 2, &knots, &mut ws, &mut d);
        // N'_{2,2} = -0.5, N'_{3,2} = 0, N'_{4,2} = 0.5; N'' = 1, -2, 1
        let expect = [0.125, 0.75, 0.125, -0.5, 0.0, 0.5, 1.0, -2.0, 1.0];
        for (a, b) in d.iter().zip(expect) {
            assert!((a - b).abs() < 1e-14, "{d:?}");
        }
    }
}
