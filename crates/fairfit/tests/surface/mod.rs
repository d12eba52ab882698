//! Tests of `fairfit::surface`: skinning, the seam of closed surfaces, dense sections and the projection.
//!
//! One file per source module it tests (`src/surface/<name>.rs`).

mod cad_skin;
mod dense;
mod measure;
mod seam;
mod skinning;
