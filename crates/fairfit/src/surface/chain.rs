//! Ordering unorganised planar points into one chain: a nearest-neighbour tour from an extreme point,
//! improved by 2-opt, then gaps found as tour edges much longer than the typical spacing. The tour is
//! never bridged silently: every gap is returned with its length, so callers report it.
//!
//! Written here (no crate orders scan slices). The cost is near linear in the point count, so a slab
//! of a 10^6-point cloud is ordered in well under a second:
//! - the nearest unused neighbour is found on a uniform grid (`surface/point_grid.rs`),
//!   exactly the one a scan of every point finds (smallest distance, then smallest index);
//! - the windowed 2-opt costs `O(n · window)` per pass, for a bounded number of passes;
//! - the global 2-opt between long edges (a tour that jumps across a hole and back) looks at the
//!   `MAX_LONG_EDGES` longest edges at most, for as many moves: a band of noisy points has many
//!   "long" edges that no global move mends, and an unbounded search over them is quadratic.

use super::point_grid::PointGrid;
use crate::nurbs::Vec3;

/// The most long edges the global 2-opt pairs up, and the most moves it makes.
const MAX_LONG_EDGES: usize = 64;

/// A long edge of a chain: likely a hole in the data.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Gap {
    /// Index of the section (slice) in which the gap lies.
    pub section: usize,
    /// The point before the gap.
    pub from: [f64; 3],
    /// The point after the gap.
    pub to: [f64; 3],
    /// Length of the gap.
    pub length: f64,
    /// Typical spacing of the chain's points, for comparison: their median spacing (for a cloud
    /// slab thinned at a tolerance, at least that tolerance).
    pub typical_spacing: f64,
    /// What was done about it: "bridged" (the chain continues across it) or "open" (the chain ends there).
    pub handling: String,
}

/// Median of the distances between consecutive points (cyclic when `closed`).
pub(crate) fn median_spacing(points: &[Vec3], closed: bool) -> f64 {
    let n = points.len();
    if n < 2 {
        return 0.0;
    }
    let mut d: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    if closed {
        d.push(points[n - 1].distance(points[0]));
    }
    d.sort_by(|a, b| a.total_cmp(b));
    d[d.len() / 2]
}

/// Orders `points` (already near one plane) into a closed tour: nearest neighbour from the point with the
/// largest coordinate along `dir`, then 2-opt passes over a window of following edges.
pub fn order_points(points: &[Vec3], dir: Vec3) -> Vec<Vec3> {
    let n = points.len();
    if n < 3 {
        return points.to_vec();
    }
    let start = (0..n)
        .max_by(|&a, &b| points[a].dot(dir).total_cmp(&points[b].dot(dir)))
        .unwrap_or(0);
    let mut unused = PointGrid::new(points);
    let mut tour = Vec::with_capacity(n);
    let mut cur = start;
    unused.remove(points, cur);
    tour.push(cur);
    while let Some(best) = unused.nearest(points, points[cur]) {
        unused.remove(points, best);
        tour.push(best);
        cur = best;
    }
    // 2-opt on the closed tour, window-limited
    let window = 60.min(n - 1);
    let mut t = tour;
    for _pass in 0..20 {
        let mut improved = false;
        for i in 0..n - 1 {
            let (a, b) = (t[i], t[i + 1]);
            for k in i + 2..(i + 2 + window).min(n) {
                let (c, e) = (t[k], t[(k + 1) % n]);
                if e == a {
                    continue;
                }
                let before = points[a].distance(points[b]) + points[c].distance(points[e]);
                let after = points[a].distance(points[c]) + points[b].distance(points[e]);
                if after < before - 1e-12 * before {
                    t[i + 1..=k].reverse();
                    improved = true;
                    break;
                }
            }
        }
        if !improved {
            break;
        }
    }
    // global 2-opt between long edges (a nearest-neighbour tour that jumps across a hole and back)
    let long = |t: &[usize]| -> Vec<usize> {
        let pts: Vec<Vec3> = t.iter().map(|&i| points[i]).collect();
        let typical = median_spacing(&pts, true);
        let length = |i: usize| points[t[i]].distance(points[t[(i + 1) % n]]);
        let mut l: Vec<usize> = (0..n).filter(|&i| length(i) > 3.0 * typical).collect();
        if l.len() > MAX_LONG_EDGES {
            // the longest ones, then back in tour order (the pairs are scanned in that order)
            l.sort_by(|&a, &b| length(b).total_cmp(&length(a)).then(a.cmp(&b)));
            l.truncate(MAX_LONG_EDGES);
            l.sort_unstable();
        }
        l
    };
    for _ in 0..n.min(MAX_LONG_EDGES) {
        let l = long(&t);
        let mut best: Option<(f64, usize, usize)> = None;
        for (x, &i) in l.iter().enumerate() {
            for &k in &l[x + 1..] {
                let (a, b, c, e) = (t[i], t[(i + 1) % n], t[k], t[(k + 1) % n]);
                let before = points[a].distance(points[b]) + points[c].distance(points[e]);
                let after = points[a].distance(points[c]) + points[b].distance(points[e]);
                let gain = before - after;
                if gain > 1e-12 * before && best.is_none_or(|bb| gain > bb.0) {
                    best = Some((gain, i, k));
                }
            }
        }
        let Some((_, i, k)) = best else { break };
        t[i + 1..=k].reverse();
    }
    t.into_iter().map(|i| points[i]).collect()
}

