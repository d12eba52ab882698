//! The piecewise power form of a non-rational B-spline curve: per non-empty knot span `[u_s, u_{s+1})`
//! the Taylor coefficients `C^(k)(u_s) / k!`, so a point and its derivatives cost one Horner scheme
//! instead of a span search and a basis-function recursion. The foot-point Newton iterations of the
//! deviation measures ([`super::foot`]) evaluate the curve thousands of times per fit through this.
//!
//! Spans are half-open on the right like [`crate::nurbs::knots::find_span`] (derivatives at an
//! interior knot are the right-hand ones; the last span includes the domain end), so results agree with
//! the basis-function evaluation to rounding. The span of the last evaluation is kept as the starting
//! guess of the next one (Newton steps move little).

use crate::nurbs::Vec3;

/// Highest degree converted to power form; above it the Taylor coefficients lose accuracy and callers
/// keep the basis-function recursion.
pub const MAX_POWER_DEGREE: usize = 7;

/// A curve in piecewise power form, buffers reused by [`PowerForm::rebuild`]. A span is converted
/// the first time it is evaluated (a probe that stops early touches few spans).
#[derive(Clone, Debug, Default)]
pub struct PowerForm {
    p: usize,
    /// start parameter of each non-empty span
    breaks: Vec<f64>,
    /// knot index `s` (`knots[s] <= u < knots[s + 1]`) of each non-empty span
    knot_of: Vec<usize>,
    /// `p + 1` Taylor coefficients per span, valid where `ready`
    coef: Vec<Vec3>,
    ready: Vec<bool>,
    /// span of the last evaluation
    last: usize,
}

impl PowerForm {
    /// An empty power form; call [`PowerForm::rebuild`].
    pub fn new() -> Self {
        Self::default()
    }

    /// Prepares the conversion of the non-rational curve of degree `p` (`p <= MAX_POWER_DEGREE`) with
    /// `knots` and `ctrl` (`knots.len() == ctrl.len() + p + 1`); pass the same `knots` and `ctrl` to
    /// [`PowerForm::eval2`].
    pub fn rebuild(&mut self, p: usize, knots: &[f64], ctrl: &[Vec3]) {
        debug_assert!(p <= MAX_POWER_DEGREE && knots.len() == ctrl.len() + p + 1);
        self.p = p;
        self.last = 0;
        self.breaks.clear();
        self.knot_of.clear();
        let n = ctrl.len() - 1;
        self.breaks.reserve(n + 1 - p);
        self.knot_of.reserve(n + 1 - p);
        for s in p..=n {
            if knots[s + 1] > knots[s] {
                self.breaks.push(knots[s]);
                self.knot_of.push(s);
            }
        }
        self.coef.clear();
        self.coef.resize(self.breaks.len() * (p + 1), Vec3::ZERO);
        self.ready.clear();
        self.ready.resize(self.breaks.len(), false);
    }

    /// Converts span `j`.
    fn convert(&mut self, j: usize, knots: &[f64], ctrl: &[Vec3]) {
        match self.p {
            1 => self.convert_const::<2>(j, knots, ctrl),
            2 => self.convert_const::<3>(j, knots, ctrl),
            3 => self.convert_const::<4>(j, knots, ctrl),
            4 => self.convert_const::<5>(j, knots, ctrl),
            5 => self.convert_const::<6>(j, knots, ctrl),
            6 => self.convert_const::<7>(j, knots, ctrl),
            _ => self.convert_const::<8>(j, knots, ctrl),
        }
    }

    /// [`PowerForm::convert`] for degree `P1 − 1` (`P1 − 1 == self.p`).
    fn convert_const<const P1: usize>(&mut self, j: usize, knots: &[f64], ctrl: &[Vec3]) {
        let p = P1 - 1;
        let s = self.knot_of[j];
        let ders = all_ders_const::<P1>(s, knots[s], knots);
        let cp = &ctrl[s - p..=s];
        let mut fact = 1.0;
        for (k, row) in ders.iter().enumerate() {
            if k > 1 {
                fact *= k as f64;
            }
            let mut c = Vec3::ZERO;
            for (q, &d) in cp.iter().zip(row) {
                c += *q * d;
            }
            self.coef[j * P1 + k] = c / fact;
        }
        self.ready[j] = true;
    }

    /// The index of the span holding `u`, walking from the last one used.
    #[inline]
    fn span(&mut self, u: f64) -> usize {
        let b = &self.breaks;
        let mut j = self.last.min(b.len() - 1);
        while j + 1 < b.len() && b[j + 1] <= u {
            j += 1;
        }
        while j > 0 && b[j] > u {
            j -= 1;
        }
        self.last = j;
        j
    }

    /// `C(u)`, `C'(u)` and `C''(u)` (`knots` and `ctrl` as given to [`PowerForm::rebuild`]).
    #[inline]
    pub fn eval2(&mut self, u: f64, knots: &[f64], ctrl: &[Vec3]) -> [Vec3; 3] {
        let j = self.span(u);
        if !self.ready[j] {
            self.convert(j, knots, ctrl);
        }
        let t = u - self.breaks[j];
        if self.p == 3 {
            horner2(&self.coef[4 * j..4 * j + 4], 3, t)
        } else {
            let p1 = self.p + 1;
            horner2(&self.coef[p1 * j..p1 * (j + 1)], self.p, t)
        }
    }
}

