//! The second start of the count descent ([`super::knot_edits::descend`]) of an open curve.
//!
//! The descent's greedy removals are deterministic; its probes are not, and where a probe lands
//! decides the knots of every count below it. The count search's swarms stay close to their seeds
//! (3 % spread, one random particle in 16), so on whitcomb at `--seed 2` its searches and a restart
//! from the same seeds on another random stream all finish with 9 curvature extrema (splprep: 8).
//! The **second descent** ([`second_descent`]) starts where the first one ran its first probe and
//! probes on other random streams ([`RESTART_SALT`]); its knots seed the count search's restart
//! ([`super::count_search`]; the first descent's count and knots are kept, so the count search
//! starts as before).

use super::count_search::CountFamily;
use super::integrated::{IntegratedOptions, OptimStats};
use super::knot_edits::{descend, Descent};

/// Added to the probes' salts on the second descent (an independent stream of the same seed).
pub(crate) const RESTART_SALT: u64 = 3_000_017;

/// The knots met by the second descent of `first` (module doc), by count, from its first probe's
/// start down to `lowest` (`removals` as for [`descend`]); empty when `first` made no probe.
#[allow(clippy::too_many_arguments)]
pub(crate) fn second_descent<C: CountFamily>(
    family: &C,
    first: &Descent,
    lowest: usize,
    tol: f64,
    removals: impl Fn(&[f64]) -> Vec<(f64, Vec<f64>)>,
    opts: &IntegratedOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    stats: &mut OptimStats,
) -> Vec<(usize, Vec<f64>)> {
    let Some((n, knots)) = first.probe_start.clone() else {
        return Vec::new();
    };
    let mut down = Descent {
        salt: RESTART_SALT,
        ..Descent::new(n, knots)
    };
    descend(
        family, &mut down, lowest, tol, removals, false, opts, progress, stats,
    );
    down.met
}
