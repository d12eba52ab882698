//! One module per subcommand; each exposes its clap `Args` struct and `run`. `files` holds the rules
//! for output paths and the all-or-nothing commit, `messages` the one-line form of what reaches stderr.

/// Queues a `warning: ...` or `note: ...` line for stderr (see [`messages`]): printed when the run
/// succeeds; on failure the warnings are folded into the one error line.
macro_rules! diag {
    ($($t:tt)*) => {
        $crate::commands::messages::diagnostic(format!($($t)*))
    };
}

pub mod batch;
pub mod cad_input;
pub mod curve;
pub mod curve_args;
pub mod curve_chain;
pub mod curve_ends;
pub mod curve_optim;
pub mod curve_points;
pub mod eval;
pub mod export;
pub mod files;
pub mod info;
pub mod messages;
pub mod outputs;
pub mod plot;
pub mod surface;
pub mod threads;
pub mod work;

/// What a subcommand returns: the library's typed error, or a CLI-level message.
pub type CmdResult = Result<(), CliError>;

/// An error to print as one line: a usage error (an option value or combination the command does not
/// accept; exit code 2, the line points at the subcommand's `--help`) or a failure of the run itself
/// (unreadable or invalid input, failed writes; exit code 1).
#[derive(Debug)]
pub struct CliError {
    /// The message, without the leading `error: `.
    pub message: String,
    /// Whether the user asked for something the command does not accept (exit code 2).
    pub usage: bool,
}

impl CliError {
    /// A failure of the run (exit code 1).
    pub fn new(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            usage: false,
        }
    }

    /// A usage error: an option value or combination the command does not accept (exit code 2).
    pub fn usage(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
            usage: true,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// The library's option errors (an invalid option value or combination, a refused setting) are usage
/// errors; everything else is a failure of the run.
impl From<fairfit::Error> for CliError {
    fn from(e: fairfit::Error) -> Self {
        match e {
            fairfit::Error::InvalidOption(_) | fairfit::Error::InvalidSetting { .. } => {
                CliError::usage(e.to_string())
            }
            _ => CliError::new(e.to_string()),
        }
    }
}

impl From<String> for CliError {
    fn from(s: String) -> Self {
        CliError::new(s)
    }
}

impl From<&str> for CliError {
    fn from(s: &str) -> Self {
        CliError::new(s)
    }
}

/// Writes `bytes` on stdout, with a newline after text that does not end with one.
pub fn write_stdout(bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)?;
    if std::str::from_utf8(bytes).is_ok() && !bytes.ends_with(b"\n") {
        out.write_all(b"\n")?;
    }
    out.flush()
}

/// Fails (one line) when the measure `what` of a result is not a finite number: outputs hold finite
/// numbers or are not written.
pub fn finite(what: &str, x: f64) -> Result<f64, CliError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(CliError::new(format!(
            "the {what} cannot be computed as a finite number at this geometry's scale (got {x}); \
             nothing was written; rescale the input"
        )))
    }
}

/// Prints `text` and a newline on stdout. A closed stdout (the reader, e.g. `head`, wanted no more)
/// ends the process quietly with exit code 0: every subcommand prints only after its files are written.
/// Any other write failure is an error.
pub fn print_stdout(text: &str) -> CmdResult {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let written = out
        .write_all(text.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush());
    match written {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(CliError::new(format!("cannot write to stdout: {e}"))),
    }
}

/// Prints a JSON value on stdout (pretty, negative zeros as 0, see [`json_pretty`]), as
/// [`print_stdout`].
pub fn print_json(v: &serde_json::Value) -> CmdResult {
    print_stdout(&json_pretty(v)?)
}

/// The pretty JSON text of `v` with every negative zero written as `0.0`: `-0.0` (e.g. the Gaussian
/// curvature `-(0 · x)` of a flat patch) means the same number and only confuses readers and `diff`.
pub fn json_pretty(v: &serde_json::Value) -> Result<String, CliError> {
    let mut v = v.clone();
    fairfit::io::numbers::clear_negative_zeros(&mut v);
    serde_json::to_string_pretty(&v)
        .map_err(|e| CliError::new(format!("internal: cannot format JSON: {e}")))
}

