//! Tests of `fairfit::surface`: skinning, the seam of closed surfaces, dense sections, the projection
//! and the slicing of dense clouds.
//!
//! One file per source module it tests (`src/surface/<name>.rs`).

mod cad_skin;
mod corners;
mod dense;
mod leading_edge;
mod measure;
mod orient;
mod seam;
mod skin_ends;
mod skinning;
mod slicing;
