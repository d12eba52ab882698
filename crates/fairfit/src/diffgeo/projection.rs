//! Closest-point projection of points onto curves: global sampling, then safeguarded Newton steps on
//! `f(u) = C'(u)·(C(u) − Q)` (NURBS Book §6.1). The result is never worse than the best sample.
//!
//! Refining only the best sample misses the global minimum when another part of the curve passes
//! nearly as close (self-intersecting or folded curves, points between two branches): about 2.5 % of
//! such random cases. So every sample interval that *could* hold a closer point is refined too: on an
//! interval `[u_i, u_{i+1}]` with arc length `L`, every point is at least
//! `(|P_i − Q| + |P_{i+1} − Q| − L) / 2` from `Q` (triangle inequality from both ends). `L` is bounded by
//! the polyline through the interval's midpoint times a safety factor; an interval whose bound is below
//! the best distance found so far is halved (branch and bound, a few levels, the bound sharpening as the
//! polyline gets finer) and its surviving pieces are refined by Newton from their nearer end and middle.
//! A best sample on a knot also gets a Newton run on its left, so corners (C0 knots) are handled.

use crate::nurbs::{NurbsCurve, Vec3};
use std::sync::OnceLock;

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

/// Safety factor on the midpoint-polyline length of a sample interval: the interval's arc length is
/// taken to be at most this multiple (a circular arc turning 180° within one interval has arc/polyline
/// ≈ 1.11; anything sharper than that inside 1/16 of a knot span is outside what fitting produces).
const ARC_SAFETY: f64 = 1.25;

/// Projects many points onto one curve: the samples are computed once.
#[derive(Clone, Debug)]
pub struct CurveProjector<'a> {
    curve: &'a NurbsCurve,
    us: Vec<f64>,
    pts: Vec<Vec3>,
    /// upper estimate of the arc length between samples `i` and `i + 1`
    arc: Vec<f64>,
    /// index in `us` of the first sample of each non-empty span, plus the end
    span_start: Vec<usize>,
    breaks: Vec<f64>,
    /// bounding box (min, max) of the control points of each non-empty span: the span's piece of the
    /// curve lies inside (convex hull property, weights > 0)
    hull: Vec<(Vec3, Vec3)>,
    /// per non-empty span, the samples of its dense search (module doc of [`Self::project`]), computed
    /// the first time a projection needs them and shared by every later one: the dense search then
    /// measures distances instead of evaluating the curve (a whole-curve projection of many points
    /// costs a few distance computations per sample, not curve evaluations)
    dense: Vec<OnceLock<Box<[DenseSample]>>>,
}

/// A sample of the dense search: the parameter and the curve point there.
type DenseSample = (f64, Vec3);

impl<'a> CurveProjector<'a> {
    /// Samples `curve` with `per_span` points in every non-empty knot span (at least 2).
    pub fn new(curve: &'a NurbsCurve, per_span: usize) -> Self {
        let per_span = per_span.max(2);
        let breaks = crate::nurbs::knots::distinct_breakpoints(curve.knots(), curve.degree());
        // samples and the midpoints between them, interleaved
        let mut all = Vec::with_capacity(2 * (breaks.len() - 1) * per_span + 1);
        let mut span_start = Vec::with_capacity(breaks.len());
        for w in breaks.windows(2) {
            span_start.push(all.len() / 2);
            let n2 = 2 * per_span;
            for k in 0..n2 {
                all.push(w[0] + (w[1] - w[0]) * k as f64 / n2 as f64);
            }
        }
        span_start.push(all.len() / 2);
        all.push(*breaks.last().unwrap_or(&1.0));
        let all_pts = curve.points(&all);
        let us: Vec<f64> = all.iter().step_by(2).copied().collect();
        let pts: Vec<Vec3> = all_pts.iter().step_by(2).copied().collect();
        let arc = (0..us.len() - 1)
            .map(|i| {
                let m = all_pts[2 * i + 1];
                ARC_SAFETY * ((m - pts[i]).norm() + (pts[i + 1] - m).norm())
            })
            .collect();
        let (p, n) = (curve.degree(), curve.n_control_points());
        let cps = curve.control_points();
        let hull = breaks
            .windows(2)
            .map(|w| {
                let k =
                    crate::nurbs::knots::find_span(n - 1, p, 0.5 * (w[0] + w[1]), curve.knots());
                cps[k - p..=k].iter().fold(
                    (
                        Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
                        -Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
                    ),
                    |(lo, hi), c| (zip(lo, *c, f64::min), zip(hi, *c, f64::max)),
                )
            })
            .collect();
        CurveProjector {
            curve,
            us,
            pts,
            arc,
            span_start,
            dense: (0..breaks.len().saturating_sub(1))
                .map(|_| OnceLock::new())
                .collect(),
            breaks,
            hull,
        }
    }

