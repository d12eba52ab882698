//! The measured policy of the fairing stages: budgets, step schedules and thresholds of band
//! fairing ([`super::band`]) and the polish ([`mod@super::polish`]), in one value with documented
//! defaults. `BandOptions::default()` and `PolishOptions::default()` read these defaults; the
//! numerical constants of the math (solver tolerances, difference steps, Cholesky guards, the node
//! and sample rules) stay with the code they belong to.
//!
//! Where each default was measured is recorded in the tuning ledger of `docs/optim.md`.

/// The relative fall of the objective (band fairing's merit, the polish's F) a trial step must
/// beat to be accepted: a gain of round-off size is no progress, and accepting it could cycle.
pub(crate) const MIN_ACCEPTED_GAIN: f64 = 1e-9;

/// The policy of the fairing stages.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FairingTuning {
    /// Band fairing.
    pub band: BandTuning,
    /// The polish.
    pub polish: PolishTuning,
}

/// The policy of band fairing: the defaults of `BandOptions` in `optim/fairing/band/`, the later passes'
/// budgets and the step schedule.
#[derive(Clone, Debug, PartialEq)]
pub struct BandTuning {
    /// Most convex subproblems of a first pass (`BandOptions::max_solves`). Default 60.
    pub max_solves: usize,
    /// The cones' radius is `tol (1 − margin)`, a little inside the band, so that the solver's
    /// own feasibility tolerance cannot push a point outside (`BandOptions::margin`). Default 1e-3.
    pub margin: f64,
    /// Relative merit gain below which steps count as small, and below which a subproblem's
    /// predicted gain ends the pass (`BandOptions::min_rel_gain`). Default 2e-3.
    pub min_rel_gain: f64,
    /// Weight of the tangential part of a point's deviation in its cone
    /// (`BandOptions::tangent_weight`; 1 would be the whole distance). Default 0.03.
    pub tangent_weight: f64,
    /// Persistence threshold of the curvature extrema the sign targets remove, as a fraction of
    /// the curvature range (`BandOptions::extrema_persistence`). Default 0.03.
    pub extrema_persistence: f64,
    /// Subproblem budget of the second pass after the polish and of the pass holding the
    /// extrema pattern (`later_passes`, `refair`). Default 15.
    pub refair_solves: usize,
    /// `extrema_persistence` of the pass that holds the present curvature-extrema pattern: merges
    /// no run but keeps the sign targets on. Default 1e-12.
    pub hold_persistence: f64,
    /// The step schedule inside a pass.
    pub step: StepTuning,
}

/// The step schedule of a band-fairing pass: the sign-target penalty, the Levenberg–Marquardt
/// multiplier `μ` and the solves and trial steps per subproblem.
#[derive(Clone, Debug, PartialEq)]
pub struct StepTuning {
    /// Weight of the sign-target penalty `Σ max(0, m − s_g r_g)` against `½ F / F_current`: large
    /// enough for the penalty to be exact. Default 30.
    pub sign_weight: f64,
    /// Nodes whose residual is on the right side by more than this fraction of the largest
    /// residual get no sign row in a subproblem (the line search's extrema count still guards
    /// them). Default 0.05.
    pub sign_near: f64,
    /// `sign_near` while every sign target is met (the rows are hard constraints then).
    /// Default 0.01.
    pub sign_near_met: f64,
    /// A step whose merit gain is below `min_rel_gain` still counts as progress when it cuts the
    /// sign violation below this fraction of the current one. Default 0.9.
    pub violation_progress: f64,
    /// Passes end after this many small accepted steps in a row. Default 2.
    pub small_gain_steps: usize,
    /// `μ` of a pass's first subproblem. Default 1e-4.
    pub mu_start: f64,
    /// After an accepted full step `μ` is divided by this. Default 3.
    pub mu_full_step_divisor: f64,
    /// Smallest `μ` after an accepted full step. Default 1e-8.
    pub mu_min: f64,
    /// `μ` grows by this factor after a solve whose line search kept no step (unless points left
    /// the band and their cones were drawn in instead). Default 8.
    pub mu_no_step_growth: f64,
    /// `μ` grows by this factor after a solve that failed. Default 10.
    pub mu_failed_solve_growth: f64,
    /// Most solves of one linearisation (each after `μ` grew or cones were drawn in). Default 3.
    pub solves_per_subproblem: usize,
    /// Trial steps `1, ½, ¼, …` of the line search along one solution. Default 3.
    pub line_search_steps: usize,
    /// After an accepted shortened step of length `t < 1`, `μ` is divided by `t` to this power:
    /// the model overreached, so the next step is shorter (×4 after a half step, ×16 after a
    /// quarter). Default 2.
    pub mu_short_step_power: i32,
}

