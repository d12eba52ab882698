//! Reading ordered point files: CSV, TSV or whitespace-separated text with 2 or 3 columns, an optional
//! header line and `#` comments, and Selig or Lednicer airfoil `.dat` files (a name line first; Lednicer
//! files have a line of point counts and the two surfaces from leading to trailing edge, joined here as
//! the upper surface reversed followed by the lower surface).
//!
//! Non-finite values are rejected with the file and line; consecutive duplicate points are dropped and
//! counted in [`PointSet::dropped_duplicates`] (the library never prints: the caller decides whether to
//! warn).

use super::limits::{self, ReadLimits};
use super::lines::Lines;
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
    let source = path.display().to_string();
    let mut lines = Lines::open(path)?;
    if lines.starts_like_json()? {
        return parse_points(&super::lines::json_text(path)?, &source);
    }
    let mut parser = PointParser::new(&source);
    while let Some((line_no, line)) = lines.next_line()? {
        parser.line(line_no, line)?;
    }
    parser.finish()
}

/// `text` without a leading UTF-8 byte-order mark (spreadsheet exports write one; unstripped, it would
/// make the first number unreadable).
pub(crate) fn without_bom(text: &str) -> &str {
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
    let mut parser = PointParser::new(source);
    for (i, raw) in text.lines().enumerate() {
        parser.line(i + 1, raw)?;
    }
    parser.finish()
}

/// One numeric line: its number, how many numbers it holds (saturating at 255) and the first three.
#[derive(Clone, Copy)]
struct Row {
    line_no: usize,
    len: usize,
    vals: [f64; 3],
}

/// The first column-count error of one reading of the file: every row a point (`Plain`), or the
/// first row a Lednicer counts line (`Lednicer`).
#[derive(Default)]
struct Columns {
    reference: Option<usize>,
    error: Option<(usize, String)>,
}

impl Columns {
    fn check(&mut self, row: &Row) {
        if self.error.is_some() {
            return;
        }
        if row.len != 2 && row.len != 3 {
            self.error = Some((
                row.line_no,
                format!("expected 2 or 3 numbers, found {}", row.len),
            ));
            return;
        }
        let columns = *self.reference.get_or_insert(row.len);
        if row.len != columns {
            self.error = Some((
                row.line_no,
                format!(
                    "expected {columns} numbers like the first point line, found {}",
                    row.len
                ),
            ));
        }
    }
}

/// The streaming state of [`read_points`] and [`parse_points`]: one line at a time, no allocation
/// per line. Whether the first numeric row is a Lednicer counts line is known only at the end, so the
/// column checks of both readings run side by side and the right one is reported.
struct PointParser<'a> {
    source: &'a str,
    name: Option<String>,
    first: Option<Row>,
    /// Points of the rows after the first.
    rest: Vec<Vec3>,
    plain: Columns,
    lednicer: Columns,
    max_points: usize,
}

impl<'a> PointParser<'a> {
    fn new(source: &'a str) -> Self {
        PointParser {
            source,
            name: None,
            first: None,
            rest: Vec::new(),
            plain: Columns::default(),
            lednicer: Columns::default(),
            max_points: ReadLimits::current().max_points,
        }
    }

    fn line(&mut self, line_no: usize, raw: &str) -> Result<()> {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            return Ok(());
        }
        let mut row = Row {
            line_no,
            len: 0,
            vals: [0.0; 3],
        };
        let fields = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|s| !s.is_empty());
        for field in fields {
            let Ok(v) = field.parse::<f64>() else {
                return self.text_line(line_no, line);
            };
            if !v.is_finite() {
                return Err(bad(
                    self.source,
                    line_no,
                    &format!("value '{field}' is not a finite number"),
                ));
            }
            if row.len < 3 {
                row.vals[row.len] = v;
            }
            row.len = (row.len + 1).min(255);
        }
        self.row(row)
    }

    /// A line that is not all numbers: the name line before the first number, an error after it.
    fn text_line(&mut self, line_no: usize, line: &str) -> Result<()> {
        if self.first.is_none() && self.name.is_none() {
            self.name = Some(line.to_string());
            return Ok(());
        }
        let shown: String = line.chars().take(40).collect();
        Err(bad(
            self.source,
            line_no,
            &format!("expected 2 or 3 numbers, found '{shown}'"),
        ))
    }

    fn row(&mut self, row: Row) -> Result<()> {
        self.plain.check(&row);
        if self.first.is_none() {
            self.first = Some(row);
            return Ok(());
        }
        self.lednicer.check(&row);
        if self.rest.len() >= self.max_points {
            return Err(limits::too_many_points(
                self.source,
                None,
                "points",
                self.max_points,
            ));
        }
        if self.rest.len() == self.rest.capacity() {
            self.rest
                .try_reserve(self.rest.len().max(1024))
                .map_err(|_| limits::out_of_memory(self.source, 48 * self.rest.len() as u64))?;
        }
        self.rest
            .push(Vec3::new(row.vals[0], row.vals[1], row.vals[2]));
        Ok(())
    }

    fn finish(self) -> Result<PointSet> {
        let Some(first) = self.first else {
            return Err(bad(self.source, 0, "no points found (empty file?)"));
        };
        let lednicer = is_lednicer_counts(&first, self.rest.len());
        let checks = if lednicer { self.lednicer } else { self.plain };
        if let Some((line_no, msg)) = checks.error {
            return Err(bad(self.source, line_no, &msg));
        }
        let columns = if lednicer {
            checks.reference.unwrap_or(0)
        } else {
            first.len
        };
        let mut raw_pts = self.rest;
        if lednicer {
            let n_upper = (first.vals[0] as usize).min(raw_pts.len());
            raw_pts[..n_upper].reverse();
        } else {
            raw_pts.insert(0, Vec3::new(first.vals[0], first.vals[1], first.vals[2]));
        }
        let (points, dropped) = drop_consecutive_duplicates(&raw_pts);
        if points.len() < MIN_POINTS {
            return Err(bad(
                self.source,
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
            name: self.name,
            lednicer,
        })
    }
}

/// A Lednicer counts line: two integral values > 1 whose sum is the number of remaining rows.
fn is_lednicer_counts(first: &Row, remaining: usize) -> bool {
    if first.len != 2 || first.vals[..2].iter().any(|v| *v < 2.0 || v.fract() != 0.0) {
        return false;
    }
    (first.vals[0] + first.vals[1]) as usize == remaining
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
