//! Tests of `fairfit::optim`: the integrated fitting-and-fairing method, stage by stage.
//!
//! One file per source module it tests (`src/optim/<name>.rs`).

mod band_curvature_tangent;
mod band_fairing;
mod closed;
mod corner_fit;
mod degree_candidates;
mod degree_search;
mod free_ends;
mod integrated;
mod periodic_fairing;
