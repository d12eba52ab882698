//! Composite curves of CAD files (STEP `COMPOSITE_CURVE`, IGES entity 102): their segments, each a
//! B-spline oriented along the composite, as one chain of points for re-fitting ([`crate::fit::sampling::sample_chain`]) and,
//! when consecutive segments meet, as one B-spline ([`join_segments`]).
//!
//! Joining: every segment is clamped (knot insertion at its domain ends, exact) and raised to the
//! highest degree among them (exact); rational segments make the joined curve rational, each segment's
//! weights scaled (the same curve) so that the weights agree where the segments meet. Each segment keeps
//! the length of its own parameter range, shifted to start where the previous one ends; the joints are
//! knots of multiplicity `p`, so the joined curve is C0 there, exactly as the composite (its corners
//! stay corners). Segments must meet within [`JOIN_TOLERANCE`] of the composite's size; the start of
//! a segment is then replaced by the end of the previous one.

use crate::errors::{Error, Result};
use crate::fit::sampling::{extent, JOIN_TOLERANCE};
#[cfg(test)]
use crate::fit::sampling::{sample_chain, sample_curve_chord, MAX_CHORD};
use crate::nurbs::{NurbsCurve, Vec3};

/// A composite curve read from a CAD file: its segments in order, each oriented along the composite,
/// in the file's unit.
#[derive(Clone, Debug)]
pub struct CadComposite {
    /// Where it is in the file and how many segments it has (`#40 (composite of 3 segments)`).
    pub source: String,
    /// The segments in order.
    pub segments: Vec<NurbsCurve>,
    /// How many of the file's single B-spline curves come before it in file order.
    pub after: usize,
}

fn ends(c: &NurbsCurve) -> (Vec3, Vec3) {
    let (a, b) = c.domain();
    (c.point(a), c.point(b))
}

/// Turns segments round that run against the chain: a segment whose end, rather than its start, is
/// nearest the previous segment's end is reversed (and the first one, when its start is nearer the
/// second segment than its end is). IGES 102 gives no sense per member; writers mostly agree with the
/// standard (each member starts where the previous ends), and this mends those that do not.
pub fn orient_segments(segments: &mut [NurbsCurve]) {
    if segments.len() < 2 {
        return;
    }
    let (s0, e0) = ends(&segments[0]);
    let (s1, e1) = ends(&segments[1]);
    let near = |p: Vec3| (p - s1).norm().min((p - e1).norm());
    if near(s0) < near(e0) {
        segments[0] = segments[0].reversed();
    }
    for k in 1..segments.len() {
        let prev_end = ends(&segments[k - 1]).1;
        let (s, e) = ends(&segments[k]);
        if (e - prev_end).norm() < (s - prev_end).norm() {
            segments[k] = segments[k].reversed();
        }
    }
}

/// The gaps wider than [`JOIN_TOLERANCE`] of the composite's size: `(k, distance)` from the end of
/// segment `k` to the start of segment `k + 1` (0-based).
pub fn open_gaps(segments: &[NurbsCurve]) -> Vec<(usize, f64)> {
    let tol = JOIN_TOLERANCE * extent(segments);
    segments
        .windows(2)
        .enumerate()
        .map(|(k, w)| (k, (ends(&w[1]).0 - ends(&w[0]).1).norm()))
        .filter(|&(_, g)| g > tol || g.is_nan())
        .collect()
}

/// `c` with knots of multiplicity `p + 1` at both ends of its domain (the same curve).
pub fn clamped(c: &NurbsCurve) -> Result<NurbsCurve> {
    let p = c.degree();
    let k = c.knots();
    let n = k.len();
    let start = k[..=p].iter().all(|&x| x == k[0]);
    let end = k[n - p - 1..].iter().all(|&x| x == k[n - 1]);
    if start && end {
        return Ok(c.clone());
    }
    let (a, b) = c.domain();
    super::cad_read::cut(c.clone(), a, b, !start, !end)
}

