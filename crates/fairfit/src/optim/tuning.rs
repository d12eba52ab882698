//! The measured thresholds of the integrated method's policy, in one value nested per stage
//! ([`Tuning`]). Every field says what it decides; its default is the value the method was
//! measured with (the measurements are in the tuning ledger of `docs/optim.md`). Changing a
//! default changes the output.
//!
//! Numerical constants of the math (solver tolerances, sampling densities) are not here: they
//! stay with the code they belong to.

use super::options::IntegratedOptions;
use super::search::pso::PsoOptions;

/// Every measured threshold of the method, per stage.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Tuning {
    /// The particle swarm's settings in the descent, the count search and the degree search.
    pub swarm: SwarmTuning,
}

/// The swarm settings of the knot searches (the count descent's probes, the count search's full
/// searches, the degree search's short searches). These are the method's own settings, not
/// [`PsoOptions::default`]'s.
#[derive(Clone, Debug, PartialEq)]
pub struct SwarmTuning {
    /// Iterations without a relative improvement of [`Self::stall_rel`] after which a full
    /// search stops (a probe runs all its iterations). Default 10.
    pub stall_iterations: usize,
    /// Relative improvement of the best fitness that resets the stall counter. Default `1e-4`.
    pub stall_rel: f64,
    /// Spread of the particles started around a seed, as a fraction of each coordinate's range:
    /// the searches stay close to their seeds. Default 0.03.
    pub seed_spread: f64,
    /// Fraction of the non-seed particles placed uniformly at random. Default 0.1.
    pub random_fraction: f64,
}

impl Default for SwarmTuning {
    fn default() -> Self {
        SwarmTuning {
            stall_iterations: 10,
            stall_rel: 1e-4,
            seed_spread: 0.03,
            random_fraction: 0.1,
        }
    }
}

impl SwarmTuning {
    /// The swarm settings of one knot search under `opts`: a short probe (stops at the first
    /// feasible position, no refinement) or the full search of `iterations`; `salt` separates
    /// the random streams of different searches of one seed.
    pub(crate) fn options(
        &self,
        opts: &IntegratedOptions,
        iterations: usize,
        probe: bool,
        salt: u64,
    ) -> PsoOptions {
        PsoOptions {
            particles: opts.particles,
            max_iterations: iterations,
            stall_iterations: if probe {
                iterations
            } else {
                self.stall_iterations
            },
            stall_rel: self.stall_rel,
            seed_spread: self.seed_spread,
            random_fraction: self.random_fraction,
            stop_when_feasible: probe,
            refine_evaluations: if probe { 0 } else { opts.refine_evaluations },
            seed: opts.seed ^ salt.wrapping_mul(0x9E37_79B9_7F4A_7C15),
        }
    }
}
