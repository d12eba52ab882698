//! Reading and writing: the fairfit JSON geometry format, point and section files, meshes and point
//! clouds (read and write), CAD files (STEP, IGES), and file helpers shared by every writer.

pub mod atomic;
pub mod cad_check;
pub mod cad_common;
pub mod iges;
pub mod json;
pub mod mesh_read;
pub mod mesh_write;
pub mod points;
pub mod sections;
pub mod step;
pub mod tessellate;

pub use atomic::write_atomic;
pub use cad_common::LengthUnit;
pub use json::{curve_to_json, read_geometry, surface_to_json, Geometry};
pub use points::{read_points, PointSet};
