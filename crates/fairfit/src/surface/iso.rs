//! Iso-parametric curves of a NURBS surface: `u ↦ S(u, v0)` and `v ↦ S(u0, v)`, exact (the homogeneous
//! control net contracted with the basis functions of the fixed parameter).
//!
//! A private stand-in for the core-ops engineer's `NurbsSurface` iso-curves, used by the surface measures.

use crate::errors::Result;
use crate::nurbs::basis::basis_funs_into;
use crate::nurbs::knots::find_span;
use crate::nurbs::{NurbsCurve, NurbsSurface};

fn contract(knots: &[f64], p: usize, n: usize, t: f64) -> (usize, Vec<f64>) {
    let span = find_span(n - 1, p, t, knots);
    let (mut l, mut r, mut nb) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
    basis_funs_into(span, t, p, knots, &mut l, &mut r, &mut nb);
    (span - p, nb)
}

/// The curve `u ↦ S(u, v)` (runs along the u direction, at fixed `v`).
pub fn iso_curve_at_v(s: &NurbsSurface, v: f64) -> Result<NurbsCurve> {
    let (n_u, n_v) = s.net_size();
    let (first, nb) = contract(s.knots_v(), s.degree_v(), n_v, v);
    let cw: Vec<[f64; 4]> = (0..n_u)
        .map(|i| {
            let mut acc = [0.0; 4];
            for (l, b) in nb.iter().enumerate() {
                let (p, w) = (s.control_point(i, first + l), s.weight(i, first + l));
                acc[0] += b * w * p.x();
                acc[1] += b * w * p.y();
                acc[2] += b * w * p.z();
                acc[3] += b * w;
            }
            acc
        })
        .collect();
    NurbsCurve::from_homogeneous(s.degree_u(), s.knots_u().to_vec(), &cw)
}

/// The curve `v ↦ S(u, v)` (runs along the v direction, across the sections, at fixed `u`).
pub fn iso_curve_at_u(s: &NurbsSurface, u: f64) -> Result<NurbsCurve> {
    let (n_u, n_v) = s.net_size();
    let (first, nb) = contract(s.knots_u(), s.degree_u(), n_u, u);
    let cw: Vec<[f64; 4]> = (0..n_v)
        .map(|j| {
            let mut acc = [0.0; 4];
            for (k, b) in nb.iter().enumerate() {
                let (p, w) = (s.control_point(first + k, j), s.weight(first + k, j));
                acc[0] += b * w * p.x();
                acc[1] += b * w * p.y();
                acc[2] += b * w * p.z();
                acc[3] += b * w;
            }
            acc
        })
        .collect();
    NurbsCurve::from_homogeneous(s.degree_v(), s.knots_v().to_vec(), &cw)
}
