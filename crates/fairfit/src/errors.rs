//! The typed errors of the fairfit library.
//!
//! Every fallible public function returns [`Result<T>`]. Messages are one line, name what is wrong and,
//! where it helps, what would be right, so the command-line tool can print them as they are.
//!
//! A failed allocation is an error too where a buffer grows with the input (samples per knot span,
//! mesh vertices): [`try_vec`] reserves such a buffer fallibly, so that a run short of memory ends
//! with one line ([`Error::out_of_memory`]) instead of an abort. Every layer may use it.

use thiserror::Error;

/// Everything that can go wrong in fairfit.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// The degree is not usable (zero, or too high for the number of control points).
    #[error("invalid degree {degree}: {reason}")]
    InvalidDegree {
        /// The degree that was given.
        degree: usize,
        /// Why it is not usable.
        reason: String,
    },
    /// The knot vector has the wrong length, decreases, holds a non-finite value, or spans a range beyond
    /// the floating-point limits (too long or too short to evaluate).
    #[error("invalid knot vector: {0}")]
    InvalidKnots(String),
    /// A weight is zero, negative, non-finite, or the count does not match the control points.
    #[error("invalid weights: {0}")]
    InvalidWeights(String),
    /// A control point is non-finite, or the net is empty or ragged.
    #[error("invalid control points: {0}")]
    InvalidControlPoints(String),
    /// A curve or surface parameter lies outside the domain.
    #[error("parameter {value} is outside the domain [{min}, {max}]")]
    ParameterOutOfDomain {
        /// The parameter given.
        value: f64,
        /// Start of the domain.
        min: f64,
        /// End of the domain.
        max: f64,
    },
    /// A JSON document could not be read; the message names the field. Displayed on one line:
    /// control characters the document put in a key or value (a `\n` escape) are escaped.
    #[error("invalid JSON: {}", printable(.0))]
    Json(String),
    /// A file could not be read or written; the message names the path.
    #[error("{path}: {message}")]
    Io {
        /// The file concerned.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// Input data (points, sections) are unusable; the message names file and line where known.
    #[error("invalid input data: {0}")]
    InvalidData(String),
    /// A fit could not be computed (ill-posed system, tolerance unreachable, ...).
    #[error("fitting failed: {0}")]
    Fit(String),
    /// A knot operation (insertion, refinement, degree elevation, reparametrisation) cannot be done as
    /// asked: parameter outside the domain, multiplicity above the degree, bad target interval.
    #[error("knot operation not possible: {0}")]
    KnotOperation(String),
    /// An option value is out of range.
    #[error("invalid option: {0}")]
    InvalidOption(String),
    /// A setting of the integrated method is out of range, or does not fit the others; `option` names
    /// it as the [`IntegratedOptions`](crate::optim::IntegratedOptions) method that sets it (e.g.
    /// `control_points`), so that a caller can point at its own name for it (the command-line tool
    /// names its flag).
    #[error("invalid option {option}: {reason}")]
    InvalidSetting {
        /// The setting, as the builder method of `IntegratedOptions` that sets it.
        option: &'static str,
        /// What is wrong with its value.
        reason: String,
    },
    /// A STEP or IGES file cannot be read, or holds no geometry fairfit reads; the message names the
    /// file (when read from one), where in it, and what to do.
    #[error("{0}")]
    Cad(String),
}

/// Shorthand for results carrying an [`Error`](enum@Error).
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// An [`Error::Io`] for `path` from a [`std::io::Error`].
    pub fn io(path: impl AsRef<std::path::Path>, err: &std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().display().to_string(),
            message: err.to_string(),
        }
    }

    /// The error of an allocation of `bytes` for `what` that failed (an [`Error::InvalidData`]:
    /// the input asks for more memory than there is).
    pub fn out_of_memory(what: &str, bytes: u64) -> Self {
        Error::InvalidData(format!(
            "{what}: not enough memory for {} MiB",
            bytes.div_ceil(1024 * 1024)
        ))
    }
}

/// A vector with room for `n` items, or [`Error::out_of_memory`] for `what` when that much memory
/// is not available (never an abort; a size beyond the address space fails the same way).
pub fn try_vec<T>(n: usize, what: &str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        Error::out_of_memory(what, (n as u64).saturating_mul(size_of::<T>() as u64))
    })?;
    Ok(v)
}

/// `text` with its control characters escaped (`\n`, `\r`, `\t`, `\u{1b}`): an error message quoting
/// what an input holds stays one line.
fn printable(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out
}
