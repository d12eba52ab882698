//! Closest-point projection of points onto curves: global sampling, then a safeguarded Newton step on
//! `f(u) = C'(u)·(C(u) − Q)` inside the bracket of the best sample (NURBS Book §6.1). The result is never
//! worse than the best sample. Newton runs on each side of the best sample, so corners (C0 knots)
//! are handled.

use crate::nurbs::{NurbsCurve, Vec3};

/// The foot of a projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Curve parameter of the foot point.
    pub u: f64,
    /// The foot point `C(u)`.
    pub point: Vec3,
    /// Distance `|C(u) − Q|`.
    pub distance: f64,
}

/// Projects many points onto one curve: the samples are computed once.
#[derive(Clone, Debug)]
pub struct CurveProjector<'a> {
    curve: &'a NurbsCurve,
    us: Vec<f64>,
    pts: Vec<Vec3>,
    /// index in `us` of the first sample of each non-empty span, plus the end
    span_start: Vec<usize>,
    breaks: Vec<f64>,
}

impl<'a> CurveProjector<'a> {
    /// Samples `curve` with `per_span` points in every non-empty knot span (at least 2).
    pub fn new(curve: &'a NurbsCurve, per_span: usize) -> Self {
        let per_span = per_span.max(2);
        let breaks = crate::nurbs::knots::distinct_breakpoints(curve.knots(), curve.degree());
        let mut us = Vec::with_capacity((breaks.len() - 1) * per_span + 1);
        let mut span_start = Vec::with_capacity(breaks.len());
        for w in breaks.windows(2) {
            span_start.push(us.len());
            for k in 0..per_span {
                us.push(w[0] + (w[1] - w[0]) * k as f64 / per_span as f64);
            }
        }
        span_start.push(us.len());
        us.push(*breaks.last().unwrap_or(&1.0));
        let pts = curve.points(&us);
        CurveProjector {
            curve,
            us,
            pts,
            span_start,
            breaks,
        }
    }

    /// The curve being projected onto.
    pub fn curve(&self) -> &NurbsCurve {
        self.curve
    }

    /// Closest point on the whole curve.
    pub fn project(&self, q: Vec3) -> Projection {
        self.project_in(q, 0, self.us.len() - 1)
    }

    /// Closest point searched near `hint`: the samples of the hint's span and its two neighbours on each
    /// side, then Newton. Use when the point's parameter is roughly known (parameter correction).
    pub fn project_near(&self, q: Vec3, hint: f64) -> Projection {
        let nspans = self.breaks.len() - 1;
        let span = match self.breaks.binary_search_by(|b| b.total_cmp(&hint)) {
            Ok(i) => i.min(nspans - 1),
            Err(i) => i.saturating_sub(1).min(nspans - 1),
        };
        let lo = self.span_start[span.saturating_sub(2)];
        let hi = self.span_start[(span + 3).min(nspans)];
        self.project_in(q, lo, hi)
    }

    fn project_in(&self, q: Vec3, lo: usize, hi: usize) -> Projection {
        let mut best = lo;
        let mut best_d2 = f64::INFINITY;
        for i in lo..=hi {
            let d2 = (self.pts[i] - q).norm_squared();
            if d2 < best_d2 {
                best_d2 = d2;
                best = i;
            }
        }
        let a = self.us[best.saturating_sub(1).max(lo)];
        let b = self.us[(best + 1).min(hi)];
        let sample = Projection {
            u: self.us[best],
            point: self.pts[best],
            distance: best_d2.sqrt(),
        };
        // Newton on each side of the best sample separately: at a C0 knot (a corner) the derivative
        // jumps, and one Newton run from the sample would only explore the side its one-sided
        // derivative points to
        let ub = self.us[best];
        let mut out = sample;
        for (lo_u, hi_u) in [(a, ub), (ub, b)] {
            if hi_u > lo_u {
                let refined = newton_in_bracket(self.curve, q, 0.5 * (lo_u + hi_u), lo_u, hi_u);
                if refined.distance < out.distance {
                    out = refined;
                }
            }
        }
        out
    }
}

/// Safeguarded Newton iteration on `f(u) = C'·(C − Q)` in `[a, b]`, starting at `u0`.
fn newton_in_bracket(curve: &NurbsCurve, q: Vec3, u0: f64, a: f64, b: f64) -> Projection {
    let mut d = [Vec3::ZERO; 3];
    let (mut lo, mut hi) = (a, b);
    let mut u = u0;
    let scale = (b - a).max(f64::MIN_POSITIVE);
    for _ in 0..30 {
        curve.derivatives_into(u, 2, &mut d);
        let diff = d[0] - q;
        let f = d[1].dot(diff);
        let fp = d[2].dot(diff) + d[1].norm_squared();
        // keep a bracket on the sign change of f where possible
        if f > 0.0 {
            hi = u;
        } else {
            lo = u;
        }
        let mut next = if fp > 0.0 { u - f / fp } else { f64::NAN };
        // a Newton step onto the bracket end is legitimate (already converged there)
        if !(next >= lo && next <= hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - u).abs() <= 1e-15 * scale.max(u.abs()) {
            u = next;
            break;
        }
        u = next;
    }
    let p = curve.point(u);
    Projection {
        u,
        point: p,
        distance: (p - q).norm(),
    }
}

/// Closest point of `curve` to `q` (16 samples per span, then Newton).
pub fn project_point(curve: &NurbsCurve, q: Vec3) -> Projection {
    CurveProjector::new(curve, 16).project(q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::knots::uniform_clamped;

    #[test]
    fn projection_of_curve_points_offset_along_normal() {
        let pts: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new(i as f64, ((i * 5) % 3) as f64 * 0.4, 0.0))
            .collect();
        let c = NurbsCurve::bspline(3, uniform_clamped(3, 8), pts).unwrap();
        let pr = CurveProjector::new(&c, 16);
        for k in 1..40 {
            let u = k as f64 / 40.0;
            let d = c.derivatives(u, 1);
            let n = Vec3::new(-d[1].y(), d[1].x(), 0.0) / d[1].norm();
            let q = d[0] + n * 1e-3;
            let p = pr.project(q);
            assert!((p.u - u).abs() < 1e-6, "u={u} got {}", p.u);
            assert!((p.distance - 1e-3).abs() < 1e-9);
            let p2 = pr.project_near(q, u + 0.01);
            assert!((p2.u - u).abs() < 1e-6);
        }
    }
}
