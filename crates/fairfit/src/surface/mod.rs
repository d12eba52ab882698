//! Surfaces from sections and point clouds: ordered sections (from files, or sliced out of meshes and
//! point clouds), made compatible on one shared knot vector with fair section curves, skinned into a
//! NURBS surface, and measured (orthogonal deviation, iso-curve fairness, net size).
//!
//! Files, one concept each: [`orient`] (sections, orientation, seams), [`seam`] (smooth or C0 seams of closed sections),
//! a private periodic least-squares fit of closed sections, a private seam tie (smooth closed
//! sections on a clamped knot vector), [`section_fit`] (least squares on
//! fixed knots), [`section_corners`] (inner corners held as C0 knot lines), [`leading_edge`] (airfoil
//! sections' leading edges pinned to one parameter), [`compatible`] (the shared
//! knot vector), [`dense`] (dense sections screened and reduced, the tolerance verified on every
//! point), [`skinning`] (with [`skin_ends`]: v end tangents), [`measure`],
//! [`pipeline`] (all steps together), [`chain`] and [`slicing`] (meshes and clouds, [`mesh`], to sections; a private
//! thinning of a cloud's slabs to tolerance-sized clusters), [`cad_skin`] (surfaces held to
//! the exact CAD section curves), plus a private dense solver. Fairness
//! comes from [`crate::fair`], iso-curves from [`crate::nurbs::NurbsSurface`].

pub mod cad_skin;
pub mod chain;
pub mod compatible;
pub mod dense;
pub mod leading_edge;
mod linalg;
pub mod measure;
pub mod mesh;
pub mod orient;
mod periodic_fit;
pub mod pipeline;
mod point_grid;
pub mod seam;
mod seam_tie;
pub mod section_corners;
pub mod section_fit;
pub mod skin_ends;
pub mod skinning;
mod slab_cells;
pub mod slicing;

pub use compatible::{make_compatible, CompatibleOptions, CompatibleSections};
pub use dense::{DenseOptions, DenseSection, DenseSummary};
pub use leading_edge::{LeadingEdges, SectionLeadingEdge};
pub use measure::{surface_deviation, surface_deviation_near, Deviation, SurfaceProjector};
pub use mesh::Mesh;
pub use orient::{align_sections, Section};
pub use pipeline::{
    reconstruct_surface, reconstruct_surface_with_progress, validate_sections, Stage,
    SurfaceOptions, SurfaceReconstruction,
};
pub use seam::{periodic_seam, seam_continuity, seam_continuity_at, SeamContinuity};
pub use section_corners::HeldCorners;
pub use skin_ends::{max_v_tangent_angle, VEndTangents, VTangentCheck};
pub use skinning::{skin, Skin, SkinOptions, VParams};
