//! The output files of a run: which paths may be written, checked before any work, and the one
//! commit that writes them all or none.
//!
//! Rules (README "Command-line tool", docs/reliability.md "Outputs and messages"):
//! - No input is ever overwritten: every output is compared with every input and every other output
//!   as the same path, through symbolic links, and as the same file (device and inode: hard links).
//!   An input folder is read whole, so an output is refused inside it when the folder would read it
//!   (a section file name) or when it names a file there; an output folder (`--pareto-curves`) is
//!   refused when an input or another output lies in it under a name the run writes there.
//! - `-` and `/dev/stdout` (`/dev/fd/1`, `/proc/self/fd/1`) write to stdout; at most one output may.
//!   A device, named pipe or socket is written directly, never replaced (several outputs may share
//!   `/dev/null`); a symbolic link is written through to its target (replaced atomically when that is
//!   a regular file; the link is kept); a link to nothing, a folder, and a file in a folder that does
//!   not exist are refused before any work.
//! - [`commit`] writes every file to a temporary beside its target (`fairfit::io::atomic`), then
//!   stdout and the devices, then renames the temporaries: a failure anywhere leaves none of the
//!   files. Text outputs holding a non-finite number (`NaN`, `inf`) are refused before anything is
//!   written.

use super::{CliError, CmdResult};
use fairfit::io::atomic::{stage_all, target_of, Target};
use std::path::{Path, PathBuf};

/// The rules for output files, shown at the end of `--help` of every subcommand that writes files.
pub const OUTPUT_RULES: &str = "Outputs: all are written or none (each goes to a temporary file \
.NAME.fairfit-PID.tmp beside it, renamed into place when every output is complete; SIGINT and \
SIGTERM remove them). An output that names an input, another output, or a file of an input folder \
is refused before any work. `-` and /dev/stdout write to stdout; a device or FIFO is written \
directly, never replaced; a symbolic link is written through to its target (replaced atomically \
when that is a regular file; the link is kept), a link to nothing is refused.";

/// Whether an output path means stdout: `-`, or a name of file descriptor 1.
pub fn is_stdout(path: &Path) -> bool {
    matches!(
        path.to_str(),
        Some("-" | "/dev/stdout" | "/dev/fd/1" | "/proc/self/fd/1")
    )
}

/// What makes two paths the same file: the canonical path (symbolic links resolved; for a file that
/// does not exist yet, its canonical folder joined with its name) and, for an existing file, its
/// device and inode (hard links).
#[derive(Debug, PartialEq, Eq, Clone)]
struct Identity {
    path: PathBuf,
    inode: Option<(u64, u64)>,
}

impl Identity {
    fn of(path: &Path) -> Identity {
        Identity {
            path: canonical(path),
            inode: inode(path),
        }
    }

    fn same(&self, other: &Identity) -> bool {
        self.path == other.path || (self.inode.is_some() && self.inode == other.inode)
    }
}

#[cfg(unix)]
fn inode(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn inode(_: &Path) -> Option<(u64, u64)> {
    None
}

/// The canonical form of `path`: canonical when it exists, else its canonical folder joined with its
/// name, else the path made absolute (so `a.out`, `./a.out` and `dir/../a.out` agree).
fn canonical(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let parent = folder_of(path);
    match (parent.canonicalize(), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
    }
}

fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// An output folder (`--pareto-curves DIR`) and the file names the run writes into it.
pub struct OutputFolder<'a> {
    /// The flag naming it.
    pub flag: &'a str,
    /// The folder (created when missing).
    pub path: &'a Path,
    /// Whether the run writes a file of this name there (`front_000.json`, ...).
    pub writes: fn(&str) -> bool,
}

/// The inputs of a run: files, and folders whose files of the given extensions are read.
#[derive(Default)]
pub struct Inputs<'a> {
    /// The paths given (files or folders).
    pub paths: Vec<&'a Path>,
    /// The extensions a folder input reads (`fairfit surface SECTIONS_DIR`: .csv, .txt, ...).
    pub folder_reads: &'a [&'a str],
}

impl<'a> Inputs<'a> {
    /// Inputs that are files only.
    pub fn files(paths: Vec<&'a Path>) -> Self {
        Inputs {
            paths,
            folder_reads: &[],
        }
    }
}

fn extension_in(path: &Path, list: &[&str]) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| list.iter().any(|k| k.eq_ignore_ascii_case(e)))
}

