//! Particle swarm optimisation of knot vectors: the integrated fitting-and-fairing method.
//!
//! - [`closed`]: closed data: periodic fits without corners, a cut at the first corner otherwise;
//! - [`periodic`]: per-candidate objectives and the swarm problem of a periodic (closed) curve;
//! - [`periodic_fairing`]: band fairing and polish of a periodic curve (seam kept `C^(p−1)`);
//! - [`corner_fit`]: the integrated method on the pieces between corners, with a shared control-point
//!   budget;
//! - [`corners`]: splitting at corner points and joining the pieces C0;
//! - [`count_search`]: the full knot search and the extra-control-point rule, open and periodic;
//! - `descent`: the second start of an open curve's count descent (the count search's restart seeds);
//! - [`encoding`]: interior knots as an always-valid particle position (softmax gaps, repair);
//! - [`objective`]: per candidate, least-squares control points, orthogonal deviation, fairness;
//! - [`pso`]: the deterministic, rayon-parallel particle swarm engine with local refinement;
//! - [`problem`]: the knot search as a swarm problem (feasibility-first ε-constraint fitness);
//! - [`polish`]: local control-point fairing moves after the knot search, within the tolerance;
//! - [`control_map`]: the control points the fairing stages move (open: interior; periodic: distinct);
//! - [`band_fairing`]: all control points faired together inside the tolerance band (sequential
//!   convex programming with second-order cones);
//! - [`band_qp`]: band fairing's convex subproblem and its general (clarabel) solver;
//! - [`cone_ipm`]: a dense primal–dual interior-point solver for that subproblem's shape;
//! - [`cone_algebra`]: the second-order cone's Jordan algebra, NT scaling, a small Cholesky;
//! - [`curvature_signs`]: the sign pattern of `dκ/ds` band fairing keeps (low-persistence curvature
//!   extrema removed);
//! - `residual_knots`: FITPACK-style knots where the least-squares residuals are largest;
//! - [`smoothing`]: a line search on the smoothing weight for fixed knots;
//! - [`prepare`]: scale-free normalisation, centripetal parameters, baseline averaging knots;
//! - [`integrated`]: [`integrated::fit_integrated`], the count search and the full knot search.
//! - `knot_edits`: knot removals and insertions, the least-squares method's knots and the
//!   descent's swarm probe, shared by open and periodic searches;
//! - [`degree_search`]: the integrated fit at several degrees and the rule that keeps one
//!   (`--degree auto`);
//! - [`degree_candidates`]: the higher degrees at the reference's count and knots (staged search);
//! - [`mopso`]: the multi-objective swarm and Pareto archive for (max deviation, F) trade-offs;
//! - [`pareto`]: the Pareto front of curves for `--pareto`;
//! - [`pareto_joined`]: the front of the returned curve, joined from the pieces' fronts at corners;
//! - [`pareto_periodic`]: the front of a periodic closed curve.
//! - [`options`]: [`IntegratedOptions`] (the builder of the user's settings), [`Budget`], validation;
//! - [`progress`]: the typed progress [`Stage`];
//! - `entry`: [`fit_integrated_with_stages`], the entry point with typed progress;
//! - `result_access`: reading an [`IntegratedResult`] ([`IntegratedResult::log10_smoothing`]).
//!
//! The public API is re-exported here (and through [`crate::prelude`]): [`fit_integrated`],
//! [`fit_integrated_with_stages`], [`IntegratedOptions`], [`Budget`], [`Stage`], [`IntegratedResult`]
//! and what it holds, the Pareto front, and the closed-curve helpers.

// index loops over bands and spans read like the formulas they implement
#![allow(clippy::needless_range_loop)]

pub mod band_fairing;
pub mod band_qp;
pub mod closed;
pub mod cone_algebra;
pub mod cone_ipm;
pub(crate) mod cone_newton;
pub mod control_map;
pub mod corner_fit;
pub mod corners;
pub mod count_search;
pub mod curvature_signs;
pub mod degree_candidates;
pub mod degree_search;
pub(crate) mod descent;
pub mod encoding;
mod entry;
pub mod free_ends;
pub mod integrated;
pub(crate) mod knot_edits;
pub mod mopso;
pub mod objective;
pub mod options;
pub mod pareto;
pub mod pareto_joined;
pub mod pareto_periodic;
pub mod periodic;
pub mod periodic_fairing;
pub mod polish;
pub mod prepare;
pub mod problem;
pub mod progress;
pub mod pso;
pub(crate) mod residual_knots;
mod result_access;
pub mod smoothing;

pub use crate::fit::tolerance::ClosedMode;
pub use crate::tolerance::Tolerance;
pub use closed::{distinct_control_points, is_closed};
pub use control_map::EndCondition;
pub use degree_search::DegreeTrial;
pub use entry::fit_integrated_with_stages;
pub use integrated::{
    fit_integrated, fit_integrated_with_progress, fit_lsq_baseline, FitQuality, IntegratedResult,
    OptimStats,
};
pub use options::{Budget, IntegratedOptions, NonExhaustive};
pub use pareto::{pareto_csv, ParetoCurve};
pub use pareto_joined::pareto_front_of_result;
pub use progress::Stage;
