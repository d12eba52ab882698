//! Fairing a knot vector's control points inside the tolerance band.

pub mod band;
pub mod band_qp;
pub mod cone_algebra;
pub mod cone_ipm;
pub(crate) mod cone_newton;
pub mod control_map;
pub mod curvature_signs;
pub mod periodic;
pub mod polish;
