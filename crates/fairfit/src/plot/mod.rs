//! Plots a person can look at (SVG, PNG) and self-contained HTML reports.
//!
//! - [`svg`]: the canvas, plot frame and size;
//! - [`curve_plots`]: curve with data and curvature comb, curvature against arc length, deviations;
//! - [`surface_plots`]: deviation colour map, iso-curve curvature;
//! - [`png`]: SVG rendered to PNG with `resvg`;
//! - [`html`]: one self-contained report page.

pub mod curve_plots;
pub mod html;
pub mod png;
pub mod surface_plots;
pub mod surface_projection;
pub mod svg;

pub use svg::PlotSize;
