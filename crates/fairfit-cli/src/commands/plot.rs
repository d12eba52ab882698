//! `fairfit plot`.

use super::{CliError, CmdResult};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `fairfit plot`.
#[derive(Args, Debug)]
pub struct PlotArgs {
    /// Input file(s).
    pub input: Vec<PathBuf>,
}

/// Runs `fairfit plot`.
pub fn run(_args: PlotArgs) -> CmdResult {
    Err(CliError("`fairfit plot` is not implemented yet".into()))
}
