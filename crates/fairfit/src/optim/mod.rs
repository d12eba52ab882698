//! Particle swarm optimisation of knot vectors: the integrated fitting-and-fairing method.
//!
//! - [`encoding`]: interior knots as an always-valid particle position (softmax gaps, repair);
//! - [`objective`]: per candidate, least-squares control points, orthogonal deviation, fairness;
//! - [`pso`]: the deterministic, rayon-parallel particle swarm engine with local refinement;

// index loops over bands and spans read like the formulas they implement
#![allow(clippy::needless_range_loop)]

mod banded;
pub mod encoding;
pub mod objective;
pub mod pso;
