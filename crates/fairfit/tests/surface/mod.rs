//! Tests of `fairfit::surface`: skinning, the seam of closed surfaces and dense sections.
//!
//! One file per source module it tests (`src/surface/<name>.rs`).

mod cad_skin;
mod dense;
mod seam;
mod skinning;
