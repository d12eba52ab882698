//! Atomic file writes, all or none: the bytes of every file go to a temporary file beside its target,
//! and the temporaries are renamed into place only when every one of them was written, so a failed
//! or interrupted write never leaves a partial file, nor some of the files without the others.
//!
//! What a target is decides how it is written ([`target_of`]):
//! - a regular file, or a name that does not exist yet: replaced atomically (temporary + rename);
//! - a device, a named pipe or a socket (`/dev/null`, `/dev/full`, a FIFO), or a name that leads
//!   to an open file descriptor (`/dev/stdout`, `/dev/fd/N`, `/proc/self/fd/N`): written directly,
//!   appended to, never replaced (renaming a file over it would replace the device or the link);
//! - a symbolic link: written through to the file it points to (that file is replaced atomically
//!   when it is a regular file; the link itself is kept); a link to nothing is refused;
//! - a folder: refused.
//!
//! Temporary files are named `.NAME.fairfit-PID.tmp`. While they exist they are held in a process-wide
//! registry, so a signal handler can remove them ([`remove_pending_temporaries`]; the CLI installs
//! one for SIGINT and SIGTERM). The temporaries of a killed run (SIGKILL leaves them) are removed by
//! the next write into the same folder when no process of their PID is alive.

use crate::errors::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The suffix of fairfit's temporary files: `.NAME.fairfit-PID.tmp`.
const TEMPORARY_TAG: &str = ".fairfit-";

/// How a target path is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// Replaced atomically: a temporary file beside `file` (the file itself, or what a symbolic
    /// link points to) is renamed onto it.
    Replace {
        /// The file renamed onto (a symbolic link's target, not the link).
        file: PathBuf,
    },
    /// Written directly, appended to (a device, pipe, socket or open file descriptor).
    Direct {
        /// The path opened for writing.
        path: PathBuf,
    },
}

/// The temporary files written and not yet renamed or removed, for [`remove_pending_temporaries`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn pending() -> MutexGuard<'static, Vec<PathBuf>> {
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every temporary file this process is writing and has not renamed yet (for a signal
/// handler: the run then ends without any of its outputs). A commit that is renaming files finishes
/// first, so the outputs of a run are still all there or none.
pub fn remove_pending_temporaries() {
    let mut list = pending();
    for t in list.drain(..) {
        let _ = std::fs::remove_file(t);
    }
}

fn io_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Io {
        path: path.display().to_string(),
        message: message.into(),
    }
}

/// Whether a path (a link's target) names an open file descriptor rather than a file.
fn is_descriptor_alias(p: &Path) -> bool {
    let s = p.to_string_lossy();
    s.starts_with("/dev/fd/")
        || matches!(s.as_ref(), "/dev/stdout" | "/dev/stderr")
        || (s.starts_with("/proc/") && s.contains("/fd/"))
}

/// Whether `path`, or any symbolic link on the way from it, names an open file descriptor.
fn leads_to_descriptor(path: &Path) -> bool {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        if is_descriptor_alias(&p) {
            return true;
        }
        match std::fs::read_link(&p) {
            Ok(next) => {
                p = match p.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                }
            }
            Err(_) => return false,
        }
    }
    false
}

/// How `path` is written (see the module documentation); fails for a folder or a link to nothing.
pub fn target_of(path: &Path) -> Result<Target> {
    let link = match std::fs::symlink_metadata(path) {
        Err(_) => return Ok(Target::Replace { file: path.into() }),
        Ok(m) => m.file_type().is_symlink(),
    };
    if link && leads_to_descriptor(path) {
        return Ok(Target::Direct { path: path.into() });
    }
    let meta = std::fs::metadata(path).map_err(|_| {
        io_error(
            path,
            "a symbolic link to a file that does not exist; name the file itself",
        )
    })?;
    if meta.is_dir() {
        return Err(io_error(path, "a folder, not a file"));
    }
    if !meta.is_file() {
        return Ok(Target::Direct { path: path.into() });
    }
    if !link {
        return Ok(Target::Replace { file: path.into() });
    }
    let file = path.canonicalize().map_err(|e| Error::io(path, &e))?;
    Ok(Target::Replace { file })
}

/// The folder of `path` (`.` for a bare name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The temporary file beside `file`: `.NAME.fairfit-PID.tmp`.
fn temporary_path(file: &Path) -> Result<PathBuf> {
    let name = file
        .file_name()
        .ok_or_else(|| io_error(file, "not a file path"))?
        .to_string_lossy()
        .to_string();
    Ok(folder_of(file).join(format!(".{name}{TEMPORARY_TAG}{}.tmp", std::process::id())))
}