/// An edge longer than this many median spacings ends a run that [`mend_detours`] may move.
const DETOUR_EDGE: f64 = 3.0;

/// The longest run of points [`mend_detours`] moves.
const MAX_RUN: usize = 8;

/// The most passes of [`mend_detours`].
const MAX_DETOUR_PASSES: usize = 50;

/// Mends the detours of a closed tour (Or-opt): a short run of points that the nearest-neighbour
/// tour left behind and fetched later, between two long edges, is moved (either way round) to the
/// edge near its ends where it lengthens the tour least, when that shortens the tour. A 2-opt
/// reversal cannot do this. Runs are at most [`MAX_RUN`] points between edges longer than
/// [`DETOUR_EDGE`] median spacings; the insertion edges are those at the points within two median
/// spacings of the run's ends (a uniform grid). Deterministic; the tour keeps its first point.
pub(crate) fn mend_detours(tour: Vec<Vec3>) -> Vec<Vec3> {
    let n = tour.len();
    let typical = median_spacing(&tour, true);
    if n < 2 * MAX_RUN || !(typical.is_finite() && typical > 0.0) {
        return tour;
    }
    let long = DETOUR_EDGE * typical;
    let key = |p: Vec3| {
        [
            (p.x() / typical).floor() as i64,
            (p.y() / typical).floor() as i64,
            (p.z() / typical).floor() as i64,
        ]
    };
    let mut grid: std::collections::HashMap<[i64; 3], Vec<usize>> = Default::default();
    for (i, &p) in tour.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i);
    }
    let near = |p: Vec3| {
        let k = key(p);
        let mut out = Vec::new();
        for dx in -2..=2 {
            for dy in -2..=2 {
                for dz in -2..=2 {
                    if let Some(v) = grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                        out.extend(v.iter().copied());
                    }
                }
            }
        }
        out.sort_unstable();
        out
    };
    let d = |a: usize, b: usize| tour[a].distance(tour[b]);
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    for _ in 0..MAX_DETOUR_PASSES {
        let mut moved = false;
        // the run starts: points after a long edge, in tour order from the first point
        let mut starts = Vec::new();
        let mut i = 0;
        for _ in 0..n {
            if d(prev[i], i) > long {
                starts.push(i);
            }
            i = next[i];
        }
        for a in starts {
            if d(prev[a], a) <= long {
                continue;
            }
            // the run a..=b, ended by a long edge
            let mut run = vec![a];
            let mut b = a;
            while run.len() <= MAX_RUN && d(b, next[b]) <= long {
                b = next[b];
                run.push(b);
            }
            if run.len() > MAX_RUN || next[b] == a || run.contains(&0) {
                continue;
            }
            let (pa, nb) = (prev[a], next[b]);
            let gain = d(pa, a) + d(b, nb) - d(pa, nb);
            let mut best: Option<(f64, usize, bool)> = None;
            let mut cands = near(tour[a]);
            cands.extend(near(tour[b]));
            cands.sort_unstable();
            cands.dedup();
            for q in cands {
                let nq = next[q];
                if run.contains(&q) || run.contains(&nq) || q == pa {
                    continue;
                }
                for rev in [false, true] {
                    let (first, last) = if rev { (b, a) } else { (a, b) };
                    let cost = d(q, first) + d(last, nq) - d(q, nq);
                    if best.is_none_or(|(c, _, _)| cost < c) {
                        best = Some((cost, q, rev));
                    }
                }
            }
            let Some((cost, q, rev)) = best else { continue };
            if gain - cost <= 1e-12 * gain {
                continue;
            }
            // unlink the run, then link it between q and next[q]
            next[pa] = nb;
            prev[nb] = pa;
            let nq = next[q];
            if rev {
                for &x in &run {
                    std::mem::swap(&mut next[x], &mut prev[x]);
                }
            }
            let (first, last) = if rev { (b, a) } else { (a, b) };
            next[q] = first;
            prev[first] = q;
            next[last] = nq;
            prev[nq] = last;
            moved = true;
        }
        if !moved {
            break;
        }
    }
    let mut out = Vec::with_capacity(n);
    let mut i = 0;
    for _ in 0..n {
        out.push(tour[i]);
        i = next[i];
    }
    out
}

