//! The piecewise power form of a non-rational B-spline curve: per non-empty knot span `[u_s, u_{s+1})`
//! the Taylor coefficients `C^(k)(u_s) / k!`, so a point and its derivatives cost one Horner scheme
//! instead of a span search and a basis-function recursion. The foot-point Newton iterations of the
//! deviation measures ([`super::foot`]) evaluate the curve thousands of times per fit through this.
//!
//! Spans are half-open on the right like [`crate::nurbs::knots::find_span`] (derivatives at an
//! interior knot are the right-hand ones; the last span includes the domain end), so results agree with
//! the basis-function evaluation to rounding. The span of the last evaluation is kept as the starting
//! guess of the next one (Newton steps move little).

use crate::nurbs::basis::ders_basis_funs_into;
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
        const P1: usize = MAX_POWER_DEGREE + 1;
        let (mut left, mut right) = ([0.0; P1], [0.0; P1]);
        let (mut ndu, mut a, mut ders) = ([0.0; P1 * P1], [0.0; 2 * P1], [0.0; P1 * P1]);
        let p = self.p;
        let s = self.knot_of[j];
        ders_basis_funs_into(
            s, knots[s], p, p, knots, &mut left, &mut right, &mut ndu, &mut a, &mut ders,
        );
        let mut fact = 1.0;
        for k in 0..=p {
            if k > 1 {
                fact *= k as f64;
            }
            let mut c = Vec3::ZERO;
            for i in 0..=p {
                c += ctrl[s - p + i] * ders[k * (p + 1) + i];
            }
            self.coef[j * (p + 1) + k] = c / fact;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

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
