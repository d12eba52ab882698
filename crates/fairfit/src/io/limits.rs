//! Bounds on what a reader accepts, so that no input file (a device such as `/dev/zero`, a sparse
//! file, a header claiming 10^9 vertices) can make fairfit read or allocate without end.
//!
//! Three limits, each with a default that covers every real file of its kind and an option that
//! raises it:
//! - [`ReadLimits::max_points`] (default [`DEFAULT_MAX_POINTS`], 10^7): points of a point, section or
//!   cloud file, vertices of a mesh, control points of a curve or surface. The CLI's `--max-points N`
//!   sets it.
//! - [`ReadLimits::max_file_bytes`] (default [`DEFAULT_MAX_FILE_BYTES`], 512 MiB): the size of a file
//!   that is read whole (fairfit JSON, STEP, IGES, PLY/STL/OBJ meshes). The CLI's `--max-file-mb N`
//!   sets it. Point files are streamed and bounded by their point count and line count instead.
//! - [`MAX_LINE_BYTES`] (64 KiB, fixed): the longest line of a streamed text file; no honest point line
//!   is longer, and the cap keeps a file without newlines from being held whole.
//!
//! The limits are a process-wide setting ([`ReadLimits::install`], read with [`ReadLimits::current`]),
//! like an allocator limit: the readers deep inside CAD and mesh parsing consult them without every
//! signature carrying them. The command-line tool installs them once from its options; a library user
//! who never calls `install` gets the defaults.
//!
//! A refusal is one line naming the file, the limit and the option that raises it
//! ([`Error::InvalidData`]).

use crate::errors::{Error, Result};
use std::io::Read;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// Default cap on the points (or vertices, or control points) of one input: 10^7.
pub const DEFAULT_MAX_POINTS: usize = 10_000_000;
/// Default cap on the size of a file read whole (JSON, STEP, IGES, meshes): 512 MiB.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 512 * 1024 * 1024;
/// Longest line of a streamed text file (point, section and cloud files).
pub const MAX_LINE_BYTES: usize = 64 * 1024;
/// Default cap on the sections of one surface (section files, a CAD file's curves, slicing planes):
/// the loft's work grows with the count (1,000 sections take about 18 s on two cores).
pub const DEFAULT_MAX_SECTIONS: usize = 1000;

static MAX_POINTS: AtomicU64 = AtomicU64::new(DEFAULT_MAX_POINTS as u64);
static MAX_FILE_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_FILE_BYTES);

/// The limits every reader applies (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadLimits {
    /// Most points, vertices or control points one input may hold.
    pub max_points: usize,
    /// Largest file, in bytes, that is read whole.
    pub max_file_bytes: u64,
}

impl Default for ReadLimits {
    fn default() -> Self {
        ReadLimits {
            max_points: DEFAULT_MAX_POINTS,
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
        }
    }
}

impl ReadLimits {
    /// The limits in force (the defaults until [`install`](Self::install) is called).
    ///
    /// ```
    /// use fairfit::io::limits::ReadLimits;
    /// assert!(ReadLimits::current().max_points >= 1_000_000);
    /// ```
    pub fn current() -> Self {
        ReadLimits {
            max_points: MAX_POINTS.load(Ordering::Relaxed) as usize,
            max_file_bytes: MAX_FILE_BYTES.load(Ordering::Relaxed),
        }
    }

    /// Makes these the limits of every later read in this process.
    pub fn install(self) {
        MAX_POINTS.store(self.max_points as u64, Ordering::Relaxed);
        MAX_FILE_BYTES.store(self.max_file_bytes, Ordering::Relaxed);
    }

    /// Refuses `count` items (points, vertices, control points, entities) of `what` over
    /// [`max_points`](Self::max_points), naming the limit and the option that raises it.
    pub fn check_points(&self, source: &str, count: usize, what: &str) -> Result<()> {
        if count > self.max_points {
            return Err(too_many_points(source, Some(count), what, self.max_points));
        }
        Ok(())
    }
}

/// The refusal of an input with more than `limit` points: `count` of them when it is known (a
/// header's claim), `None` when a streamed read stops at the limit.
pub(crate) fn too_many_points(
    source: &str,
    count: Option<usize>,
    what: &str,
    limit: usize,
) -> Error {
    let counted = match count {
        Some(n) => format!("{n} {what}, over the limit of {limit}"),
        None => format!("more {what} than the limit of {limit}"),
    };
    Error::InvalidData(format!(
        "{source}: {counted} (raise it with --max-points N, or ReadLimits::max_points in the library)"
    ))
}

/// The refusal of a file over the size limit.
fn too_large(source: &str, limit: u64) -> Error {
    Error::InvalidData(format!(
        "{source}: larger than the file size limit of {} MiB (raise it with --max-file-mb N, \
         or ReadLimits::max_file_bytes in the library)",
        limit.div_ceil(1024 * 1024)
    ))
}

