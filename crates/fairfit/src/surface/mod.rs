//! Surfaces from sections and point clouds: ordered sections (from files, or sliced out of meshes and
//! point clouds), made compatible on one shared knot vector with fair section curves, skinned into a
//! NURBS surface, and measured (orthogonal deviation, iso-curve fairness, net size).
//!
//! Files, one concept each: [`orient`] (sections, orientation, seams), [`section_fit`] (least squares on
//! fixed knots), [`compatible`] (the shared knot vector), [`skinning`], [`measure`], [`iso`],
//! [`pipeline`] (all steps together), plus private helpers.

pub mod chain;
pub mod compatible;
mod fairness_proxy;
pub mod iso;
mod linalg;
pub mod measure;
pub mod orient;
pub mod pipeline;
pub mod section_fit;
pub mod skinning;
pub mod slicing;

pub use compatible::{make_compatible, CompatibleOptions, CompatibleSections};
pub use fairness_proxy::{curve_fairness as span_fairness, CurveFairness};
pub use measure::{
    iso_fairness, surface_deviation, Deviation, IsoFairness, SurfaceFairness, SurfaceProjector,
};
pub use orient::{align_sections, Section};
pub use pipeline::{
    reconstruct_surface, reconstruct_surface_with_progress, validate_sections, Stage,
    SurfaceOptions, SurfaceReconstruction,
};
pub use skinning::{skin, Skin, SkinOptions, VParams};
