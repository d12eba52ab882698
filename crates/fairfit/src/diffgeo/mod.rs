//! Differential geometry of NURBS curves and surfaces: curvature (signed for planar curves), torsion,
//! dκ/ds with the guard for |C'×C''| → 0, arc length by Gauss-Legendre per knot span, closest-point
//! projection, and Gaussian and mean curvature of surfaces.
