//! The sign pattern `dκ/ds` should follow: curvature extrema of low persistence removed.
//!
//! Band fairing minimises `F = L³ ∫(dκ/ds)² ds` under point constraints; the minimiser's curvature
//! bends where a data point touches the band, so `κ(s)` tends to get small kinks (often exactly at
//! knots, where `dκ/ds` may jump) that are extrema of their own: a fair curve by `F`, but with
//! more curvature extrema than a plain least-squares fit. [`target_signs`] takes the signs of
//! `dκ/ds` along the curve (with the benchmark's hysteresis floor), cuts them into runs of one sign
//! and merges away the run with the smallest curvature change `|Δκ|` while that change is below
//! `theta` times the curve's curvature range (a run inside the curve merges with both neighbours,
//! removing two extrema; a run at an end with its one neighbour, removing one). This is the
//! persistence simplification of the curvature profile: big features (a leading edge's peak,
//! a real inflection region) stay, small wiggles go. Band fairing then asks every node to follow
//! its run's sign ([`super::band`]).

/// Hysteresis floor of the extrema count on `signal` (the benchmark measurer's: `1e-6` of the
/// largest magnitude plus `1e-9`, on `dκ/ds L²`).
pub(crate) fn hysteresis_floor(signal: &[f64]) -> f64 {
    1e-6 * signal.iter().fold(0.0f64, |a, v| a.max(v.abs())) + 1e-9
}

/// One run of equal sign: `[start, end)` node range, sign, curvature change.
#[derive(Clone, Copy, Debug)]
struct Run {
    start: usize,
    end: usize,
    sign: i8,
    delta: f64,
}

/// Target signs (`+1`, `−1`) of `dκ/ds` at the nodes, written into `out`; returns the number of
/// extrema the pattern has (its runs minus one).
///
/// `signal[g]` is `dκ/ds` at node `g` in any positive scaling (its sign and the hysteresis floor
/// decide the runs; nodes inside the floor belong to the run around them) and `increment[g]` the
/// curvature change the node carries (`w_g dκ/du`, so that a run's sum is its `Δκ`). Nodes are in
/// parameter order. A curve whose `dκ/ds` never leaves the floor gets all zeros (no target).
pub fn target_signs(signal: &[f64], increment: &[f64], theta: f64, out: &mut Vec<i8>) -> usize {
    out.clear();
    out.resize(signal.len(), 0);
    let floor = hysteresis_floor(signal);
    let mut runs: Vec<Run> = Vec::new();
    for (g, (&v, &inc)) in signal.iter().zip(increment).enumerate() {
        let s = if v >= floor {
            1
        } else if v <= -floor {
            -1
        } else {
            0
        };
        match runs.last_mut() {
            Some(r) if s == 0 || s == r.sign => {
                r.end = g + 1;
                r.delta += inc;
            }
            _ if s != 0 => runs.push(Run {
                start: g,
                end: g + 1,
                sign: s,
                delta: inc,
            }),
            _ => {}
        }
    }
    let Some(first) = runs.first_mut() else {
        return 0;
    };
    // nodes before the first signed node belong to the first run
    first.start = 0;
    if let Some(last) = runs.last_mut() {
        last.end = signal.len();
    }
    // the curvature range: extremes of the running sum of increments
    let (mut k, mut lo, mut hi) = (0.0f64, 0.0f64, 0.0f64);
    for inc in increment {
        k += inc;
        lo = lo.min(k);
        hi = hi.max(k);
    }
    let limit = theta * (hi - lo);
    while runs.len() > 1 {
        let (i, small) = runs
            .iter()
            .enumerate()
            .map(|(i, r)| (i, r.delta.abs()))
            .fold((0, f64::INFINITY), |b, c| if c.1 < b.1 { c } else { b });
        if small >= limit {
            break;
        }
        let last = runs.len() - 1;
        let (a, b) = if i == 0 {
            (0, 1)
        } else if i == last {
            (last - 1, last)
        } else {
            (i - 1, i + 1)
        };
        let sign = if i == 0 { runs[1].sign } else { runs[a].sign };
        let merged = Run {
            start: runs[a].start,
            end: runs[b].end,
            sign,
            delta: runs[a..=b].iter().map(|r| r.delta).sum(),
        };
        runs.splice(a..=b, [merged]);
    }
    for r in &runs {
        out[r.start..r.end].fill(r.sign);
    }
    runs.len() - 1
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sampled profile `κ(s)` on a uniform grid: the signal is its difference quotient.
    fn profile(kappa: impl Fn(f64) -> f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let h = 1.0 / n as f64;
        let inc: Vec<f64> = (0..n)
            .map(|g| kappa((g as f64 + 1.0) * h) - kappa(g as f64 * h))
            .collect();
        (inc.iter().map(|d| d / h).collect(), inc)
    }

    #[test]
    fn a_small_wiggle_on_a_peak_is_merged_and_the_peak_kept() {
        // κ = 100 exp(−50 (s − 0.5)²) (one peak, range ≈ 100) plus a wiggle of amplitude 0.5 at
        // s = 0.8: 3 extrema (peak + wiggle's max and min). theta 2 %: only the peak remains,
        // rising before it and falling after it.
        let k = |s: f64| {
            100.0 * (-50.0 * (s - 0.5) * (s - 0.5)).exp()
                + 0.5 * (40.0 * (s - 0.8)).sin() * {
                    let d = (s - 0.8) / 0.06;
                    (-d * d).exp()
                }
        };
        let (sig, inc) = profile(k, 1000);
        let mut out = Vec::new();
        assert_eq!(target_signs(&sig, &inc, 0.0, &mut out), 3);
        assert_eq!(target_signs(&sig, &inc, 0.02, &mut out), 1);
        assert!(out[..500].iter().all(|&s| s == 1));
        assert!(out[501..].iter().all(|&s| s == -1));
    }

    #[test]
    fn a_large_second_feature_stays() {
        // two peaks of 100 and 30 with a dip to ≈ 0 between them: 3 extrema of large persistence
        let k = |s: f64| {
            100.0 * (-200.0 * (s - 0.3) * (s - 0.3)).exp()
                + 30.0 * (-200.0 * (s - 0.7) * (s - 0.7)).exp()
        };
        let (sig, inc) = profile(k, 1000);
        let mut out = Vec::new();
        assert_eq!(target_signs(&sig, &inc, 0.1, &mut out), 3);
        // theta above 30 % of the range merges the second peak (change 30 < 0.35 * 100)
        assert_eq!(target_signs(&sig, &inc, 0.35, &mut out), 1);
    }

    #[test]
    fn a_flat_profile_has_no_target() {
        let sig = vec![0.0; 10];
        let mut out = Vec::new();
        assert_eq!(target_signs(&sig, &sig, 0.1, &mut out), 0);
        assert!(out.iter().all(|&s| s == 0));
    }
}
