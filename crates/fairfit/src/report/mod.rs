//! What a fit reports and how its files are made: the `--report` JSON of curve and surface fits
//! ([`curve`], [`surface`], a curve's [`end_conditions`] and [`point_constraints`]), a chain's
//! joined curve and report ([`chain`]) and the bytes of every output file, the format chosen by the
//! file's extension or by the caller ([`files`]).
//!
//! The command-line tool and the Python package both build their reports and files here, so the same
//! fit gives the same bytes through either. Nothing here writes a file or prints: callers write the
//! bytes (all or none, see [`crate::io::atomic`]).
//!
//! The top layer below the prelude: it reads the results of [`crate::fit`], [`crate::optim`] and
//! [`crate::surface`] and formats them with [`crate::io`] and [`crate::plot`].

pub mod chain;
pub mod curve;
pub mod end_conditions;
pub mod files;
pub mod point_constraints;
pub mod surface;
