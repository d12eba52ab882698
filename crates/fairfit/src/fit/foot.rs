//! Foot points from a parameter hint: a few Newton steps on `f(u) = C'(u)·(C(u) − Q)` starting at the
//! point's fitting parameter, for non-rational B-splines, with buffers held across points.
//!
//! This is the cheap first try of the deviation measures in [`super::deviation`]. Any curve point
//! bounds the orthogonal distance from above, so the best distance seen is an upper bound; a converged
//! step (a stationary point of the distance near the hint) is the local foot. Points whose foot is not
//! found this way go to the sampled projector ([`crate::diffgeo::CurveProjector`]).
//!
//! Curves of degree up to [`super::power::MAX_POWER_DEGREE`] are evaluated through their piecewise
//! power form ([`super::power`]), converted once per curve; higher degrees use the basis functions.

use super::power::{PowerForm, MAX_POWER_DEGREE};
use crate::nurbs::basis::ders_basis_funs_into;
use crate::nurbs::knots::find_span;
use crate::nurbs::{NurbsCurve, Vec3};

/// Newton steps tried from the hint.
const MAX_STEPS: usize = 8;

/// The result of [`FootFinder::refine`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Foot {
    /// Parameter of the best point seen.
    pub u: f64,
    /// Its distance to the data point (an upper bound of the orthogonal distance).
    pub distance: f64,
    /// True when Newton converged onto a minimum of the distance inside the domain (or onto a domain
    /// end with the distance growing inward).
    pub converged: bool,
}

/// Newton foot-point refinement on one non-rational curve.
#[derive(Clone, Debug)]
pub struct FootFinder<'a> {
    knots: &'a [f64],
    ctrl: &'a [Vec3],
    p: usize,
    n: usize,
    lo: f64,
    hi: f64,
    left: Vec<f64>,
    right: Vec<f64>,
    ndu: Vec<f64>,
    a: Vec<f64>,
    ders: Vec<f64>,
    /// the curve in power form (degrees up to [`MAX_POWER_DEGREE`])
    power: Option<PowerForm>,
}

impl<'a> FootFinder<'a> {
    /// A finder for `curve`, or `None` for rational curves (use the sampled projector there).
    pub fn new(curve: &'a NurbsCurve) -> Option<Self> {
        if curve.is_rational() {
            return None;
        }
        let p = curve.degree();
        let p1 = p + 1;
        let (lo, hi) = curve.domain();
        let buffer = |len: usize| {
            if p <= MAX_POWER_DEGREE {
                Vec::new()
            } else {
                vec![0.0; len]
            }
        };
        let power = (p <= MAX_POWER_DEGREE).then(|| {
            let mut f = PowerForm::new();
            f.rebuild(p, curve.knots(), curve.control_points());
            f
        });
        Some(FootFinder {
            knots: curve.knots(),
            ctrl: curve.control_points(),
            p,
            n: curve.control_points().len() - 1,
            lo,
            hi,
            // the basis-function buffers serve degrees above the power form's only
            left: buffer(p1),
            right: buffer(p1),
            ndu: buffer(p1 * p1),
            a: buffer(2 * p1),
            ders: buffer(3 * p1),
            power,
        })
    }

    /// `C(u)`, `C'(u)`, `C''(u)`.
    #[inline]
    fn eval2(&mut self, u: f64) -> [Vec3; 3] {
        if let Some(f) = self.power.as_mut() {
            return f.eval2(u, self.knots, self.ctrl);
        }
        let p = self.p;
        let span = find_span(self.n, p, u, self.knots);
        ders_basis_funs_into(
            span,
            u,
            p,
            2,
            self.knots,
            &mut self.left,
            &mut self.right,
            &mut self.ndu,
            &mut self.a,
            &mut self.ders,
        );
        let p1 = p + 1;
        let mut out = [Vec3::ZERO; 3];
        for (k, o) in out.iter_mut().enumerate() {
            let row = &self.ders[k * p1..(k + 1) * p1];
            for (j, &nj) in row.iter().enumerate() {
                *o += self.ctrl[span - p + j] * nj;
            }
        }
        out
    }

