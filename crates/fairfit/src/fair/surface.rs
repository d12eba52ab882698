//! Fairness of surfaces through their iso-parametric curves (method reconstruction §2.5: the paper fairs
//! section curves and skins them, so the practical surface check is the curve metric on iso-curves in
//! both directions).
//!
//! Directions: a curve *along u* is `u ↦ S(u, v_k)` at a fixed `v_k` (for a skinned surface, a section
//! curve); a curve *along v* is `v ↦ S(u_k, v)` at a fixed `u_k` (across the sections). The Rust fields
//! `v_iso` / `u_iso` name the fixed parameter; the JSON form (what `fairfit info` and the `fairfit surface`
//! report print) names the running direction: `along_u` / `along_v`, `max_fairness_along_u`, ...
//! [`DEFAULT_ISO_CURVES`] is the count per direction both commands use.
//!
//! The iso-curves are extracted exactly by [`NurbsSurface::iso_curve_u`] / [`NurbsSurface::iso_curve_v`]
//! (the homogeneous control net contracted with the basis functions of one direction).

use super::metrics::{curve_fairness, CurveFairness};
use crate::errors::Result;
use crate::nurbs::NurbsSurface;
use serde::Serialize;

/// Iso-curves per direction used by `fairfit info` and `fairfit surface` unless told otherwise (ends
/// included, so a step of a tenth of the domain).
pub const DEFAULT_ISO_CURVES: usize = 11;

/// Fairness of one iso-parametric curve (the [`CurveFairness`] summary without the per-span list).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct IsoCurveFairness {
    /// The fixed parameter: v for curves along u (`v_iso`), u for curves along v (`u_iso`).
    pub parameter: f64,
    /// Arc length.
    pub length: f64,
    /// `F = L³ ∫ (dκ/ds)² ds`.
    pub fairness: f64,
    /// `max_j F_j`.
    pub max_span_fairness: f64,
    /// `∫ κ² ds`.
    pub bending_energy: f64,
    /// Number of curvature extrema.
    pub curvature_extrema: usize,
    /// Number of inflections.
    pub inflections: usize,
}

impl IsoCurveFairness {
    fn from_curve(parameter: f64, f: &CurveFairness) -> Self {
        IsoCurveFairness {
            parameter,
            length: f.length,
            fairness: f.fairness,
            max_span_fairness: f.max_span_fairness,
            bending_energy: f.bending_energy,
            curvature_extrema: f.curvature_extrema,
            inflections: f.inflections,
        }
    }
}

/// Fairness summary of a surface over iso-parametric curves in both directions.
///
/// Serialised with the running direction in the keys (`along_u`, `max_fairness_along_u`, ...; see the
/// module documentation); the `_u` / `_v` of the Rust fields name the *fixed* parameter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SurfaceFairness {
    /// Number of iso-curves asked for per direction.
    pub iso_curves_per_direction: usize,
    /// Curves `v ↦ S(u_k, v)` at fixed `u_k` (equally spaced over the u domain, ends included): the
    /// curves along v. JSON: `along_v`.
    #[serde(rename = "along_v")]
    pub u_iso: Vec<IsoCurveFairness>,
    /// Curves `u ↦ S(u, v_k)` at fixed `v_k`: the curves along u. JSON: `along_u`.
    #[serde(rename = "along_u")]
    pub v_iso: Vec<IsoCurveFairness>,
    /// Largest `F` over `u_iso`, the curves along v (0 when empty). JSON: `max_fairness_along_v`.
    #[serde(rename = "max_fairness_along_v")]
    pub max_fairness_u: f64,
    /// Largest `F` over `v_iso`, the curves along u. JSON: `max_fairness_along_u`.
    #[serde(rename = "max_fairness_along_u")]
    pub max_fairness_v: f64,
    /// Mean `F` over `u_iso` (along v). JSON: `mean_fairness_along_v`.
    #[serde(rename = "mean_fairness_along_v")]
    pub mean_fairness_u: f64,
    /// Mean `F` over `v_iso` (along u). JSON: `mean_fairness_along_u`.
    #[serde(rename = "mean_fairness_along_u")]
    pub mean_fairness_v: f64,
    /// Largest `F_j` over every span of every `u_iso` curve (along v). JSON:
    /// `max_span_fairness_along_v`.
    #[serde(rename = "max_span_fairness_along_v")]
    pub max_span_fairness_u: f64,
    /// Largest `F_j` over every span of every `v_iso` curve (along u). JSON:
    /// `max_span_fairness_along_u`.
    #[serde(rename = "max_span_fairness_along_u")]
    pub max_span_fairness_v: f64,
}

