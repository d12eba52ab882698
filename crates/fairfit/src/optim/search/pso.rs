//! A deterministic, rayon-parallel particle swarm optimiser with per-particle repair, seeded initial
//! positions, early exit and a final pattern-search refinement of the best particle.
//!
//! Written here instead of using `argmin`'s `ParticleSwarm` because the knot search needs what that
//! solver does not offer: a repair hook that maps every moved particle back onto the feasible set
//! (Schoenberg–Whitney), initial particles placed at given positions (the least-squares baseline's
//! knots), feasibility-first comparison of constrained candidates, per-particle reusable workspaces
//! (no allocation per evaluation), and bit-identical results for any thread count. The multi-objective
//! archive lives in `mopso.rs` and reuses the same problem trait.
//!
//! Update rule (Clerc–Kennedy constriction): `v ← χ (v + c1 r1 (pbest − x) + c2 r2 (gbest − x))`,
//! `χ = 0.7298`, `c1 = c2 = 1.49618`, `|v_d| ≤ 0.2 (hi_d − lo_d)`, positions clamped to the bounds and
//! then repaired. Determinism: particle `i` draws from its own `ChaCha8` stream `i` of the seed;
//! evaluations run in parallel but results are stored per particle and the global best is chosen by
//! a sequential scan in particle order.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Constriction factor χ.
pub(crate) const CHI: f64 = 0.7298;
/// Cognitive and social acceleration c1 = c2.
pub(crate) const C_ACC: f64 = 1.49618;

/// Feasibility-first fitness: smaller `violation` wins; among equal violations smaller `objective`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fitness {
    /// Constraint violation (0 when feasible).
    pub violation: f64,
    /// Objective to minimise.
    pub objective: f64,
}

impl Fitness {
    /// The worst possible fitness.
    pub const WORST: Fitness = Fitness {
        violation: f64::INFINITY,
        objective: f64::INFINITY,
    };

    /// Whether `self` is strictly better than `other` (NaN counts as infinitely bad).
    pub fn better_than(&self, other: &Fitness) -> bool {
        let v = |x: f64| if x.is_nan() { f64::INFINITY } else { x };
        let (va, vb) = (v(self.violation), v(other.violation));
        if va != vb {
            return va < vb;
        }
        v(self.objective) < v(other.objective)
    }

    /// Whether the constraint holds.
    pub fn feasible(&self) -> bool {
        self.violation == 0.0
    }
}

/// A problem the swarm can optimise.
pub trait SwarmProblem: Sync {
    /// Per-particle reusable buffers.
    type Workspace: Send;
    /// What one evaluation returns.
    type Output: Clone + Send + Sync;
    /// Dimension of a position.
    fn dim(&self) -> usize;
    /// Lower and upper bounds per coordinate.
    fn bounds(&self) -> (Vec<f64>, Vec<f64>);
    /// Fresh buffers for one particle.
    fn workspace(&self) -> Self::Workspace;
    /// Maps `x` onto the feasible set in place (default: nothing).
    fn repair(&self, _x: &mut [f64], _ws: &mut Self::Workspace) {}
    /// Evaluates position `x`.
    fn evaluate(&self, x: &[f64], ws: &mut Self::Workspace) -> Self::Output;
    /// Evaluates position `x`, allowed to stop early once its fitness is certain not to be better
    /// than `cutoff`, returning then an output whose fitness is not better than `cutoff` either
    /// (the swarm only compares it with `cutoff` or worse). Default: [`SwarmProblem::evaluate`].
    fn evaluate_within(
        &self,
        x: &[f64],
        ws: &mut Self::Workspace,
        cutoff: &Fitness,
    ) -> Self::Output {
        let _ = cutoff;
        self.evaluate(x, ws)
    }
    /// The scalar fitness of an output.
    fn fitness(&self, out: &Self::Output) -> Fitness;
}