/// The PID in the name of one of fairfit's temporary files, `.NAME.fairfit-PID.tmp`.
fn temporary_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (_, pid) = rest.rsplit_once(TEMPORARY_TAG)?;
    if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether a process `pid` may be alive: decided by `/proc` where there is one; elsewhere every
/// process is taken as alive (its files are never removed).
fn may_be_alive(pid: u32) -> bool {
    if pid == std::process::id() || !Path::new("/proc/self").exists() {
        return true;
    }
    Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes the temporary files of fairfit runs that were killed before they could remove them (named
/// `.NAME.fairfit-PID.tmp`, a regular file, no process PID alive) from `folder`. Errors are ignored:
/// this is housekeeping, never a reason to fail a write.
pub(crate) fn remove_stale_temporaries(folder: &Path) {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = temporary_pid(&name.to_string_lossy()) else {
            continue;
        };
        let regular = e.file_type().is_ok_and(|t| t.is_file());
        if regular && !may_be_alive(pid) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Writes and syncs `bytes` to the registered temporary `tmp`; errors name `path`.
fn write_temporary(tmp: &Path, path: &Path, bytes: &[u8]) -> Result<()> {
    pending().push(tmp.to_path_buf());
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(tmp)
            .or_else(|_| {
                // a temporary of this PID left by an earlier, killed process
                std::fs::remove_file(tmp)?;
                std::fs::File::create(tmp)
            })?;
        f.write_all(bytes)?;
        f.sync_all()
    })();
    result.map_err(|e| Error::io(path, &e))
}

/// Writes `bytes` into the special file `path` (appended; see the module documentation).
fn write_direct(path: &Path, bytes: &[u8]) -> Result<()> {
    std::fs::OpenOptions::new()
        .append(true)
        .open(path)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.flush()))
        .map_err(|e| Error::io(path, &e))
}

/// Files written to their temporaries, not yet in place: [`Staged::commit`] puts them there, and
/// dropping it (or a failed commit) removes the temporaries, leaving no file behind.
#[derive(Debug)]
pub struct Staged {
    /// (temporary, target file, path as given) of every replaced file.
    replaced: Vec<(PathBuf, PathBuf, PathBuf)>,
    /// (path, bytes) of every file written directly at the commit.
    direct: Vec<(PathBuf, Vec<u8>)>,
}

impl Staged {
    fn remove_temporaries(&mut self) {
        let mut list = pending();
        for (tmp, _, _) in self.replaced.drain(..) {
            let _ = std::fs::remove_file(&tmp);
            list.retain(|t| *t != tmp);
        }
    }

    /// Writes the direct targets (devices, pipes), then renames every temporary into place. A failed
    /// direct write removes the temporaries (no file is written; what reached a device cannot be
    /// taken back). A signal arriving during the renames waits for them to end.
    pub fn commit(mut self) -> Result<()> {
        for (path, bytes) in std::mem::take(&mut self.direct) {
            write_direct(&path, &bytes)?; // `self` dropped: temporaries removed
        }
        let mut list = pending();
        let replaced = std::mem::take(&mut self.replaced);
        for (k, (tmp, file, given)) in replaced.iter().enumerate() {
            if let Err(e) = std::fs::rename(tmp, file) {
                // needs a race (the folder removed meanwhile): the rest is not written
                for (t, _, _) in &replaced[k..] {
                    let _ = std::fs::remove_file(t);
                }
                list.retain(|t| !replaced[k..].iter().any(|(r, _, _)| r == t));
                return Err(Error::io(given, &e));
            }
            list.retain(|t| t != tmp);
        }
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        self.remove_temporaries();
    }
}

/// Writes every file to its temporary (the first step of [`write_all_atomic`]); nothing is in place
/// until [`Staged::commit`]. A failure removes the temporaries written so far and names its path.
/// Stale temporaries of killed runs in the target folders are removed first.
pub fn stage_all<P: AsRef<Path>>(files: &[(P, Vec<u8>)]) -> Result<Staged> {
    let mut staged = Staged {
        replaced: Vec::with_capacity(files.len()),
        direct: Vec::new(),
    };
    let mut cleaned: Vec<PathBuf> = Vec::new();
    for (path, bytes) in files {
        let path = path.as_ref();
        match target_of(path)? {
            Target::Direct { path } => staged.direct.push((path, bytes.clone())),
            Target::Replace { file } => {
                let folder = folder_of(&file);
                if !cleaned.contains(&folder) {
                    remove_stale_temporaries(&folder);
                    cleaned.push(folder);
                }
                let tmp = temporary_path(&file)?;
                write_temporary(&tmp, path, bytes)?; // `staged` dropped: temporaries removed
                staged.replaced.push((tmp, file, path.to_path_buf()));
            }
        }
    }
    Ok(staged)
}

