//! Reading ordered point files: CSV, TSV or whitespace-separated text with 2 or 3 columns, an optional
//! header line and `#` comments, and Selig or Lednicer airfoil `.dat` files (a name line first; Lednicer
//! files have a line of point counts and the two surfaces from leading to trailing edge, joined here as
//! the upper surface reversed followed by the lower surface).
//!
//! Non-finite values are rejected with the file and line; consecutive duplicate points are dropped and
//! counted in [`PointSet::dropped_duplicates`] (the library never prints: the caller decides whether to
//! warn).

use crate::errors::{Error, Result};
use crate::fit::points::drop_consecutive_duplicates;
use crate::nurbs::Vec3;
use std::path::Path;

/// Points read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct PointSet {
    /// The points in file order (z = 0 for 2-column files), consecutive duplicates removed.
    pub points: Vec<Vec3>,
    /// How many consecutive duplicate points were dropped.
    pub dropped_duplicates: usize,
    /// Number of columns in the file (2 or 3).
    pub columns: usize,
    /// The header or name line, if the file had one.
    pub name: Option<String>,
    /// True when the file was recognised as a Lednicer airfoil file (surfaces joined).
    pub lednicer: bool,
}

/// Fewest distinct points a file must hold.
pub const MIN_POINTS: usize = 2;

/// Reads a point file (see the module documentation for the accepted formats).
///
/// ```
/// let dir = std::env::temp_dir().join("fairfit_points_doc");
/// std::fs::create_dir_all(&dir).unwrap();
/// let f = dir.join("p.csv");
/// std::fs::write(&f, "x,y\n0,0\n1,0\n1,0\n2,1\n").unwrap();
/// let ps = fairfit::io::points::read_points(&f).unwrap();
/// assert_eq!(ps.points.len(), 3);
/// assert_eq!(ps.dropped_duplicates, 1);
/// ```
pub fn read_points(path: impl AsRef<Path>) -> Result<PointSet> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, &e))?;
    let text = String::from_utf8(bytes).map_err(|_| Error::Io {
        path: path.display().to_string(),
        message: "not a text file (invalid UTF-8)".into(),
    })?;
    parse_points(&text, &path.display().to_string())
}

/// `text` without a leading UTF-8 byte-order mark (spreadsheet exports write one; unstripped, it would
/// make the first number unreadable).
pub fn without_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// Parses point text; `source` names the origin in error messages.
pub fn parse_points(text: &str, source: &str) -> Result<PointSet> {
    let text = without_bom(text);
    if text.contains('\0') {
        return Err(bad(source, 0, "not a text file (contains NUL bytes)"));
    }
    if let Some(kind) = super::json::json_kind_of(text) {
        return Err(super::json::not_points_error(source, kind));
    }
    // (line number, numbers) for every numeric line; blank lines kept as section separators
    let mut rows: Vec<(usize, Vec<f64>)> = Vec::new();
    let mut name: Option<String> = None;
    let mut seen_numbers = false;
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        let parsed: std::result::Result<Vec<f64>, _> =
            fields.iter().map(|f| f.parse::<f64>()).collect();
        match parsed {
            Ok(vals) => {
                if let Some(j) = vals.iter().position(|v| !v.is_finite()) {
                    return Err(bad(
                        source,
                        line_no,
                        &format!("value '{}' is not a finite number", fields[j]),
                    ));
                }
                seen_numbers = true;
                rows.push((line_no, vals));
            }
            Err(_) => {
                if !seen_numbers && name.is_none() {
                    name = Some(line.to_string());
                } else {
                    let shown: String = line.chars().take(40).collect();
                    return Err(bad(
                        source,
                        line_no,
                        &format!("expected 2 or 3 numbers, found '{shown}'"),
                    ));
                }
            }
        }
    }
    if rows.is_empty() {
        return Err(bad(source, 0, "no points found (empty file?)"));
    }
    let lednicer = is_lednicer_counts(&rows);
    let data: &[(usize, Vec<f64>)] = if lednicer { &rows[1..] } else { &rows };
    let columns = data.first().map(|r| r.1.len()).unwrap_or(0);
    let mut raw_pts = Vec::with_capacity(data.len());
    for (line_no, vals) in data {
        if vals.len() != 2 && vals.len() != 3 {
            return Err(bad(
                source,
                *line_no,
                &format!("expected 2 or 3 numbers, found {}", vals.len()),
            ));
        }
        if vals.len() != columns {
            return Err(bad(
                source,
                *line_no,
                &format!(
                    "expected {columns} numbers like the first point line, found {}",
                    vals.len()
                ),
            ));
        }
        raw_pts.push(Vec3::new(
            vals[0],
            vals[1],
            vals.get(2).copied().unwrap_or(0.0),
        ));
    }
    if lednicer {
        let n_upper = rows[0].1[0] as usize;
        let (upper, lower) = raw_pts.split_at(n_upper.min(raw_pts.len()));
        let mut joined: Vec<Vec3> = upper.iter().rev().copied().collect();
        joined.extend_from_slice(lower);
        raw_pts = joined;
    }
    let (points, dropped) = drop_consecutive_duplicates(&raw_pts);
    if points.len() < MIN_POINTS {
        return Err(bad(
            source,
            0,
            &format!(
                "at least {MIN_POINTS} distinct points are needed, found {}",
                points.len()
            ),
        ));
    }
    Ok(PointSet {
        points,
        dropped_duplicates: dropped,
        columns,
        name,
        lednicer,
    })
}

