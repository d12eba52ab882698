//! Differential geometry of NURBS curves and surfaces: curvature (signed for planar curves), torsion,
//! dκ/ds with the guard for |C'×C''| → 0, arc length by Gauss-Legendre per knot span, closest-point
//! projection, and Gaussian and mean curvature of surfaces.

pub mod arc_length;
pub mod curvature;
pub mod projection;
pub mod quadrature;
pub mod surface_curvature;

pub use arc_length::{arc_length, arc_length_between, span_arc_lengths};
pub use curvature::{
    curvature, differentials, differentials_from, is_xy_planar, CurveDifferentials,
    REGULAR_SPEED_EPS,
};
pub use projection::{project_point, CurveProjector, Projection};
pub use surface_curvature::{surface_curvature, surface_curvature_from, SurfaceCurvature};
