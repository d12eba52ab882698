//! Tests of `fairfit::optim`: the integrated fitting-and-fairing method, stage by stage.
//!
//! One file per source module it tests (`src/optim/<name>.rs`).

mod chain;
mod closed;
mod cornered;
mod fairing;
mod pipeline;
mod stages;
