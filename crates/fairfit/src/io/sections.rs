//! Reading section files: each file is one ordered curve, one point per line as 2 or 3 numbers separated
//! by commas, semicolons or white space (2 columns mean z = 0). Lines starting with `#` and one header
//! line of names before the data are skipped; a leading byte-order mark is ignored. Every point line
//! has as many numbers as the first (a file mixing 2 and 3 columns is refused). A folder means all its `.csv`, `.txt`, `.dat` and `.xyz`
//! files, sorted by name.

use super::limits::{self, ReadLimits};
use super::lines::Lines;
use crate::errors::{Error, Result};
use crate::nurbs::Vec3;
use std::path::{Path, PathBuf};

/// File extensions taken from a folder of sections.
pub const SECTION_EXTENSIONS: [&str; 4] = ["csv", "txt", "dat", "xyz"];

/// Parses the text of one section file; `name` is used in error messages.
pub fn parse_section_text(text: &str, name: &str) -> Result<Vec<Vec3>> {
    let text = super::points::without_bom(text);
    if let Some(kind) = super::json::json_kind_of(text) {
        return Err(super::json::not_points_error(name, kind));
    }
    let mut parser = SectionParser::new(name);
    for (ln, line) in text.lines().enumerate() {
        parser.line(ln + 1, line)?;
    }
    Ok(parser.pts)
}

/// Reads one section file (or an XYZ/CSV point cloud), streaming: one reused line buffer, nothing
/// allocated per line, at most [`ReadLimits::max_points`] points.
pub fn read_section_file(path: impl AsRef<Path>) -> Result<Vec<Vec3>> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let mut lines = Lines::open(path)?;
    if lines.starts_like_json()? {
        return parse_section_text(&super::lines::json_text(path)?, &name);
    }
    let mut parser = SectionParser::new(&name);
    while let Some((ln, line)) = lines.next_line()? {
        parser.line(ln, line)?;
    }
    Ok(parser.pts)
}

/// The state of a section read, one line at a time.
struct SectionParser<'a> {
    name: &'a str,
    pts: Vec<Vec3>,
    header_seen: bool,
    columns: Option<usize>,
    max_points: usize,
}

impl<'a> SectionParser<'a> {
    fn new(name: &'a str) -> Self {
        SectionParser {
            name,
            pts: Vec::new(),
            header_seen: false,
            columns: None,
            max_points: ReadLimits::current().max_points,
        }
    }

    fn line(&mut self, ln: usize, line: &str) -> Result<()> {
        let name = self.name;
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') || t.starts_with("//") {
            return Ok(());
        }
        let fields = t
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|s| !s.is_empty());
        // the first three numbers (None where a field is not a number), and how many fields
        let mut nums = [None; 3];
        let mut count = 0usize;
        let mut any_number = false;
        for f in fields {
            let v = f.parse::<f64>().ok();
            any_number |= v.is_some();
            if count < 3 {
                nums[count] = v;
            }
            count += 1;
        }
        if !any_number && self.pts.is_empty() && !self.header_seen {
            self.header_seen = true;
            return Ok(());
        }
        if count < 2 || nums[..count.min(3)].iter().any(|n| n.is_none()) {
            return Err(Error::InvalidData(format!(
                "{name}:{ln}: expected 2 or 3 numbers, got `{t}`"
            )));
        }
        let n = count.min(3);
        if *self.columns.get_or_insert(n) != n {
            return Err(Error::InvalidData(format!(
                "{name}:{ln}: expected {} numbers like the first point line, got `{t}`",
                self.columns.unwrap_or(n)
            )));
        }
        let z = if count >= 3 {
            nums[2].unwrap_or(0.0)
        } else {
            0.0
        };
        let p = Vec3::new(nums[0].unwrap_or(0.0), nums[1].unwrap_or(0.0), z);
        if !p.is_finite() {
            return Err(Error::InvalidData(format!(
                "{name}:{ln}: non-finite coordinate"
            )));
        }
        self.push(p)
    }

    fn push(&mut self, p: Vec3) -> Result<()> {
        if self.pts.len() >= self.max_points {
            return Err(limits::too_many_points(
                self.name,
                None,
                "points",
                self.max_points,
            ));
        }
        if self.pts.len() == self.pts.capacity() {
            self.pts
                .try_reserve(self.pts.len().max(1024))
                .map_err(|_| limits::out_of_memory(self.name, 48 * self.pts.len() as u64))?;
        }
        self.pts.push(p);
        Ok(())
    }
}

/// Expands folders into their section files (sorted by name); files are kept in the given order.
pub fn expand_section_inputs(inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in inputs {
        if p.is_dir() {
            let rd = std::fs::read_dir(p).map_err(|e| Error::io(p, &e))?;
            let mut files: Vec<PathBuf> = rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    f.is_file()
                        && f.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                            SECTION_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str())
                        })
                })
                .collect();
            files.sort();
            if files.is_empty() {
                return Err(Error::InvalidData(format!(
                    "{}: folder holds no .csv/.txt/.dat/.xyz section files",
                    p.display()
                )));
            }
            out.extend(files);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_headers_comments_and_separators() {
        let t = "\u{feff}# comment\nx,y,z\n1,2,3\n4 5 6\n7;8;9\n";
        let p = parse_section_text(t, "t").unwrap();
        assert_eq!(
            p,
            vec![
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(4.0, 5.0, 6.0),
                Vec3::new(7.0, 8.0, 9.0)
            ]
        );
        // a byte-order mark before the first point keeps that point; 2 columns mean z = 0
        let p = parse_section_text("\u{feff}1,2\n3,4\n", "t").unwrap();
        assert_eq!(p, vec![Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 4.0, 0.0)]);
        // a file mixing 2 and 3 columns is refused at the first odd line
        let e = parse_section_text("1,2,3\n4,5,6\n7;8\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("f.csv:3") && e.contains("expected 3 numbers"),
            "{e}"
        );
        let e = parse_section_text("1,2,3\n1,a,3\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains("f.csv:2"), "{e}");
        let e = parse_section_text("1,2,3\n4\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains("f.csv:2"), "{e}");
    }
}
