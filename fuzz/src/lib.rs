//! What every fuzz target shares: the input is written to a file of the target's extension (the readers
//! take paths, so the bounded and streamed code paths the CLI uses are the ones fuzzed), read, and the
//! outcome checked: `Ok`, or an error whose message is one non-empty line. A panic aborts the run
//! (libFuzzer reports it as a crash); allocation and time bounds are libFuzzer's own
//! (`-malloc_limit_mb`, `-rss_limit_mb`, `-timeout`, set by `fuzz/run.sh`).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Largest input the targets read (libFuzzer's `-max_len` is set to the same by `fuzz/run.sh`).
pub const MAX_INPUT: usize = 1 << 20;

/// The file this process writes its inputs to, `name` in a folder of its own under the temporary folder.
fn path(name: &str) -> &'static Path {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("fairfit_cargo_fuzz_{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder for the fuzz input");
        dir.join(name)
    })
}

/// Writes `data` to `file_name` and checks the outcome of `read` on it.
pub fn check<T>(data: &[u8], file_name: &str, read: impl Fn(&Path) -> fairfit::Result<T>) {
    if data.len() > MAX_INPUT {
        return;
    }
    let p = path(file_name);
    std::fs::write(p, data).expect("the fuzz input written");
    if let Err(e) = read(p) {
        let msg = e.to_string();
        assert!(!msg.is_empty(), "an empty error message");
        assert!(!msg.contains('\n'), "an error of more than one line: {msg:?}");
    }
}
