//! The measured thresholds of the integrated method's policy, in one value nested per stage
//! ([`Tuning`]). Every field says what it decides; its default is the value the method was
//! measured with (the measurements are in the tuning ledger of `docs/optim.md`). Changing a
//! default changes the output.
//!
//! Numerical constants of the math (solver tolerances, sampling densities) are not here: they
//! stay with the code they belong to.

pub use super::fairing::{BandTuning, FairingTuning, PolishTuning, StepTuning};
use super::options::IntegratedOptions;
use super::search::pso::PsoOptions;
pub use crate::fit::reduce::ReduceTuning;

/// Every measured threshold of the method, per stage.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Tuning {
    /// The count descent from the least-squares baseline (`optim/stages/descent.rs`).
    pub descent: DescentTuning,
    /// The count search's choice of the control-point count (`optim/stages/count_search.rs`).
    pub count: CountTuning,
    /// The degree search: the higher degrees' finishing budgets and the triggers of the next
    /// degree's own count search (`optim/stages/degree_candidates.rs`).
    pub degree: DegreeTuning,
    /// The particle swarm's settings in the descent, the count search and the degree search.
    pub swarm: SwarmTuning,
    /// The finishing stages: band fairing and the polish (`optim/fairing/`).
    pub fairing: FairingTuning,
    /// The reduction of dense data before every stage (`optim/stages/reduce.rs`).
    pub reduce: ReduceTuning,
    /// Weights and points to interpolate inside the search
    /// (`PointBands` in `optim/search/objective/`).
    pub points: PointTuning,
}

/// How the search holds points to interpolate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointTuning {
    /// A point to interpolate is held to `tol / interpolation_band` by the band fairing and the
    /// polish (every least-squares solve meets it exactly); the last exact move
    /// ([`crate::fit::point_constraints`]) is then at most that long, so it changes `F` little.
    /// 1000: on NACA 4412 with 4 points to interpolate the move changes F by under 2 % (test
    /// `the_integrated_search_holds_interpolated_points_without_an_extra_control_point`).
    pub interpolation_band: f64,
}

impl Default for PointTuning {
    fn default() -> Self {
        PointTuning {
            interpolation_band: 1e3,
        }
    }
}

/// The count descent's policy.
#[derive(Clone, Debug, PartialEq)]
pub struct DescentTuning {
    /// How many of the best knot removals seed a probe at the next count (beside the spread
    /// knots). Default 3.
    pub probe_removal_seeds: usize,
    /// The fewest control points an open curve's descent goes down to (besides `p + 1`; a fixed
    /// count is kept as given). Default 4.
    pub min_control_points: usize,
}

impl Default for DescentTuning {
    fn default() -> Self {
        DescentTuning {
            probe_removal_seeds: 3,
            min_control_points: 4,
        }
    }
}

/// The count search's policy.
#[derive(Clone, Debug, PartialEq)]
pub struct CountTuning {
    /// The factor by which the finished F must fall per control point above the smallest
    /// feasible count for the larger count to be kept (the count rule, `choose_count`); also the
    /// price of every control point a higher degree adds above the reference's (the degree
    /// rule). Default 1.05.
    pub extra_point_gain: f64,
    /// The relative drop in swarm F from one count to the next below which the next count's
    /// searches are not finished as candidates (`weak_step`). Default 0.02.
    pub weak_step_gain: f64,
    /// The fewest curvature extrema of the chosen curve that call for the restart at the chosen
    /// count (one extremum, an airfoil's leading edge or a quarter ellipse's vertex, leaves no
    /// wiggle to remove); also the fewest for the next degree to try one count above the
    /// least-squares baseline. Default 2.
    pub restart_min_extrema: usize,
}

impl Default for CountTuning {
    fn default() -> Self {
        CountTuning {
            extra_point_gain: 1.05,
            weak_step_gain: 0.02,
            restart_min_extrema: 2,
        }
    }
}

/// The degree search's policy.
#[derive(Clone, Debug, PartialEq)]
pub struct DegreeTuning {
    /// Band-fairing subproblems of a higher degree's candidate (the reference degree gets
    /// `IntegratedOptions::band_solves`); a capped stage can only make a higher degree less
    /// fair, never a worse curve in place of the reference's. Default 8.
    pub candidate_band_solves: usize,
    /// Polish measurements of a higher degree's candidate (the reference degree gets
    /// `IntegratedOptions::polish_evaluations`). Default 500.
    pub candidate_polish_evaluations: usize,
    /// The extrema cost of the reference's count choice (the kept curve's score over the fairest
    /// finished candidate's) from which the next degree gets a count search of its own. Default
    /// 1.5.
    pub own_count_search_cost: f64,
    /// The count gain of the reference's count choice (the least fair finished search at the
    /// kept count over the fairest at the smallest) at or below which the next degree gets a
    /// count search of its own, its counts also seeded with residual-driven knots. Default 0.8.
    pub steep_count_gain: f64,
    /// Curvature extrema of the reference's kept curve from which the next degree searches
    /// counts above the least-squares baseline, priced for the degree step only (the wiggly
    /// trigger). Default 6.
    pub wiggly_extrema: usize,
    /// How many counts above the least-squares baseline the wiggly trigger searches. Default 1.
    pub wiggly_counts_above: usize,
    /// The wiggly trigger's counts keep at least this many data points per control point.
    /// Default 4.
    pub wiggly_points_per_control_point: usize,
    /// Swarm iterations of a higher degree's short search from the reference's knots (0: the
    /// seeds are only measured, the best is finished). Default 0.
    pub short_search_iterations: usize,
    /// The price per control point above the reference's in the degree rule after the wiggly
    /// trigger (its counts pay only the degree's price). Default 1.0.
    pub wiggly_point_gain: f64,
    /// The factor by which F must shrink per degree step for a higher degree to be kept (the
    /// degree rule, `choose_degree_priced`): F differences of a few per cent (the swarm's own
    /// noise) do not change the degree. Default 1.1.
    pub fairness_gain: f64,
}

impl Default for DegreeTuning {
    fn default() -> Self {
        DegreeTuning {
            candidate_band_solves: 8,
            candidate_polish_evaluations: 500,
            own_count_search_cost: 1.5,
            steep_count_gain: 0.8,
            wiggly_extrema: 6,
            wiggly_counts_above: 1,
            wiggly_points_per_control_point: 4,
            short_search_iterations: 0,
            wiggly_point_gain: 1.0,
            fairness_gain: 1.1,
        }
    }
}

/// The swarm settings of the knot searches (the count descent's probes, the count search's full
/// searches, the degree search's short searches). These are the method's own settings, not
/// `PsoOptions::default`'s.
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
    /// Whether the knot searches carry the smoothing weight `log λ` as one more coordinate beside
    /// the knots (else every candidate is a plain least-squares fit). Default true.
    pub search_smoothing: bool,
}

impl Default for SwarmTuning {
    fn default() -> Self {
        SwarmTuning {
            stall_iterations: 10,
            stall_rel: 1e-4,
            seed_spread: 0.03,
            random_fraction: 0.1,
            search_smoothing: true,
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
