//! Least-squares fitting of ordered points: point input, parameterisation, knot placement, banded
//! least squares with optional smoothing, parameter correction, closed curves, corners and
//! tolerance-driven knot counts; an airfoil's leading edge ([`airfoil`]); dense samples of a CAD
//! curve ([`sampling`]) and fits held to the exact curve they were sampled from ([`cad_fit`]).

pub mod airfoil;
pub mod banded;
pub mod cad_fit;
pub mod closure;
pub mod constrained_points;
pub mod corners;
pub mod correction;
pub mod data_basis;
pub mod dense;
pub mod deviation;
pub mod end_constraints;
pub mod foot;
pub mod hooks;
pub mod knot_placement;
pub mod lsq;
pub mod method;
pub mod noise;
pub mod outliers;
pub mod parameterize;
pub mod point_constraints;
pub mod points;
pub mod power;
pub mod reduce;
pub mod sampling;
pub mod screening;
pub mod shape;
pub mod tolerance;

pub use deviation::{max_orthogonal_deviation, screened_deviation, Deviation};
pub use lsq::{fit_fixed_knots, LsqOptions, LsqSolver, SmoothingOrder};
pub use parameterize::Parameterization;
pub use tolerance::{fit_to_tolerance, ClosedMode, FitOptions, FitResult, KnotRule, Tolerance};
