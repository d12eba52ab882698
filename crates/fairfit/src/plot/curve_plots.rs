//! Curve plots: the curve with its data points, knots and curvature comb; curvature against arc length
//! with the knots marked; the deviation of every data point from the curve.
//!
//! Curvature is sampled at nodes strictly inside each knot span (never at a knot), from first and
//! second derivatives. A non-planar curve is drawn in the coordinate plane where it is widest.

use super::svg::{bounds, marker_stride, Canvas, Frame, PlotSize};
use crate::diffgeo::{is_xy_planar, CurveProjector};
use crate::errors::{try_vec, Error, Result};
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsCurve, Vec3};
use rayon::prelude::*;

/// Samples per knot span for curvature plots.
const PER_SPAN: usize = 32;
/// SVG text reserved per sample of a polyline (`"123.45,678.90 "`, with room to spare).
const POLYLINE_BYTES_PER_POINT: usize = 16;
/// SVG text reserved per sample of the comb plot: its tooth (a `<line .../>`, ~90 bytes) and its
/// points on two polylines.
const COMB_BYTES_PER_SAMPLE: usize = 128;

/// One curvature sample.
#[derive(Clone, Copy, Debug)]
pub struct CurvatureSample {
    /// Parameter (strictly inside a span).
    pub u: f64,
    /// Arc length from the curve start.
    pub s: f64,
    /// Point on the curve.
    pub point: Vec3,
    /// Curvature vector `κ N` (zero where the speed vanishes).
    pub kappa_vec: Vec3,
    /// Curvature, signed for curves in an xy plane.
    pub kappa: f64,
}

/// Curvature samples (nodes strictly inside every span) and the arc length at each breakpoint.
///
/// Far outside unit size (near 1e±300, where `|C'|⁴` over- or underflows) the samples come from an
/// exactly rescaled copy (see [`crate::nurbs::scale`]) and are scaled back. The sample buffer grows
/// with the span count and is reserved fallibly: an error, not an abort, when memory runs out.
pub fn curvature_samples(c: &NurbsCurve) -> Result<(Vec<CurvatureSample>, Vec<f64>)> {
    let f = crate::nurbs::scale::normalising_factor(c.control_points());
    if let Some(t) = (f != 1.0)
        .then(|| crate::nurbs::scale::scaled_curve(c, f).ok())
        .flatten()
    {
        let (mut samples, mut knot_s) = curvature_samples_as_is(&t)?;
        let g = 1.0 / f;
        for x in &mut samples {
            x.s *= g;
            x.point = x.point * g;
            x.kappa_vec = x.kappa_vec * f;
            x.kappa *= f;
        }
        knot_s.iter_mut().for_each(|s| *s *= g);
        return Ok((samples, knot_s));
    }
    curvature_samples_as_is(c)
}

fn curvature_samples_as_is(c: &NurbsCurve) -> Result<(Vec<CurvatureSample>, Vec<f64>)> {
    let planar = is_xy_planar(c);
    let bp = distinct_breakpoints(c.knots(), c.degree());
    let mut d = [Vec3::ZERO; 3];
    let mut out = try_vec(
        bp.len().saturating_mul(PER_SPAN),
        "the curvature plot's samples",
    )?;
    let mut knot_s = try_vec(bp.len(), "the curvature plot's knots")?;
    knot_s.push(0.0);
    let (mut s, mut prev) = (0.0, c.point(bp[0]));
    for w in bp.windows(2) {
        for k in 0..=PER_SPAN {
            let u = if k < PER_SPAN {
                w[0] + (w[1] - w[0]) * (k as f64 + 0.5) / PER_SPAN as f64
            } else {
                w[1]
            };
            c.derivatives_into(u, 2, &mut d);
            s += (d[0] - prev).norm();
            prev = d[0];
            if k == PER_SPAN {
                knot_s.push(s);
                continue;
            }
            let (r, a) = (d[1], d[2]);
            let v2 = r.norm_squared();
            let guard = v2 <= f64::MIN_POSITIVE.sqrt();
            let kappa_vec = if guard {
                Vec3::ZERO
            } else {
                r.cross(a).cross(r) / (v2 * v2)
            };
            let kappa = if guard {
                0.0
            } else if planar {
                (r.x() * a.y() - r.y() * a.x()) / (v2 * v2.sqrt())
            } else {
                kappa_vec.norm()
            };
            out.push(CurvatureSample {
                u,
                s,
                point: d[0],
                kappa_vec,
                kappa,
            });
        }
    }
    Ok((out, knot_s))
}

