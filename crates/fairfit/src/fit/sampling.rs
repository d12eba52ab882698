//! Dense samples of a curve, or of a chain of curves, for re-fitting it: points close enough along the
//! exact curve that a fit within the tolerance of the samples stays within it between them.
//!
//! A curve is sampled per knot span ([`samples_per_span`] points equally spaced in parameter), each
//! interval halved while its midpoint sags off the chord or its chord is longer than [`MAX_CHORD`] of
//! the curve's extent ([`sample_curve`]). A chain (the segments of a CAD composite curve, oriented
//! along it) is sampled segment by segment with the chord cap of the whole chain, a joint point taken
//! once when the segments meet within [`JOIN_TOLERANCE`] ([`sample_chain_params`]); every sample keeps
//! its segment and parameter, so that the exact curve can be evaluated between samples (see
//! [`super::cad_fit`]).

use crate::nurbs::{NurbsCurve, Vec3};

/// Largest gap between consecutive segments, relative to the extent of all control points, that
/// [`crate::io::cad_chain::join_segments`] closes (CAD files are written with 10 to 17 significant digits).
pub const JOIN_TOLERANCE: f64 = 1e-6;

/// Samples per non-empty knot span: `max(20, 4 (p + 1))`.
pub fn samples_per_span(degree: usize) -> usize {
    20.max(4 * (degree + 1))
}

/// Largest distance between consecutive samples, as a fraction of the extent (the largest side of the
/// control points' bounding box): `1/200`, five times the default relative tolerance. Measured on an
/// airfoil-like section whose 95 mm straight side meets its leading-edge arc with a 2.7-degree kink,
/// fitted to `1e-3` of the extent: the exact curve strays up to 1.059 of the tolerance from the fit
/// between samples without the cap, 1.005 with `1/50`, 0.9993 with `1/100`, 0.9981 with `1/200`.
pub const MAX_CHORD: f64 = 5e-3;

/// The largest side of the bounding box of `pts` (a CAD curve's control points: the scale of its
/// sampling, join and trim tolerances). Unlike [`crate::fit::points::bounding_box_extent`] a side that
/// overflows stays infinite.
pub(crate) fn control_extent(pts: &[Vec3]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in pts {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max)
}

/// Dense points on a curve for re-fitting it: [`samples_per_span`] points per non-empty knot span,
/// equally spaced in parameter, each interval halved (up to 6 times) while the curve's midpoint lies
/// farther than `1e-5` of the control polygon's extent from the chord, and further halved while the
/// chord is longer than [`MAX_CHORD`] of that extent (so that a long straight or flat stretch is
/// sampled as densely as the tolerance needs); consecutive points closer than `1e-12` of the extent
/// (a stationary parameterisation) are merged. Both ends are included, so a closed curve gives a
/// closed point set.
pub fn sample_curve(c: &NurbsCurve) -> Vec<Vec3> {
    let extent = control_extent(c.control_points());
    points_of(sample_within(c, extent, MAX_CHORD * extent))
}

/// [`sample_curve`] with the longest chord between consecutive samples given (a composite passes
/// [`MAX_CHORD`] of the extent of all its segments, so that a short segment is not oversampled).
pub fn sample_curve_chord(c: &NurbsCurve, max_chord: f64) -> Vec<Vec3> {
    points_of(sample_curve_params(c, max_chord))
}

fn points_of(samples: Vec<(f64, Vec3)>) -> Vec<Vec3> {
    samples.into_iter().map(|(_, p)| p).collect()
}

/// [`sample_curve_chord`] with the parameter of every sample: `(u, C(u))` in increasing `u`.
pub fn sample_curve_params(c: &NurbsCurve, max_chord: f64) -> Vec<(f64, Vec3)> {
    sample_within(c, control_extent(c.control_points()), max_chord)
}

/// [`sample_curve_params`] with the extent of `c`'s control points given.
fn sample_within(c: &NurbsCurve, extent: f64, max_chord: f64) -> Vec<(f64, Vec3)> {
    let (sag_tol, dup_tol) = (1e-5 * extent, 1e-12 * extent);
    let max_chord = if max_chord > 0.0 {
        max_chord
    } else {
        f64::INFINITY
    };
    let m = samples_per_span(c.degree());
    let k = c.knots();
    let (a, b) = c.domain();
    let mut params = Vec::new();
    for w in k.windows(2) {
        let (u0, u1) = (w[0].max(a), w[1].min(b));
        if u1 > u0 {
            params.extend((0..m).map(|j| u0 + (u1 - u0) * j as f64 / m as f64));
        }
    }
    params.push(b);
    let mut out = vec![(params[0], c.point(params[0]))];
    let limits = Limits {
        sag: sag_tol,
        chord: max_chord,
    };
    for w in params.windows(2) {
        refine(
            c,
            (w[0], w[1]),
            (out[out.len() - 1].1, c.point(w[1])),
            &limits,
            SAG_HALVINGS,
            &mut out,
        );
    }
    let mut merged: Vec<(f64, Vec3)> = Vec::with_capacity(out.len());
    for (u, p) in out {
        match merged.last() {
            Some((_, q)) if (p - *q).norm() <= dup_tol => {}
            _ => merged.push((u, p)),
        }
    }
    // keep the exact end point (a closed curve must end where it starts)
    if let Some(last) = merged.last_mut() {
        *last = (b, c.point(b));
    }
    merged
}

