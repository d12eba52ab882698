//! Progress bars on stderr, shown only when stderr is a terminal.
//!
//! A curve fit shows its stage ([`FitBar`], or [`with_spinner`] for the methods without stages) once
//! it has run for about a second. A fit's own bars are hidden while `fairfit batch` runs
//! ([`hide_fit_bars`]): its one bar ([`batch_bar`]) counts the inputs instead.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

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

/// How long a fit runs before its bar appears: a fit that ends sooner shows nothing.
const SHOW_AFTER: Duration = Duration::from_secs(1);

/// The bar of one curve fit: hidden until the fit has run for [`SHOW_AFTER`], then the stage's name
/// and its `done` of `total` steps on stderr (only when stderr is a terminal, never in a batch).
pub struct FitBar {
    bar: ProgressBar,
    start: Instant,
    /// Whether the bar may ever be drawn (a terminal, no batch).
    visible: bool,
    shown: AtomicBool,
}

impl FitBar {
    /// A bar not drawn yet.
    pub fn new() -> Self {
        let visible = !FIT_BARS_HIDDEN.load(Ordering::Relaxed) && std::io::stderr().is_terminal();
        let bar = ProgressBar::with_draw_target(Some(1), ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template("{msg:28} [{bar:30}] {pos}/{len} {elapsed_precise}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        FitBar {
            bar,
            start: Instant::now(),
            visible,
            shown: AtomicBool::new(false),
        }
    }

    /// Reports `stage` at `done` of `total`; draws the bar once the fit has run long enough.
    pub fn update(&self, stage: impl std::fmt::Display, done: usize, total: usize) {
        if !self.visible {
            return;
        }
        if !self.shown.load(Ordering::Relaxed) {
            if self.start.elapsed() < SHOW_AFTER || self.shown.swap(true, Ordering::Relaxed) {
                return;
            }
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.bar.enable_steady_tick(Duration::from_millis(200));
        }
        self.bar.set_message(stage.to_string());
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
    }

    /// Clears the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// Runs `f` with a spinner named `what` on stderr once it has run for [`SHOW_AFTER`] (only when
/// stderr is a terminal, never in a batch): for the fits that report no stages.
pub fn with_spinner<T>(what: &str, f: impl FnOnce() -> T) -> T {
    if FIT_BARS_HIDDEN.load(Ordering::Relaxed) || !std::io::stderr().is_terminal() {
        return f();
    }
    let (done, wait) = std::sync::mpsc::channel::<()>();
    let what = what.to_string();
    let spinner = std::thread::spawn(move || {
        if wait.recv_timeout(SHOW_AFTER).is_ok() {
            return;
        }
        let pb = ProgressBar::new_spinner();
        pb.set_message(what);
        pb.enable_steady_tick(Duration::from_millis(120));
        let _ = wait.recv();
        pb.finish_and_clear();
    });
    let out = f();
    let _ = done.send(());
    let _ = spinner.join();
    out
}