/// A tour is opened at its largest gap only when that gap is more than this many times the tour's
/// second-longest edge ([`break_at_gaps`]).
pub(crate) const OPENING_RATIO: f64 = 3.0;

/// Splits a closed tour at gaps longer than `factor` times its typical spacing: the median spacing,
/// at least `min_spacing` (the scale below which the points were merged: a thinned slab's points
/// are a tolerance's sample of the curve, and a random cloud's holes shorter than a few tolerances
/// are no holes at that scale). Returns the open chain starting right after the largest gap (or the
/// tour unchanged, closed, when there is no gap) and the gaps.
///
/// The tour is opened only when its largest gap stands out: longer than [`OPENING_RATIO`] times
/// the second-longest edge. A real opening (a C-shaped section, a cut) is one such gap; the holes
/// of a randomly sampled cloud are many, of similar lengths (the largest of `N` random spacings
/// exceeds the next by about one mean spacing, against `ln N` mean spacings for either), and
/// opening the ring at the largest of them starts each section at a random place round it, which
/// twists the surface between sections. Such gaps are all bridged and the section stays closed.
pub(crate) fn break_at_gaps(
    tour: Vec<Vec3>,
    factor: f64,
    section: usize,
    min_spacing: f64,
) -> (Vec<Vec3>, bool, Vec<Gap>) {
    let n = tour.len();
    if n < 3 {
        return (tour, false, Vec::new());
    }
    let typical = median_spacing(&tour, true).max(min_spacing);
    let mut gaps = Vec::new();
    // the longest edge (its first occurrence) and the longest of the others
    let (mut largest, mut second) = ((usize::MAX, 0.0), 0.0f64);
    for i in 0..n {
        let (a, b) = (tour[i], tour[(i + 1) % n]);
        let l = a.distance(b);
        if l > factor * typical {
            gaps.push(Gap {
                section,
                from: a.0,
                to: b.0,
                length: l,
                typical_spacing: typical,
                handling: "bridged".into(),
            });
        }
        if l > largest.1 {
            second = second.max(largest.1);
            largest = (i, l);
        } else {
            second = second.max(l);
        }
    }
    // no gap, or none that stands out: closed
    if gaps.is_empty() || largest.1 <= OPENING_RATIO * second {
        return (tour, true, gaps);
    }
    // open the tour at the largest gap; the others stay bridged
    for g in gaps.iter_mut() {
        if g.length == largest.1 {
            g.handling = "open".into();
            break;
        }
    }
    let mut t = tour;
    t.rotate_left((largest.0 + 1) % n);
    (t, false, gaps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shuffled_circle_is_ordered_and_a_missing_arc_is_a_gap() {
        let n = 200;
        let mut pts: Vec<Vec3> = (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                Vec3::new(2.0 * t.cos(), 2.0 * t.sin(), 0.0)
            })
            .collect();
        // deterministic shuffle
        let mut s = 12345u64;
        for i in (1..n).rev() {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            pts.swap(i, (s >> 33) as usize % (i + 1));
        }
        let tour = order_points(&pts, Vec3::new(1.0, 0.0, 0.0));
        let h = 2.0 * 2.0 * (std::f64::consts::PI / n as f64).sin();
        let (chain, closed, gaps) = break_at_gaps(tour, 4.0, 0, 0.0);
        assert!(closed && gaps.is_empty());
        for w in chain.windows(2) {
            assert!((w[0].distance(w[1]) - h).abs() < 1e-12);
        }
        // remove an arc of 20 points: one gap of the right length, chain opened there
        let kept: Vec<Vec3> = pts
            .iter()
            .copied()
            .filter(|p| !(p.x() < 0.0 && p.y().abs() < 0.6))
            .collect();
        let removed = n - kept.len();
        let tour = order_points(&kept, Vec3::new(1.0, 0.0, 0.0));
        let (chain, closed, gaps) = break_at_gaps(tour, 4.0, 3, 0.0);
        assert!(!closed);
        assert_eq!(gaps.len(), 1);
        let want = 2.0 * 2.0 * (std::f64::consts::PI * (removed + 1) as f64 / n as f64).sin();
        assert!(
            (gaps[0].length - want).abs() < 1e-9,
            "{} vs {want}",
            gaps[0].length
        );
        assert_eq!(gaps[0].section, 3);
        assert!(chain[0].distance(chain[chain.len() - 1]) > 10.0 * h);
    }

    #[test]
    fn holes_of_similar_lengths_are_bridged_and_the_ring_stays_closed() {
        let n = 200;
        let at = |k: usize| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            Vec3::new(t.cos(), t.sin(), 0.0)
        };
        let ring_without = |missing: &dyn Fn(usize) -> bool| -> Vec<Vec3> {
            (0..n).filter(|&k| !missing(k)).map(at).collect()
        };
        // a ring of 200 points with three holes of 6, 7 and 8 missing points: three gaps, none
        // standing out (8 + 1 steps against 7 + 1), so all are bridged
        let ring = ring_without(&|k| {
            (20..26).contains(&k) || (90..97).contains(&k) || (150..158).contains(&k)
        });
        let (chain, closed, gaps) = break_at_gaps(ring.clone(), 4.0, 0, 0.0);
        assert!(closed);
        assert_eq!(chain, ring);
        assert_eq!(gaps.len(), 3);
        assert!(gaps.iter().all(|g| g.handling == "bridged"));
        // one hole alone of 9 steps against 1-step edges (over 3 times): a real opening
        let one = ring_without(&|k| (150..158).contains(&k));
        let (chain, closed, gaps) = break_at_gaps(one, 4.0, 0, 0.0);
        assert!(!closed && gaps.len() == 1 && gaps[0].handling == "open");
        // opened right after the gap: starts at point 158
        assert!(chain[0].distance(at(158)) < 1e-15);
    }
}
