//! Tests of `fairfit::fit`: the least-squares tolerance fit and its hook guard.
//!
//! One file per source module it tests (`src/fit/<name>.rs`).

mod cad_fit;
mod closure;
mod corners;
mod end_constraints;
mod hooks;
mod noise;
mod outliers;
mod point_constraints;
mod screening;
mod tolerance;
