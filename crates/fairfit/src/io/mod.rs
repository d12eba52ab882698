//! Reading and writing: the fairfit JSON geometry format, file helpers shared by every writer, section
//! files and meshes / point clouds.

pub mod atomic;
pub mod json;
pub mod mesh_read;
pub mod sections;

pub use atomic::write_atomic;
pub use json::{curve_to_json, read_geometry, surface_to_json, Geometry};