/// Settings of [`run_pso`].
#[derive(Clone, Debug, PartialEq)]
pub struct PsoOptions {
    /// Number of particles.
    pub particles: usize,
    /// Maximum number of iterations.
    pub max_iterations: usize,
    /// Stop after this many iterations without a relative improvement of `stall_rel` of the best.
    pub stall_iterations: usize,
    /// Relative improvement that resets the stall counter.
    pub stall_rel: f64,
    /// Spread of the perturbations around the seed positions, as a fraction of each coordinate's range.
    pub seed_spread: f64,
    /// Fraction of the non-seed particles placed uniformly at random (the rest perturb the seeds).
    pub random_fraction: f64,
    /// Stop as soon as any feasible position is found (for feasibility probes).
    pub stop_when_feasible: bool,
    /// Evaluations of the final pattern search (0 = no refinement).
    pub refine_evaluations: usize,
    /// Seed of the random streams.
    pub seed: u64,
}

impl Default for PsoOptions {
    fn default() -> Self {
        PsoOptions {
            particles: 24,
            max_iterations: 40,
            stall_iterations: 8,
            stall_rel: 1e-4,
            seed_spread: 0.05,
            random_fraction: 0.2,
            stop_when_feasible: false,
            refine_evaluations: 200,
            seed: 0,
        }
    }
}

/// The best position found and what it cost.
#[derive(Clone, Debug)]
pub struct PsoResult<O> {
    /// Best position.
    pub position: Vec<f64>,
    /// Its evaluation.
    pub output: O,
    /// Its fitness.
    pub fitness: Fitness,
    /// Number of evaluations made.
    pub evaluations: usize,
    /// Number of swarm iterations made (the initial evaluation is iteration 0).
    pub iterations: usize,
}

struct Particle<W> {
    x: Vec<f64>,
    v: Vec<f64>,
    best_x: Vec<f64>,
    best_f: Fitness,
    rng: ChaCha8Rng,
    ws: W,
}

/// Runs the swarm from `seeds` (at least one position; extra particles perturb them or start at
/// random), then refines the best particle by pattern search. `progress` is called after every
/// iteration with the iteration number.
pub fn run_pso<P: SwarmProblem>(
    problem: &P,
    seeds: &[Vec<f64>],
    opts: &PsoOptions,
    progress: &(dyn Fn(usize) + Sync),
) -> PsoResult<P::Output> {
    let dim = problem.dim();
    let (lo, hi) = problem.bounds();
    let range: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| b - a).collect();
    let vmax: Vec<f64> = range.iter().map(|r| 0.2 * r).collect();
    let n_part = opts.particles.max(seeds.len()).max(1);
    let n_random =
        ((n_part - seeds.len().min(n_part)) as f64 * opts.random_fraction).round() as usize;
    let mut swarm: Vec<Particle<P::Workspace>> = (0..n_part)
        .map(|i| {
            let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
            rng.set_stream(i as u64);
            let x: Vec<f64> = if i < seeds.len() {
                seeds[i].clone()
            } else if i >= n_part - n_random {
                (0..dim)
                    .map(|d| lo[d] + rng.random::<f64>() * range[d])
                    .collect()
            } else {
                let s = &seeds[i % seeds.len().max(1)];
                (0..dim)
                    .map(|d| {
                        let r: f64 = rng.random::<f64>() * 2.0 - 1.0;
                        (s[d] + r * opts.seed_spread * range[d]).clamp(lo[d], hi[d])
                    })
                    .collect()
            };
            let v = (0..dim)
                .map(|d| (rng.random::<f64>() * 2.0 - 1.0) * 0.1 * vmax[d])
                .collect();
            Particle {
                best_x: x.clone(),
                x,
                v,
                best_f: Fitness::WORST,
                rng,
                ws: problem.workspace(),
            }
        })
        .collect();

    let mut best_out: Option<P::Output> = None;
    let mut best_x = swarm[0].x.clone();
    let mut best_f = Fitness::WORST;
    let mut evaluations = 0usize;
    let mut iterations = 0usize;
    let mut stall = 0usize;

    for it in 0..=opts.max_iterations {
        if it > 0 {
            let gb = &best_x;
            swarm.par_iter_mut().for_each(|p| {
                for d in 0..dim {
                    let r1: f64 = p.rng.random();
                    let r2: f64 = p.rng.random();
                    let v = CHI
                        * (p.v[d]
                            + C_ACC * r1 * (p.best_x[d] - p.x[d])
                            + C_ACC * r2 * (gb[d] - p.x[d]));
                    p.v[d] = v.clamp(-vmax[d], vmax[d]);
                    p.x[d] = (p.x[d] + p.v[d]).clamp(lo[d], hi[d]);
                }
            });
        }
        let results: Vec<(P::Output, Fitness)> = swarm
            .par_iter_mut()
            .map(|p| {
                problem.repair(&mut p.x, &mut p.ws);
                // the global best is at least as good as the particle's: a candidate that cannot
                // beat the particle's best changes nothing
                let cutoff = p.best_f;
                let out = problem.evaluate_within(&p.x, &mut p.ws, &cutoff);
                let f = problem.fitness(&out);
                if f.better_than(&p.best_f) {
                    p.best_f = f;
                    p.best_x.copy_from_slice(&p.x);
                }
                (out, f)
            })
            .collect();
        evaluations += n_part;
        iterations = it;
        let prev = best_f;
        for (i, (out, f)) in results.into_iter().enumerate() {
            if f.better_than(&best_f) {
                best_f = f;
                best_x.copy_from_slice(&swarm[i].x);
                best_out = Some(out);
            }
        }
        progress(it);
        if opts.stop_when_feasible && best_f.feasible() {
            break;
        }
        let improved = best_f.violation < prev.violation
            || (best_f.violation == prev.violation
                && best_f.objective < prev.objective - opts.stall_rel * prev.objective.abs());
        if improved {
            stall = 0;
        } else {
            stall += 1;
            if stall >= opts.stall_iterations {
                break;
            }
        }
    }
    let mut result = PsoResult {
        position: best_x,
        output: match best_out {
            Some(o) => o,
            None => {
                let p0 = &mut swarm[0];
                problem.evaluate(&p0.x, &mut p0.ws)
            }
        },
        fitness: best_f,
        evaluations,
        iterations,
    };
    if opts.refine_evaluations > 0 && !(opts.stop_when_feasible && best_f.feasible()) {
        refine(
            problem,
            &mut result,
            &mut swarm,
            &range,
            opts.refine_evaluations,
        );
    }
    result
}

