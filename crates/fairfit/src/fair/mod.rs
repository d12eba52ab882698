//! Fairness metrics: the MVC energy E = ∫(dκ/ds)² ds integrated span by span, the scale-free F = L³·E and
//! its per-span parts F_j (Σ F_j = F), bending energy, counts of curvature extrema and inflections, and
//! the same measures on iso-parametric curves of surfaces.
