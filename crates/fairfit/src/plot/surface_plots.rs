//! Surface plots: a deviation colour map of the data points over the parameter domain (each point at
//! its closest-point parameters, coloured by distance, with a colour bar), and iso-curve curvature plots
//! (curvature against arc length of several exact iso-parametric curves).

use super::curve_plots::curvature_samples;
use super::surface_projection::project_points;
use super::svg::{bounds, marker_stride, Canvas, Frame, PlotSize};
use crate::errors::{Error, Result};
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsSurface, Vec3};

/// Which parameter is held fixed along an iso-curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IsoDirection {
    /// `u` fixed: the curves run along v.
    FixedU,
    /// `v` fixed: the curves run along u.
    FixedV,
}

const VIRIDIS: [(f64, f64, f64); 5] = [
    (68.0, 1.0, 84.0),
    (59.0, 82.0, 139.0),
    (33.0, 145.0, 140.0),
    (94.0, 201.0, 98.0),
    (253.0, 231.0, 37.0),
];

/// A viridis-like colour for `t` in `[0, 1]` as `#rrggbb`.
pub fn colour(t: f64) -> String {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(a.0, b.0),
        mix(a.1, b.1),
        mix(a.2, b.2)
    )
}

/// Deviation of the data points from the surface, drawn over the parameter domain.
pub fn deviation_map_svg(s: &NurbsSurface, points: &[Vec3], size: PlotSize) -> Result<String> {
    if points.is_empty() {
        return Err(Error::InvalidData(
            "a deviation map needs data points".into(),
        ));
    }
    let feet = project_points(s, points);
    let max = feet.iter().fold(0.0_f64, |m, f| m.max(f.distance));
    // relative to the largest distance, so the squares stay in range near 1e±300
    let unit = if max > 0.0 && max.is_finite() {
        max
    } else {
        1.0
    };
    let rms = unit
        * (feet
            .iter()
            .map(|f| (f.distance / unit).powi(2))
            .sum::<f64>()
            / feet.len() as f64)
            .sqrt();
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let bar = PlotSize {
        width: size.width.saturating_sub(90).max(100),
        height: size.height,
    };
    let frame = Frame::new(bar, (u0, u1, v0, v1), false);
    let mut cv = Canvas::new(size);
    frame.axes(
        &mut cv,
        &format!("Deviation map over (u, v) (max {max:.3e}, RMS {rms:.3e})"),
        "u",
        "v",
    );
    for u in distinct_breakpoints(s.knots_u(), s.degree_u()) {
        let (x, _) = frame.map(u, v0);
        cv.line((x, frame.px.1), (x, frame.px.3), "#bbbbbb", 0.6, true);
    }
    for v in distinct_breakpoints(s.knots_v(), s.degree_v()) {
        let (_, y) = frame.map(u0, v);
        cv.line((frame.px.0, y), (frame.px.2, y), "#bbbbbb", 0.6, true);
    }
    let top = if max > 0.0 { max } else { 1.0 };
    let radius = (600.0 / (feet.len() as f64).sqrt()).clamp(1.5, 6.0);
    for f in feet.iter().step_by(marker_stride(feet.len())) {
        cv.circle(frame.map(f.u, f.v), radius, &colour(f.distance / top));
    }
    // colour bar
    let (x, t, b) = (size.width as f64 - 80.0, frame.px.1, frame.px.3);
    let steps = 50;
    for k in 0..steps {
        let y = b - (b - t) * (k + 1) as f64 / steps as f64;
        let h = (b - t) / steps as f64 + 0.5;
        cv.rect(
            x,
            y,
            18.0,
            h,
            &colour((k as f64 + 0.5) / steps as f64),
            None,
        );
    }
    cv.rect(x, t, 18.0, b - t, "none", Some("#444444"));
    cv.text(
        (x + 22.0, t + 10.0),
        &format!("{top:.2e}"),
        10.0,
        "start",
        false,
    );
    cv.text((x + 22.0, b), "0", 10.0, "start", false);
    cv.finish()
}

/// Curvature against arc length of `count` iso-curves with `dir` fixed at evenly spaced values.
pub fn iso_curvature_svg(
    s: &NurbsSurface,
    dir: IsoDirection,
    count: usize,
    size: PlotSize,
) -> Result<String> {
    let (lo, hi) = match dir {
        IsoDirection::FixedU => s.domain_u(),
        IsoDirection::FixedV => s.domain_v(),
    };
    let count = count.max(1);
    let mut series = Vec::with_capacity(count);
    for k in 0..count {
        let t = (lo + (hi - lo) * k as f64 / (count - 1).max(1) as f64).min(hi);
        let c = match dir {
            IsoDirection::FixedU => s.iso_curve_u(t)?,
            IsoDirection::FixedV => s.iso_curve_v(t)?,
        };
        let (samples, _) = curvature_samples(&c)?;
        let pts: Vec<(f64, f64)> = samples.iter().map(|x| (x.s, x.kappa_vec.norm())).collect();
        series.push((t, pts));
    }
    let b = bounds(series.iter().flat_map(|(_, p)| p.iter().copied()))
        .ok_or_else(|| Error::InvalidData("no finite curvature samples".into()))?;
    let frame = Frame::new(size, (b.0.min(0.0), b.1, 0.0, b.3.max(0.0)), false);
    let mut cv = Canvas::new(size);
    let (fixed, along) = match dir {
        IsoDirection::FixedU => ("u", "v"),
        IsoDirection::FixedV => ("v", "u"),
    };
    frame.axes(
        &mut cv,
        &format!("Curvature of iso-curves along {along} ({fixed} fixed)"),
        "arc length s",
        "curvature κ",
    );
    for (k, (t, pts)) in series.iter().enumerate() {
        let col = colour(k as f64 / (count - 1).max(1) as f64 * 0.9);
        let px: Vec<(f64, f64)> = pts.iter().map(|&(x, y)| frame.map(x, y)).collect();
        cv.polyline(&px, &col, 1.5);
        let ly = frame.px.1 + 16.0 + 14.0 * k as f64;
        cv.line(
            (frame.px.2 - 120.0, ly - 4.0),
            (frame.px.2 - 100.0, ly - 4.0),
            &col,
            2.0,
            false,
        );
        cv.text(
            (frame.px.2 - 95.0, ly),
            &format!("{fixed} = {}", crate::io::numbers::fixed(*t, 3)),
            11.0,
            "start",
            false,
        );
    }
    cv.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_ends_and_middle() {
        assert_eq!(colour(0.0), "#440154");
        assert_eq!(colour(1.0), "#fde725");
        assert_eq!(colour(0.5), "#21918c");
        assert_eq!(colour(f64::NAN), "#440154");
    }
}
