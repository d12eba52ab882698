//! The NURBS geometry core: vectors, knot vectors, basis functions, curves and surfaces, and the
//! knot operations that keep geometry exactly (insertion, refinement, degree elevation, reversal).
//!
//! Everything here follows *The NURBS Book* (Piegl & Tiller, 2nd ed.); algorithm numbers are cited in
//! each item's documentation. Written in-house because fairfit needs allocation-free batched evaluation
//! and exact rational derivatives that no maintained crate provides together.

pub mod basis;
mod circle;
mod clamp;
pub mod curve;
mod elevate;
mod insert;
mod iso_curve;
pub mod knots;
mod refine;
mod reparam;
pub mod scale;
pub mod surface;
mod surface_knot_ops;
mod surface_periodic;
pub mod vec3;

pub use curve::NurbsCurve;
pub use surface::{NurbsSurface, SurfaceWorkspace};
pub use vec3::Vec3;
