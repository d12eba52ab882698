//! Particle swarm optimisation of knot vectors: the integrated fitting-and-fairing method.
//!
//! [`fit_integrated`] searches the knot vector by particle swarm optimisation so that the curve
//! stays within the tolerance of the data while its fairness `F` (and the worst span's `F_j`) is
//! as small as possible, with the fewest control points that allow it.
//!
//! # Pipelines
//!
//! `pipeline` (`pipeline.rs`) validates the options, reduces dense data
//! (`stages::reduce`, `stages/reduce.rs`: representative points of tolerance-sized arcs, the fit
//! then verified against every input point and repaired), and sends the data to one pipeline;
//! none calls back into it:
//!
//! - closed data → `closed` (`closed.rs`): periodic without corners, else cut at the first
//!   corner and fitted as open data;
//! - open data → `cornered` (`cornered.rs`): with corners, every piece between them by the open
//!   pipeline, a shared budget for a fixed count, the pieces joined C0 (`corners`); without
//!   corners, the open pipeline;
//! - `open` (`open.rs`), the open pipeline, runs these stages in order:
//!
//! 1. **least-squares baseline** — `stages::baseline` (`stages/baseline.rs`): the fewest
//!    control points the least-squares knots need to meet the tolerance, and the descent's start;
//! 2. **count descent** — `stages::descent` (`stages/descent.rs`): one control point fewer at a
//!    time while the tolerance can be met, then a second descent on other random streams;
//! 3. **count search** — `stages::count_search` (`stages/count_search.rs`): full searches at
//!    the smallest feasible count and above, every candidate finished, the count chosen on the
//!    finished curves; beside it the next degree's first candidate,
//!    `stages::degree_candidates` (`stages/degree_candidates.rs`);
//! 4. **degree search** — `stages::own_count_search` (`stages/own_count_search.rs`: the next
//!    degree's own count search when a trigger fires) and `stages::degree_search`
//!    (`stages/degree_search.rs`: the rule that keeps one degree);
//! 5. **release ends** — `stages::release_ends` (`stages/release_ends.rs`): the last fairing
//!    pass with the requested end condition.
//!
//! [`chain`] (`chain.rs`) fits several point sets as one chain of curves joining with G1 or G2
//! continuity, each piece by [`fit_integrated`].
//!
//! The closed pipeline runs stages 1-4 on the periodic kind. The `--pareto` fronts are in
//! `pareto` (`pareto/`).
//!
//! # Layers
//!
//! Bottom to top; a module imports only from its own layer or below:
//!
//! 1. `search` (`search/`): the swarm, the per-candidate objectives, the knot encoding;
//! 2. `fairing` (`fairing/`): finishing a knot vector's control points inside the tolerance
//!    band (band fairing by sequential convex programming, the polish, the periodic variants);
//! 3. `options` (`options.rs`), `result` (`result.rs`); [`tuning`] (`tuning.rs`: every
//!    measured threshold of the policy), `context.rs` (the context every stage reads);
//! 4. `kind` (`kind/`): the curve kinds, open and periodic, behind one trait;
//! 5. `stages` (`stages/`): the stages above, written once against the curve kind;
//! 6. the pipelines (`open` < `cornered` < `closed` < `pipeline` < `chain`), `corners`, and
//!    `pareto`.

// index loops over bands and spans read like the formulas they implement
#![allow(clippy::needless_range_loop)]

pub mod chain;
pub(crate) mod closed;
pub(crate) mod condition_checks;
pub(crate) mod context;
pub(crate) mod cornered;
pub(crate) mod corners;
pub(crate) mod fairing;
pub(crate) mod kind;
pub(crate) mod open;
pub(crate) mod options;
pub(crate) mod pareto;
pub(crate) mod pipeline;
pub(crate) mod progress;
pub(crate) mod result;
pub(crate) mod search;
pub(crate) mod stages;
pub mod tuning;

pub use crate::fit::closure::Closure;
pub use crate::fit::tolerance::ClosedMode;
pub use crate::tolerance::Tolerance;
pub use closed::{closure, is_closed};
pub use fairing::EndCondition;
pub use kind::periodic::distinct_control_points;
pub use options::{Budget, IntegratedOptions, NonExhaustive};
pub use pareto::{pareto_csv, pareto_front, pareto_front_of_result, ParetoCurve};
pub use pipeline::{fit_integrated, fit_integrated_with_stages, fit_lsq_baseline};
pub use progress::Stage;
pub use result::{DegreeTrial, FitQuality, IntegratedResult, OptimStats};
pub use tuning::Tuning;
