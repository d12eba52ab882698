//! The Pareto front of (maximum orthogonal deviation, F) at a fixed number of control points, for
//! `--pareto`: a user picks the trade-off between closeness to the data and fairness.
//!
//! The multi-objective swarm of [`crate::optim::search::mopso`] runs over the same encoded knot vectors (and smoothing
//! weight) as the integrated method, seeded with its knots; candidates deviating more than
//! [`DEVIATION_CAP`] times the tolerance are left out, so the front covers the useful range.

use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::context::tolerance_of;
use crate::optim::kind::open::finish_curve;
use crate::optim::kind::periodic::distinct_control_points;
use crate::optim::options::IntegratedOptions;
use crate::optim::result::FitQuality;
use crate::optim::search::encoding::{KnotEncoding, LOG_LAMBDA_RANGE};
use crate::optim::search::mopso::{run_mopso, MopsoOptions, ParetoArchive};
use crate::optim::search::objective::CandidateEval;
use crate::optim::search::prepare::{averaging_interior_knots, prepare};
use crate::optim::search::problem::KnotProblem;
use crate::optim::search::pso::SwarmProblem;

/// Front members deviate at most this many times the tolerance.
pub(crate) const DEVIATION_CAP: f64 = 10.0;

/// One curve of the front.
#[derive(Clone, Debug)]
pub struct ParetoCurve {
    /// The curve (in the input's coordinates).
    pub curve: NurbsCurve,
    /// Its deviation and fairness.
    pub quality: FitQuality,
}

/// The front for `n_ctrl` control points, sorted by increasing deviation (so decreasing F), seeded with
/// the interior knots `seed_knots` (normalised to `[0, 1]`, e.g. the integrated result's) when given.
pub fn pareto_front(
    points: &[Vec3],
    opts: &IntegratedOptions,
    n_ctrl: usize,
    seed_knots: Option<(&[f64], f64)>,
) -> Result<Vec<ParetoCurve>> {
    let prep = prepare(points, opts.degree)?;
    let p = opts.degree;
    if n_ctrl < p + 1 || n_ctrl > prep.data.points.len() {
        return Err(Error::InvalidSetting {
            option: "control_points",
            reason: format!(
                "{n_ctrl} control points: need between {} and {}",
                p + 1,
                prep.data.points.len()
            ),
        });
    }
    let tol = tolerance_of(opts, prep.scale);
    let problem = KnotProblem {
        data: &prep.data,
        encoding: KnotEncoding::new(n_ctrl - p - 1, 1e-4, true),
        tolerance: tol,
        span_target: None,
        fairness_cutoff: DEVIATION_CAP,
    };
    let mut seeds = Vec::new();
    let avg = averaging_interior_knots(&prep.data.params, p, n_ctrl);
    for (knots, ll) in seed_knots
        .into_iter()
        .chain(std::iter::once((avg.as_slice(), LOG_LAMBDA_RANGE.0)))
    {
        if knots.len() != problem.encoding.interior {
            continue;
        }
        let mut x = vec![0.0; problem.encoding.dim()];
        problem.encoding.encode(knots, &mut x);
        x[problem.encoding.interior + 1] = ll.clamp(LOG_LAMBDA_RANGE.0, LOG_LAMBDA_RANGE.1);
        seeds.push(x);
    }
    let archive = front_archive(&problem, &seeds, opts, tol);
    let mut out = Vec::with_capacity(archive.members.len());
    let mut kw = Default::default();
    for m in &archive.members {
        if !problem.decode_into(&m.position, &mut kw) {
            continue;
        }
        let (curve, quality, _) = finish_curve(
            &prep,
            &kw.interior,
            problem.encoding.log_lambda(&m.position),
            p,
            None,
        )?;
        out.push(ParetoCurve { curve, quality });
    }
    Ok(out)
}

/// The multi-objective swarm of a front from `seeds`: objectives (max deviation, F) for every solved
/// candidate within [`DEVIATION_CAP`] tolerances (others are dominated by all), the user's seed, at
/// least 20 particles. Shared by the open and the periodic fronts.
pub(super) fn front_archive<P: SwarmProblem<Output = CandidateEval>>(
    problem: &P,
    seeds: &[Vec<f64>],
    opts: &IntegratedOptions,
    tol: f64,
) -> ParetoArchive {
    let mopts = MopsoOptions {
        seed: opts.seed,
        particles: opts.particles.max(20),
        ..MopsoOptions::default()
    };
    run_mopso(
        problem,
        seeds,
        &|e: &CandidateEval| {
            if e.solved && e.max_deviation <= DEVIATION_CAP * tol {
                [e.max_deviation, e.fairness]
            } else {
                [f64::INFINITY; 2]
            }
        },
        &mopts,
    )
}

/// The front as CSV: `index,control_points,max_deviation,rms_deviation,fairness,max_span_fairness`
/// (distinct control points: a periodic member stores `n + p`, the last `p` repeating the first).
pub fn pareto_csv(front: &[ParetoCurve]) -> String {
    let mut s = String::from(
        "index,control_points,max_deviation,rms_deviation,fairness,max_span_fairness\n",
    );
    for (i, c) in front.iter().enumerate() {
        s.push_str(&format!(
            "{i},{},{:e},{:e},{:e},{:e}\n",
            distinct_control_points(&c.curve),
            c.quality.max_deviation,
            c.quality.rms_deviation,
            c.quality.fairness,
            c.quality.max_span_fairness
        ));
    }
    s
}
