//! Streaming the lines of a text file (point, section and cloud files) with bounded memory: one
//! buffered reader and one reused line buffer, so reading 10^6 lines allocates nothing per line.
//!
//! Invariants: a line (and so every token in it) is at most [`MAX_LINE_BYTES`] long; a file has at most
//! [`max_lines`] lines; a NUL byte or invalid UTF-8 ends the read with one line naming the file. A leading
//! UTF-8 byte-order mark is dropped; the line ending (`\n` or `\r\n`) is not part of the line.

use super::limits::{ReadLimits, MAX_LINE_BYTES};
use crate::errors::{Error, Result};
use std::io::{BufRead, BufReader};
use std::path::Path;

/// Most lines (blank and comment lines included) a streamed file may have: four per allowed point,
/// and never fewer than 2^20.
pub fn max_lines(limits: &ReadLimits) -> usize {
    limits.max_points.saturating_mul(4).max(1 << 20)
}

/// A line-by-line reader of one text file (see the module documentation).
pub struct Lines {
    reader: BufReader<std::fs::File>,
    buf: Vec<u8>,
    line_no: usize,
    max_lines: usize,
    source: String,
}

impl Lines {
    /// Opens `path` for reading under the current [`ReadLimits`].
    pub fn open(path: &Path) -> Result<Lines> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, &e))?;
        Ok(Lines {
            reader: BufReader::with_capacity(1 << 16, file),
            buf: Vec::with_capacity(256),
            line_no: 0,
            max_lines: max_lines(&ReadLimits::current()),
            source: path.display().to_string(),
        })
    }

    /// True when the file's first non-blank byte (after a byte-order mark) is `{`: a JSON file, which
    /// the point readers refuse by name (call before the first [`next_line`](Self::next_line)).
    pub fn starts_like_json(&mut self) -> Result<bool> {
        let source = &self.source;
        let head = (self.reader.fill_buf()).map_err(|e| Error::io(Path::new(source), &e))?;
        let head = head.strip_prefix("\u{feff}".as_bytes()).unwrap_or(head);
        Ok(head
            .iter()
            .find(|b| !b.is_ascii_whitespace())
            .is_some_and(|&b| b == b'{'))
    }

    /// The next line as `(line number, text)`, `None` at the end of the file.
    pub fn next_line(&mut self) -> Result<Option<(usize, &str)>> {
        if !self.fill_line()? {
            return Ok(None);
        }
        self.line_no += 1;
        if self.line_no > self.max_lines {
            return Err(Error::InvalidData(format!(
                "{}: more than {} lines, over the limit of 4 lines per allowed point (raise it with \
                 --max-points N, or ReadLimits::max_points in the library)",
                self.source, self.max_lines
            )));
        }
        let mut line: &[u8] = &self.buf;
        line = line.strip_suffix(b"\n").unwrap_or(line);
        line = line.strip_suffix(b"\r").unwrap_or(line);
        if self.line_no == 1 {
            line = line.strip_prefix("\u{feff}".as_bytes()).unwrap_or(line);
        }
        let text = std::str::from_utf8(line).map_err(|_| Error::Io {
            path: self.source.clone(),
            message: "not a text file (invalid UTF-8)".into(),
        })?;
        Ok(Some((self.line_no, text)))
    }

    /// Reads the next line, newline included, into `buf`; false at the end of the file.
    fn fill_line(&mut self) -> Result<bool> {
        self.buf.clear();
        loop {
            let chunk = match self.reader.fill_buf() {
                Ok(c) => c,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(self.io_error(&e)),
            };
            if chunk.is_empty() {
                return Ok(!self.buf.is_empty());
            }
            let (take, done) = match chunk.iter().position(|&b| b == b'\n') {
                Some(i) => (i + 1, true),
                None => (chunk.len(), false),
            };
            let part = &chunk[..take];
            if part.contains(&0) {
                return Err(Error::InvalidData(format!(
                    "{}: not a text file (contains NUL bytes)",
                    self.source
                )));
            }
            if self.buf.len() + take > MAX_LINE_BYTES + 2 {
                return Err(Error::InvalidData(format!(
                    "{}:{}: a line longer than the limit of {MAX_LINE_BYTES} bytes (not a point file?)",
                    self.source,
                    self.line_no + 1
                )));
            }
            self.buf.extend_from_slice(part);
            self.reader.consume(take);
            if done {
                return Ok(true);
            }
        }
    }

    fn io_error(&self, e: &std::io::Error) -> Error {
        Error::io(Path::new(&self.source), e)
    }
}

/// The whole of a file that [`Lines::starts_like_json`] found to be JSON, bounded like every file read
/// whole ([`super::limits::read_bounded`]), as text (lossy: it is only inspected for its kind).
pub(crate) fn json_text(path: &Path) -> Result<String> {
    let bytes = super::limits::read_bounded_text(path)?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join("fairfit_lines_test");
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join(name);
        std::fs::write(&f, bytes).unwrap();
        f
    }

    #[test]
    fn lines_drop_the_bom_and_line_endings() {
        let f = file("a.txt", b"\xef\xbb\xbf1 2\r\n\n3 4");
        let mut l = Lines::open(&f).unwrap();
        assert_eq!(l.next_line().unwrap(), Some((1, "1 2")));
        assert_eq!(l.next_line().unwrap(), Some((2, "")));
        assert_eq!(l.next_line().unwrap(), Some((3, "3 4")));
        assert_eq!(l.next_line().unwrap(), None);
    }

    #[test]
    fn a_long_line_a_nul_and_bad_utf8_are_refused_by_name() {
        let long = vec![b'1'; MAX_LINE_BYTES + 10];
        let f = file("long.txt", &long);
        let e = Lines::open(&f)
            .unwrap()
            .next_line()
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("long.txt:1: a line longer than the limit of 65536 bytes"),
            "{e}"
        );
        let e = Lines::open(Path::new("/dev/zero"))
            .unwrap()
            .next_line()
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "invalid input data: /dev/zero: not a text file (contains NUL bytes)"
        );
        let f = file("bad.txt", b"1 2\n\xff\xfe 3\n");
        let mut l = Lines::open(&f).unwrap();
        l.next_line().unwrap();
        let e = l.next_line().unwrap_err().to_string();
        assert!(
            e.ends_with("bad.txt: not a text file (invalid UTF-8)"),
            "{e}"
        );
    }

    #[test]
    fn json_is_recognised_from_the_head() {
        let f = file("j.csv", b"\xef\xbb\xbf  \n {\"kind\": \"curve\"}");
        assert!(Lines::open(&f).unwrap().starts_like_json().unwrap());
        let f = file("p.csv", b"0 0\n");
        assert!(!Lines::open(&f).unwrap().starts_like_json().unwrap());
    }
}
