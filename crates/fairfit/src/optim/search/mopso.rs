//! Multi-objective particle swarm (MOPSO, Coello Coello, Pulido & Lechuga 2004) for the trade-off
//! between fitting error and fairness at a fixed number of control points: the Pareto front of
//! (maximum orthogonal deviation, F).
//!
//! Mechanism: an external archive of non-dominated solutions; an adaptive hypergrid (7 divisions per
//! objective, 10 % inflation) over the archive; each particle's leader is drawn by roulette over the
//! occupied cells with weight `count^−β` (β = 2), favouring sparse regions; when the archive overflows,
//! members are deleted from crowded cells (weight `count^γ`, γ = 2); a mutation whose rate decays as
//! `(1 − it/T)^{1/μ}` (μ = 0.1) perturbs one coordinate. Swarm moves use the constriction update of
//! [`super::pso`]; the archive's random choices draw from a stream of their own, sequentially, so the
//! front is bit-identical for any thread count.

use super::pso::{SwarmProblem, CHI, C_ACC};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Settings of [`run_mopso`].
#[derive(Clone, Debug, PartialEq)]
pub struct MopsoOptions {
    /// Particles.
    pub particles: usize,
    /// Iterations.
    pub iterations: usize,
    /// Archive capacity.
    pub archive_size: usize,
    /// Grid divisions per objective.
    pub grid: usize,
    /// Leader selection pressure β.
    pub beta: f64,
    /// Deletion pressure γ.
    pub gamma: f64,
    /// Mutation rate μ.
    pub mutation: f64,
    /// Seed of the random streams.
    pub seed: u64,
}

impl Default for MopsoOptions {
    fn default() -> Self {
        MopsoOptions {
            particles: 40,
            iterations: 60,
            archive_size: 50,
            grid: 7,
            beta: 2.0,
            gamma: 2.0,
            mutation: 0.1,
            seed: 0,
        }
    }
}

/// One member of the Pareto archive.
#[derive(Clone, Debug)]
pub struct ArchiveMember {
    /// Position.
    pub position: Vec<f64>,
    /// Objective values (both minimised).
    pub objectives: [f64; 2],
}

/// Whether `a` Pareto-dominates `b` (no worse in both, better in one).
pub fn dominates(a: &[f64; 2], b: &[f64; 2]) -> bool {
    a[0] <= b[0] && a[1] <= b[1] && (a[0] < b[0] || a[1] < b[1])
}

/// An external archive holding only mutually non-dominated members.
#[derive(Clone, Debug, Default)]
pub struct ParetoArchive {
    /// The members, in insertion order.
    pub members: Vec<ArchiveMember>,
}

impl ParetoArchive {
    /// Inserts `m` unless an existing member dominates or equals it; removes the members it
    /// dominates. Non-finite objectives are refused. Returns whether it was inserted.
    pub fn insert(&mut self, m: ArchiveMember) -> bool {
        if !m.objectives.iter().all(|v| v.is_finite()) {
            return false;
        }
        if self
            .members
            .iter()
            .any(|e| dominates(&e.objectives, &m.objectives) || e.objectives == m.objectives)
        {
            return false;
        }
        self.members
            .retain(|e| !dominates(&m.objectives, &e.objectives));
        self.members.push(m);
        true
    }

    /// The grid cell of every member (index into a `grid × grid` array).
    fn cells(&self, grid: usize) -> Vec<usize> {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for m in &self.members {
            for d in 0..2 {
                lo[d] = lo[d].min(m.objectives[d]);
                hi[d] = hi[d].max(m.objectives[d]);
            }
        }
        for d in 0..2 {
            let infl = 0.1 * (hi[d] - lo[d]).max(1e-300);
            lo[d] -= infl;
            hi[d] += infl;
        }
        self.members
            .iter()
            .map(|m| {
                let mut c = 0;
                for d in 0..2 {
                    let t = ((m.objectives[d] - lo[d]) / (hi[d] - lo[d]) * grid as f64) as usize;
                    c = c * grid + t.min(grid - 1);
                }
                c
            })
            .collect()
    }

    /// A member drawn by roulette over occupied cells with weight `count^−β`, uniform inside the cell.
    fn select_leader(&self, grid: usize, beta: f64, rng: &mut ChaCha8Rng) -> usize {
        let cells = self.cells(grid);
        roulette_by_cell(&cells, grid, -beta, rng)
    }

