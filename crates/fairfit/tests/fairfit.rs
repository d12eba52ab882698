//! The integration tests of the `fairfit` library, one test binary whose modules mirror `src`:
//! `tests/<layer>/<module>.rs` tests `src/<layer>/<module>.rs`. Helpers shared by several files live
//! in `common` (used as `crate::common::...`); `regression` holds the golden results of whole fits.
//!
//! Run one layer or file with a filter, e.g. `cargo test -p fairfit --test fairfit optim::closed::`.

mod architecture;
mod common;

mod diffgeo;
mod fair;
mod fit;
mod io;
mod nurbs;
mod optim;
mod plot;
mod regression;
mod surface;

/// The benchmark's own Python tests (`bench/`), not a module of `src`.
mod bench_scripts;
