//! The count descent: from the baseline's count, one control point fewer at a time while the
//! tolerance (and `F*`) can be met, by the best single-knot removal, else by a short swarm probe
//! (seeded with the three best removals and the spread knots); the first count where the probe
//! finds nothing ends it. The feasible knots met on the way down, by count, seed the count
//! search.
//!
//! The greedy removals are deterministic; the probes are not, and where a probe lands decides the
//! knots of every count below it. So an open curve's descent is run a second time from where the
//! first one ran its first probe, with the probes on other random streams (`SECOND_DESCENT_SALT`);
//! its knots seed the count search's restart ([`super::count_search`]). With a fixed count the
//! tolerance cannot reach, the least harmful removals (or the spread knots) are taken instead of
//! probes.

use super::baseline::BaselineOutput;
use crate::optim::context::FitContext;
use crate::optim::kind::CurveKind;
use crate::optim::options::IntegratedOptions;
use crate::optim::progress::Stage;
use crate::optim::result::OptimStats;
use crate::optim::search::problem::CountProblem;
use crate::optim::search::pso::run_pso;

/// Added to the probes' salts on the second descent (an independent stream of the same seed).
pub(crate) const SECOND_DESCENT_SALT: u64 = 3_000_017;

/// Where the descent starts and how it runs.
#[derive(Clone, Debug)]
pub(crate) struct DescentInput {
    /// The starting count (the baseline's, or a fixed count above it).
    pub n: usize,
    /// Its interior knots.
    pub knots: Vec<f64>,
    /// The descent stops here.
    pub lowest: usize,
    /// Take the least harmful removal where the tolerance cannot be met (a fixed count).
    pub force: bool,
    /// Run the second descent on other random streams (open curves).
    pub second: bool,
    /// A fixed count the descent did not reach: the knots that hurt least are removed anyway.
    pub trim_to: Option<usize>,
}

impl DescentInput {
    /// The open pipeline's descent from `base`: down to the degree's fewest control points (or
    /// the fixed count, never below `min_control_points`), a second descent on other streams, the
    /// fixed count trimmed to when the descent stops above it.
    pub fn open(
        base: &BaselineOutput,
        opts: &IntegratedOptions,
        min_control_points: usize,
    ) -> Self {
        let p = opts.degree;
        let fixed = opts.control_points;
        DescentInput {
            n: base.n,
            knots: base.knots.clone(),
            lowest: fixed.unwrap_or(p + 1).max(p + 1).max(min_control_points),
            force: false,
            second: true,
            trim_to: fixed,
        }
    }

    /// The periodic pipeline's descent from `base`: down to the degree's fewest control points
    /// (or the fixed count, reached by force), no second descent.
    pub fn periodic(base: &BaselineOutput, opts: &IntegratedOptions) -> Self {
        let p = opts.degree;
        let fixed = opts.control_points;
        DescentInput {
            n: base.n,
            knots: base.knots.clone(),
            lowest: fixed.unwrap_or(p + 1).max(p + 1),
            force: fixed.is_some(),
            second: false,
            trim_to: None,
        }
    }
}

/// What the descent found.
#[derive(Clone, Debug)]
pub(crate) struct DescentOutput {
    /// The smallest feasible count (or the fixed one).
    pub n: usize,
    /// Its interior knots.
    pub knots: Vec<f64>,
    /// The feasible knots met on the way down, by count.
    pub met: Vec<(usize, Vec<f64>)>,
    /// The second descent's feasible knots by count (empty: none).
    pub alt: Vec<(usize, Vec<f64>)>,
}

/// The count descent of `kind` (module doc).
pub(crate) fn run<K: CurveKind>(ctx: &FitContext, kind: &K, input: DescentInput) -> DescentOutput {
    let mut stats = ctx.stats();
    let mut down = Descent::new(input.n, input.knots);
    descend(ctx, kind, &mut down, input.lowest, input.force, &mut stats);
    let alt = if input.second {
        second_descent(ctx, kind, &down, input.lowest, &mut stats)
    } else {
        Vec::new()
    };
    let Descent {
        n: mut best_n,
        knots: mut best_knots,
        met,
        ..
    } = down;
    if let Some(n) = input.trim_to {
        // the tolerance cannot be met at the fixed count: remove the knots that hurt least anyway
        while best_n > n {
            match kind.removal_candidates(&best_knots).into_iter().next() {
                Some((_, k)) => best_knots = k,
                None => best_knots = kind.spread_knots(n),
            }
            best_n -= 1;
        }
    }
    DescentOutput {
        n: best_n,
        knots: best_knots,
        met,
        alt,
    }
}

/// The knots met by the second descent of `first` (module doc), by count, from its first probe's
/// start down to `lowest`; empty when `first` made no probe.
fn second_descent<K: CurveKind>(
    ctx: &FitContext,
    kind: &K,
    first: &Descent,
    lowest: usize,
    stats: &mut OptimStats,
) -> Vec<(usize, Vec<f64>)> {
    let Some((n, knots)) = first.probe_start.clone() else {
        return Vec::new();
    };
    let mut down = Descent {
        salt: SECOND_DESCENT_SALT,
        ..Descent::new(n, knots)
    };
    descend(ctx, kind, &mut down, lowest, false, stats);
    down.met
}

