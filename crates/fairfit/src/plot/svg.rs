//! A minimal SVG canvas and a 2D plot frame (data → pixel mapping, axes, ticks, labels).
//!
//! Hand-written SVG text: the plots need lines, circles, rectangles and text only, and the output must
//! be a self-contained string that embeds in HTML and renders with `resvg`.

use crate::errors::{Error, Result};
use crate::io::numbers::fixed;
use std::fmt::Write as _;

/// Explicit plot size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlotSize {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl PlotSize {
    /// A validated size (each side 100 to 10000 pixels).
    pub fn new(width: u32, height: u32) -> Result<Self> {
        let ok = |x: u32| (100..=10_000).contains(&x);
        if !(ok(width) && ok(height)) {
            return Err(Error::InvalidOption(format!(
                "plot size {width}x{height}: each side must be 100 to 10000 pixels"
            )));
        }
        Ok(PlotSize { width, height })
    }
}

impl Default for PlotSize {
    fn default() -> Self {
        PlotSize {
            width: 900,
            height: 600,
        }
    }
}

/// Escapes text for SVG/HTML content and attributes.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// SVG text being built.
pub struct Canvas {
    size: PlotSize,
    body: String,
}

impl Canvas {
    /// An empty canvas with a white background.
    pub fn new(size: PlotSize) -> Self {
        let mut c = Canvas {
            size,
            body: String::new(),
        };
        c.rect(
            0.0,
            0.0,
            size.width as f64,
            size.height as f64,
            "#ffffff",
            None,
        );
        c
    }
    /// A polyline through pixel points (non-finite points break the line).
    pub fn polyline(&mut self, pts: &[(f64, f64)], stroke: &str, width: f64) {
        for run in pts.split(|p| !(p.0.is_finite() && p.1.is_finite())) {
            if run.len() < 2 {
                continue;
            }
            let mut d = String::new();
            for (x, y) in run {
                let _ = write!(d, "{},{} ", px(*x), px(*y));
            }
            let _ = writeln!(
                self.body,
                r#"<polyline points="{}" fill="none" stroke="{stroke}" stroke-width="{width}"/>"#,
                d.trim_end()
            );
        }
    }
    /// A line segment, optionally dashed.
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), stroke: &str, width: f64, dashed: bool) {
        let dash = if dashed {
            r#" stroke-dasharray="4 3""#
        } else {
            ""
        };
        let _ = writeln!(
            self.body,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{stroke}" stroke-width="{width}"{dash}/>"#,
            px(a.0),
            px(a.1),
            px(b.0),
            px(b.1)
        );
    }
    /// A filled circle.
    pub fn circle(&mut self, c: (f64, f64), r: f64, fill: &str) {
        let _ = writeln!(
            self.body,
            r#"<circle cx="{}" cy="{}" r="{r}" fill="{fill}"/>"#,
            px(c.0),
            px(c.1)
        );
    }
    /// A rectangle, filled and optionally outlined.
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, stroke: Option<&str>) {
        let stroke = stroke
            .map(|s| format!(r#" stroke="{s}" stroke-width="1""#))
            .unwrap_or_default();
        let _ = writeln!(
            self.body,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{fill}"{stroke}/>"#,
            px(x),
            px(y),
            px(w),
            px(h)
        );
    }
    /// Text; `anchor` is `start`, `middle` or `end`; `rotate` turns it by -90 degrees.
    pub fn text(&mut self, p: (f64, f64), s: &str, size: f64, anchor: &str, rotate: bool) {
        let rot = if rotate {
            format!(r#" transform="rotate(-90 {} {})""#, px(p.0), px(p.1))
        } else {
            String::new()
        };
        let _ = writeln!(
            self.body,
            r#"<text x="{}" y="{}" font-family="DejaVu Sans, Arial, sans-serif" font-size="{size}" text-anchor="{anchor}"{rot}>{}</text>"#,
            px(p.0),
            px(p.1),
            escape(s)
        );
    }
    /// Reserves room for `bytes` more of SVG text, fallibly: a plot of very many samples fails with
    /// one line ([`Error::out_of_memory`] for `what`) instead of aborting while it is drawn.
    pub fn reserve(&mut self, bytes: usize, what: &str) -> Result<()> {
        self.body
            .try_reserve(bytes)
            .map_err(|_| Error::out_of_memory(what, bytes as u64))
    }
    /// The finished SVG document (the text reserved fallibly, see [`Canvas::reserve`]).
    pub fn finish(self) -> Result<String> {
        let (w, h) = (self.size.width, self.size.height);
        let head = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n"
        );
        let tail = "</svg>\n";
        let mut out = String::new();
        let n = head.len() + self.body.len() + tail.len();
        out.try_reserve_exact(n)
            .map_err(|_| Error::out_of_memory("the SVG plot", n as u64))?;
        out.push_str(&head);
        out.push_str(&self.body);
        out.push_str(tail);
        Ok(out)
    }
}

/// A pixel coordinate with 2 decimals (a value rounding to zero is `0.00`, never `-0.00`).
fn px(x: f64) -> String {
    fixed(x, 2)
}

/// "Nice" tick values covering `[lo, hi]` (steps of 1, 2 or 5 times a power of ten).
pub fn ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, f64) {
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    let raw = span / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    ((first..=last).map(|k| k as f64 * step).collect(), step)
}

fn tick_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    if v.abs() >= 1e5 || (v != 0.0 && v.abs() < 1e-4) {
        format!("{v:.2e}")
    } else {
        fixed(v, decimals)
    }
}

/// A plot area mapping data coordinates to pixels, with axes drawn on a [`Canvas`].
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Pixel rectangle: left, top, right, bottom.
    pub px: (f64, f64, f64, f64),
    /// Data ranges: x min, x max, y min, y max.
    pub data: (f64, f64, f64, f64),
}

