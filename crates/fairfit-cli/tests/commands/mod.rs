//! One file per subcommand module of `src/commands`, each running the `fairfit` binary end to end.
//! `cad_input` holds the CAD files (STEP, IGES) as input of every subcommand, `curve_optim` the
//! integrated method of `fairfit curve`.

mod batch;
mod cad_input;
mod curve;
mod curve_optim;
mod eval;
mod export;
mod hostile;
mod info;
mod outputs;
mod surface;