/// The count descent: the current count and knots, and the feasible knots met on the way down.
struct Descent {
    /// The current (smallest so far) count.
    pub n: usize,
    /// Its knots.
    pub knots: Vec<f64>,
    /// The knots met at every count, from the start down.
    pub met: Vec<(usize, Vec<f64>)>,
    /// The count and knots the first probe started from (`None`: no probe yet).
    pub probe_start: Option<(usize, Vec<f64>)>,
    /// Added to the probes' salts (0; another stream for the second descent, [`SECOND_DESCENT_SALT`]).
    pub salt: u64,
}

impl Descent {
    /// The descent starting at `n` control points with `knots`.
    fn new(n: usize, knots: Vec<f64>) -> Self {
        Descent {
            n,
            met: vec![(n, knots.clone())],
            knots,
            probe_start: None,
            salt: 0,
        }
    }

    /// One count down to `knots`.
    fn step(&mut self, knots: Vec<f64>) {
        self.n -= 1;
        self.met.push((self.n, knots.clone()));
        self.knots = knots;
    }

    /// One count down by the best single-knot removal of `removals` (the removal candidates of the
    /// current knots, counted in `stats`) when it meets `tol`; else the removals are handed back.
    fn remove(
        &mut self,
        removals: Vec<(f64, Vec<f64>)>,
        tol: f64,
        stats: &mut OptimStats,
    ) -> Result<(), Vec<(f64, Vec<f64>)>> {
        stats.counts_tried.push(self.n - 1);
        stats.evaluations += self.knots.len();
        match removals.first() {
            Some((dev, k)) if *dev <= tol => {
                let k = k.clone();
                self.step(k);
                Ok(())
            }
            _ => Err(removals),
        }
    }
}

/// Runs the count descent of `family` from `down` towards `lowest`: one count down at a time by
/// the best single-knot removal ([`CurveKind::removal_candidates`] of the current knots) when
/// it meets `tol`, else by a short swarm probe (stops at the first feasible position, seeded with
/// the three best removals and the spread knots); the first count where the probe finds nothing
/// ends it. With `force` (a fixed count the tolerance cannot reach) the least harmful removal (or
/// the spread knots) is taken instead of a probe.
fn descend<K: CurveKind>(
    ctx: &FitContext,
    family: &K,
    down: &mut Descent,
    lowest: usize,
    force: bool,
    stats: &mut OptimStats,
) {
    let (tol, opts, progress) = (ctx.tol, ctx.opts, ctx.progress);
    while down.n > lowest {
        let cand = down.n - 1;
        let removals = match down.remove(family.removal_candidates(&down.knots), tol, stats) {
            Ok(()) => continue,
            Err(removals) => removals,
        };
        if force {
            match removals.into_iter().next() {
                Some((_, k)) => down.step(k),
                None => down.step(family.spread_knots(cand)),
            }
            continue;
        }
        if down.probe_start.is_none() {
            down.probe_start = Some((down.n, down.knots.clone()));
        }
        let pr = family.problem(cand);
        let mut seeds: Vec<Vec<f64>> = removals
            .iter()
            .take(ctx.tuning.descent.probe_removal_seeds)
            .map(|(_, k)| pr.position(k))
            .collect();
        seeds.push(pr.position(&family.spread_knots(cand)));
        let r = run_pso(
            &pr,
            &seeds,
            &ctx.tuning
                .swarm
                .options(opts, opts.probe_iterations, true, cand as u64 + down.salt),
            &|it| {
                let stage = Stage::Descent {
                    control_points: cand,
                };
                progress(stage, it, opts.probe_iterations)
            },
        );
        stats.evaluations += r.evaluations;
        stats.iterations += r.iterations;
        let Some(k) = r
            .fitness
            .feasible()
            .then(|| pr.decode(&r.position))
            .flatten()
        else {
            break;
        };
        down.step(k);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_descent_step_records_the_knots_met() {
        let mut d = Descent::new(7, vec![0.2, 0.5, 0.8]);
        let mut stats = OptimStats::default();
        let removals = vec![(0.5, vec![0.2, 0.8]), (0.9, vec![0.5, 0.8])];
        // the best removal misses the tolerance: handed back, nothing changes
        let back = d.remove(removals.clone(), 0.1, &mut stats).unwrap_err();
        assert_eq!(back, removals);
        assert_eq!((d.n, d.met.len()), (7, 1));
        // within it: one count down
        assert!(d.remove(removals, 0.6, &mut stats).is_ok());
        assert_eq!((d.n, d.knots.clone()), (6, vec![0.2, 0.8]));
        assert_eq!(d.met, vec![(7, vec![0.2, 0.5, 0.8]), (6, vec![0.2, 0.8])]);
        assert_eq!(
            (stats.counts_tried.clone(), stats.evaluations),
            (vec![6, 6], 6)
        );
    }
}