/// The two coordinate axes in which the curve (and points) are widest, xy for planar curves.
fn view_axes(pts: &[Vec3]) -> (usize, usize) {
    let ext = |k: usize| {
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                (l.min(p.0[k]), h.max(p.0[k]))
            });
        hi - lo
    };
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| ext(b).total_cmp(&ext(a)));
    let (a, b) = (axes[0].min(axes[1]), axes[0].max(axes[1]));
    if ext(2) <= 1e-12 * (ext(0) + ext(1)) {
        (0, 1)
    } else {
        (a, b)
    }
}

const AXIS: [&str; 3] = ["x", "y", "z"];

/// The curve, its data points, knot points and curvature comb (teeth point away from the centre of
/// curvature; the longest tooth is 15% of the view).
pub fn curve_comb_svg(c: &NurbsCurve, points: Option<&[Vec3]>, size: PlotSize) -> Result<String> {
    let (samples, _) = curvature_samples(c)?;
    // per sample: a comb tooth (~90 bytes) and a point of two polylines (~30 bytes)
    let mut cv = Canvas::new(size);
    cv.reserve(
        samples.len().saturating_mul(COMB_BYTES_PER_SAMPLE),
        "the curvature comb plot",
    )?;
    let dense: Vec<Vec3> = samples.iter().map(|s| s.point).collect();
    let mut all = dense.clone();
    all.extend(points.unwrap_or(&[]));
    let (ax, ay) = view_axes(&all);
    let proj = |p: Vec3| (p.0[ax], p.0[ay]);
    let b = bounds(all.iter().map(|&p| proj(p)))
        .ok_or_else(|| Error::InvalidData("nothing finite to plot".into()))?;
    let diag = ((b.1 - b.0).powi(2) + (b.3 - b.2).powi(2)).sqrt();
    let kmax = samples
        .iter()
        .fold(0.0_f64, |m, s| m.max(s.kappa_vec.norm()));
    let scale = if kmax > 0.0 { 0.15 * diag / kmax } else { 0.0 };
    let tips: Vec<Vec3> = samples
        .iter()
        .map(|s| s.point - s.kappa_vec * scale)
        .collect();
    let bb = bounds(all.iter().chain(&tips).map(|&p| proj(p))).unwrap_or(b);
    let frame = Frame::new(size, bb, true);
    frame.axes(
        &mut cv,
        "Curve, data points and curvature comb",
        AXIS[ax],
        AXIS[ay],
    );
    let px = |p: Vec3| {
        let (x, y) = proj(p);
        frame.map(x, y)
    };
    for (s, &t) in samples.iter().zip(&tips) {
        cv.line(px(s.point), px(t), "#f4a582", 0.8, false);
    }
    let tip_px: Vec<(f64, f64)> = tips.iter().map(|&t| px(t)).collect();
    cv.polyline(&tip_px, "#d6604d", 1.0);
    let curve_px: Vec<(f64, f64)> = dense.iter().map(|&p| px(p)).collect();
    cv.polyline(&curve_px, "#2166ac", 2.0);
    let data = points.unwrap_or(&[]);
    for &q in data.iter().step_by(marker_stride(data.len())) {
        cv.circle(px(q), 2.5, "#b2182b");
    }
    for u in distinct_breakpoints(c.knots(), c.degree()) {
        let (x, y) = px(c.point(u));
        cv.rect(x - 3.0, y - 3.0, 6.0, 6.0, "#000000", None);
    }
    let legend = format!(
        "blue: curve · red dots: {} data points · black squares: knots · comb: κ (max {:.4e})",
        points.map_or(0, |p| p.len()),
        kmax
    );
    cv.text(
        (frame.px.0 + 6.0, frame.px.1 + 16.0),
        &legend,
        11.0,
        "start",
        false,
    );
    cv.finish()
}

