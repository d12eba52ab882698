//! Reading and writing: the fairfit JSON geometry format, point files, and file helpers shared by every
//! writer.

pub mod atomic;
pub mod json;
pub mod points;

pub use atomic::write_atomic;
pub use json::{curve_to_json, read_geometry, surface_to_json, Geometry};
pub use points::{read_points, PointSet};
