//! Tests of `fairfit::nurbs`: basis, curves and surfaces, knot operations, the exact circle.
//!
//! One file per source module it tests (`src/nurbs/<name>.rs`), except:
//! - `knot_ops`: insert, refine, elevate, clamp, reversal and reparametrisation keep the geometry.
//! - `curvo_agreement`: evaluation against the independent `curvo` crate.
//! - `derivatives`: curve and surface derivatives against finite differences.

mod basis;
mod circle;
mod curve;
mod curvo_agreement;
mod derivatives;
mod knot_ops;
