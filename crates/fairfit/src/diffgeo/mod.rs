//! Differential geometry of NURBS curves and surfaces: curvature (signed for planar curves), torsion,
//! dκ/ds with the guard for |C'×C''| → 0, arc length by Gauss-Legendre per knot span, closest-point
//! projection, and Gaussian and mean curvature of surfaces.

pub mod curvature;
pub mod projection;
pub mod surface_curvature;

pub use curvature::{curvature, differentials, is_xy_planar, CurveDifferentials};
pub use projection::{project_point, CurveProjector, Projection};
pub use surface_curvature::{surface_curvature, surface_curvature_from, SurfaceCurvature};
