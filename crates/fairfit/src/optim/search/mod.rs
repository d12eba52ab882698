//! The search layer: the swarm machinery and the per-candidate objectives, agnostic of the
//! pipeline that uses them.
//!
//! - [`prepare`]: scale-free normalisation, centripetal parameters, baseline averaging knots;
//! - [`objective`]: per candidate, least-squares control points, orthogonal deviation, fairness;
//! - [`encoding`]: interior knots as an always-valid particle position (softmax gaps, repair);
//! - [`problem`]: the open knot search as a swarm problem (feasibility-first ε-constraint
//!   fitness), and `problem::CountProblem`, the knot search at one count of either kind;
//! - [`periodic`]: per-candidate objectives and the swarm problem of a periodic (closed) curve;
//! - [`pso`]: the deterministic, rayon-parallel particle swarm engine with local refinement;
//! - [`mopso`]: the multi-objective swarm and Pareto archive for (max deviation, F) trade-offs;
//! - [`smoothing`]: a line search on the smoothing weight for fixed knots;
//! - `knot_edits`: knot removals and insertions and the least-squares method's knots, shared by
//!   the open and periodic kinds;
//! - `residual_knots`: FITPACK-style knots where the least-squares residuals are largest.

pub mod encoding;
pub(crate) mod knot_edits;
pub mod mopso;
pub mod objective;
pub mod periodic;
pub mod prepare;
pub mod problem;
pub mod pso;
pub(crate) mod residual_knots;
pub mod smoothing;