/// How far exact CAD geometry lies from what was fitted to its samples, for [`note_exact_deviation`]
/// (from `fairfit::fit::cad_fit::ExactFit` or `fairfit::surface::cad_skin::ExactSkin`).
pub struct ExactDeviation {
    /// The largest distance of the checked points of the exact geometry.
    pub max_deviation: f64,
    /// The tolerance asked for.
    pub tolerance: f64,
    /// Whether the exact geometry is within the tolerance.
    pub met: bool,
    /// How many points of the exact geometry were checked.
    pub checked: usize,
    /// Refits with points of the exact geometry added.
    pub refits: usize,
    /// The points added.
    pub added: usize,
    /// The largest distance after the first fit.
    pub first_max_deviation: f64,
    /// The tolerance of the last refit.
    pub fit_tolerance: f64,
}

/// The note on stderr on how far `exact` (e.g. "the exact curve"; `plural` for "the exact sections")
/// lies from `near` (what it was checked against) and the warning when it strays beyond the tolerance
/// from `the {fitted}` (the fit or the surface).
pub fn note_exact_deviation(
    path: &std::path::Path,
    exact: &str,
    plural: bool,
    fitted: &str,
    near: &str,
    d: &ExactDeviation,
) {
    let (lie, stray, them) = if plural {
        ("lie", "stray", "them")
    } else {
        ("lies", "strays", "it")
    };
    let refits = if d.refits == 0 {
        String::new()
    } else {
        format!(
            "; the first {fitted} let {them} stray {:.4} of the tolerance: {} refit(s) with {} points \
             of {exact} added, the last at the tolerance {:.3e}",
            d.first_max_deviation / d.tolerance,
            d.refits,
            d.added,
            d.fit_tolerance,
        )
    };
    diag!(
        "note: {}: {exact} {lie} within {:.3e} of {near} ({:.4} of the tolerance; {} points of {them} \
         checked){refits}",
        path.display(),
        d.max_deviation,
        d.max_deviation / d.tolerance,
        d.checked
    );
    if !d.met {
        diag!(
            "warning: {exact} {stray} {:.3e} from the {fitted}, beyond the tolerance {:.3e}",
            d.max_deviation,
            d.tolerance
        );
    }
}

/// clap value parser: a whole number `>= 0` (a count), with a message that says so for `-1` or `2.5`
/// (clap's own is "invalid digit found in string").
pub fn whole_number(s: &str) -> Result<usize, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("expected a whole number >= 0, got {s}"))
}

/// clap value parser: a whole number in `0..=u64::MAX` (a seed), as [`whole_number`].
pub fn whole_number_u64(s: &str) -> Result<u64, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("expected a whole number from 0 to {}, got {s}", u64::MAX))
}

/// clap value parser: a finite number `>= 0` (NaN and infinities are refused up front, even for
/// options the chosen method does not use).
pub fn finite_non_negative(s: &str) -> Result<f64, String> {
    let x: f64 = s.trim().parse().map_err(|e| format!("{e}"))?;
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("expected a finite number >= 0, got {s}"))
    }
}

/// clap value parser: a finite number `> 0`.
pub fn finite_positive(s: &str) -> Result<f64, String> {
    let x: f64 = s.trim().parse().map_err(|e| format!("{e}"))?;
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(format!("expected a finite number > 0, got {s}"))
    }
}

/// clap value parser: a turning angle in degrees, in `(0, 180]` (the library's
/// [`check_corner_angle`](fairfit::fit::shape::check_corner_angle)).
pub fn corner_angle(s: &str) -> Result<f64, String> {
    let x: f64 = s.trim().parse().map_err(|e| format!("{e}"))?;
    fairfit::fit::shape::check_corner_angle(x).map_err(setting_reason)
}

/// What is wrong with a setting the library refused ([`fairfit::Error::InvalidSetting`]'s reason,
/// which reads after the setting's name); any other error as it prints.
pub fn setting_reason(e: fairfit::Error) -> String {
    match e {
        fairfit::Error::InvalidSetting { reason, .. } => reason,
        e => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn negative_zeros_become_zero_at_any_depth_and_nothing_else_changes() {
        let v = serde_json::json!({"a": -0.0, "b": [1.5, -0.0, {"c": -0.0, "d": -2.0}], "e": 0, "f": "-0.0"});
        let text = json_pretty(&v).unwrap();
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(
            back,
            serde_json::json!({"a": 0.0, "b": [1.5, 0.0, {"c": 0.0, "d": -2.0}], "e": 0, "f": "-0.0"})
        );
        // the value compares equal either way: check the sign on the text
        assert_eq!(text.matches("-0.0").count(), 1, "{text}"); // only the string
        assert!(text.contains("-2.0"));
    }
}
