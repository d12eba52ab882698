//! Fairness metrics: the MVC energy E = ∫(dκ/ds)² ds integrated span by span, the scale-free F = L³·E and
//! its per-span parts F_j (Σ F_j = F), bending energy, counts of curvature extrema and inflections, and
//! the same measures on iso-parametric curves of surfaces.
//!
//! - [`energy`]: the MVC integrand at one parameter (signed planar or guarded spatial formula);
//! - [`evaluator`]: [`FairnessEvaluator`], the allocation-free adaptive span-by-span integrator used by
//!   the optimiser (`F`, `max F_j`, `F_j`);
//! - [`extrema`]: curvature extrema and inflections by sign changes above a scale-free noise floor;
//! - [`exact_extrema`]: the exact count of curvature extrema (the real roots of the `dκ/du`
//!   numerator per span, no sampling), on [`bernstein`] polynomials; rational and spatial curves
//!   through [`exact_nurbs`] on the numerators of [`curvature_numerators`] and the span
//!   hodographs of [`span_hodograph`]; [`exact_inflections`]: the same for planar inflections, and
//!   both counts in one pass ([`count_shape_exact`]);
//! - [`metrics`]: [`curve_fairness`], the full [`CurveFairness`] summary;
//! - [`surface`]: [`surface_fairness`], the metrics on iso-parametric curves in both directions;
//! - [`gram`]: Gram matrices of basis derivatives (parametric energies as quadratic forms);
//! - [`fairing`]: [`fair_curve`], the fit-then-fair baseline (Eck–Hadenfeld local energy fairing held
//!   to a tolerance).

pub mod bernstein;
pub mod curvature_numerators;
pub mod energy;
pub mod evaluator;
pub mod exact_extrema;
pub mod exact_inflections;
pub mod exact_nurbs;
pub mod extrema;
pub mod fairing;
pub mod gram;
pub mod metrics;
pub mod span_hodograph;
pub mod surface;

pub use evaluator::{EvaluatorOptions, FairnessEvaluator, SpanIntegrals};
pub use exact_extrema::{count_extrema_exact, ExactExtrema};
pub use exact_inflections::{
    count_inflections_exact, count_shape_exact, ExactInflections, ExactShape,
};
pub use extrema::{count_extrema, count_extrema_sampled, try_count_extrema, ExtremaCounts};
pub use fairing::{fair_curve, FairingOptions, FairingResult};
pub use metrics::{curve_fairness, try_curve_fairness, CurveFairness};
pub use surface::{surface_fairness, IsoCurveFairness, SurfaceFairness, DEFAULT_ISO_CURVES};
