//! The knot-vector edits and start-up steps the open ([`super::integrated`]) and periodic
//! ([`super::closed`]) searches share, on interior knots (or breakpoints) in `(0, 1)`:
//!
//! - [`lsq_method_fit`], [`map_knots`]: the least-squares method's own fit of the data and its knots
//!   mapped piecewise linearly onto the search's parameters (the baseline's start);
//! - [`Descent`]: the count descent's state, and [`removal_candidates`], every single-knot
//!   removal refitted and ranked by its maximum deviation;
//! - [`descend`]: the descent itself, by removals and short swarm probes;
//! - [`insertion_spans`]: the spans an inserted knot may split.
//!
//! Only the candidate evaluation differs between open and periodic curves; it is passed in.

use super::count_search::{pso_options, CountFamily, CountProblem};
use super::encoding::KnotEncoding;
use super::integrated::{IntegratedOptions, OptimStats};
use super::objective::CandidateEval;
use super::pso::run_pso;
use crate::fit::tolerance::{fit_to_tolerance, ClosedMode, FitOptions, FitResult, Tolerance};
use crate::nurbs::Vec3;
use rayon::prelude::*;

/// The least-squares method's fit (`fit::tolerance`: centripetal as the search, corners off) of
/// the normalised `points` at degree `p` within the absolute tolerance `tol`; `None` when it fails.
pub(crate) fn lsq_method_fit(
    points: &[Vec3],
    p: usize,
    tol: f64,
    closed: ClosedMode,
) -> Option<FitResult> {
    fit_to_tolerance(
        points,
        &FitOptions {
            degree: p,
            tolerance: Tolerance::Absolute(tol),
            closed,
            corner_angle_deg: None,
            parameterization: crate::fit::Parameterization::Centripetal,
            ..FitOptions::default()
        },
    )
    .ok()
}