/// A Lednicer counts line: two integral values > 1 whose sum is the number of remaining rows.
fn is_lednicer_counts(rows: &[(usize, Vec<f64>)]) -> bool {
    let Some((_, first)) = rows.first() else {
        return false;
    };
    if first.len() != 2 || first.iter().any(|v| *v < 2.0 || v.fract() != 0.0) {
        return false;
    }
    (first[0] + first[1]) as usize == rows.len() - 1
}

fn bad(source: &str, line: usize, msg: &str) -> Error {
    if line == 0 {
        Error::InvalidData(format!("{source}: {msg}"))
    } else {
        Error::InvalidData(format!("{source}:{line}: {msg}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_with_header_comments_and_3_columns() {
        let ps = parse_points("# c\nx,y,z\n0,0,1\n1,2,3 # tail\n\n4,5,6\n", "t").unwrap();
        assert_eq!(ps.columns, 3);
        assert_eq!(ps.points[1], Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(ps.name.as_deref(), Some("x,y,z"));
    }

    #[test]
    fn a_byte_order_mark_keeps_the_first_point() {
        // spreadsheet exports start with U+FEFF; it once made the first point a silent "name" line
        let ps = parse_points("\u{feff}0,0\n1,0.8\n2,0.1\n", "t").unwrap();
        assert_eq!(ps.points.len(), 3);
        assert_eq!(ps.points[0], Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(ps.name, None);
        let ps = parse_points("\u{feff}x,y\n0,0\n1,1\n", "t").unwrap();
        assert_eq!(ps.name.as_deref(), Some("x,y"));
        assert_eq!(ps.points.len(), 2);
    }

    #[test]
    fn tsv_and_whitespace() {
        let ps = parse_points("0\t0\n1\t1\n2   4\n", "t").unwrap();
        assert_eq!(ps.points.len(), 3);
        assert_eq!(ps.points[2], Vec3::new(2.0, 4.0, 0.0));
    }

    #[test]
    fn selig_dat() {
        let ps = parse_points(
            "NACA 0012\n1.0 0.0\n0.5 0.06\n0.0 0.0\n0.5 -0.06\n1.0 0.0\n",
            "t",
        )
        .unwrap();
        assert_eq!(ps.name.as_deref(), Some("NACA 0012"));
        assert_eq!(ps.points.len(), 5);
        assert!(!ps.lednicer);
    }

    #[test]
    fn lednicer_dat_joins_surfaces() {
        let text = "NACA X\n3. 3.\n\n0 0\n0.5 0.1\n1 0\n\n0 0\n0.5 -0.1\n1 0\n";
        let ps = parse_points(text, "t").unwrap();
        assert!(ps.lednicer);
        // upper reversed (1,0),(0.5,0.1),(0,0) then lower without the duplicate LE
        assert_eq!(ps.points.len(), 5);
        assert_eq!(ps.points[0], Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(ps.points[2], Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(ps.points[3], Vec3::new(0.5, -0.1, 0.0));
        assert_eq!(ps.dropped_duplicates, 1);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_points("x,y\n0,0\n1,nan\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("f.csv:3"), "{e}");
        let e = parse_points("0,0\n1,1\nabc,2\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("f.csv:3"), "{e}");
        let e = parse_points("0,0\n1,1,1\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("f.csv:2"), "{e}");
        let e = parse_points("", "f.csv").unwrap_err();
        assert!(e.to_string().contains("no points"), "{e}");
        let e = parse_points("1,1\n1,1\n1,1\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("distinct"), "{e}");
        let e = parse_points("0 0 0 0\n", "f.csv").unwrap_err();
        assert!(e.to_string().contains("2 or 3"), "{e}");
    }

    #[test]
    fn reads_the_example_airfoil() {
        let p = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/data/fx77w343.csv"
        );
        let ps = read_points(p).unwrap();
        assert!(ps.points.len() > 50);
        assert_eq!(ps.points[0], Vec3::new(0.99893, 0.02139, 0.0));
    }
}
