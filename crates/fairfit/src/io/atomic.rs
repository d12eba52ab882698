//! Atomic file writes: the bytes go to a temporary file beside the target, which is renamed into place,
//! so a failed or interrupted write never leaves a partial file behind. [`write_all_atomic`] does the
//! same for several files at once: all temporary files first, renamed only when every one was written.
//! A target that exists and is neither a regular file nor a folder (a device such as `/dev/null` or
//! `/dev/stdout`, a named pipe) is written directly: renaming a file over it would replace the device.

use crate::errors::{Error, Result};
use std::io::Write;
use std::path::Path;

/// The temporary file beside `path` that [`write_atomic`] writes first.
fn temporary_path(path: &Path) -> Result<std::path::PathBuf> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| Error::Io {
            path: path.display().to_string(),
            message: "not a file path".into(),
        })?
        .to_string_lossy()
        .to_string();
    Ok(dir.join(format!(".{name}.tmp{}", std::process::id())))
}

/// Writes and syncs `bytes` to `tmp`; on failure removes it and returns an error naming `path`.
fn write_temporary(tmp: &Path, path: &Path, bytes: &[u8]) -> Result<()> {
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(tmp);
        Error::io(path, &e)
    })
}

/// Whether `path` exists and is neither a regular file nor a folder (a device, pipe or socket).
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Writes `bytes` straight into the existing special file `path` (see the module documentation).
fn write_direct(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .and_then(|mut f| f.write_all(bytes))
        .map_err(|e| Error::io(path, &e))
}

/// Writes `bytes` to `path` atomically (directly into a device or pipe). Errors name the path.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    let path = path.as_ref();
    if is_special(path) {
        return write_direct(path, bytes);
    }
    let tmp = temporary_path(path)?;
    write_temporary(&tmp, path, bytes)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, &e)
    })
}

/// Writes several files, all or none: every file goes to its temporary first; only when all were
/// written are they renamed into place. A failure removes the temporaries and names the failing path
/// (a rename failing after others succeeded, which needs a race, can still leave earlier files).
pub fn write_all_atomic<P: AsRef<Path>>(files: &[(P, Vec<u8>)]) -> Result<()> {
    // `None` for a special file, written directly once every temporary is in place
    let mut written: Vec<Option<std::path::PathBuf>> = Vec::with_capacity(files.len());
    let cleanup = |written: &[Option<std::path::PathBuf>]| {
        for t in written.iter().flatten() {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, bytes) in files {
        let path = path.as_ref();
        if is_special(path) {
            written.push(None);
            continue;
        }
        let step = temporary_path(path).and_then(|tmp| {
            write_temporary(&tmp, path, bytes)?;
            Ok(tmp)
        });
        match step {
            Ok(tmp) => written.push(Some(tmp)),
            Err(e) => {
                cleanup(&written);
                return Err(e);
            }
        }
    }
    for (k, ((path, bytes), tmp)) in files.iter().zip(&written).enumerate() {
        let done = match tmp {
            Some(tmp) => {
                std::fs::rename(tmp, path.as_ref()).map_err(|e| Error::io(path.as_ref(), &e))
            }
            None => write_direct(path.as_ref(), bytes),
        };
        if let Err(e) = done {
            cleanup(&written[k..]);
            return Err(e);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unwritable_path_names_the_path_and_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("fairfit-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("no_such_dir").join("out.json");
        let err = write_atomic(&target, b"{}").unwrap_err();
        assert!(err.to_string().contains("out.json"), "{err}");
        assert!(!target.exists());
        let ok = dir.join("ok.json");
        write_atomic(&ok, b"[1]").unwrap();
        assert_eq!(std::fs::read(&ok).unwrap(), b"[1]");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary file left"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    #[cfg(unix)]
    fn devices_are_written_directly_not_replaced() {
        let null = Path::new("/dev/null");
        if !is_special(null) {
            return; // no /dev/null here: nothing to check
        }
        write_atomic(null, b"discarded").unwrap();
        write_all_atomic(&[(null, b"a".to_vec()), (null, b"b".to_vec())]).unwrap();
        let meta = std::fs::metadata(null).unwrap();
        assert!(
            !meta.is_file() && !meta.is_dir(),
            "/dev/null is still a device"
        );
        assert_eq!(
            std::fs::read(null).unwrap(),
            b"",
            "/dev/null still reads empty"
        );
    }

    #[test]
    fn several_files_are_written_all_or_none() {
        let dir = std::env::temp_dir().join(format!("fairfit-atomic-all-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.step"), dir.join("b.igs"));
        let bad = dir.join("missing").join("c.obj");
        let err = write_all_atomic(&[
            (a.clone(), b"A".to_vec()),
            (bad, b"C".to_vec()),
            (b.clone(), b"B".to_vec()),
        ])
        .unwrap_err();
        assert!(err.to_string().contains("missing/c.obj"), "{err}");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "nothing left");
        write_all_atomic(&[(a.clone(), b"A".to_vec()), (b.clone(), b"B".to_vec())]).unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"A");
        assert_eq!(std::fs::read(&b).unwrap(), b"B");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
