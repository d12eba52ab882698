//! The types and functions a user of the library needs, in one import.
//!
//! ```
//! use fairfit::prelude::*;
//! let pts: Vec<Vec3> = (0..60)
//!     .map(|i| {
//!         let t = i as f64 / 59.0 * 1.5;
//!         Vec3::new(2.0 * t.cos(), t.sin(), 0.0)
//!     })
//!     .collect();
//! // the integrated method: fair, within 1e-3 of the data's size, degrees 3 to 5 searched
//! let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).degree_search(5);
//! let fair: IntegratedResult = fit_integrated(&pts, &opts)?;
//! assert!(fair.met && fair.quality.max_deviation <= fair.tolerance);
//! // the least-squares method at the same tolerance
//! let lsq = fit_to_tolerance(&pts, &FitOptions { tolerance: Tolerance::Relative(1e-3), ..FitOptions::default() })?;
//! assert!(lsq.deviation.max <= lsq.tolerance);
//! # Ok::<(), fairfit::Error>(())
//! ```

pub use crate::errors::Error;
pub use crate::fit::{fit_to_tolerance, ClosedMode, FitOptions, FitResult};
pub use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
pub use crate::optim::{
    fit_integrated, fit_integrated_with_stages, Budget, EndCondition, IntegratedOptions,
    IntegratedResult, Stage,
};
pub use crate::surface::{reconstruct_surface, Section, SurfaceOptions, SurfaceReconstruction};
pub use crate::tolerance::Tolerance;
