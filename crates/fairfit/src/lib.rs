//! # fairfit
//!
//! Fair NURBS curves and surfaces from measured points: within a tolerance of the data, with few control
//! points, and with curvature that changes calmly. fairfit implements the integrated fitting-and-fairing
//! method of Hashemian & Hosseini (knot vectors searched by particle swarm optimisation, control points by
//! least squares, fairness measured per knot span by the scale-free metric `F = L³ ∫ (dκ/ds)² ds`).
//!
//! Modules, one concept each:
//! - [`nurbs`]: the geometry core (curves, surfaces, evaluation, knot operations);
//! - [`diffgeo`]: differential geometry of curves and surfaces (curvature, torsion, dκ/ds, arc length,
//!   closest-point projection);
//! - [`fair`]: fairness metrics (MVC energy, the scale-free `F`, per-span `F_j`, extrema, inflections);
//! - [`fit`]: point input preparation and least-squares fitting with tolerance control;
//! - [`optim`]: particle swarm optimisation of knot vectors (the integrated fitting-and-fairing method);
//! - [`surface`]: sections and point clouds to compatible fair curves, skinned into surfaces;
//! - [`io`]: the JSON geometry format, point files, STEP, IGES and meshes;
//! - [`plot`]: SVG/PNG plots and HTML reports;
//! - [`report`]: the `--report` JSON of curve and surface fits, and the bytes of every output file;
//! - [`errors`]: the typed [`Error`] every fallible function returns;
//! - [`prelude`]: what a user of the library needs in one import (`use fairfit::prelude::*`).
//!
//! [`Tolerance`] (the allowed maximum orthogonal deviation) is the one tolerance type of [`fit`] and
//! [`optim`].
//!
//! The library never prints; the `fairfit` command-line tool is a separate crate.

pub mod diffgeo;
pub mod errors;
pub mod fair;
pub mod fit;
pub mod io;
pub mod nurbs;
pub mod optim;
pub mod plot;
pub mod prelude;
pub mod report;
pub mod surface;
mod tolerance;

pub use errors::{Error, Result};
pub use nurbs::{NurbsCurve, NurbsSurface, Vec3};
pub use tolerance::Tolerance;
