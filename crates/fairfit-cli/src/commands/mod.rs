//! One module per subcommand; each exposes its clap `Args` struct and `run`.

pub mod curve;
pub mod curve_optim;
pub mod eval;
pub mod export;
pub mod info;
pub mod outputs;
pub mod plot;
pub mod surface;

/// What a subcommand returns: the library's typed error, or a CLI-level message.
pub type CmdResult = Result<(), CliError>;

/// An error to print as one line.
#[derive(Debug)]
pub struct CliError(pub String);

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl From<fairfit::Error> for CliError {
    fn from(e: fairfit::Error) -> Self {
        CliError(e.to_string())
    }
}

impl From<String> for CliError {
    fn from(s: String) -> Self {
        CliError(s)
    }
}

impl From<&str> for CliError {
    fn from(s: &str) -> Self {
        CliError(s.to_string())
    }
}

/// Prints a JSON value to stdout (pretty).
#[allow(dead_code)]
pub fn print_json(v: &serde_json::Value) {
    println!(
        "{}",
        serde_json::to_string_pretty(v).unwrap_or_else(|_| "null".into())
    );
}
