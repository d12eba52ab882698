//! `fairfit surface`.

use super::{CliError, CmdResult};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `fairfit surface`.
#[derive(Args, Debug)]
pub struct SurfaceArgs {
    /// Input file(s).
    pub input: Vec<PathBuf>,
}

/// Runs `fairfit surface`.
pub fn run(_args: SurfaceArgs) -> CmdResult {
    Err(CliError("`fairfit surface` is not implemented yet".into()))
}
