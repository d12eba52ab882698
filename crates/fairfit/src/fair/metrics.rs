//! The full fairness summary of one curve ([`CurveFairness`]): length, MVC energy, the scale-free
//! `F = L³ E` and its per-span parts, bending energy and the counts of curvature extrema and inflections.
//! For the optimiser's inner loop use [`super::FairnessEvaluator`] directly.

use super::evaluator::FairnessEvaluator;
use super::extrema::{count_extrema, try_count_extrema, ExtremaCounts};
use crate::errors::Result;
use crate::nurbs::NurbsCurve;
use serde::Serialize;
use std::convert::Infallible;

/// Fairness measures of a curve (method reconstruction §2.3).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurveFairness {
    /// Arc length `L`.
    pub length: f64,
    /// MVC energy `E = ∫ (dκ/ds)² ds`.
    pub energy: f64,
    /// Scale-free fairness `F = L³ E` (0 for lines and circular arcs; smaller is fairer).
    pub fairness: f64,
    /// `F_j = L³ ∫_{span j} (dκ/ds)² ds` for each distinct knot span; `Σ F_j = F`.
    pub span_fairness: Vec<f64>,
    /// `max_j F_j` (0 for a curve without spans).
    pub max_span_fairness: f64,
    /// Bending energy `∫ κ² ds`.
    pub bending_energy: f64,
    /// Number of interior curvature extrema (see [`super::extrema`]).
    pub curvature_extrema: usize,
    /// Number of inflections (see [`super::extrema`]).
    pub inflections: usize,
}

/// Computes every fairness measure of `curve`.
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3};
/// use fairfit::fair::curve_fairness;
/// // a quarter circle of radius 2 (exact rational quadratic): F = 0, ∫κ² ds = (π/2)·2 / 4
/// let h = std::f64::consts::FRAC_1_SQRT_2;
/// let pts = vec![Vec3::new(2., 0., 0.), Vec3::new(2., 2., 0.), Vec3::new(0., 2., 0.)];
/// let c = NurbsCurve::new(2, vec![0., 0., 0., 1., 1., 1.], pts, Some(vec![1., h, 1.])).unwrap();
/// let f = curve_fairness(&c);
/// assert!((f.length - std::f64::consts::PI).abs() < 1e-12);
/// assert!(f.fairness < 1e-20);
/// assert!((f.bending_energy - std::f64::consts::PI / 4.0).abs() < 1e-12);
/// assert_eq!((f.curvature_extrema, f.inflections), (0, 0));
/// ```
pub fn curve_fairness(curve: &NurbsCurve) -> CurveFairness {
    // the counter cannot fail, so neither can the summary: no error to handle, no panic
    let Ok(m) = fairness_with(curve, &|c, l| Ok::<_, Infallible>(count_extrema(c, l)));
    m
}

/// [`curve_fairness`] with the extrema's sample buffers (which grow with the span count) reserved
/// fallibly: [`crate::Error::out_of_memory`] instead of an abort (`fairfit info` on a curve of very
/// many spans). The measures are the same as [`curve_fairness`]'s.
pub fn try_curve_fairness(curve: &NurbsCurve) -> Result<CurveFairness> {
    fairness_with(curve, &try_count_extrema)
}

/// The fairness summary, the extrema counted by `count` (given the curve and its length); it fails
/// only when `count` does.
fn fairness_with<E>(
    curve: &NurbsCurve,
    count: &dyn Fn(&NurbsCurve, f64) -> std::result::Result<ExtremaCounts, E>,
) -> std::result::Result<CurveFairness, E> {
    // far outside unit size, measure an exactly rescaled copy (see `nurbs::scale`)
    let f = crate::nurbs::scale::normalising_factor(curve.control_points());
    if let Some(s) = (f != 1.0)
        .then(|| crate::nurbs::scale::scaled_curve(curve, f).ok())
        .flatten()
    {
        let mut m = fairness_with(&s, count)?;
        m.length /= f; // lengths scale with the curve
        m.energy *= f * f * f; // ∫ (dκ/ds)² ds scales as 1/L³
        m.bending_energy *= f; // ∫ κ² ds scales as 1/L
        return Ok(m); // F, F_j and the counts are scale-free
    }
    let mut ev = FairnessEvaluator::new();
    let spans = ev.integrate(curve);
    let length: f64 = spans.iter().map(|s| s.length).sum();
    let energy: f64 = spans.iter().map(|s| s.energy).sum();
    let bending_energy: f64 = spans.iter().map(|s| s.bending).sum();
    let l3 = length * length * length;
    let span_fairness: Vec<f64> = spans.iter().map(|s| l3 * s.energy).collect();
    let fairness = span_fairness.iter().sum();
    let max_span_fairness = span_fairness.iter().fold(0.0f64, |m, &f| m.max(f));
    let counts = count(curve, length)?;
    Ok(CurveFairness {
        length,
        energy,
        fairness,
        span_fairness,
        max_span_fairness,
        bending_energy,
        curvature_extrema: counts.curvature_extrema,
        inflections: counts.inflections,
    })
}
