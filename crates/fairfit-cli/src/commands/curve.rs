//! `fairfit curve`.

use super::{CliError, CmdResult};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `fairfit curve`.
#[derive(Args, Debug)]
pub struct CurveArgs {
    /// Input file(s).
    pub input: Vec<PathBuf>,
}

/// Runs `fairfit curve`.
pub fn run(_args: CurveArgs) -> CmdResult {
    Err(CliError("`fairfit curve` is not implemented yet".into()))
}
