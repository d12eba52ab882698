//! Particle swarm optimisation of knot vectors: the integrated fitting-and-fairing method.
//!
//! [`fit_integrated`] searches the knot vector by particle swarm optimisation so that the curve
//! stays within the tolerance of the data while its fairness `F` (and the worst span's `F_j`) is
//! as small as possible, with the fewest control points that allow it. It sends the data to one
//! of three pipelines ([`pipeline`]): closed data to [`closed`], data with corners to
//! [`cornered`], and everything else to the open pipeline ([`open`]), which runs these stages in
//! order:
//!
//! 1. **least-squares baseline** ([`stages::baseline`]): the fewest control points the
//!    least-squares method's knots need to meet the tolerance; no count above it is tried;
//! 2. **count descent** ([`stages::descent`]): one control point fewer at a time, by the best
//!    single-knot removal or a short swarm probe, while the tolerance can be met; a second
//!    descent on other random streams seeds the count search's restart;
//! 3. **count search** ([`stages::count_search`]): full swarm searches at the smallest feasible
//!    count and at extra counts, every candidate finished (band fairing, polish) and the count
//!    chosen on the finished curves; beside it, the next degree's first candidate
//!    ([`stages::degree_candidates`]);
//! 4. **degree search** ([`stages::degree_search`], [`stages::degree_candidates`]): the higher
//!    degrees from the chosen count's knots, one degree kept;
//! 5. **release ends** ([`stages::release_ends`]): one more fairing pass on the chosen curve with
//!    the requested end condition.
//!
//! The closed pipeline runs stages 1-4 on the periodic curve kind; the cornered pipeline runs the
//! open pipeline on every piece between corners and joins them C0 ([`corners`]). The stages are
//! written once against the curve kind ([`kind`]: open, periodic) on the search layer
//! ([`search`]: swarm, objectives, encoding); the fairing stages finish a knot vector's control
//! points inside the tolerance band ([`band_fairing`], [`polish`], [`periodic_fairing`] with
//! [`band_qp`], [`cone_ipm`], [`cone_algebra`], [`curvature_signs`], [`control_map`]). Every
//! stage reads one context ([`context`]: data, tolerance, options, [`tuning`], progress,
//! statistics). The `--pareto` fronts are in [`pareto`].
//!
//! Layers, bottom to top (a module imports only from its own layer or below): [`options`],
//! [`result`]; [`search`]; fairing; [`tuning`], [`context`]; [`kind`]; [`stages`]; the
//! pipelines ([`open`], [`cornered`], [`closed`], [`pipeline`]), [`corners`] and [`pareto`].

// index loops over bands and spans read like the formulas they implement
#![allow(clippy::needless_range_loop)]

pub mod band_fairing;
pub mod band_qp;
pub mod closed;
pub mod cone_algebra;
pub mod cone_ipm;
pub(crate) mod cone_newton;
pub(crate) mod context;
pub mod control_map;
pub mod cornered;
pub mod corners;
pub mod curvature_signs;
pub mod kind;
pub mod open;
pub mod options;
pub mod pareto;
pub mod periodic_fairing;
pub mod pipeline;
pub mod polish;
pub mod result;
pub mod search;
pub mod stages;
pub mod tuning;

pub use control_map::EndCondition;
pub use kind::periodic::distinct_control_points;
pub use options::{IntegratedOptions, Tolerance};
pub use pareto::{pareto_csv, pareto_front, pareto_front_of_result, ParetoCurve};
pub use pipeline::{fit_integrated, fit_integrated_with_progress, fit_lsq_baseline};
pub use result::{DegreeTrial, FitQuality, IntegratedResult, OptimStats};
pub use tuning::Tuning;
