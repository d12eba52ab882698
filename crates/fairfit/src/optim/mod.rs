//! Particle swarm optimisation of knot vectors: the integrated fitting-and-fairing method.
//!
//! - [`corners`]: splitting at corner points and joining the pieces C0;
//! - [`encoding`]: interior knots as an always-valid particle position (softmax gaps, repair);
//! - [`objective`]: per candidate, least-squares control points, orthogonal deviation, fairness;
//! - [`pso`]: the deterministic, rayon-parallel particle swarm engine with local refinement;
//! - [`problem`]: the knot search as a swarm problem (feasibility-first ε-constraint fitness);
//! - [`polish`]: local control-point fairing moves after the knot search, within the tolerance;
//! - [`band_fairing`]: all control points faired together inside the tolerance band (sequential
//!   convex programming with second-order cones);
//! - [`smoothing`]: a line search on the smoothing weight for fixed knots;
//! - [`prepare`]: scale-free normalisation, centripetal parameters, baseline averaging knots;
//! - [`integrated`]: [`integrated::fit_integrated`], the count search and the full knot search.
//! - [`mopso`]: the multi-objective swarm and Pareto archive for (max deviation, F) trade-offs;
//! - [`pareto`]: the Pareto front of curves for `--pareto`.

// index loops over bands and spans read like the formulas they implement
#![allow(clippy::needless_range_loop)]

pub mod band_fairing;
pub mod corners;
pub mod encoding;
pub mod integrated;
pub mod mopso;
pub mod objective;
pub mod pareto;
pub mod polish;
pub mod prepare;
pub mod problem;
pub mod pso;
pub mod smoothing;
