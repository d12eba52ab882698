//! Reading and writing: the fairfit JSON geometry format and file helpers shared by every writer.

pub mod atomic;
pub mod json;

pub use atomic::write_atomic;
pub use json::{curve_to_json, read_geometry, surface_to_json, Geometry};
