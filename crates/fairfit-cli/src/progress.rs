//! Progress bars on stderr, shown only when stderr is a terminal.
//!
//! A fit's own bars ([`bar`]) are hidden while `fairfit batch` runs ([`hide_fit_bars`]): its one bar
//! ([`batch_bar`]) counts the inputs instead.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether [`bar`] hides every bar (set once by `fairfit batch`).
static FIT_BARS_HIDDEN: AtomicBool = AtomicBool::new(false);

/// Hides every bar [`bar`] makes from now on.
pub fn hide_fit_bars() {
    FIT_BARS_HIDDEN.store(true, Ordering::Relaxed);
}

/// A progress bar of `len` steps with a message; hidden when stderr is not a terminal, or inside a
/// batch.
pub fn bar(len: u64, msg: &str) -> ProgressBar {
    if FIT_BARS_HIDDEN.load(Ordering::Relaxed) {
        return ProgressBar::hidden();
    }
    batch_bar(len, msg)
}

/// A progress bar of `len` steps with a message; hidden when stderr is not a terminal.
pub fn batch_bar(len: u64, msg: &str) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
    }
    let pb = ProgressBar::new(len);
    pb.set_style(
        ProgressStyle::with_template("{msg:20} [{bar:40}] {pos}/{len} {elapsed_precise}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    pb.set_message(msg.to_string());
    pb
}
