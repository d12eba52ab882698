//! Tests of `fairfit::plot`: rendered plots.
//!
//! One file per source module it tests (`src/plot/<name>.rs`).

mod svg;
