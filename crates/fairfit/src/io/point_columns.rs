//! Point files with named columns: a header line naming `x`, `y`, optionally `z`, and a weight
//! (`w` or `weight`) and/or an interpolation flag (`i` or `interpolate`, 0 or 1) per point, in any
//! order, separated like the plain point files (commas, semicolons, whitespace); `#` comments.
//!
//! [`read_point_columns`] answers `None` for every file without such a header (no weight or flag
//! column), which the plain reader ([`super::points`]) reads as before. Consecutive duplicate points
//! are dropped as the plain reader drops them (the first of a run keeps its weight, the flag is
//! kept when any of the run has it), so indices are those of the points as fitted.

use super::limits::{self, ReadLimits};
use super::lines::Lines;
use crate::errors::{Error, Result};
use crate::fit::points::bounding_box_extent;
use crate::nurbs::Vec3;
use std::path::Path;

/// Points read from a file with named columns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColumnPoints {
    /// The points, consecutive duplicates dropped.
    pub points: Vec<Vec3>,
    /// How many consecutive duplicates were dropped.
    pub dropped_duplicates: usize,
    /// The weight column, one per point (`None`: the file has none).
    pub weights: Option<Vec<f64>>,
    /// The indices of the points flagged 1 in the interpolation column.
    pub interpolate: Vec<usize>,
    /// Whether the file has a `z` column.
    pub has_z: bool,
}

/// Where each named column is.
#[derive(Clone, Copy, Debug, Default)]
struct Header {
    x: usize,
    y: usize,
    z: Option<usize>,
    w: Option<usize>,
    i: Option<usize>,
    n: usize,
}

fn fields(line: &str) -> impl Iterator<Item = &str> {
    line.split(|c: char| c == ',' || c == ';' || c.is_whitespace())
        .filter(|s| !s.is_empty())
}

/// The header of a line naming x, y and a weight or flag column; `None` for any other line.
fn header(line: &str) -> Option<Header> {
    let (mut x, mut y, mut h) = (None, None, Header::default());
    for (k, name) in fields(line).enumerate() {
        let slot = match name.to_ascii_lowercase().as_str() {
            "x" => &mut x,
            "y" => &mut y,
            "z" => &mut h.z,
            "w" | "weight" => &mut h.w,
            "i" | "interpolate" => &mut h.i,
            _ => return None,
        };
        if slot.replace(k).is_some() {
            return None;
        }
        h.n = k + 1;
    }
    (h.w.is_some() || h.i.is_some()).then_some(Header { x: x?, y: y?, ..h })
}

/// Reads `path` when its first line that is neither blank nor a comment names a weight or flag
/// column (module docs); `Ok(None)` otherwise. Errors name the file and line.
pub fn read_point_columns(path: impl AsRef<Path>) -> Result<Option<ColumnPoints>> {
    let path = path.as_ref();
    let source = path.display().to_string();
    let bad = |line: usize, msg: String| Error::InvalidData(format!("{source}:{line}: {msg}"));
    let mut lines = Lines::open(path)?;
    let max_points = ReadLimits::current().max_points;
    let mut head: Option<Header> = None;
    let mut raw: Vec<(Vec3, f64, bool)> = Vec::new();
    while let Some((line_no, text)) = lines.next_line()? {
        let line = text.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let Some(h) = head else {
            match header(line) {
                Some(h) => {
                    head = Some(h);
                    continue;
                }
                None => return Ok(None),
            }
        };
        let vals: Vec<f64> = fields(line)
            .map(|f| f.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad(line_no, format!("expected {} numbers", h.n)))?;
        if vals.len() != h.n {
            return Err(bad(
                line_no,
                format!(
                    "expected {} numbers like the header, found {}",
                    h.n,
                    vals.len()
                ),
            ));
        }
        let coord = [Some(h.x), Some(h.y), h.z].map(|c| c.map_or(0.0, |c| vals[c]));
        if coord.iter().any(|v| !v.is_finite()) {
            return Err(bad(line_no, "a coordinate is not a finite number".into()));
        }
        let w = h.w.map_or(1.0, |c| vals[c]);
        if !(w.is_finite() && w >= 0.0) {
            return Err(bad(
                line_no,
                format!("weight {w} is not a finite number >= 0"),
            ));
        }
        let flag = match h.i.map(|c| vals[c]) {
            None => false,
            Some(0.0) => false,
            Some(1.0) => true,
            Some(f) => {
                return Err(bad(
                    line_no,
                    format!("the interpolation flag must be 0 or 1, found {f}"),
                ))
            }
        };
        if raw.len() >= max_points {
            return Err(limits::too_many_points(&source, None, "points", max_points));
        }
        raw.push((Vec3(coord), w, flag));
    }
    let Some(h) = head else {
        return Ok(None);
    };
    Ok(Some(dedup(&raw, h)))
}

/// The points of `raw` with consecutive duplicates dropped as [`crate::fit::points`] drops them.
fn dedup(raw: &[(Vec3, f64, bool)], h: Header) -> ColumnPoints {
    let pts: Vec<Vec3> = raw.iter().map(|r| r.0).collect();
    let eps = 1e-12 * bounding_box_extent(&pts).max(f64::MIN_POSITIVE);
    let mut out = ColumnPoints {
        has_z: h.z.is_some(),
        ..Default::default()
    };
    let mut weights = Vec::new();
    for &(p, w, flag) in raw {
        match out.points.last() {
            Some(&l) if (p - l).max_abs() <= eps => {
                out.dropped_duplicates += 1;
                let last = out.points.len() - 1;
                if flag && out.interpolate.last() != Some(&last) {
                    out.interpolate.push(last);
                }
            }
            _ => {
                if flag {
                    out.interpolate.push(out.points.len());
                }
                out.points.push(p);
                weights.push(w);
            }
        }
    }
    out.weights = h.w.map(|_| weights);
    out
}