    /// Deletes members from crowded cells until at most `cap` remain.
    fn truncate(&mut self, cap: usize, grid: usize, gamma: f64, rng: &mut ChaCha8Rng) {
        while self.members.len() > cap {
            let cells = self.cells(grid);
            let i = roulette_by_cell(&cells, grid, gamma, rng);
            self.members.remove(i);
        }
    }
}

/// Picks a cell with weight `count^power` (cells in ascending index order), then a member uniformly.
fn roulette_by_cell(cells: &[usize], grid: usize, power: f64, rng: &mut ChaCha8Rng) -> usize {
    let mut counts = vec![0usize; grid * grid];
    for &c in cells {
        counts[c] += 1;
    }
    let weights: Vec<(usize, f64)> = counts
        .iter()
        .enumerate()
        .filter(|(_, &n)| n > 0)
        .map(|(c, &n)| (c, (n as f64).powf(power)))
        .collect();
    let total: f64 = weights.iter().map(|w| w.1).sum();
    let mut r = rng.random::<f64>() * total;
    let mut cell = weights.last().map(|w| w.0).unwrap_or(0);
    for &(c, w) in &weights {
        if r < w {
            cell = c;
            break;
        }
        r -= w;
    }
    let inside: Vec<usize> = (0..cells.len()).filter(|&i| cells[i] == cell).collect();
    if inside.is_empty() {
        return 0;
    }
    inside[rng.random_range(0..inside.len())]
}

