//! Tests of `fairfit::surface`: skinning and the seam of closed surfaces.
//!
//! One file per source module it tests (`src/surface/<name>.rs`).

mod cad_skin;
mod seam;
mod skinning;