/// Evaluates the curve fairness metrics on `n_iso` iso-curves in each direction (`n_iso >= 2` puts them
/// at equal parameter steps including both domain ends; `n_iso = 1` takes the middle; `0` gives empty
/// lists).
///
/// ```
/// use fairfit::nurbs::{knots::uniform_clamped, NurbsSurface, Vec3};
/// use fairfit::fair::surface_fairness;
/// // a bilinear-in-v sheet over a planar cubic: straight rulings (F = 0) one way
/// let net: Vec<Vec<Vec3>> = (0..5)
///     .map(|i| (0..2).map(|j| Vec3::new(i as f64, ((i * i) % 3) as f64, j as f64)).collect())
///     .collect();
/// let s = NurbsSurface::new(3, 1, uniform_clamped(3, 5), uniform_clamped(1, 2), net, None).unwrap();
/// let f = surface_fairness(&s, 5).unwrap();
/// assert_eq!(f.u_iso.len(), 5);
/// assert!(f.max_fairness_u < 1e-20);
/// assert!(f.max_fairness_v > 1.0);
/// ```
pub fn surface_fairness(surface: &NurbsSurface, n_iso: usize) -> Result<SurfaceFairness> {
    let params = |(a, b): (f64, f64)| -> Vec<f64> {
        match n_iso {
            0 => Vec::new(),
            1 => vec![0.5 * (a + b)],
            n => (0..n)
                .map(|k| {
                    if k + 1 == n {
                        b
                    } else {
                        a + (b - a) * k as f64 / (n - 1) as f64
                    }
                })
                .collect(),
        }
    };
    let mut u_iso = Vec::new();
    let mut max_span_fairness_u = 0.0f64;
    for u in params(surface.domain_u()) {
        let f = curve_fairness(&surface.iso_curve_u(u)?);
        max_span_fairness_u = max_span_fairness_u.max(f.max_span_fairness);
        u_iso.push(IsoCurveFairness::from_curve(u, &f));
    }
    let mut v_iso = Vec::new();
    let mut max_span_fairness_v = 0.0f64;
    for v in params(surface.domain_v()) {
        let f = curve_fairness(&surface.iso_curve_v(v)?);
        max_span_fairness_v = max_span_fairness_v.max(f.max_span_fairness);
        v_iso.push(IsoCurveFairness::from_curve(v, &f));
    }
    let max = |xs: &[IsoCurveFairness]| xs.iter().fold(0.0f64, |m, x| m.max(x.fairness));
    let mean = |xs: &[IsoCurveFairness]| {
        if xs.is_empty() {
            0.0
        } else {
            xs.iter().map(|x| x.fairness).sum::<f64>() / xs.len() as f64
        }
    };
    Ok(SurfaceFairness {
        iso_curves_per_direction: n_iso,
        max_fairness_u: max(&u_iso),
        max_fairness_v: max(&v_iso),
        mean_fairness_u: mean(&u_iso),
        mean_fairness_v: mean(&v_iso),
        max_span_fairness_u,
        max_span_fairness_v,
        u_iso,
        v_iso,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::knots::uniform_clamped;
    use crate::nurbs::{NurbsCurve, Vec3};

    #[test]
    fn ruled_sheet_over_a_curve_has_the_curve_fairness_one_way_and_zero_the_other() {
        // S(u, v) = C(u) + v·(0, 0, 2): v-iso curves are translated copies of C, u-iso ones straight
        let base: Vec<Vec3> = [
            (0.0, 0.0),
            (1.0, 1.5),
            (2.5, 2.0),
            (3.5, 0.5),
            (4.5, -1.0),
            (6.0, 0.2),
        ]
        .iter()
        .map(|&(x, y)| Vec3::new(x, y, 0.0))
        .collect();
        let w = vec![1.0, 0.8, 1.3, 1.0, 0.7, 1.0];
        let c = NurbsCurve::new(3, uniform_clamped(3, 6), base.clone(), Some(w.clone())).unwrap();
        let net: Vec<Vec<Vec3>> = base
            .iter()
            .map(|&p| vec![p, p + Vec3::new(0.0, 0.0, 2.0)])
            .collect();
        let wn: Vec<Vec<f64>> = w.iter().map(|&x| vec![x, x]).collect();
        let s = NurbsSurface::new(
            3,
            1,
            uniform_clamped(3, 6),
            uniform_clamped(1, 2),
            net,
            Some(wn),
        )
        .unwrap();
        let f = surface_fairness(&s, 4).unwrap();
        let fc = curve_fairness(&c);
        assert_eq!(f.v_iso.len(), 4);
        for iso in &f.v_iso {
            assert!((iso.fairness - fc.fairness).abs() < 1e-9 * fc.fairness);
            assert_eq!(iso.inflections, fc.inflections);
        }
        assert!((f.max_fairness_v - fc.fairness).abs() < 1e-9 * fc.fairness);
        assert!((f.max_span_fairness_v - fc.max_span_fairness).abs() < 1e-9 * fc.fairness);
        assert!(f.max_fairness_u < 1e-20);
        for iso in &f.u_iso {
            assert!((iso.length - 2.0).abs() < 1e-12);
        }
        assert_eq!(f.u_iso[0].parameter, 0.0);
        assert_eq!(f.u_iso[3].parameter, 1.0);
        // the JSON names the running direction: the copies of C run along u
        let j = serde_json::to_value(&f).unwrap();
        assert_eq!(j["iso_curves_per_direction"], 4);
        let along_u = j["max_fairness_along_u"].as_f64().unwrap();
        assert!((along_u - fc.fairness).abs() < 1e-9 * fc.fairness);
        assert!(j["max_fairness_along_v"].as_f64().unwrap() < 1e-20);
        assert_eq!(j["along_u"].as_array().unwrap().len(), 4);
        assert_eq!(
            j["along_v"][1]["length"].as_f64().unwrap(),
            f.u_iso[1].length
        );
        assert_eq!(j["along_u"][2]["parameter"].as_f64().unwrap(), 2.0 / 3.0);
        assert!(j.get("u_iso").is_none() && j.get("max_fairness_u").is_none());
    }
}
