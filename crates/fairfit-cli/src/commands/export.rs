//! `fairfit export`.

use super::{CliError, CmdResult};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `fairfit export`.
#[derive(Args, Debug)]
pub struct ExportArgs {
    /// Input file(s).
    pub input: Vec<PathBuf>,
}

/// Runs `fairfit export`.
pub fn run(_args: ExportArgs) -> CmdResult {
    Err(CliError("`fairfit export` is not implemented yet".into()))
}