/// Pattern search around the best position: all `2 dim` poll points are evaluated in parallel (one
/// particle workspace each), the best improving one (first in poll order on ties) is taken, and the
/// step halves when none improves.
fn refine<P: SwarmProblem>(
    problem: &P,
    res: &mut PsoResult<P::Output>,
    swarm: &mut [Particle<P::Workspace>],
    range: &[f64],
    budget: usize,
) {
    let dim = res.position.len();
    let (lo, hi) = problem.bounds();
    let mut step = 0.02;
    let mut used = 0usize;
    let polls = 2 * dim;
    while used < budget && step > 1e-4 {
        let base = res.position.clone();
        // only a poll better than the best at the start of its chunk can be taken
        let mut improved = false;
        for chunk_start in (0..polls).step_by(swarm.len().max(1)) {
            let chunk_end = (chunk_start + swarm.len()).min(polls);
            let cutoff = res.fitness;
            let results: Vec<(Vec<f64>, P::Output, Fitness)> = swarm[..chunk_end - chunk_start]
                .par_iter_mut()
                .enumerate()
                .map(|(j, p)| {
                    let poll = chunk_start + j;
                    let d = poll / 2;
                    let sign = if poll % 2 == 0 { 1.0 } else { -1.0 };
                    p.x.copy_from_slice(&base);
                    p.x[d] = (p.x[d] + sign * step * range[d]).clamp(lo[d], hi[d]);
                    problem.repair(&mut p.x, &mut p.ws);
                    let out = problem.evaluate_within(&p.x, &mut p.ws, &cutoff);
                    let f = problem.fitness(&out);
                    (p.x.clone(), out, f)
                })
                .collect();
            used += results.len();
            for (x, out, f) in results {
                if f.better_than(&res.fitness) {
                    res.fitness = f;
                    res.position = x;
                    res.output = out;
                    improved = true;
                }
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    res.evaluations += used;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shifted sphere or Rosenbrock in `dim` dimensions on `[-5, 5]^dim`, optionally with the
    /// constraint `x_0 >= 1.5` (violation `max(0, 1.5 − x_0)`).
    struct Analytic {
        dim: usize,
        rosenbrock: bool,
        constrained: bool,
    }

    impl SwarmProblem for Analytic {
        type Workspace = ();
        type Output = f64;
        fn dim(&self) -> usize {
            self.dim
        }
        fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
            (vec![-5.0; self.dim], vec![5.0; self.dim])
        }
        fn workspace(&self) {}
        fn evaluate(&self, x: &[f64], _ws: &mut ()) -> f64 {
            if self.rosenbrock {
                x.windows(2)
                    .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
                    .sum()
            } else {
                x.iter()
                    .enumerate()
                    .map(|(i, v)| (v - 0.1 * i as f64).powi(2))
                    .sum()
            }
        }
        fn fitness(&self, out: &f64) -> Fitness {
            Fitness {
                violation: 0.0,
                objective: *out,
            }
        }
    }

    struct Constrained;
    impl SwarmProblem for Constrained {
        type Workspace = ();
        type Output = (f64, f64);
        fn dim(&self) -> usize {
            2
        }
        fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
            (vec![-5.0; 2], vec![5.0; 2])
        }
        fn workspace(&self) {}
        fn repair(&self, x: &mut [f64], _ws: &mut ()) {
            // feasible set of the repair: x_1 <= 2
            x[1] = x[1].min(2.0);
        }
        fn evaluate(&self, x: &[f64], _ws: &mut ()) -> (f64, f64) {
            (x[0] * x[0] + x[1] * x[1], (1.5 - x[0]).max(0.0))
        }
        fn fitness(&self, out: &(f64, f64)) -> Fitness {
            Fitness {
                violation: out.1,
                objective: out.0,
            }
        }
    }

    fn opts(seed: u64) -> PsoOptions {
        PsoOptions {
            particles: 30,
            max_iterations: 300,
            stall_iterations: 40,
            stall_rel: 1e-9,
            refine_evaluations: 2000,
            seed,
            ..PsoOptions::default()
        }
    }

    #[test]
    fn finds_the_sphere_minimum() {
        let p = Analytic {
            dim: 5,
            rosenbrock: false,
            constrained: false,
        };
        let _ = p.constrained;
        let r = run_pso(&p, &[vec![4.0; 5]], &opts(7), &|_| {});
        assert!(r.output < 1e-8, "{}", r.output);
        for (i, v) in r.position.iter().enumerate() {
            assert!((v - 0.1 * i as f64).abs() < 1e-4);
        }
    }

    #[test]
    fn finds_the_rosenbrock_minimum() {
        let p = Analytic {
            dim: 2,
            rosenbrock: true,
            constrained: false,
        };
        let r = run_pso(&p, &[vec![-3.0, 4.0]], &opts(3), &|_| {});
        assert!(r.output < 1e-6, "{}", r.output);
        assert!((r.position[0] - 1.0).abs() < 1e-2 && (r.position[1] - 1.0).abs() < 2e-2);
    }

    #[test]
    fn constrained_minimum_and_repair_hold() {
        // minimise |x|² s.t. x_0 >= 1.5, repaired onto x_1 <= 2: optimum (1.5, 0), value 2.25
        let r = run_pso(&Constrained, &[vec![-4.0, 4.0]], &opts(11), &|_| {});
        assert!(r.fitness.feasible());
        assert!((r.output.0 - 2.25).abs() < 1e-5, "{:?}", r.output);
        assert!(r.position[1] <= 2.0);
    }

    #[test]
    fn same_seed_same_bits_for_any_thread_count() {
        let p = Analytic {
            dim: 4,
            rosenbrock: true,
            constrained: false,
        };
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| e.to_string());
            match pool {
                Ok(pool) => pool.install(|| run_pso(&p, &[vec![0.0; 4]], &opts(5), &|_| {})),
                Err(e) => panic!("{e}"),
            }
        };
        let (a, b) = (run(1), run(2));
        assert_eq!(a.output.to_bits(), b.output.to_bits());
        assert_eq!(a.evaluations, b.evaluations);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.position), bits(&b.position));
        // a different seed takes a different path
        let c = run_pso(&p, &[vec![0.0; 4]], &opts(6), &|_| {});
        assert_ne!(bits(&a.position), bits(&c.position));
    }
}
