//! `fairfit info`.

use super::{CliError, CmdResult};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `fairfit info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Input file(s).
    pub input: Vec<PathBuf>,
}

/// Runs `fairfit info`.
pub fn run(_args: InfoArgs) -> CmdResult {
    Err(CliError("`fairfit info` is not implemented yet".into()))
}
