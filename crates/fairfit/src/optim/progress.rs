//! Typed progress of the integrated method: the [`Stage`] a fit is in, reported with how far it is
//! (`done` of `total` steps), as [`crate::surface::Stage`] does for surfaces.
//!
//! Every pipeline reports its stages in the order of the map in [`super`]: the screening, the
//! reduction of dense data (when it applies), the least-squares
//! baseline, the count descent's probes, the count search's swarms, the band fairing of its
//! candidates, the degree search, the release of the ends. Progress only observes: the result
//! does not depend on the callback.

/// The stage a running fit is in, reported by
/// [`fit_integrated_with_stages`](super::fit_integrated_with_stages) with `(done, total)`.
///
/// Reports come from the thread running the work concerned: swarms at several counts, the pieces
/// between corners and the degree search's candidates run side by side, so reports of different
/// stages and counts interleave, and `done` may repeat or step back between them.
///
/// ```
/// use fairfit::optim::Stage;
/// let s = Stage::CountSearch { control_points: 12 };
/// assert_eq!(s.to_string(), "count search, 12 points");
/// assert_eq!(Stage::BandFairing.to_string(), "band fairing");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Stage {
    /// The screening of the data before any fit: noise, spikes, a tolerance below the noise
    /// ([`crate::fit::screening`]; `done` 0 of 1 when it starts).
    Screening,
    /// The reduction of dense data to representatives of tolerance-sized arcs
    /// (`optim/stages/reduce.rs`; `done` 0 of 1 when it starts; reported only when it applies).
    Reduce,
    /// The least-squares baseline (`done` 0 of 1 when it starts).
    Baseline,
    /// A feasibility probe of the count descent at `control_points` (`done`: swarm iterations of
    /// the probe's budget).
    Descent {
        /// The control-point count probed.
        control_points: usize,
    },
    /// A full swarm search of the count search at `control_points` (`done`: swarm iterations of
    /// the search's budget).
    CountSearch {
        /// The control-point count searched.
        control_points: usize,
    },
    /// The band fairing of the count search's candidates (`done` of `total` candidates finished).
    BandFairing,
    /// The degree search: the next degrees tried at the reference's counts (`done` 0 of 1 when it
    /// starts).
    DegreeSearch,
    /// The last fairing pass of an open curve, with the requested end condition (`done` 0 of 1
    /// when it starts).
    ReleaseEnds,
}

impl std::fmt::Display for Stage {
    /// A short label for a progress bar (e.g. `count search, 12 points`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stage::Screening => f.write_str("screening"),
            Stage::Reduce => f.write_str("reduction"),
            Stage::Baseline => f.write_str("least-squares baseline"),
            Stage::Descent { control_points } => write!(f, "descent, {control_points} points"),
            Stage::CountSearch { control_points } => {
                write!(f, "count search, {control_points} points")
            }
            Stage::BandFairing => f.write_str("band fairing"),
            Stage::DegreeSearch => f.write_str("degree search"),
            Stage::ReleaseEnds => f.write_str("release ends"),
        }
    }
}
