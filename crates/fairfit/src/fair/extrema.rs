//! Counting curvature extrema and inflections of a curve by sign changes on a dense sampling.
//!
//! Every distinct knot span is sampled at [`SAMPLES_PER_SPAN`] parameters strictly inside it (midpoints
//! of equal sub-intervals, so never on a knot where dκ/ds jumps). Along the whole curve, in order:
//!
//! - **curvature extrema** = sign changes of `dκ/ds` (signed `κ_s` for planar curves, in any plane, see
//!   [`super::energy::plane_normal`]; unsigned `κ` for spatial curves, where a zero of κ is a minimum and
//!   counts; a sign change across a knot is a corner extremum of κ and counts too);
//! - **inflections** = sign changes of `κ_s` for planar curves; for spatial curves, reversals of the
//!   binormal direction `c = C' × C''` between consecutive samples (`c_k · c_{k+1} < 0`), i.e. points
//!   where `κ` passes through (or very near) 0.
//!
//! **Noise floor** (scale-free): with `L` the arc length and `K = max(max |κ|, 1/L)`, samples with
//! `|κ| <= η K` are ignored for inflections and samples with `|dκ/ds| <= η K / L` are ignored for
//! extrema, with `η =` [`NOISE_FLOOR`]. A sign change is counted between consecutive samples that are
//! both above the floor, so a zero crossing through a flat stretch still counts once, while rounding
//! noise on a line (`κ ≈ 0`) or a circle (`dκ/ds ≈ 0`) counts nothing. The floors scale like `κ` and
//! `dκ/ds`, so counts are invariant under scaling and rigid motion.

use super::energy::{mvc_point, plane_normal};
use crate::nurbs::knots::distinct_breakpoints;
use crate::nurbs::{NurbsCurve, Vec3};

/// Samples per distinct knot span.
pub const SAMPLES_PER_SPAN: usize = 32;
/// Relative noise floor `η` (see the module documentation).
pub const NOISE_FLOOR: f64 = 1e-6;

/// Counts of curvature extrema and inflections.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExtremaCounts {
    /// Interior extrema of curvature (sign changes of dκ/ds).
    pub curvature_extrema: usize,
    /// Inflections (sign changes of the signed curvature / binormal reversals).
    pub inflections: usize,
}

/// Counts curvature extrema and inflections of `curve`, whose arc length is `length` (used for the
/// scale-free noise floor; pass [`crate::diffgeo::arc_length()`] or the `length` of a fairness summary).
pub fn count_extrema(curve: &NurbsCurve, length: f64) -> ExtremaCounts {
    count_extrema_sampled(curve, length, SAMPLES_PER_SPAN)
}

/// [`count_extrema`] with `samples_per_span` samples in every distinct knot span: a denser sampling
/// also finds the shallow wiggles that [`SAMPLES_PER_SPAN`] samples step over (the benchmark's
/// measurer takes 192).
pub fn count_extrema_sampled(
    curve: &NurbsCurve,
    length: f64,
    samples_per_span: usize,
) -> ExtremaCounts {
    let planar = plane_normal(curve);
    let breaks = distinct_breakpoints(curve.knots(), curve.degree());
    let mut kappa = Vec::with_capacity(breaks.len() * samples_per_span);
    let mut dkds = Vec::with_capacity(kappa.capacity());
    let mut binormal = Vec::with_capacity(kappa.capacity());
    let mut d = [Vec3::ZERO; 4];
    for w in breaks.windows(2) {
        for k in 0..samples_per_span {
            let u = w[0] + (w[1] - w[0]) * (k as f64 + 0.5) / samples_per_span as f64;
            curve.derivatives_into(u, 3, &mut d);
            let m = mvc_point(&d, planar);
            kappa.push(m.kappa);
            dkds.push(m.dkappa_ds());
            binormal.push(d[1].cross(d[2]));
        }
    }
    let coord = curve
        .control_points()
        .iter()
        .fold(0.0f64, |m, p| m.max(p.max_abs()));
    if length.is_nan() || length <= 1e-12 * coord || kappa.is_empty() {
        return ExtremaCounts::default();
    }
    let kmax = kappa.iter().fold(0.0f64, |m, k| m.max(k.abs()));
    let kref = kmax.max(1.0 / length);
    let floor_k = NOISE_FLOOR * kref;
    let floor_d = NOISE_FLOOR * kref / length;
    let curvature_extrema = sign_changes(&dkds, floor_d);
    let inflections = if planar.is_some() {
        sign_changes(&kappa, floor_k)
    } else {
        binormal_reversals(&binormal, &kappa, floor_k)
    };
    ExtremaCounts {
        curvature_extrema,
        inflections,
    }
}

/// Sign changes between consecutive entries of `xs` whose magnitude exceeds `floor`.
pub fn sign_changes(xs: &[f64], floor: f64) -> usize {
    let mut last = 0.0f64;
    let mut n = 0;
    for &x in xs {
        if x.is_nan() || x.abs() <= floor {
            continue;
        }
        if last != 0.0 && (x > 0.0) != (last > 0.0) {
            n += 1;
        }
        last = x;
    }
    n
}

fn binormal_reversals(c: &[Vec3], kappa: &[f64], floor: f64) -> usize {
    let mut last: Option<Vec3> = None;
    let mut n = 0;
    for (ci, k) in c.iter().zip(kappa) {
        if k.is_nan() || k.abs() <= floor {
            continue;
        }
        if let Some(l) = last {
            if l.dot(*ci) < 0.0 {
                n += 1;
            }
        }
        last = Some(*ci);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sampled_count_at_the_default_samples_is_count_extrema() {
        // an S-shaped Bézier cubic: a curvature extremum in each lobe, one inflection, and the
        // counts do not change with six times the samples
        let c = NurbsCurve::bspline(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
            vec![
                Vec3([0.0, 0.0, 0.0]),
                Vec3([1.0, 1.0, 0.0]),
                Vec3([2.0, -1.0, 0.0]),
                Vec3([3.0, 0.0, 0.0]),
            ],
        )
        .unwrap();
        let l = crate::diffgeo::arc_length(&c);
        let plain = count_extrema(&c, l);
        assert_eq!(count_extrema_sampled(&c, l, SAMPLES_PER_SPAN), plain);
        assert_eq!(count_extrema_sampled(&c, l, 6 * SAMPLES_PER_SPAN), plain);
        assert_eq!((plain.curvature_extrema, plain.inflections), (2, 1));
    }

    #[test]
    fn sign_changes_skip_the_floor() {
        assert_eq!(sign_changes(&[1.0, 1e-9, -1.0, -2.0, 3.0], 1e-6), 2);
        assert_eq!(sign_changes(&[1e-9, -1e-9, 1e-9], 1e-6), 0);
        assert_eq!(sign_changes(&[], 0.0), 0);
    }
}