/// Curvature against arc length, knot positions as dashed vertical lines.
pub fn curvature_svg(c: &NurbsCurve, size: PlotSize) -> Result<String> {
    let (samples, knot_s) = curvature_samples(c)?;
    let pts: Vec<(f64, f64)> = samples.iter().map(|s| (s.s, s.kappa)).collect();
    let (x0, x1, mut y0, mut y1) =
        bounds(pts.iter().copied()).ok_or_else(|| Error::InvalidData("no samples".into()))?;
    y0 = y0.min(0.0);
    y1 = y1.max(0.0);
    let last = knot_s.last().copied().unwrap_or(x1);
    let frame = Frame::new(size, (x0.min(0.0), x1.max(last), y0, y1), false);
    let mut cv = Canvas::new(size);
    cv.reserve(
        pts.len().saturating_mul(POLYLINE_BYTES_PER_POINT),
        "the curvature plot",
    )?;
    let signed = if is_xy_planar(c) { "signed " } else { "" };
    frame.axes(
        &mut cv,
        "Curvature along the curve (dashed: knots)",
        "arc length s",
        &format!("{signed}curvature κ"),
    );
    for &s in &knot_s {
        let (x, _) = frame.map(s, 0.0);
        cv.line((x, frame.px.1), (x, frame.px.3), "#888888", 0.8, true);
    }
    let (l, r) = (frame.map(frame.data.0, 0.0), frame.map(frame.data.1, 0.0));
    cv.line(l, r, "#888888", 0.8, false);
    let px: Vec<(f64, f64)> = pts.iter().map(|&(s, k)| frame.map(s, k)).collect();
    cv.polyline(&px, "#2166ac", 1.6);
    cv.finish()
}

/// Distances of the data points to the curve (closest points), per point index, with RMS and max.
pub fn deviation_svg(c: &NurbsCurve, points: &[Vec3], size: PlotSize) -> Result<String> {
    if points.is_empty() {
        return Err(Error::InvalidData(
            "a deviation plot needs data points".into(),
        ));
    }
    let proj = CurveProjector::new(c, 16);
    // one projection per point, each independent: the same numbers on any thread count
    let dev: Vec<f64> = points
        .par_iter()
        .map(|&q| proj.project(q).distance)
        .collect();
    let max = dev.iter().fold(0.0_f64, |m, &d| m.max(d));
    let rms = (dev.iter().map(|d| d * d).sum::<f64>() / dev.len() as f64).sqrt();
    let top = if max > 0.0 { max } else { 1.0 };
    let frame = Frame::new(size, (0.0, (dev.len() - 1).max(1) as f64, 0.0, top), false);
    let mut cv = Canvas::new(size);
    frame.axes(
        &mut cv,
        &format!("Deviation of the data points (max {max:.3e}, RMS {rms:.3e})"),
        "point index",
        "distance to the curve",
    );
    // beyond the marker cap, each marker stands for a run of `stride` points and shows its largest
    // deviation (at that point's index): thinning never hides the worst point
    let stride = marker_stride(dev.len());
    for (start, run) in dev.chunks(stride).enumerate().map(|(k, r)| (k * stride, r)) {
        let (j, d) =
            run.iter().enumerate().fold(
                (0, f64::NEG_INFINITY),
                |m, (j, &d)| if d > m.1 { (j, d) } else { m },
            );
        let i = start + j;
        let (a, b) = (frame.map(i as f64, 0.0), frame.map(i as f64, d));
        cv.line(a, b, "#92c5de", 1.0, false);
        cv.circle(b, 2.0, "#2166ac");
    }
    cv.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_curvature_and_arc_length_are_exact_enough() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let r = 4.0;
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Vec3::new(r, 0.0, 0.0),
                Vec3::new(r, r, 0.0),
                Vec3::new(0.0, r, 0.0),
            ],
            Some(vec![1.0, h, 1.0]),
        )
        .unwrap();
        let (samples, knot_s) = curvature_samples(&c).unwrap();
        for s in &samples {
            assert!((s.kappa - 1.0 / r).abs() < 1e-12, "{}", s.kappa);
            // κN points to the centre (origin).
            assert!((s.point + s.kappa_vec * (r * r)).norm() < 1e-9);
        }
        let quarter = std::f64::consts::FRAC_PI_2 * r;
        assert!((knot_s[1] - quarter).abs() < 1e-3 * quarter);
        let svg = curve_comb_svg(&c, None, PlotSize::default()).unwrap();
        assert!(svg.matches("<line").count() >= samples.len());
    }
}
