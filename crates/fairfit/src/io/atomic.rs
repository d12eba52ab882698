//! Atomic file writes: the bytes go to a temporary file beside the target, which is renamed into place,
//! so a failed or interrupted write never leaves a partial file behind.

use crate::errors::{Error, Result};
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically. Errors name the path.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    let path = path.as_ref();
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
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, &e));
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
}