/// Reads a whole file, refusing it (before holding more than the limit) when it is larger than
/// [`ReadLimits::max_file_bytes`]. Devices and pipes are read up to the limit, never further.
pub fn read_bounded(path: &Path) -> Result<Vec<u8>> {
    read_with_limit(path, ReadLimits::current().max_file_bytes)
}

/// [`read_bounded`] for a text format (JSON, STEP, IGES, OBJ): also refused, as soon as one is read,
/// at a NUL byte, so that `/dev/zero` ends the read at once.
pub fn read_bounded_text(path: &Path) -> Result<Vec<u8>> {
    read_limited(path, ReadLimits::current().max_file_bytes, true)
}

/// [`read_bounded_text`], with `not_text` as the error at a NUL byte (a reader's own wording).
pub(crate) fn read_bounded_text_or(
    path: &Path,
    not_text: impl FnOnce() -> Error,
) -> Result<Vec<u8>> {
    match read_limited(path, ReadLimits::current().max_file_bytes, true) {
        Err(Error::InvalidData(m)) if m.ends_with(NOT_TEXT) => Err(not_text()),
        other => other,
    }
}

/// The end of the error at a NUL byte.
const NOT_TEXT: &str = "not a text file (contains NUL bytes)";

/// [`read_bounded`] with an explicit limit in bytes.
fn read_with_limit(path: &Path, limit: u64) -> Result<Vec<u8>> {
    read_limited(path, limit, false)
}

/// Reads `path` whole, up to `limit` bytes, refusing NUL bytes when `text`.
fn read_limited(path: &Path, limit: u64, text: bool) -> Result<Vec<u8>> {
    let source = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, &e))?;
    let len = file.metadata().map(|m| m.len()).unwrap_or(0);
    if len > limit {
        return Err(too_large(&source, limit));
    }
    let mut bytes = Vec::new();
    bytes
        .try_reserve(len as usize)
        .map_err(|_| out_of_memory(&source, len))?;
    let mut reader = file.take(limit.saturating_add(1));
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        let n = match reader.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(Error::io(path, &e)),
        };
        if text && chunk[..n].contains(&0) {
            return Err(Error::InvalidData(format!("{source}: {NOT_TEXT}")));
        }
        bytes
            .try_reserve(n)
            .map_err(|_| out_of_memory(&source, (bytes.len() + n) as u64))?;
        bytes.extend_from_slice(&chunk[..n]);
    }
    if bytes.len() as u64 > limit {
        return Err(too_large(&source, limit));
    }
    Ok(bytes)
}

/// The error of an allocation of `bytes` that failed.
pub(crate) fn out_of_memory(source: &str, bytes: u64) -> Error {
    Error::out_of_memory(source, bytes)
}

/// A vector with room for `n` items, or a one-line error when that much memory is not available
/// (never an abort): [`crate::errors::try_vec`].
pub fn try_vec<T>(n: usize, source: &str) -> Result<Vec<T>> {
    crate::errors::try_vec(n, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_is_read_up_to_the_limit_and_refused() {
        // /dev/zero has no length: it is read up to the limit (+1 byte) and refused
        let e = read_with_limit(Path::new("/dev/zero"), 3 << 20)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "invalid input data: /dev/zero: larger than the file size limit of 3 MiB (raise it \
             with --max-file-mb N, or ReadLimits::max_file_bytes in the library)"
        );
        // a regular file over the limit is refused by its length, before it is read
        let dir = std::env::temp_dir().join("fairfit_limits_test");
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("sparse.bin");
        let file = std::fs::File::create(&f).unwrap();
        file.set_len(1 << 40).unwrap(); // 1 TiB, sparse
        assert!(read_with_limit(&f, 1 << 20).is_err());
        std::fs::write(&f, b"abc").unwrap();
        assert_eq!(read_with_limit(&f, 3).unwrap(), b"abc");
        assert!(read_with_limit(&f, 2).is_err());
        let e = read_limited(Path::new("/dev/zero"), 1 << 40, true).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid input data: /dev/zero: not a text file (contains NUL bytes)"
        );
    }

    #[test]
    fn a_count_over_the_limit_is_refused_by_name() {
        let lim = ReadLimits {
            max_points: 10,
            max_file_bytes: 1,
        };
        assert!(lim.check_points("f", 10, "points").is_ok());
        let e = lim.check_points("f", 11, "points").unwrap_err().to_string();
        assert!(
            e.contains("f: 11 points, over the limit of 10 (raise it with --max-points N"),
            "{e}"
        );
        assert!(e.contains("--max-points"), "{e}");
    }

    #[test]
    fn an_impossible_vector_is_an_error_not_an_abort() {
        assert!(try_vec::<[f64; 3]>(usize::MAX / 8, "f").is_err());
        assert_eq!(try_vec::<f64>(10, "f").unwrap().capacity(), 10);
    }
}