/// The segments of a composite as one B-spline (see the module documentation). Errors for no
/// segments and for segments that do not meet within [`JOIN_TOLERANCE`].
pub fn join_segments(segments: &[NurbsCurve]) -> Result<NurbsCurve> {
    let Some(first) = segments.first() else {
        return Err(Error::Cad("a composite curve without segments".into()));
    };
    if segments.len() == 1 {
        return Ok(first.clone());
    }
    let ext = extent(segments);
    if let Some(&(k, g)) = open_gaps(segments).first() {
        return Err(Error::Cad(format!(
            "segments {} and {} are {g:.3e} apart (more than {JOIN_TOLERANCE:e} of the composite's size \
             {ext:.3e}): it is no single curve",
            k + 1,
            k + 2
        )));
    }
    let p = segments.iter().map(NurbsCurve::degree).max().unwrap_or(1);
    let rational = segments.iter().any(NurbsCurve::is_rational);
    let (mut knots, mut pts, mut weights) = (Vec::new(), Vec::new(), Vec::<f64>::new());
    let mut offset = first.domain().0;
    for (i, seg) in segments.iter().enumerate() {
        let mut c = clamped(seg)?;
        if c.degree() < p {
            c = c.elevate_degree(p - c.degree())?;
        }
        let (a, b) = c.domain();
        let shift = offset - a;
        let k = c.knots();
        let cw = c.weights();
        let cp = c.control_points();
        if i == 0 {
            // all but the last knot: the joint keeps multiplicity p
            knots.extend(k[..k.len() - 1].iter().map(|x| x + shift));
            pts.extend_from_slice(cp);
            weights.extend_from_slice(cw);
        } else {
            let scale = weights.last().copied().unwrap_or(1.0) / cw[0];
            let last = segments.len() - 1;
            let take = if i == last { k.len() } else { k.len() - 1 };
            knots.extend(k[p + 1..take].iter().map(|x| x + shift));
            pts.extend_from_slice(&cp[1..]);
            weights.extend(cw[1..].iter().map(|w| w * scale));
        }
        offset += b - a;
    }
    NurbsCurve::new(p, knots, pts, rational.then_some(weights))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quarter(centre: Vec3, r: f64, from: f64) -> NurbsCurve {
        // a rational quadratic quarter circle starting at angle `from`
        let (c, s) = (from.cos(), from.sin());
        let a = centre + Vec3::new(r * c, r * s, 0.0);
        let m = centre + Vec3::new(r * (c - s), r * (s + c), 0.0);
        let b = centre + Vec3::new(-r * s, r * c, 0.0);
        let w = std::f64::consts::FRAC_1_SQRT_2;
        NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![a, m, b],
            Some(vec![1.0, w, 1.0]),
        )
        .unwrap()
    }

    fn cubic() -> NurbsCurve {
        let pts = vec![
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(-1.0, 3.0, 1.0),
            Vec3::new(-2.0, 2.5, 0.0),
            Vec3::new(-3.0, 4.0, 0.5),
            Vec3::new(-4.0, 3.0, 0.0),
        ];
        NurbsCurve::bspline(3, vec![0.0, 0.0, 0.0, 0.0, 1.5, 3.0, 3.0, 3.0, 3.0], pts).unwrap()
    }

    #[test]
    fn a_rational_arc_and_a_cubic_join_exactly() {
        // quarter circle of radius 2 from (2, 0) to (0, 2), then a cubic on [0, 3] from (0, 2)
        let segs = vec![quarter(Vec3::ZERO, 2.0, 0.0), cubic()];
        let j = join_segments(&segs).unwrap();
        assert_eq!(j.degree(), 3);
        assert!(j.is_rational());
        assert_eq!(j.domain(), (0.0, 4.0));
        for i in 0..=40 {
            let u = i as f64 / 40.0;
            assert!((j.point(u).norm() - 2.0).abs() < 1e-14, "{u}");
            let v = 3.0 * i as f64 / 40.0;
            assert!((j.point(1.0 + v) - segs[1].point(v)).norm() < 1e-14, "{v}");
        }
        // the joint is C0: a knot of multiplicity 3 at 1
        assert_eq!(j.knots().iter().filter(|&&k| k == 1.0).count(), 3);
    }

    #[test]
    fn reversed_members_are_turned_and_gaps_refused() {
        let mut segs = vec![quarter(Vec3::ZERO, 2.0, 0.0).reversed(), cubic().reversed()];
        orient_segments(&mut segs);
        assert!((ends(&segs[0]).0 - Vec3::new(2.0, 0.0, 0.0)).norm() < 1e-15);
        assert!((ends(&segs[1]).1 - Vec3::new(-4.0, 3.0, 0.0)).norm() < 1e-15);
        let pts = sample_chain(&segs);
        let cap = MAX_CHORD * extent(&segs);
        let n0 = sample_curve_chord(&segs[0], cap).len();
        assert_eq!(pts.len(), n0 + sample_curve_chord(&segs[1], cap).len() - 1);
        let apart = vec![quarter(Vec3::new(0.0, -0.01, 0.0), 2.0, 0.0), cubic()];
        let e = join_segments(&apart).unwrap_err().to_string();
        assert!(e.contains("segments 1 and 2 are 1.000e-2 apart"), "{e}");
        assert_eq!(sample_chain(&apart).len(), pts.len() + 1);
    }

    #[test]
    fn odd_segments_join_or_fail_without_panic() {
        let line = |a: Vec3, b: Vec3| NurbsCurve::bspline(1, vec![0.0, 0.0, 1.0, 1.0], vec![a, b]);
        let (a, b, c) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        );
        // two lines: a degree-1 polyline with a C0 knot at 1
        let j = join_segments(&[line(a, b).unwrap(), line(b, c).unwrap()]).unwrap();
        assert_eq!(j.knots(), &[0.0, 0.0, 1.0, 2.0, 2.0]);
        assert!((j.point(1.5) - Vec3::new(1.0, 0.5, 0.0)).norm() < 1e-15);
        // a degree-0 piece (if the curve type admits one) must not panic
        if let Ok(step) = NurbsCurve::bspline(0, vec![0.0, 1.0], vec![b]) {
            let _ = join_segments(&[line(a, b).unwrap(), step.clone()]);
            let _ = clamped(&step);
            let _ = sample_chain(&[step]);
        }
        // a point-like segment between two lines
        let dot = line(b, b).unwrap();
        let j = join_segments(&[line(a, b).unwrap(), dot, line(b, c).unwrap()]).unwrap();
        assert!((j.point(j.domain().1) - c).norm() < 1e-15);
    }

    #[test]
    fn unclamped_segments_are_clamped_first() {
        let pts: Vec<Vec3> = (0..5)
            .map(|i| Vec3::new(i as f64, (i * i) as f64 * 0.1, 0.0))
            .collect();
        let uniform = NurbsCurve::bspline(2, (0..8).map(|i| i as f64).collect(), pts).unwrap();
        let c = clamped(&uniform).unwrap();
        assert_eq!(c.domain(), uniform.domain());
        assert_eq!(&c.knots()[..3], &[2.0, 2.0, 2.0]);
        for i in 0..=30 {
            let u = 2.0 + 3.0 * i as f64 / 30.0;
            assert!((c.point(u) - uniform.point(u)).norm() < 1e-13);
        }
    }
}
