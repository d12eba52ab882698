//! Reading and writing: the fairfit JSON geometry format, point and section files, meshes and point
//! clouds (read and write), CAD files (STEP, IGES; written, and their B-splines read), and file helpers shared by every writer.
//!
//! io only reads and writes: what samples or fits the geometry it reads lives below it
//! ([`crate::fit::sampling`], [`crate::fit::cad_fit`], [`crate::surface::cad_skin`]), and the types it
//! fills ([`crate::surface::Mesh`], the point-set helpers of [`crate::fit::points`]) live with their users.

pub mod atomic;
pub mod cad_chain;
pub mod cad_check;
pub mod cad_common;
pub mod cad_conic;
pub mod cad_read;
pub mod cad_sections;
pub mod iges;
pub mod iges_read;
pub mod json;
pub mod limits;
pub mod lines;
pub mod mesh_read;
pub mod mesh_write;
pub mod numbers;
pub mod p21;
pub mod point_columns;
pub mod points;
pub mod samples;
pub mod sections;
pub mod step;
mod step_composite;
mod step_conic;
mod step_edge;
pub mod step_read;
pub mod tessellate;

pub use atomic::write_atomic;
pub use cad_common::LengthUnit;
pub use json::{curve_to_json, read_geometry, surface_to_json, Geometry};
pub use points::{read_points, PointSet};
