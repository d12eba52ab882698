//! Fairing a knot vector's control points inside the tolerance band: the last stages of the
//! integrated method, after the knot search has fixed the knots and the control-point count.
//!
//! Bottom to top (a module imports only from the ones above it in this list, from `optim`'s
//! search layer and from the crate's lower layers):
//!
//! - [`tuning`]: [`FairingTuning`], the measured policy of band fairing and the polish;
//! - [`cone_algebra`]: the second-order cone's Jordan algebra, NT scaling, a small Cholesky;
//! - [`band_qp`]: band fairing's convex subproblem (a QP with small second-order cones and linear
//!   rows) and its general (clarabel) solver;
//! - `cone_newton`: the Newton system of the interior-point iterations;
//! - [`cone_ipm`]: a dense primal–dual interior-point solver for that subproblem's shape;
//! - `nodes`: node rules (basis derivatives precomputed at fixed parameters) and `dκ/ds` sign
//!   changes;
//! - [`extrema`]: the curvature-extrema count the band fairing and polish guards use;
//! - [`curvature_signs`]: the sign pattern of `dκ/ds` band fairing keeps (low-persistence
//!   curvature extrema removed);
//! - [`control_map`]: the control points the fairing stages move (open: interior or all;
//!   periodic: distinct), [`EndCondition`];
//! - [`band`]: all control points faired together inside the tolerance band (sequential convex
//!   programming), and the later passes after the polish;
//! - [`mod@polish`]: local control-point fairing moves within the tolerance;
//! - [`periodic`]: band fairing and polish of a periodic curve (seam kept `C^(p−1)`).

pub mod band;
pub mod band_qp;
pub mod cone_algebra;
pub mod cone_ipm;
pub(crate) mod cone_newton;
pub mod control_map;
pub mod curvature_signs;
pub mod extrema;
pub(crate) mod nodes;
pub mod periodic;
pub mod polish;
pub mod tuning;

pub use band::{band_fair, later_passes, refair, BandOptions};
pub use control_map::EndCondition;
pub use periodic::fair_periodic;
pub use polish::{polish, PolishOptions, Polished};
pub use tuning::{BandTuning, FairingTuning, PolishTuning, StepTuning};
