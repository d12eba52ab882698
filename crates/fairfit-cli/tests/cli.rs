//! The integration tests of the `fairfit` command line, one test binary whose modules mirror `src`:
//! `commands/<name>.rs` runs the subcommand implemented in `src/commands/<name>.rs` end to end, and
//! `contract` checks what every subcommand shares (usage errors, exit codes, one-line failures).
//! Helpers shared by several files live in `common` (used as `crate::common::...`).
//!
//! Run one file with a filter, e.g. `cargo test -p fairfit-cli --test cli commands::surface::`.

mod commands;
mod common;
mod contract;