impl Frame {
    /// A frame for the data bounds inside `size` (margins for labels); `equal` keeps one scale for both
    /// axes (geometry views).
    pub fn new(size: PlotSize, bounds: (f64, f64, f64, f64), equal: bool) -> Self {
        let px = (
            80.0,
            40.0,
            size.width as f64 - 30.0,
            size.height as f64 - 55.0,
        );
        let (mut x0, mut x1, mut y0, mut y1) = bounds;
        let pad = |a: f64, b: f64| {
            let d = (b - a).abs();
            let d = if d > 0.0 { d } else { a.abs().max(1.0) };
            (a - 0.04 * d, b + 0.04 * d)
        };
        (x0, x1) = pad(x0, x1);
        (y0, y1) = pad(y0, y1);
        if equal {
            let (pw, ph) = (px.2 - px.0, px.3 - px.1);
            let scale = ((x1 - x0) / pw).max((y1 - y0) / ph);
            let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
            (x0, x1) = (cx - 0.5 * scale * pw, cx + 0.5 * scale * pw);
            (y0, y1) = (cy - 0.5 * scale * ph, cy + 0.5 * scale * ph);
        }
        Frame {
            px,
            data: (x0, x1, y0, y1),
        }
    }
    /// Pixel position of a data point.
    pub fn map(&self, x: f64, y: f64) -> (f64, f64) {
        let (l, t, r, b) = self.px;
        let (x0, x1, y0, y1) = self.data;
        (
            l + (x - x0) / (x1 - x0) * (r - l),
            b - (y - y0) / (y1 - y0) * (b - t),
        )
    }
    /// Pixels per data unit along x.
    pub fn x_scale(&self) -> f64 {
        (self.px.2 - self.px.0) / (self.data.1 - self.data.0)
    }
    /// Draws the box, ticks, tick labels, axis labels and the title.
    pub fn axes(&self, c: &mut Canvas, title: &str, xlabel: &str, ylabel: &str) {
        let (l, t, r, b) = self.px;
        c.rect(l, t, r - l, b - t, "none", Some("#444444"));
        let (xt, xs) = ticks(self.data.0, self.data.1, 8);
        for v in xt {
            let (x, _) = self.map(v, self.data.2);
            c.line((x, b), (x, b + 5.0), "#444444", 1.0, false);
            c.line((x, t), (x, b), "#e6e6e6", 0.6, false);
            c.text((x, b + 18.0), &tick_label(v, xs), 11.0, "middle", false);
        }
        let (yt, ys) = ticks(self.data.2, self.data.3, 6);
        for v in yt {
            let (_, y) = self.map(self.data.0, v);
            c.line((l - 5.0, y), (l, y), "#444444", 1.0, false);
            c.line((l, y), (r, y), "#e6e6e6", 0.6, false);
            c.text((l - 8.0, y + 4.0), &tick_label(v, ys), 11.0, "end", false);
        }
        c.text((0.5 * (l + r), b + 42.0), xlabel, 13.0, "middle", false);
        c.text((18.0, 0.5 * (t + b)), ylabel, 13.0, "middle", true);
        c.text((0.5 * (l + r), 24.0), title, 15.0, "middle", false);
    }
}

/// Most data markers drawn in one plot; larger sets are thinned evenly (statistics use every point).
pub const MAX_MARKERS: usize = 20_000;

/// The stride that keeps `n` markers at or below [`MAX_MARKERS`].
pub(crate) fn marker_stride(n: usize) -> usize {
    n.div_ceil(MAX_MARKERS).max(1)
}

/// Bounds `(xmin, xmax, ymin, ymax)` of finite points; `None` when there are none.
pub fn bounds(pts: impl IntoIterator<Item = (f64, f64)>) -> Option<(f64, f64, f64, f64)> {
    let mut b: Option<(f64, f64, f64, f64)> = None;
    for (x, y) in pts {
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        b = Some(match b {
            None => (x, x, y, y),
            Some((a, bx, c, d)) => (a.min(x), bx.max(x), c.min(y), d.max(y)),
        });
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice_and_cover_the_range() {
        let (t, s) = ticks(0.0, 1.0, 5);
        assert_eq!(s, 0.2);
        assert_eq!(t.len(), 6);
        let (t, s) = ticks(-37.0, 112.0, 8);
        assert_eq!(s, 20.0);
        assert_eq!((t[0], *t.last().unwrap()), (-20.0, 100.0));
    }

    #[test]
    fn frame_maps_corners_and_keeps_equal_scale() {
        let size = PlotSize::new(500, 300).unwrap();
        let f = Frame::new(size, (0.0, 10.0, 0.0, 1.0), true);
        let (a, b) = (f.map(0.0, 0.0), f.map(1.0, 1.0));
        assert!(((b.0 - a.0) - (a.1 - b.1)).abs() < 1e-9, "equal scale");
        let g = Frame::new(size, (0.0, 10.0, 0.0, 1.0), false);
        let (l, _, r, _) = g.px;
        assert!(g.map(0.0, 0.5).0 > l && g.map(10.0, 0.5).0 < r);
        assert!(PlotSize::new(20, 300).is_err());
    }

    #[test]
    fn marker_stride_caps_the_count() {
        assert_eq!(marker_stride(0), 1);
        assert_eq!(marker_stride(MAX_MARKERS), 1);
        assert_eq!(marker_stride(MAX_MARKERS + 1), 2);
        let n: usize = 1_000_003;
        assert!(n.div_ceil(marker_stride(n)) <= MAX_MARKERS);
    }
}
