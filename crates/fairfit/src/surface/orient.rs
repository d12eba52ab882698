//! Consistent orientation and aligned seams of section polylines before they are made compatible, so a
//! skinned surface does not twist: every section runs the same way round (sign of its Newell normal
//! along the stacking direction; an open section whose chord is at least a quarter of its extent runs
//! along the first such section's chord instead) and every closed section starts where the others do (the point farthest
//! from its centroid in a common reference direction, unless its own start already lies within 45° of it).

use crate::fit::closure::closure_at_tolerance;
use crate::nurbs::Vec3;

/// An ordered section: points in order, and whether the chain closes on itself.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// Ordered points; a closed section repeats its first point at the end.
    pub points: Vec<Vec3>,
    /// True when the chain is a loop.
    pub closed: bool,
}

impl Section {
    /// A section from ordered points; it counts as closed when the last point repeats the first (within
    /// 1e-9 of the section's extent). Pass `closed = true` to close an open loop explicitly.
    pub fn from_points(points: Vec<Vec3>) -> Self {
        let ext = extent(&points);
        let closed = points.len() > 3
            && points[0].distance(points[points.len() - 1]) <= 1e-9 * ext.max(f64::MIN_POSITIVE);
        Section { points, closed }
    }

    /// A closed section from a loop of points (the first point is appended at the end if needed).
    pub fn closed_loop(mut points: Vec<Vec3>) -> Self {
        let ext = extent(&points);
        if let (Some(&f), Some(&l)) = (points.first(), points.last()) {
            if points.len() > 1 && f.distance(l) > 1e-9 * ext {
                points.push(f);
            }
        }
        Section {
            points,
            closed: true,
        }
    }

    /// Closes an open section whose ends meet at the tolerance's scale, as `fairfit curve` closes
    /// open-looking data ([`crate::fit::closure`]): the gap from its last point to its first is at
    /// most `tol` and a few of its own spacings, and the section continues smoothly through it
    /// (turning by at most `angle_deg`). The first point is then repeated at the end and the gap's
    /// length returned; otherwise (closed already, or open at this scale) nothing changes and
    /// `None` is returned.
    ///
    /// ```
    /// use fairfit::nurbs::Vec3;
    /// use fairfit::surface::Section;
    /// // a ring of 200 points whose last point is one step before its first
    /// let ring: Vec<Vec3> = (0..200)
    ///     .map(|i| {
    ///         let t = std::f64::consts::TAU * i as f64 / 200.0;
    ///         Vec3::new(t.cos(), t.sin(), 0.0)
    ///     })
    ///     .collect();
    /// let mut s = Section::from_points(ring);
    /// assert!(!s.closed);
    /// let gap = s.close_at_tolerance(0.05, 30.0).unwrap();
    /// assert!(s.closed && s.points.len() == 201 && (gap - 0.0314).abs() < 1e-4);
    /// ```
    pub fn close_at_tolerance(&mut self, tol: f64, angle_deg: f64) -> Option<f64> {
        if self.closed {
            return None;
        }
        let gap = closure_at_tolerance(&self.points, tol, angle_deg).gap()?;
        let first = self.points[0];
        self.points.push(first);
        self.closed = true;
        Some(gap)
    }

    /// Centroid of the points (the repeated end point of a closed section counted once).
    pub fn centroid(&self) -> Vec3 {
        let pts = self.distinct();
        let n = pts.len().max(1) as f64;
        pts.iter().fold(Vec3::ZERO, |s, &p| s + p) / n
    }

    /// Newell normal of the polygon (closed by its chord when open); length = twice the area.
    pub fn newell_normal(&self) -> Vec3 {
        let pts = self.distinct();
        let mut n = Vec3::ZERO;
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            n += Vec3::new(
                (a.y() - b.y()) * (a.z() + b.z()),
                (a.z() - b.z()) * (a.x() + b.x()),
                (a.x() - b.x()) * (a.y() + b.y()),
            );
        }
        n
    }

    /// End minus start of an open section whose chord is at least a quarter of its extent.
    fn long_chord(&self) -> Option<Vec3> {
        let (&a, &b) = (self.points.first()?, self.points.last()?);
        (!self.closed && (b - a).norm() >= 0.25 * extent(&self.points)).then_some(b - a)
    }

    fn distinct(&self) -> &[Vec3] {
        if self.closed && self.points.len() > 1 {
            &self.points[..self.points.len() - 1]
        } else {
            &self.points
        }
    }

    fn reverse(&mut self) {
        self.points.reverse();
    }

    /// Rotates a closed section so that distinct point `start` comes first.
    fn rotate_to(&mut self, start: usize) {
        if !self.closed || start == 0 {
            return;
        }
        let mut pts: Vec<Vec3> = self.distinct().to_vec();
        pts.rotate_left(start);
        pts.push(pts[0]);
        self.points = pts;
    }
}

/// Largest bounding-box extent of a point set.
pub fn extent(points: &[Vec3]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max)
}

