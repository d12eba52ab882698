//! A line search on the smoothing weight `log10 λ` for fixed knots: the swarm moves knots well but
//! explores the one smoothing coordinate poorly (its seeds start without smoothing), while the fairest
//! curve for given knots is usually the one smoothed until the tolerance is nearly used up.
//!
//! The search evaluates a fixed grid of `log10 λ` values in parallel (results collected in grid
//! order, so the choice does not depend on the thread count), keeps the best by the problem's
//! feasibility-first fitness, and refines it by a few bisection-like halvings of the grid step.

use super::pso::{Fitness, SwarmProblem};
use rayon::prelude::*;

/// Grid of the line search: from `GRID_LO` to the encoding's upper bound in steps of `GRID_STEP`.
const GRID_LO: f64 = -20.0;
const GRID_STEP: f64 = 0.5;
/// Halvings of the step around the best grid point.
const REFINE_ROUNDS: usize = 4;

/// The outcome of [`tune_smoothing`].
#[derive(Clone, Debug)]
pub struct Tuned<O> {
    /// The position with the chosen `log10 λ` coordinate.
    pub position: Vec<f64>,
    /// Its evaluation.
    pub output: O,
    /// Its fitness.
    pub fitness: Fitness,
    /// Evaluations spent.
    pub evaluations: usize,
}

/// Searches coordinate `coord` (the `log10 λ` of `position`) for the best fitness, starting from the
/// evaluated `(position, output, fitness)`; never returns anything worse than the start.
pub fn tune_smoothing<P: SwarmProblem>(
    problem: &P,
    coord: usize,
    start: (&[f64], &P::Output, Fitness),
) -> Tuned<P::Output> {
    let (lo, hi) = problem.bounds();
    let (lo, hi) = (lo[coord], hi[coord]);
    let mut best = Tuned {
        position: start.0.to_vec(),
        output: start.1.clone(),
        fitness: start.2,
        evaluations: 0,
    };
    let mut values: Vec<f64> = Vec::new();
    let mut v = GRID_LO.max(lo);
    while v <= hi + 1e-12 {
        values.push(v);
        v += GRID_STEP;
    }
    let mut step = GRID_STEP;
    for round in 0..=REFINE_ROUNDS {
        if round > 0 {
            step *= 0.5;
            let c = best.position[coord];
            values = vec![(c - step).max(lo), (c + step).min(hi)];
        }
        let base = best.position.clone();
        let results: Vec<(Vec<f64>, P::Output, Fitness)> = values
            .par_iter()
            .map_init(
                || problem.workspace(),
                |ws, &val| {
                    let mut x = base.clone();
                    x[coord] = val;
                    problem.repair(&mut x, ws);
                    let out = problem.evaluate(&x, ws);
                    let f = problem.fitness(&out);
                    (x, out, f)
                },
            )
            .collect();
        best.evaluations += results.len();
        for (x, out, f) in results {
            if f.better_than(&best.fitness) {
                best.position = x;
                best.output = out;
                best.fitness = f;
            }
        }
    }
    best
}