    /// Newton from `hint` toward the foot of `q`; never worse than the distance at `hint`.
    pub fn refine(&mut self, q: Vec3, hint: f64) -> Foot {
        self.refine_until(q, hint, 0.0)
    }

    /// [`FootFinder::refine`], stopping as soon as a curve point within `enough` of `q` is found (then
    /// `converged` is false but the distance already answers "within `enough`?").
    pub fn refine_until(&mut self, q: Vec3, hint: f64, enough: f64) -> Foot {
        let scale = self.hi - self.lo;
        let mut u = hint.clamp(self.lo, self.hi);
        let mut best = Foot {
            u,
            distance: f64::INFINITY,
            converged: false,
        };
        for _ in 0..MAX_STEPS {
            let [c, d1, d2] = self.eval2(u);
            let diff = c - q;
            let dist = diff.norm();
            if dist < best.distance {
                best.u = u;
                best.distance = dist;
                if dist <= enough {
                    // a point on the curve is its own foot
                    best.converged = dist == 0.0;
                    return best;
                }
            }
            let f = d1.dot(diff);
            let fp = d2.dot(diff) + d1.norm_squared();
            if fp <= 0.0 || !fp.is_finite() {
                return best;
            }
            let next = (u - f / fp).clamp(self.lo, self.hi);
            let step = (next - u).abs();
            // at a domain end with the distance growing inward: a (one-sided) minimum
            let pinned = step == 0.0 && (u == self.lo || u == self.hi);
            if step <= 1e-13 * scale || pinned {
                // the distance at `next` differs from the one at `u` by O(step²); the best point
                // seen is within rounding of it
                best.converged = true;
                return best;
            }
            u = next;
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diffgeo::CurveProjector;
    use crate::nurbs::knots::uniform_clamped;

    #[test]
    fn agrees_with_the_sampled_projector_near_a_good_hint() {
        let pts: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new(i as f64, ((i * 5) % 3) as f64 * 0.4, 0.1 * i as f64))
            .collect();
        let c = NurbsCurve::bspline(3, uniform_clamped(3, 8), pts).unwrap();
        let proj = CurveProjector::new(&c, 32);
        let mut f = FootFinder::new(&c).unwrap();
        for k in 0..=60 {
            let u = k as f64 / 60.0;
            let d = c.derivatives(u, 1);
            let side = Vec3::new(-d[1].y(), d[1].x(), 0.3).cross(d[1]);
            let side = side * (2e-3 / side.norm());
            let q = d[0] + side;
            let got = f.refine(q, (u + 0.01).min(1.0));
            let want = proj.project(q);
            assert!(got.converged, "u={u}");
            assert!((got.distance - want.distance).abs() < 1e-12, "u={u}");
            assert!(
                (got.u - want.u).abs() < 1e-8,
                "u={u}: {} vs {}",
                got.u,
                want.u
            );
        }
    }

    #[test]
    fn a_point_on_the_curve_is_its_own_converged_foot() {
        // an interpolated end point: distance exactly 0 at the hint (the deviation measure used to
        // send it to the sampled projector)
        let pts: Vec<Vec3> = (0..6)
            .map(|i| Vec3::new(i as f64, (i as f64).sqrt(), 0.0))
            .collect();
        let c = NurbsCurve::bspline(3, uniform_clamped(3, 6), pts.clone()).unwrap();
        let mut f = FootFinder::new(&c).unwrap();
        let got = f.refine(pts[0], 0.0);
        assert_eq!((got.u, got.distance, got.converged), (0.0, 0.0, true));
        // at the far end the power form rounds (t = 1 − last break): Newton converges there
        let got = f.refine(pts[5], 1.0);
        assert!(
            got.converged && got.u == 1.0 && got.distance < 1e-14,
            "{got:?}"
        );
        // a point off the curve within `enough` is not reported converged
        let got = f.refine_until(pts[0] + Vec3::new(0.0, 1e-3, 0.0), 0.0, 1e-2);
        assert!(!got.converged && got.distance <= 1e-2);
    }

    #[test]
    fn rational_curves_are_declined() {
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::ZERO,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
            ],
            Some(vec![1.0, 0.5, 1.0]),
        )
        .unwrap();
        assert!(FootFinder::new(&c).is_none());
    }
}