/// Makes the orientation of all sections agree with the first one and aligns the seams of the closed
/// sections. Returns, per section, whether it was reversed and by how many points its start moved.
pub fn align_sections(sections: &mut [Section]) -> Vec<(bool, usize)> {
    let k = sections.len();
    let mut changes = vec![(false, 0usize); k];
    if k == 0 {
        return changes;
    }
    let axis = if k > 1 {
        sections[k - 1].centroid() - sections[0].centroid()
    } else {
        sections[0].newell_normal()
    };
    let sign0 = sections[0].newell_normal().dot(axis).signum();
    // open sections with a clear chord follow the first such one's chord: the area normal of a flat
    // open section flips with a small wiggle across its chord (CAD iso-curves of a wavy surface)
    let ref_chord = sections.iter().find_map(Section::long_chord);
    for (s, ch) in sections.iter_mut().zip(changes.iter_mut()) {
        if let (Some(c), Some(r)) = (s.long_chord(), ref_chord) {
            if c.dot(r) < 0.0 {
                s.reverse();
                ch.0 = true;
            }
            continue;
        }
        let sg = s.newell_normal().dot(axis).signum();
        if sg != 0.0 && sign0 != 0.0 && sg != sign0 {
            s.reverse();
            ch.0 = true;
        }
    }
    // reference seam direction: from the first open section if any (its seam is fixed), else section 0
    let refsec = sections.iter().position(|s| !s.closed).unwrap_or(0);
    let rs = &sections[refsec];
    let seam = rs.points[0] + (rs.points[rs.points.len() - 1] - rs.points[0]) * 0.5;
    let mut dir = seam - rs.centroid();
    let dn = dir.norm();
    if dn.is_nan() || dn <= 0.0 {
        return changes;
    }
    dir = dir / dn;
    for (s, ch) in sections.iter_mut().zip(changes.iter_mut()) {
        if !s.closed || s.points.len() < 4 {
            continue;
        }
        let c = s.centroid();
        let start = s.points[0] - c;
        let sn = start.norm();
        if sn > 0.0 && start.dot(dir) / sn >= std::f64::consts::FRAC_1_SQRT_2 {
            continue;
        }
        let best = s
            .distinct()
            .iter()
            .enumerate()
            .map(|(i, &p)| (i, (p - c).dot(dir)))
            .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a })
            .0;
        s.rotate_to(best);
        ch.1 = best;
    }
    changes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(z: f64, start: f64, ccw: bool, n: usize) -> Vec<Vec3> {
        (0..=n)
            .map(|k| {
                let t = start
                    + if ccw { 1.0 } else { -1.0 } * std::f64::consts::TAU * k as f64 / n as f64;
                Vec3::new(t.cos(), t.sin(), z)
            })
            .collect()
    }

    #[test]
    fn reversed_and_rotated_loops_are_aligned() {
        let mut s = vec![
            Section::from_points(circle(0.0, 0.0, true, 40)),
            Section::from_points(circle(1.0, 7.0 * std::f64::consts::TAU / 40.0, false, 40)),
            Section::from_points(circle(2.0, 23.0 * std::f64::consts::TAU / 40.0, true, 40)),
        ];
        assert!(s.iter().all(|s| s.closed));
        let ch = align_sections(&mut s);
        assert!(!ch[0].0 && ch[1].0 && !ch[2].0, "{ch:?}");
        for sec in &s {
            // starts at angle 0 (x = 1, y = 0) and runs counter-clockwise
            assert!((sec.points[0] - Vec3::new(1.0, 0.0, sec.points[0].z())).norm() < 1e-9);
            assert!(sec.points[1].y() > 0.0);
            assert!(sec.newell_normal().z() > 0.0);
        }
    }

    #[test]
    fn flat_open_sections_follow_their_chords() {
        // open sections in the planes y = k, bulging by a_k sin(pi x) in z: the area normal (along y)
        // flips with the sign of a_k, the chord does not; the third runs backwards
        let open = |y: f64, a: f64, backwards: bool| {
            let mut p: Vec<Vec3> = (0..=30)
                .map(|i| {
                    let x = i as f64 / 30.0;
                    Vec3::new(x, y, a * (std::f64::consts::PI * x).sin())
                })
                .collect();
            if backwards {
                p.reverse();
            }
            Section::from_points(p)
        };
        let mut s = vec![
            open(0.0, 0.1, false),
            open(1.0, -0.1, false),
            open(2.0, 0.05, true),
            open(3.0, -0.02, false),
        ];
        assert!(s[0].newell_normal().y() * s[1].newell_normal().y() < 0.0);
        let ch = align_sections(&mut s);
        let reversed: Vec<bool> = ch.iter().map(|c| c.0).collect();
        assert_eq!(reversed, vec![false, false, true, false]);
        assert!(s.iter().all(|sec| sec.points[0].x() == 0.0));
    }
}