    /// The curve being projected onto.
    pub fn curve(&self) -> &NurbsCurve {
        self.curve
    }

    /// Closest point on the whole curve. After the sampled search, every knot span whose control
    /// points' bounding box comes closer to `q` than the best point found is searched again at
    /// `DENSE_PER_SPAN` intervals, so folds and near-touching branches are not missed.
    pub fn project(&self, q: Vec3) -> Projection {
        let mut out = self.project_in(q, 0, self.us.len() - 1);
        for (s, w) in self.breaks.windows(2).enumerate() {
            let (lo, hi) = self.hull[s];
            let gap = zip(zip(lo - q, q - hi, f64::max), Vec3::ZERO, f64::max).norm();
            if gap < out.distance {
                self.dense_span(q, s, w[0], w[1], &mut out);
            }
        }
        out
    }

    /// `[a, b]` (span `s`) cut into [`DENSE_PER_SPAN`] intervals, each searched by
    /// [`refine_interval`] when its distance bound is below `out.distance`.
    fn dense_span(&self, q: Vec3, s: usize, a: f64, b: f64, out: &mut Projection) {
        let samples = self.dense[s].get_or_init(|| dense_samples(self.curve, a, b));
        // samples[2k] is the k-th interval end, samples[2k + 1] the midpoint of interval k
        let at = |i: usize| {
            let (u, p) = samples[i];
            (u, p, (p - q).norm())
        };
        let mut left = at(0);
        for k in 0..DENSE_PER_SPAN {
            let right = at(2 * k + 2);
            refine_from_mid(self.curve, q, left, right, at(2 * k + 1), 2, out);
            left = right;
        }
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
        let d = |i: usize| (self.pts[i] - q).norm();
        let mut best = lo;
        let mut best_d = f64::INFINITY;
        for i in lo..=hi {
            let di = d(i);
            if di < best_d {
                best_d = di;
                best = i;
            }
        }
        let a = self.us[best.saturating_sub(1).max(lo)];
        let b = self.us[(best + 1).min(hi)];
        let ub = self.us[best];
        let mut out = Projection {
            u: ub,
            point: self.pts[best],
            distance: best_d,
        };
        let keep = |p: Projection, out: &mut Projection| {
            if p.distance < out.distance {
                *out = p;
            }
        };
        let (p, mut settled) = newton_local_min(self.curve, q, ub, a, b);
        keep(p, &mut out);
        // at a knot the derivative may jump (a C0 corner): Newton from the knot follows the one-sided
        // derivative to the right, so the left side gets its own run
        if ub > a && self.breaks.binary_search_by(|k| k.total_cmp(&ub)).is_ok() {
            let (p, ok) = newton_local_min(self.curve, q, 0.5 * (a + ub), a, ub);
            settled &= ok;
            keep(p, &mut out);
        }
        // every interval that may hold a closer point (no allocation: one more pass); the two around
        // the best sample only when Newton did not end in a local minimum inside them
        let mut d_left = d(lo);
        for i in lo..hi {
            let d_right = d(i + 1);
            let bound = 0.5 * (d_left + d_right - self.arc[i]);
            if bound < out.distance && !(settled && (i + 1 == best || i == best)) {
                let a = (self.us[i], self.pts[i], d_left);
                let b = (self.us[i + 1], self.pts[i + 1], d_right);
                refine_interval(self.curve, q, a, b, REFINE_DEPTH, &mut out);
            }
            d_left = d_right;
        }
        out
    }
}

/// Component-wise `f` of two vectors.
fn zip(a: Vec3, b: Vec3, f: fn(f64, f64) -> f64) -> Vec3 {
    Vec3::new(f(a.x(), b.x()), f(a.y(), b.y()), f(a.z(), b.z()))
}

/// Intervals per knot span of the second, dense search of [`CurveProjector::project`].
const DENSE_PER_SPAN: usize = 32;

