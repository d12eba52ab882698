//! The knot search as a [`SwarmProblem`]: a particle is an encoded interior-knot vector (and smoothing
//! weight); its fitness is feasibility-first: violation `max(0, d_max/tol − 1)` (+ `max(0,
//! max_j F_j / F* − 1)` when a per-span target `F*` is given), objective `F + max_j F_j`.

use super::encoding::KnotEncoding;
use super::objective::{
    evaluate_candidate_bounded, evaluate_candidate_within, set_knots, CandidateEval, EvalWorkspace,
    FitData,
};
use super::pso::{Fitness, SwarmProblem};

/// One fixed number of control points to search knots for.
#[derive(Clone, Debug)]
pub struct KnotProblem<'a> {
    /// The normalised data.
    pub data: &'a FitData,
    /// How particles encode the knots.
    pub encoding: KnotEncoding,
    /// Maximum orthogonal deviation allowed (normalised units).
    pub tolerance: f64,
    /// Per-span fairness target `F*`.
    pub span_target: Option<f64>,
    /// The fairness integral is only computed for candidates within this many tolerances.
    pub fairness_cutoff: f64,
}

/// Buffers of one particle.
#[derive(Clone, Debug, Default)]
pub struct KnotWorkspace {
    /// Interior knots of the last decoded position.
    pub interior: Vec<f64>,
    /// Evaluation buffers.
    pub eval: EvalWorkspace,
}

impl KnotProblem<'_> {
    /// Decodes and repairs `x` into `ws.interior`; false if no valid knot vector exists.
    pub fn decode_into(&self, x: &[f64], ws: &mut KnotWorkspace) -> bool {
        ws.interior.resize(self.encoding.interior, 0.0);
        self.encoding.decode(x, &mut ws.interior);
        self.encoding.repair(&mut ws.interior, &self.data.params)
    }
}

impl SwarmProblem for KnotProblem<'_> {
    type Workspace = KnotWorkspace;
    type Output = CandidateEval;

    fn dim(&self) -> usize {
        self.encoding.dim()
    }

    fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        self.encoding.bounds()
    }

    fn workspace(&self) -> KnotWorkspace {
        KnotWorkspace::default()
    }

    fn repair(&self, x: &mut [f64], ws: &mut KnotWorkspace) {
        if self.decode_into(x, ws) {
            self.encoding.encode(&ws.interior, x);
        }
    }

    fn evaluate(&self, x: &[f64], ws: &mut KnotWorkspace) -> CandidateEval {
        if !self.decode_into(x, ws) {
            return CandidateEval::failed();
        }
        set_knots(self.data.degree, &ws.interior, &mut ws.eval);
        evaluate_candidate_within(
            self.data,
            self.encoding.log_lambda(x),
            self.fairness_cutoff * self.tolerance,
            &mut ws.eval,
        )
    }

    fn evaluate_within(
        &self,
        x: &[f64],
        ws: &mut KnotWorkspace,
        cutoff: &Fitness,
    ) -> CandidateEval {
        if !self.decode_into(x, ws) {
            return CandidateEval::failed();
        }
        set_knots(self.data.degree, &ws.interior, &mut ws.eval);
        // a candidate whose deviation violation exceeds the cutoff's total violation cannot beat it
        let give_up = cutoff
            .violation
            .is_finite()
            .then_some((self.tolerance, cutoff.violation));
        evaluate_candidate_bounded(
            self.data,
            self.encoding.log_lambda(x),
            self.fairness_cutoff * self.tolerance,
            give_up,
            &mut ws.eval,
        )
    }

    fn fitness(&self, e: &CandidateEval) -> Fitness {
        if !e.solved || e.fairness.is_nan() {
            return Fitness::WORST;
        }
        let mut violation = (e.max_deviation / self.tolerance - 1.0).max(0.0);
        if violation > 0.0 {
            // ranked by violation alone (the fairness may not have been computed)
            return Fitness {
                violation,
                objective: f64::INFINITY,
            };
        }
        if let Some(t) = self.span_target {
            violation += (e.max_span_fairness / t - 1.0).max(0.0);
        }
        Fitness {
            violation,
            objective: e.fairness + e.max_span_fairness,
        }
    }
}

/// The knot search at one control-point count.
pub(crate) trait CountProblem: SwarmProblem<Output = CandidateEval> + Clone + Send {
    /// The particle position of interior knots, smoothing coordinate at its lower bound.
    fn position(&self, knots: &[f64]) -> Vec<f64>;
    /// The repaired interior knots of position `x` (`None` when no valid knot vector exists).
    fn decode(&self, x: &[f64]) -> Option<Vec<f64>>;
    /// The coordinate of `log10 λ` when the smoothing weight is searched.
    fn smoothing_coord(&self) -> Option<usize>;
    /// `log10 λ` of position `x`.
    fn log_lambda(&self, x: &[f64]) -> f64;
}

impl CountProblem for KnotProblem<'_> {
    fn position(&self, knots: &[f64]) -> Vec<f64> {
        let mut x = vec![0.0; self.encoding.dim()];
        self.encoding.encode(knots, &mut x);
        if self.encoding.with_smoothing {
            x[self.encoding.interior + 1] = super::encoding::LOG_LAMBDA_RANGE.0;
        }
        x
    }

    fn decode(&self, x: &[f64]) -> Option<Vec<f64>> {
        let mut kw = KnotWorkspace::default();
        self.decode_into(x, &mut kw).then_some(kw.interior)
    }

    fn smoothing_coord(&self) -> Option<usize> {
        self.encoding
            .with_smoothing
            .then_some(self.encoding.interior + 1)
    }

    fn log_lambda(&self, x: &[f64]) -> f64 {
        self.encoding.log_lambda(x)
    }
}