/// Fails unless `path` (given by `flag`) may be written: not a folder, not a link to nothing, in a
/// folder that exists.
fn check_writable(flag: &str, path: &Path) -> CmdResult {
    if is_stdout(path) {
        return Ok(());
    }
    match target_of(path) {
        Err(_) if path.is_dir() => Err(CliError::new(format!(
            "{flag} names the folder {}; name a file (e.g. {})",
            path.display(),
            path.join("out.json").display()
        ))),
        Err(e) => Err(CliError::new(format!("{flag}: {e}"))),
        Ok(Target::Direct { .. }) => Ok(()),
        Ok(Target::Replace { file }) => {
            let folder = folder_of(&file);
            if folder.is_dir() {
                Ok(())
            } else {
                Err(CliError::new(format!(
                    "{flag} {}: the folder {} does not exist",
                    path.display(),
                    folder.display()
                )))
            }
        }
    }
}

/// Whether an output is written directly into a special file (device, pipe), which several outputs
/// may share.
fn is_special(path: &Path) -> bool {
    matches!(target_of(path), Ok(Target::Direct { .. }))
}

/// Fails, before any work, when an output would overwrite an input or another output, names a folder,
/// a link to nothing or a missing folder, when two outputs write to stdout, when an output folder
/// would receive an input or another output, or when a `--plot`/`--mesh` file name has an unknown
/// extension (see the module documentation). `outputs` are (flag, path) pairs such as
/// `("--step", a.out)`.
pub fn check_outputs(
    outputs: &[(&str, &Path)],
    folders: &[OutputFolder<'_>],
    inputs: &Inputs<'_>,
) -> CmdResult {
    for (flag, path) in outputs {
        check_writable(flag, path)?;
    }
    let input_ids: Vec<(&Path, Identity, bool)> = inputs
        .paths
        .iter()
        .map(|p| (*p, Identity::of(p), p.is_dir()))
        .collect();
    let ids: Vec<Identity> = outputs.iter().map(|(_, p)| Identity::of(p)).collect();
    let stdout: Vec<&str> = outputs
        .iter()
        .filter(|(_, p)| is_stdout(p))
        .map(|(f, _)| *f)
        .collect();
    if let [a, b, ..] = stdout[..] {
        return Err(CliError::usage(format!(
            "{a} and {b} both write to stdout; give one of them a file"
        )));
    }
    for (i, (flag, path)) in outputs.iter().enumerate() {
        if is_stdout(path) {
            continue;
        }
        for (input, id, is_dir) in &input_ids {
            if id.same(&ids[i]) {
                return Err(CliError::usage(format!(
                    "{flag} names the input file {}; choose another output file",
                    path.display()
                )));
            }
            if *is_dir && Identity::of(&folder_of(&ids[i].path)).same(id) {
                let read = extension_in(path, inputs.folder_reads) || path.exists();
                if read {
                    return Err(CliError::usage(format!(
                        "{flag} {} lies in the input folder {}, which is read; write it elsewhere",
                        path.display(),
                        input.display()
                    )));
                }
            }
        }
        if is_special(path) {
            continue; // a device: several outputs may share it (`/dev/null`)
        }
        if let Some(j) = ids[..i].iter().position(|id| id.same(&ids[i])) {
            return Err(CliError::usage(format!(
                "{} and {flag} both name the file {}; give each output its own file",
                outputs[j].0,
                path.display()
            )));
        }
    }
    for f in folders {
        check_output_folder(f, outputs, &input_ids)?;
    }
    Ok(())
}

/// The checks of one output folder: it is no file and no input, and nothing read or written by the
/// run lies in it under a name the run writes there.
fn check_output_folder(
    f: &OutputFolder<'_>,
    outputs: &[(&str, &Path)],
    inputs: &[(&Path, Identity, bool)],
) -> CmdResult {
    if f.path.exists() && !f.path.is_dir() {
        return Err(CliError::usage(format!(
            "{} {} is a file; name a folder (created when missing)",
            f.flag,
            f.path.display()
        )));
    }
    let dir = Identity::of(f.path);
    for (input, id, _) in inputs {
        if id.same(&dir) {
            return Err(CliError::usage(format!(
                "{} names the input {}; choose another folder",
                f.flag,
                input.display()
            )));
        }
    }
    let inside = |p: &Path| {
        let c = canonical(p);
        let name = c.file_name().map(|n| n.to_string_lossy().into_owned());
        Identity::of(&folder_of(&c)).same(&dir) && name.is_some_and(|n| (f.writes)(&n))
    };
    for (input, _, _) in inputs {
        if inside(input) {
            return Err(CliError::usage(format!(
                "{} {} would overwrite the input {}; choose another folder",
                f.flag,
                f.path.display(),
                input.display()
            )));
        }
    }
    for (flag, path) in outputs {
        if !is_stdout(path) && inside(path) {
            return Err(CliError::usage(format!(
                "{} {} would overwrite {flag} {}; give each output its own file",
                f.flag,
                f.path.display(),
                path.display()
            )));
        }
    }
    Ok(())
}

/// Whether `bytes` (text) hold a non-finite number as Rust and serde print them: a `NaN`, `inf` or
/// `-inf` token (letters on neither side), or, with `json_geometry`, a `null`.
fn non_finite_token(text: &str, json_geometry: bool) -> Option<&'static str> {
    let tokens: &[&'static str] = if json_geometry {
        &["NaN", "inf", "null"]
    } else {
        &["NaN", "inf"]
    };
    let b = text.as_bytes();
    for t in tokens {
        let mut from = 0;
        while let Some(k) = text[from..].find(t) {
            let (s, e) = (from + k, from + k + t.len());
            let before = s > 0 && b[s - 1].is_ascii_alphanumeric();
            // `inf.step` (a file name in a STEP header) is no number
            let after = e < b.len() && (b[e].is_ascii_alphanumeric() || b[e] == b'.');
            if !before && !after {
                return Some(t);
            }
            from = e;
        }
    }
    None
}

