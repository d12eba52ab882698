//! Tests of `fairfit::diffgeo`: closest-point projection.
//!
//! One file per source module it tests (`src/diffgeo/<name>.rs`).

mod projection;
