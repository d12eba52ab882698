//! `fairfit eval`.

use super::{CliError, CmdResult};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `fairfit eval`.
#[derive(Args, Debug)]
pub struct EvalArgs {
    /// Input file(s).
    pub input: Vec<PathBuf>,
}

/// Runs `fairfit eval`.
pub fn run(_args: EvalArgs) -> CmdResult {
    Err(CliError("`fairfit eval` is not implemented yet".into()))
}
