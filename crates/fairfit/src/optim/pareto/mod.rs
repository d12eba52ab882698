//! The Pareto fronts of `--pareto`: (maximum deviation, F) trade-offs at a fixed count.
//!
//! - [`front`]: the front of an open curve at a fixed number of control points;
//! - [`joined`]: the front of the returned curve, joined from the pieces' fronts at corners;
//! - [`periodic`]: the front of a periodic closed curve.

pub mod front;
pub mod joined;
pub mod periodic;

pub use front::{pareto_csv, pareto_front, ParetoCurve};
pub use joined::pareto_front_of_result;
