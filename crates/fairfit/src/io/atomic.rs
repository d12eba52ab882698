//! Atomic file writes: the bytes go to a temporary file beside the target, which is renamed into place,
//! so a failed or interrupted write never leaves a partial file behind. [`write_all_atomic`] does the
//! same for several files at once: all temporary files first, renamed only when every one was written.

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

/// Writes `bytes` to `path` atomically. Errors name the path.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    let path = path.as_ref();
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
    let mut written: Vec<std::path::PathBuf> = Vec::with_capacity(files.len());
    let cleanup = |written: &[std::path::PathBuf]| {
        for t in written {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, bytes) in files {
        let path = path.as_ref();
        let step = temporary_path(path).and_then(|tmp| {
            write_temporary(&tmp, path, bytes)?;
            Ok(tmp)
        });
        match step {
            Ok(tmp) => written.push(tmp),
            Err(e) => {
                cleanup(&written);
                return Err(e);
            }
        }
    }
    for (k, ((path, _), tmp)) in files.iter().zip(&written).enumerate() {
        if let Err(e) = std::fs::rename(tmp, path.as_ref()) {
            cleanup(&written[k..]);
            return Err(Error::io(path.as_ref(), &e));
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