/// The knots `interior` of a fit with data parameters `from` mapped onto the parameters `onto`
/// of the same points, piecewise linearly between consecutive points.
pub(crate) fn map_knots(interior: &[f64], from: &[f64], onto: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(interior.len());
    for &t in interior {
        let i = from.partition_point(|&u| u <= t).clamp(1, from.len() - 1) - 1;
        let w = from[i + 1] - from[i];
        let a = if w > 0.0 {
            ((t - from[i]) / w).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(onto[i] + a * (onto[i + 1] - onto[i]));
    }
    out
}

/// Every way to remove one interior knot of `knots` (repaired on `params`), evaluated by `eval`
/// without smoothing, sorted by the resulting maximum deviation (ties by knot index):
/// `(deviation, knots)`. Evaluated in parallel (one `W::default()` workspace per worker),
/// collected in order.
pub(crate) fn removal_candidates<W, E>(
    knots: &[f64],
    params: &[f64],
    eval: E,
) -> Vec<(f64, Vec<f64>)>
where
    W: Default + Send,
    E: Fn(&mut W, &[f64]) -> CandidateEval + Sync + Send,
{
    let enc = KnotEncoding::new(knots.len().saturating_sub(1), 0.0, false);
    let mut out: Vec<(usize, f64, Vec<f64>)> = (0..knots.len())
        .into_par_iter()
        .map_init(W::default, |ws, j| {
            let mut k: Vec<f64> = knots.to_vec();
            k.remove(j);
            if !enc.repair(&mut k, params) {
                return (j, f64::INFINITY, k);
            }
            let e = eval(ws, &k);
            let dev = if e.solved {
                e.max_deviation
            } else {
                f64::INFINITY
            };
            (j, dev, k)
        })
        .collect();
    out.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    out.into_iter().map(|(_, d, k)| (d, k)).collect()
}

/// The count descent: the current count and knots, and the feasible knots met on the way down.
pub(crate) struct Descent {
    /// The current (smallest so far) count.
    pub n: usize,
    /// Its knots.
    pub knots: Vec<f64>,
    /// The knots met at every count, from the start down.
    pub met: Vec<(usize, Vec<f64>)>,
    /// The count and knots the first probe started from (`None`: no probe yet).
    pub probe_start: Option<(usize, Vec<f64>)>,
    /// Added to the probes' salts (0; another stream for a second descent, [`super::descent`]).
    pub salt: u64,
}

impl Descent {
    /// The descent starting at `n` control points with `knots`.
    pub fn new(n: usize, knots: Vec<f64>) -> Self {
        Descent {
            n,
            met: vec![(n, knots.clone())],
            knots,
            probe_start: None,
            salt: 0,
        }
    }

    /// One count down to `knots`.
    pub fn step(&mut self, knots: Vec<f64>) {
        self.n -= 1;
        self.met.push((self.n, knots.clone()));
        self.knots = knots;
    }

    /// One count down by the best single-knot removal of `removals` ([`removal_candidates`] of the
    /// current knots, counted in `stats`) when it meets `tol`; else the removals are handed back.
    pub fn remove(
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
/// the best single-knot removal ([`removal_candidates`] of the current knots, by `removals`) when
/// it meets `tol`, else by a short swarm probe (stops at the first feasible position, seeded with
/// the three best removals and the spread knots); the first count where the probe finds nothing
/// ends it. With `force` (a fixed count the tolerance cannot reach) the least harmful removal (or
/// the spread knots) is taken instead of a probe.
#[allow(clippy::too_many_arguments)]
pub(crate) fn descend<C: CountFamily>(
    family: &C,
    down: &mut Descent,
    lowest: usize,
    tol: f64,
    removals: impl Fn(&[f64]) -> Vec<(f64, Vec<f64>)>,
    force: bool,
    opts: &IntegratedOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    stats: &mut OptimStats,
) {
    while down.n > lowest {
        let cand = down.n - 1;
        let removals = match down.remove(removals(&down.knots), tol, stats) {
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
            .take(3)
            .map(|(_, k)| pr.position(k))
            .collect();
        seeds.push(pr.position(&family.spread_knots(cand)));
        let r = run_pso(
            &pr,
            &seeds,
            &pso_options(opts, opts.probe_iterations, true, cand as u64 + down.salt),
            &|it| progress(cand, it),
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

/// The interior knots with `0` and `1` added (the span edges), and the spans holding at least
/// two of `params` strictly inside: those an inserted knot may split.
pub(crate) fn insertion_spans(knots: &[f64], params: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut edges = Vec::with_capacity(knots.len() + 2);
    edges.push(0.0);
    edges.extend_from_slice(knots);
    edges.push(1.0);
    let spans: Vec<usize> = (0..edges.len() - 1)
        .filter(|&j| {
            params
                .iter()
                .filter(|&&u| u > edges[j] && u < edges[j + 1])
                .count()
                >= 2
        })
        .collect();
    (edges, spans)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knots_map_linearly_between_the_points() {
        // points at 0, 0.5, 1 in one parameterisation and 0, 0.2, 1 in the other: 0.25 is halfway
        // through the first interval (0.1), 0.75 halfway through the second (0.6)
        let m = map_knots(&[0.25, 0.5, 0.75], &[0.0, 0.5, 1.0], &[0.0, 0.2, 1.0]);
        let expect = [0.1, 0.2, 0.6];
        for (a, b) in m.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{m:?}");
        }
    }

    #[test]
    fn only_spans_with_two_inner_parameters_may_be_split() {
        let params = [0.05, 0.1, 0.3, 0.6, 0.7, 0.8];
        let (edges, spans) = insertion_spans(&[0.2, 0.5], &params);
        assert_eq!(edges, vec![0.0, 0.2, 0.5, 1.0]);
        // (0, 0.2) holds 0.05 and 0.1, (0.2, 0.5) only 0.3, (0.5, 1) holds three
        assert_eq!(spans, vec![0, 2]);
    }

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