/// The `2 DENSE_PER_SPAN + 1` samples of the dense search of `[a, b]`: the ends of the intervals
/// (`a + (b − a) k / DENSE_PER_SPAN`, `b` exactly at the end) and, between them, the midpoints
/// [`refine_interval`] takes.
fn dense_samples(curve: &NurbsCurve, a: f64, b: f64) -> Box<[DenseSample]> {
    let end = |k: usize| {
        if k == DENSE_PER_SPAN {
            b
        } else {
            a + (b - a) * k as f64 / DENSE_PER_SPAN as f64
        }
    };
    let mut out = Vec::with_capacity(2 * DENSE_PER_SPAN + 1);
    for k in 0..DENSE_PER_SPAN {
        let (u0, u1) = (end(k), end(k + 1));
        let um = 0.5 * (u0 + u1);
        out.push((u0, curve.point(u0)));
        out.push((um, curve.point(um)));
    }
    out.push((b, curve.point(b)));
    out.into_boxed_slice()
}

/// Halvings of a candidate interval before Newton (at most `2^REFINE_DEPTH` Newton brackets, only
/// those whose bound stays below the best distance).
const REFINE_DEPTH: u32 = 3;

/// Branch and bound on `[a, b]` (each end as (u, C(u), |C(u) − Q|)): the midpoint is a sample, halves
/// whose distance bound is below `out.distance` are split again, `depth` times, then refined by Newton
/// from their nearer end and from their middle. Halving makes the bound sharper (a finer polyline) and
/// separates several critical points of the distance in one interval.
fn refine_interval(
    curve: &NurbsCurve,
    q: Vec3,
    a: (f64, Vec3, f64),
    b: (f64, Vec3, f64),
    depth: u32,
    out: &mut Projection,
) {
    let um = 0.5 * (a.0 + b.0);
    let pm = curve.point(um);
    refine_from_mid(curve, q, a, b, (um, pm, (pm - q).norm()), depth, out);
}

/// [`refine_interval`] with the midpoint sample `m` of `[a, b]` given.
fn refine_from_mid(
    curve: &NurbsCurve,
    q: Vec3,
    a: (f64, Vec3, f64),
    b: (f64, Vec3, f64),
    m: (f64, Vec3, f64),
    depth: u32,
    out: &mut Projection,
) {
    let (um, pm) = (m.0, m.1);
    if m.2 < out.distance {
        *out = Projection {
            u: um,
            point: pm,
            distance: m.2,
        };
    }
    let arc = ARC_SAFETY * ((pm - a.1).norm() + (b.1 - pm).norm());
    if 0.5 * (a.2 + b.2 - arc) >= out.distance {
        return;
    }
    if depth == 0 {
        let start = if a.2 <= b.2 { a.0 } else { b.0 };
        for u0 in [start, um] {
            let p = newton_in_bracket(curve, q, u0, a.0, b.0);
            if p.distance < out.distance {
                *out = p;
            }
        }
        return;
    }
    let (first, second) = if a.2 <= b.2 {
        ((a, m), (m, b))
    } else {
        ((m, b), (a, m))
    };
    for (x, y) in [first, second] {
        refine_interval(curve, q, x, y, depth - 1, out);
    }
}

/// Safeguarded Newton iteration on `f(u) = C'·(C − Q)` in `[a, b]`, starting at `u0`.
fn newton_in_bracket(curve: &NurbsCurve, q: Vec3, u0: f64, a: f64, b: f64) -> Projection {
    newton_local_min(curve, q, u0, a, b).0
}

/// [`newton_in_bracket`], also telling whether it converged to a local minimum of the distance strictly
/// inside `(a, b)` (`f = 0`, `f' > 0`).
fn newton_local_min(curve: &NurbsCurve, q: Vec3, u0: f64, a: f64, b: f64) -> (Projection, bool) {
    let mut d = [Vec3::ZERO; 3];
    let (mut lo, mut hi) = (a, b);
    let mut u = u0;
    let scale = (b - a).max(f64::MIN_POSITIVE);
    let mut converged = false;
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
        if (next - u).abs() <= 1e-14 * scale.max(u.abs()) {
            converged = fp > 0.0 && next > a && next < b;
            u = next;
            break;
        }
        u = next;
    }
    let p = curve.point(u);
    let proj = Projection {
        u,
        point: p,
        distance: (p - q).norm(),
    };
    (proj, converged)
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
