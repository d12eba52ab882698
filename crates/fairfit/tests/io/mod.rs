//! Tests of `fairfit::io`: the readers and writers of every file format, CAD chains and fits of CAD curves.
//!
//! One file per source module it tests (`src/io/<name>.rs`), except:
//! - `cad_roundtrip`: the STEP and IGES writers, read back by OpenCASCADE.
//! - `malformed_input`: every reader on hostile input.

mod cad_chain;
mod cad_check;
mod cad_conic;
mod cad_read;
mod cad_roundtrip;
mod malformed_input;
mod numbers;
mod step_edge;
mod tessellate;