/// Writes several files, all or none: every file goes to its temporary first; only when all were
/// written are the devices written and the temporaries renamed into place. A failure removes the
/// temporaries and names the failing path (a rename failing after others succeeded, which needs a
/// race, can still leave earlier files).
pub fn write_all_atomic<P: AsRef<Path>>(files: &[(P, Vec<u8>)]) -> Result<()> {
    stage_all(files)?.commit()
}

/// Writes `bytes` to `path` atomically (directly into a device or pipe; through a symbolic link).
/// Errors name the path.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    write_all_atomic(&[(path.as_ref(), bytes.to_vec())])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

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
        assert_eq!(names(&dir), ["ok.json"], "no temporary file left");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    #[cfg(unix)]
    fn devices_are_written_directly_not_replaced() {
        let null = Path::new("/dev/null");
        if !null.exists() {
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
    #[cfg(unix)]
    fn a_failing_device_leaves_no_file() {
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let dir = std::env::temp_dir().join(format!("fairfit-atomic-full-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let a = dir.join("a.json");
        let err = write_all_atomic(&[(a.clone(), b"A".to_vec()), (full.into(), b"B".to_vec())])
            .unwrap_err();
        assert!(err.to_string().contains("/dev/full"), "{err}");
        assert!(names(&dir).is_empty(), "{:?}", names(&dir));
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
        assert!(names(&dir).is_empty(), "nothing left");
        write_all_atomic(&[(a.clone(), b"A".to_vec()), (b.clone(), b"B".to_vec())]).unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"A");
        assert_eq!(std::fs::read(&b).unwrap(), b"B");
        assert_eq!(names(&dir).len(), 2);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    #[cfg(unix)]
    fn a_symlink_is_written_through_and_kept() {
        let dir = std::env::temp_dir().join(format!("fairfit-atomic-link-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("real")).unwrap();
        let file = dir.join("real").join("f.json");
        std::fs::write(&file, b"old").unwrap();
        let link = dir.join("l.json");
        std::os::unix::fs::symlink(&file, &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&file).unwrap(), b"new");
        assert_eq!(names(&dir.join("real")), ["f.json"]);
        let dangling = dir.join("d.json");
        std::os::unix::fs::symlink(dir.join("nothing"), &dangling).unwrap();
        let err = write_atomic(&dangling, b"x").unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
        assert!(!dir.join("nothing").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = std::env::temp_dir().join(format!("fairfit-atomic-stale-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // PIDs above the kernel's largest (2^22) are never alive
        let dead = dir.join(".a.json.fairfit-4999999.tmp");
        let mine = dir.join(format!(".b.json.fairfit-{}.tmp", std::process::id()));
        let other = dir.join(".c.json.tmp123");
        for f in [&dead, &mine, &other] {
            std::fs::write(f, b"x").unwrap();
        }
        write_atomic(dir.join("out.json"), b"{}").unwrap();
        let left = names(&dir);
        let expected = [other.clone(), mine.clone(), dir.join("out.json")];
        let mut expected: Vec<String> = expected
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        expected.sort();
        if Path::new("/proc/self").exists() {
            assert_eq!(left, expected);
        }
        assert_eq!(temporary_pid(".x.fairfit-12.tmp"), Some(12));
        assert_eq!(temporary_pid(".x.fairfit-.tmp"), None);
        assert_eq!(temporary_pid("x.fairfit-12.tmp"), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn staged_temporaries_are_registered_until_dropped() {
        // (the registry is process-wide: removing its files here would race the other tests)
        let dir = std::env::temp_dir().join(format!("fairfit-atomic-sig-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let staged = stage_all(&[(dir.join("a.json"), b"A".to_vec())]).unwrap();
        let tmp = dir.join(format!(".a.json.fairfit-{}.tmp", std::process::id()));
        assert_eq!(names(&dir), [tmp.file_name().unwrap().to_string_lossy()]);
        assert!(pending().contains(&tmp));
        drop(staged);
        assert!(!pending().contains(&tmp));
        assert!(names(&dir).is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