/// Halvings of an initial interval for the sag test.
const SAG_HALVINGS: i32 = 6;
/// Further halvings allowed for the chord test (a guard: a continuous curve's chords shrink).
const CHORD_HALVINGS: i32 = 40;

struct Limits {
    sag: f64,
    chord: f64,
}

/// Appends the points of `(u0, u1]`, halving while the midpoint is off the chord (while `depth > 0`)
/// or the chord is too long.
fn refine(
    c: &NurbsCurve,
    (u0, u1): (f64, f64),
    (p0, p1): (Vec3, Vec3),
    lim: &Limits,
    depth: i32,
    out: &mut Vec<(f64, Vec3)>,
) {
    let um = 0.5 * (u0 + u1);
    let pm = c.point(um);
    let sag = depth > 0 && (pm - (p0 + p1) * 0.5).norm() > lim.sag;
    let long = depth > -CHORD_HALVINGS && (p1 - p0).norm() > lim.chord;
    if sag || long {
        refine(c, (u0, um), (p0, pm), lim, depth - 1, out);
        refine(c, (um, u1), (pm, p1), lim, depth - 1, out);
    } else {
        out.push((u1, p1));
    }
}

/// The largest side of the bounding box of all segments' control points (the scale of the join
/// tolerance and of the sampling).
pub fn extent(segments: &[NurbsCurve]) -> f64 {
    let pts: Vec<Vec3> = segments
        .iter()
        .flat_map(|c| c.control_points().iter().copied())
        .collect();
    control_extent(&pts)
}

/// Dense points along the chain: every segment sampled as [`sample_curve`] samples a
/// curve, but with chords of at most [`MAX_CHORD`] of the chain's [`extent`]; a joint point taken once
/// when the segments meet within [`JOIN_TOLERANCE`] (else both ends are kept).
pub fn sample_chain(segments: &[NurbsCurve]) -> Vec<Vec3> {
    sample_chain_params(segments)
        .into_iter()
        .map(|s| s.point)
        .collect()
}

/// One point of a chain's samples: which segment, at which parameter of it, and the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainSample {
    /// The segment (0-based).
    pub segment: usize,
    /// The segment's parameter.
    pub u: f64,
    /// The point on the segment at `u`.
    pub point: Vec3,
}

/// [`sample_chain`] with every point's segment and parameter (in order along the chain).
pub fn sample_chain_params(segments: &[NurbsCurve]) -> Vec<ChainSample> {
    let ext = extent(segments);
    let tol = JOIN_TOLERANCE * ext;
    let mut out: Vec<ChainSample> = Vec::new();
    for (segment, c) in segments.iter().enumerate() {
        let pts = sample_curve_params(c, MAX_CHORD * ext);
        let skip = match (out.last(), pts.first()) {
            (Some(a), Some(b)) => usize::from((a.point - b.1).norm() <= tol),
            _ => 0,
        };
        out.extend(
            pts[skip..]
                .iter()
                .map(|&(u, point)| ChainSample { segment, u, point }),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_of_a_circle_lie_on_it_and_close() {
        // a rational quadratic circle of radius 2 (4 spans): every sample is at radius 2, the set is
        // closed, and no chord is farther from the arc than the sagitta tolerance 1e-5 * extent (4)
        let c = NurbsCurve::circle(Vec3::ZERO, 2.0).unwrap();
        let s = sample_curve(&c);
        let spans = c.knots().windows(2).filter(|w| w[1] > w[0]).count();
        assert!(s.len() > spans * samples_per_span(2), "{}", s.len());
        assert_eq!(s[0], *s.last().unwrap());
        let mut max_sagitta = 0.0f64;
        for w in s.windows(2) {
            assert!((w[0].norm() - 2.0).abs() < 1e-14);
            let theta = (w[0].dot(w[1]) / 4.0).clamp(-1.0, 1.0).acos();
            assert!(theta > 0.0 && theta < 0.1, "{theta}");
            max_sagitta = max_sagitta.max(2.0 * (1.0 - (0.5 * theta).cos()));
        }
        assert!(max_sagitta <= 4e-5, "{max_sagitta}");
        assert_eq!(samples_per_span(3), 20);
        assert_eq!(samples_per_span(5), 24);
    }
}