/// Fails when the text output `bytes` for `path` holds a non-finite number (a binary file, such as a
/// PNG or binary STL, is not scanned: its numbers are checked where they are made).
pub fn check_finite_output(path: &Path, bytes: &[u8], json_geometry: bool) -> CmdResult {
    let Ok(text) = std::str::from_utf8(bytes) else {
        return Ok(());
    };
    match non_finite_token(text, json_geometry) {
        None => Ok(()),
        Some(t) => Err(CliError::new(format!(
            "{}: a value cannot be computed as a finite number at this geometry's scale (it would be \
             written as {t}); nothing was written; rescale the input",
            shown(path)
        ))),
    }
}

fn shown(path: &Path) -> String {
    if is_stdout(path) {
        "stdout".into()
    } else {
        path.display().to_string()
    }
}

/// One output of a run: where, its bytes, and whether it is a curve or surface JSON (where `null`
/// is never a value).
pub struct Output {
    /// The path (`-` for stdout).
    pub path: PathBuf,
    /// The bytes.
    pub bytes: Vec<u8>,
    /// A curve or surface JSON.
    pub geometry_json: bool,
}

impl Output {
    /// An output that is not a geometry JSON.
    pub fn new(path: impl Into<PathBuf>, bytes: Vec<u8>) -> Self {
        Output {
            path: path.into(),
            bytes,
            geometry_json: false,
        }
    }

    /// A curve or surface JSON.
    pub fn geometry(path: impl Into<PathBuf>, bytes: Vec<u8>) -> Self {
        Output {
            path: path.into(),
            bytes,
            geometry_json: true,
        }
    }
}

/// Writes every output of a run, all or none: each is checked finite, written to a temporary beside
/// its target, then stdout and the devices are written, then the temporaries renamed into place. A
/// closed stdout (`| head`) still puts the files in place and then ends the run quietly (exit 0).
pub fn commit(outputs: Vec<Output>) -> CmdResult {
    for o in &outputs {
        check_finite_output(&o.path, &o.bytes, o.geometry_json)?;
    }
    let (to_stdout, files): (Vec<Output>, Vec<Output>) =
        outputs.into_iter().partition(|o| is_stdout(&o.path));
    let files: Vec<(PathBuf, Vec<u8>)> = files.into_iter().map(|o| (o.path, o.bytes)).collect();
    let staged = stage_all(&files)?;
    let mut closed = false;
    for o in to_stdout {
        match super::write_stdout(&o.bytes) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => closed = true,
            Err(e) => return Err(CliError::new(format!("cannot write to stdout: {e}"))),
        }
    }
    staged.commit()?;
    if closed {
        std::process::exit(0);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_tokens_are_found_only_as_words() {
        assert_eq!(non_finite_token("x=\"NaN\"", false), Some("NaN"));
        assert_eq!(non_finite_token("1 -inf 2", false), Some("inf"));
        assert_eq!(
            non_finite_token("info infinite nano 'inf.step'", false),
            None
        );
        assert_eq!(non_finite_token("[1, null]", false), None);
        assert_eq!(non_finite_token("[1, null]", true), Some("null"));
    }
}
