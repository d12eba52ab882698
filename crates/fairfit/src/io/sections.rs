//! Reading section files: each file is one ordered curve, one point per line as 2 or 3 numbers separated
//! by commas, semicolons or white space (2 columns mean z = 0). Lines starting with `#` and one header
//! line of names before the data are skipped; a leading byte-order mark is ignored. Every point line
//! has as many numbers as the first (a file mixing 2 and 3 columns is refused). A folder means all its `.csv`, `.txt`, `.dat` and `.xyz`
//! files, sorted by name.

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
    let mut pts = Vec::new();
    let mut header_seen = false;
    let mut columns = None;
    for (ln, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') || t.starts_with("//") {
            continue;
        }
        let fields: Vec<&str> = t
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        let nums: Vec<Option<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        if nums.iter().all(|n| n.is_none()) && pts.is_empty() && !header_seen {
            header_seen = true;
            continue;
        }
        if fields.len() < 2 || nums.iter().take(3).any(|n| n.is_none()) {
            return Err(Error::InvalidData(format!(
                "{name}:{}: expected 2 or 3 numbers, got `{t}`",
                ln + 1
            )));
        }
        let n = fields.len().min(3);
        if *columns.get_or_insert(n) != n {
            return Err(Error::InvalidData(format!(
                "{name}:{}: expected {} numbers like the first point line, got `{t}`",
                ln + 1,
                columns.unwrap_or(n)
            )));
        }
        let x = nums[0].unwrap_or(0.0);
        let y = nums[1].unwrap_or(0.0);
        let z = if fields.len() >= 3 {
            nums[2].unwrap_or(0.0)
        } else {
            0.0
        };
        let p = Vec3::new(x, y, z);
        if !p.is_finite() {
            return Err(Error::InvalidData(format!(
                "{name}:{}: non-finite coordinate",
                ln + 1
            )));
        }
        pts.push(p);
    }
    Ok(pts)
}

/// Reads one section file.
pub fn read_section_file(path: impl AsRef<Path>) -> Result<Vec<Vec3>> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, &e))?;
    parse_section_text(&text, &path.display().to_string())
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
