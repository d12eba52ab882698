//! Counting curvature extrema: sign changes of `dκ/ds` on dense samples of every knot span, with
//! the benchmark measurer's hysteresis floor. Band fairing's line search and sign guard and the
//! polish's move guard use it; a count after moving a few control points re-evaluates only the
//! spans they reach, with the same arithmetic, so it equals the full count.

use super::nodes::{basis_ders, node_derivatives, sign_changes, Node};
use crate::nurbs::Vec3;
use crate::optim::search::objective::{speed_and_dkappa_du, MAX_DEGREE};

/// Samples per knot span of [`ExtremaCount`] (midpoints of equal cells), plus one sample at
/// `EXTREMA_EDGE` of the span from each end: a cubic's `dκ/ds` can change sign between the Gauss
/// nodes (32 per span), and it may jump at a knot, so a sign change right next to a knot is only
/// seen close to it.
const EXTREMA_SAMPLES: usize = 96;
/// See [`EXTREMA_SAMPLES`]: close enough to the knot that a sign flip in a span's first or last
/// sliver is seen (the edge sign targets hold `dκ/ds` at the same offset), so the guards leave no
/// pair of extrema that only the exact count ([`crate::fair::exact_extrema`]) finds.
const EXTREMA_EDGE: f64 = 1e-6;

/// Counts curvature extrema: sign changes of `dκ/ds` with the measurer's hysteresis floor on
/// `EXTREMA_SAMPLES` (96) samples per knot span and one next to each knot; used by band fairing's
/// and the polish's guards. No allocation per count.
pub struct ExtremaCount {
    pub(crate) nodes: Vec<Node>,
    degree: usize,
    planar: bool,
    /// Per sample of the last count: `dκ/ds` and its share `w |C'|` of the length.
    dkds: Vec<f64>,
    wv: Vec<f64>,
    /// The samples [`ExtremaCount::count_moved`] changed and their values before.
    changed: std::ops::Range<usize>,
    saved: Vec<(f64, f64)>,
}

impl ExtremaCount {
    /// The node rule of a B-spline of degree `p` (at most [`MAX_DEGREE`]) with `n` control points
    /// on `knots`.
    pub fn new(knots: &[f64], p: usize, n: usize, planar: bool) -> Self {
        assert!(p <= MAX_DEGREE, "degree {p} above {MAX_DEGREE}");
        let mut nodes = Vec::new();
        for s in p..n {
            let (a, b) = (knots[s], knots[s + 1]);
            if b <= a {
                continue;
            }
            let h = (b - a) / EXTREMA_SAMPLES as f64;
            let at = |u: f64, weight: f64| Node {
                span: s,
                weight,
                ders: basis_ders(knots, p, s, u, 3.min(p)),
            };
            nodes.push(at(a + EXTREMA_EDGE * (b - a), 0.0));
            for k in 0..EXTREMA_SAMPLES {
                nodes.push(at(a + (k as f64 + 0.5) * h, h));
            }
            nodes.push(at(b - EXTREMA_EDGE * (b - a), 0.0));
        }
        ExtremaCount {
            dkds: vec![0.0; nodes.len()],
            wv: vec![0.0; nodes.len()],
            nodes,
            degree: p,
            planar,
            changed: 0..0,
            saved: Vec::new(),
        }
    }

    /// The sign of `dκ/ds` at every sample (0 inside the hysteresis floor) into `out`.
    pub(crate) fn signs(&mut self, ctrl: &[Vec3], out: &mut Vec<i8>) {
        self.count(ctrl);
        let peak = self.dkds.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let floor = 1e-6 * peak;
        out.clear();
        out.extend(self.dkds.iter().map(|&v| {
            if v >= floor && v > 0.0 {
                1
            } else if v <= -floor && v < 0.0 {
                -1
            } else {
                0
            }
        }));
    }

    /// Curvature extrema of the curve with control points `ctrl`.
    pub fn count(&mut self, ctrl: &[Vec3]) -> usize {
        self.changed = 0..0;
        self.sample(ctrl, 0..self.nodes.len());
        self.total()
    }

    /// [`ExtremaCount::count`] of `ctrl` when it differs from the last counted curve only in the
    /// control points `moved` (clamped indices): only the samples of the knot spans those reach
    /// are evaluated again, with the same arithmetic, so the count is the full one's.
    /// [`ExtremaCount::revert`] restores the last counted curve's samples.
    pub fn count_moved(&mut self, ctrl: &[Vec3], moved: std::ops::RangeInclusive<usize>) -> usize {
        let (lo, hi) = (*moved.start(), moved.end() + self.degree);
        let a = self.nodes.partition_point(|nd| nd.span < lo);
        let b = self.nodes.partition_point(|nd| nd.span <= hi);
        self.saved.clear();
        self.saved.extend(
            self.dkds[a..b]
                .iter()
                .copied()
                .zip(self.wv[a..b].iter().copied()),
        );
        self.changed = a..b;
        self.sample(ctrl, a..b);
        self.total()
    }

    /// Restores the samples of the curve counted before the last
    /// [`ExtremaCount::count_moved`].
    pub fn revert(&mut self) {
        for (k, &(d, w)) in self.changed.clone().zip(&self.saved) {
            self.dkds[k] = d;
            self.wv[k] = w;
        }
        self.changed = 0..0;
    }

    /// Evaluates the samples `range` of the curve with control points `ctrl`.
    fn sample(&mut self, ctrl: &[Vec3], range: std::ops::Range<usize>) {
        for k in range {
            let nd = &self.nodes[k];
            let (v, dk) =
                speed_and_dkappa_du(&node_derivatives(nd, ctrl, self.degree), self.planar);
            self.wv[k] = nd.weight * v;
            self.dkds[k] = if v > 0.0 { dk / v } else { 0.0 };
        }
    }

    /// The extrema of the sampled curve (the length summed in sample order).
    fn total(&self) -> usize {
        let mut length = 0.0;
        for &w in &self.wv {
            length += w;
        }
        sign_changes(&self.dkds, length * length)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_after_moving_one_control_point_is_the_full_count() {
        // a cubic with 10 control points on a wave: its curvature has extrema between the
        // bumps; pushing one control point across adds a wiggle. The incremental count must
        // equal a fresh full count of the moved curve, and after `revert` the original count.
        let n = 10;
        let knots: Vec<f64> = [0.0; 4]
            .into_iter()
            .chain((1..n - 3).map(|i| i as f64 / (n - 3) as f64))
            .chain([1.0; 4])
            .collect();
        let ctrl: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f64, (0.9 * i as f64).sin(), 0.0))
            .collect();
        let mut counter = ExtremaCount::new(&knots, 3, n, true);
        let before = counter.count(&ctrl);
        let mut moved = ctrl.clone();
        moved[5] += Vec3::new(0.0, -2.5, 0.0);
        let full = ExtremaCount::new(&knots, 3, n, true).count(&moved);
        assert!(full != before, "{full} {before}");
        assert_eq!(counter.count_moved(&moved, 5..=5), full);
        counter.revert();
        assert_eq!(counter.count_moved(&ctrl, 5..=5), before);
    }
}