/// Runs the MOPSO from `seeds`; `objectives` maps an evaluation to its two minimised objectives
/// (non-finite = rejected). Returns the archive sorted by the first objective.
pub fn run_mopso<P: SwarmProblem>(
    problem: &P,
    seeds: &[Vec<f64>],
    objectives: &(dyn Fn(&P::Output) -> [f64; 2] + Sync),
    opts: &MopsoOptions,
) -> ParetoArchive {
    let dim = problem.dim();
    let (lo, hi) = problem.bounds();
    let range: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| b - a).collect();
    let vmax: Vec<f64> = range.iter().map(|r| 0.2 * r).collect();
    let n_part = opts.particles.max(seeds.len()).max(1);
    struct Part<W> {
        x: Vec<f64>,
        v: Vec<f64>,
        best_x: Vec<f64>,
        best_o: [f64; 2],
        rng: ChaCha8Rng,
        ws: W,
    }
    let mut swarm: Vec<Part<P::Workspace>> = (0..n_part)
        .map(|i| {
            let mut rng = ChaCha8Rng::seed_from_u64(opts.seed);
            rng.set_stream(i as u64);
            let x: Vec<f64> = if i < seeds.len() {
                seeds[i].clone()
            } else {
                let s = &seeds[i % seeds.len().max(1)];
                (0..dim)
                    .map(|d| {
                        let r = rng.random::<f64>() * 2.0 - 1.0;
                        let spread = if i % 2 == 0 { 0.05 } else { 0.2 };
                        (s[d] + r * spread * range[d]).clamp(lo[d], hi[d])
                    })
                    .collect()
            };
            Part {
                best_x: x.clone(),
                v: vec![0.0; dim],
                x,
                best_o: [f64::INFINITY; 2],
                rng,
                ws: problem.workspace(),
            }
        })
        .collect();
    let mut arng = ChaCha8Rng::seed_from_u64(opts.seed);
    arng.set_stream(u64::MAX);
    let mut archive = ParetoArchive {
        members: Vec::new(),
    };
    let mut leaders = vec![0usize; n_part];
    for it in 0..=opts.iterations {
        if it > 0 && !archive.members.is_empty() {
            for l in leaders.iter_mut() {
                *l = archive.select_leader(opts.grid, opts.beta, &mut arng);
            }
            let pm = (1.0 - (it - 1) as f64 / opts.iterations.max(1) as f64)
                .max(0.0)
                .powf(1.0 / opts.mutation);
            let arch = &archive;
            swarm.par_iter_mut().zip(&leaders).for_each(|(p, &l)| {
                let g = &arch.members[l].position;
                for d in 0..dim {
                    let (r1, r2): (f64, f64) = (p.rng.random(), p.rng.random());
                    let v = CHI
                        * (p.v[d]
                            + C_ACC * r1 * (p.best_x[d] - p.x[d])
                            + C_ACC * r2 * (g[d] - p.x[d]));
                    p.v[d] = v.clamp(-vmax[d], vmax[d]);
                    p.x[d] = (p.x[d] + p.v[d]).clamp(lo[d], hi[d]);
                }
                if p.rng.random::<f64>() < pm {
                    let d = p.rng.random_range(0..dim);
                    let w = pm * range[d];
                    let a = (p.x[d] - w).max(lo[d]);
                    let b = (p.x[d] + w).min(hi[d]);
                    p.x[d] = a + p.rng.random::<f64>() * (b - a);
                }
            });
        }
        let results: Vec<(Vec<f64>, [f64; 2])> = swarm
            .par_iter_mut()
            .map(|p| {
                problem.repair(&mut p.x, &mut p.ws);
                let out = problem.evaluate(&p.x, &mut p.ws);
                let o = objectives(&out);
                let better = dominates(&o, &p.best_o)
                    || (!dominates(&p.best_o, &o) && p.rng.random::<f64>() < 0.5);
                if better && o.iter().all(|v| v.is_finite()) {
                    p.best_o = o;
                    p.best_x.copy_from_slice(&p.x);
                }
                (p.x.clone(), o)
            })
            .collect();
        for (x, o) in results {
            archive.insert(ArchiveMember {
                position: x,
                objectives: o,
            });
        }
        archive.truncate(opts.archive_size, opts.grid, opts.gamma, &mut arng);
    }
    archive
        .members
        .sort_by(|a, b| a.objectives[0].total_cmp(&b.objectives[0]));
    archive
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::search::pso::Fitness;

    /// Schaffer's problem N.1 in 1-D on [-5, 5]: f1 = x², f2 = (x − 2)²; front x ∈ [0, 2].
    struct Schaffer;
    impl SwarmProblem for Schaffer {
        type Workspace = ();
        type Output = [f64; 2];
        fn dim(&self) -> usize {
            1
        }
        fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
            (vec![-5.0], vec![5.0])
        }
        fn workspace(&self) {}
        fn evaluate(&self, x: &[f64], _: &mut ()) -> [f64; 2] {
            [x[0] * x[0], (x[0] - 2.0) * (x[0] - 2.0)]
        }
        fn fitness(&self, o: &[f64; 2]) -> Fitness {
            Fitness {
                violation: 0.0,
                objective: o[0] + o[1],
            }
        }
    }

    #[test]
    fn archive_holds_no_dominated_point_and_covers_the_schaffer_front() {
        let opts = MopsoOptions {
            seed: 9,
            ..MopsoOptions::default()
        };
        let a = run_mopso(&Schaffer, &[vec![4.0]], &|o| *o, &opts);
        assert!(a.members.len() >= 20, "{}", a.members.len());
        for m in &a.members {
            // every member lies on the true front: x in [0, 2] (up to the swarm's precision)
            assert!(
                m.position[0] > -1e-3 && m.position[0] < 2.0 + 1e-3,
                "{:?}",
                m.position
            );
            for n in &a.members {
                assert!(!dominates(&n.objectives, &m.objectives));
            }
        }
        // the front spans most of its range
        let xs: Vec<f64> = a.members.iter().map(|m| m.position[0]).collect();
        let (mn, mx) = xs
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(mn < 0.2 && mx > 1.8, "{mn} {mx}");
    }

    #[test]
    fn insertion_removes_dominated_members() {
        let mut a = ParetoArchive::default();
        let m = |x: f64, y: f64| ArchiveMember {
            position: vec![],
            objectives: [x, y],
        };
        assert!(a.insert(m(1.0, 5.0)));
        assert!(a.insert(m(2.0, 3.0)));
        assert!(!a.insert(m(2.0, 4.0))); // dominated by (2, 3)
        assert!(!a.insert(m(2.0, 3.0))); // duplicate
        assert!(!a.insert(m(f64::NAN, 0.0)));
        assert!(a.insert(m(0.5, 3.0))); // dominates both
        assert_eq!(a.members.len(), 1);
        assert_eq!(a.members[0].objectives, [0.5, 3.0]);
    }
}
