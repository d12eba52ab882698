//! Tests of `fairfit::fair`: fairness metrics, exact extrema and inflections, the fairness evaluator, Eck–Hadenfeld fairing.
//!
//! One file per source module it tests (`src/fair/<name>.rs`), except:
//! - `knot_invariance`: exact knot operations keep the fairness measures.

mod evaluator;
mod exact_extrema;
mod exact_nurbs;
mod fairing;
mod knot_invariance;
mod metrics;