/// Value, first and second derivative of `Σ c_k t^k` (always inlined so a constant degree unrolls).
#[inline(always)]
fn horner2(c: &[Vec3], p: usize, t: f64) -> [Vec3; 3] {
    let (mut v0, mut v1, mut v2) = (c[p], Vec3::ZERO, Vec3::ZERO);
    for k in (0..p).rev() {
        v2 = v2 * t + v1;
        v1 = v1 * t + v0;
        v0 = v0 * t + c[k];
    }
    [v0, v1, v2 * 2.0]
}

/// All derivatives (orders `0..=p`, `p = P1 − 1`) of the `P1` non-zero basis functions at `u` in
/// `span`: [`crate::nurbs::basis::ders_basis_funs_into`] with `nd = p` on fixed-size arrays (the same
/// operations in the same order, hence the same values bit for bit, without its index arithmetic).
#[allow(clippy::needless_range_loop)] // the NURBS Book's indices, kept for the bit-for-bit match
fn all_ders_const<const P1: usize>(span: usize, u: f64, knots: &[f64]) -> [[f64; P1]; P1] {
    let p = P1 - 1;
    let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
    // ndu[j][r]: upper triangle basis values, lower triangle knot differences
    let mut ndu = [[0.0; P1]; P1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0; P1]; P1];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let mut a = [[0.0; P1]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=p {
            let mut d = 0.0;
            let pk = p - k;
            if r >= k {
                let rk = r - k;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            // j from max(1, k − r) to min(k − 1, p − r), with rk + j = r + j − k
            let j1 = if r + 1 >= k { 1 } else { k - r };
            let j2 = if r <= pk + 1 { k - 1 } else { p - r };
            for j in j1..=j2 {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][r + j - k];
                d += a[s2][j] * ndu[r + j - k][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut f = p as f64;
    for k in 1..=p {
        for j in 0..=p {
            ders[k][j] *= f;
        }
        f *= (p - k) as f64;
    }
    ders
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

    #[test]
    fn fixed_size_derivatives_equal_the_reference_recursion_bit_for_bit() {
        use crate::nurbs::basis::ders_basis_funs_into;
        fn check<const P1: usize>() {
            let p = P1 - 1;
            let mut knots = vec![0.0; p + 1];
            knots.extend_from_slice(&[0.1, 0.25, 0.25, 0.5, 0.55, 0.8]);
            knots.extend(std::iter::repeat_n(1.0, p + 1));
            let n = knots.len() - p - 2;
            let (mut l, mut r, mut ndu) = (vec![0.0; P1], vec![0.0; P1], vec![0.0; P1 * P1]);
            let (mut a, mut want) = (vec![0.0; 2 * P1], vec![0.0; P1 * P1]);
            for s in p..=n {
                if knots[s + 1] <= knots[s] {
                    continue;
                }
                for u in [knots[s], 0.3 * knots[s] + 0.7 * knots[s + 1]] {
                    ders_basis_funs_into(
                        s, u, p, p, &knots, &mut l, &mut r, &mut ndu, &mut a, &mut want,
                    );
                    let got = all_ders_const::<P1>(s, u, &knots);
                    for k in 0..=p {
                        for j in 0..=p {
                            let (g, w) = (got[k][j], want[k * P1 + j]);
                            assert_eq!(g.to_bits(), w.to_bits(), "p={p} s={s} u={u} k={k} j={j}");
                        }
                    }
                }
            }
        }
        check::<2>();
        check::<3>();
        check::<4>();
        check::<5>();
        check::<6>();
        check::<7>();
        check::<8>();
    }

    #[test]
    fn agrees_with_the_basis_function_evaluation() {
        for p in 1..=MAX_POWER_DEGREE {
            let n = p + 6;
            let ctrl: Vec<Vec3> = (0..n)
                .map(|i| {
                    let t = i as f64;
                    Vec3::new(t, (1.3 * t).sin(), 0.2 * (0.7 * t).cos())
                })
                .collect();
            // uneven interior knots, one of them double
            let mut knots = vec![0.0; p + 1];
            let inner = [0.1, 0.25, 0.25, 0.5, 0.55, 0.8];
            knots.extend_from_slice(&inner[..n - p - 1]);
            knots.extend(std::iter::repeat_n(1.0, p + 1));
            let c = NurbsCurve::bspline(p, knots.clone(), ctrl.clone()).unwrap();
            let mut pf = PowerForm::new();
            pf.rebuild(p, &knots, &ctrl);
            for k in 0..=200 {
                // visit spans out of order, knots included
                let u = ((k * 37) % 201) as f64 / 200.0;
                let want = c.derivatives(u, 2);
                let got = pf.eval2(u, &knots, &ctrl);
                for d in 0..3 {
                    let tol = 1e-12 * (1.0 + want[d].norm());
                    assert!(
                        (got[d] - want[d]).norm() <= tol,
                        "p={p} u={u} order {d}: {:?} vs {:?}",
                        got[d],
                        want[d]
                    );
                }
            }
        }
    }
}