/// The policy of the polish: the defaults of `PolishOptions` in `optim/fairing/polish.rs`.
#[derive(Clone, Debug, PartialEq)]
pub struct PolishTuning {
    /// Most accepted moves. Default 400.
    pub max_moves: usize,
    /// Candidates (by decreasing energy gain) tried per move before giving up. Default 8.
    pub max_candidates: usize,
    /// Step halvings tried per candidate after the full step. Default 6.
    pub step_halvings: usize,
    /// Most curve measurements in total. Default 2000.
    pub max_evaluations: usize,
}

impl BandTuning {
    /// The defaults (as [`Default`], usable in constants).
    pub const fn new() -> Self {
        BandTuning {
            max_solves: 60,
            margin: 1e-3,
            min_rel_gain: 2e-3,
            tangent_weight: 0.03,
            extrema_persistence: 0.03,
            refair_solves: 15,
            hold_persistence: 1e-12,
            step: StepTuning::new(),
        }
    }
}

impl Default for BandTuning {
    fn default() -> Self {
        Self::new()
    }
}

impl StepTuning {
    /// The defaults (as [`Default`], usable in constants).
    pub const fn new() -> Self {
        StepTuning {
            sign_weight: 30.0,
            sign_near: 0.05,
            sign_near_met: 0.01,
            violation_progress: 0.9,
            small_gain_steps: 2,
            mu_start: 1e-4,
            mu_full_step_divisor: 3.0,
            mu_min: 1e-8,
            mu_no_step_growth: 8.0,
            mu_failed_solve_growth: 10.0,
            solves_per_subproblem: 3,
            line_search_steps: 3,
            mu_short_step_power: 2,
        }
    }
}

impl Default for StepTuning {
    fn default() -> Self {
        Self::new()
    }
}

impl PolishTuning {
    /// The defaults (as [`Default`], usable in constants).
    pub const fn new() -> Self {
        PolishTuning {
            max_moves: 400,
            max_candidates: 8,
            step_halvings: 6,
            max_evaluations: 2000,
        }
    }
}

impl Default for PolishTuning {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_measured_values() {
        let t = FairingTuning::default();
        assert_eq!(t.band.max_solves, 60);
        assert_eq!(t.band.refair_solves, 15);
        assert_eq!(t.band.hold_persistence, 1e-12);
        assert_eq!(t.band.extrema_persistence, 0.03);
        assert_eq!(t.band.step.sign_weight, 30.0);
        assert_eq!(t.band.step.sign_near_met, 0.01);
        assert_eq!(t.polish.max_evaluations, 2000);
        assert_eq!(t.polish.max_moves, 400);
        assert_eq!(t.band.step.mu_short_step_power, 2);
        assert_eq!(MIN_ACCEPTED_GAIN, 1e-9);
    }

    #[test]
    fn the_short_step_rule_divides_mu_by_t_squared_exactly() {
        // the line search's steps are powers of one half: t^2 by powi is the product t * t
        let p = StepTuning::default().mu_short_step_power;
        for t in [0.5f64, 0.25, 0.125] {
            assert_eq!(t.powi(p), t * t);
            assert_eq!(3e-4 / t.powi(p), 3e-4 / (t * t));
        }
    }
}
