//! Typed progress of the integrated method: the [`Stage`] a fit reports, as
//! [`crate::surface::Stage`] does for surfaces.
//!
//! The stages call an untyped `Fn(control_points, iteration)`; `untyped` turns a typed callback
//! into one, so a caller sees only [`Stage`] values.

/// What a running fit is doing, reported by
/// [`fit_integrated_with_stages`](super::fit_integrated_with_stages).
///
/// Reports come from the thread running the search concerned: with a degree search every degree
/// reports from its own worker, so iterations of different counts interleave.
///
/// ```
/// use fairfit::optim::Stage;
/// let s = Stage::KnotSearch { control_points: 12, iteration: 3 };
/// assert_eq!(s.to_string(), "12 control points");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Stage {
    /// A swarm iteration of a knot search (a feasibility probe or a full search) at
    /// `control_points` control points.
    KnotSearch {
        /// The control-point count searched.
        control_points: usize,
        /// The swarm iteration just finished (0: the initial swarm).
        iteration: usize,
    },
}

impl std::fmt::Display for Stage {
    /// A short label for a progress bar (e.g. `12 control points`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stage::KnotSearch { control_points, .. } => {
                write!(f, "{control_points} control points")
            }
        }
    }
}

/// The untyped `(control_points, iteration)` callback the stages call, reporting to `typed`.
pub(crate) fn untyped(typed: &(dyn Fn(Stage) + Sync)) -> impl Fn(usize, usize) + Sync + '_ {
    move |control_points, iteration| {
        typed(Stage::KnotSearch {
            control_points,
            iteration,
        })
    }
}
