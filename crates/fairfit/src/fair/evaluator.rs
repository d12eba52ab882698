//! The hot-path fairness evaluator used by the optimiser: `F = L³ ∫ (dκ/ds)² ds` and the per-span
//! `F_j = L³ ∫_{span j} (dκ/ds)² ds` of a curve, thousands of times per fit, without allocating after
//! the first call (the breakpoints, per-span results and bisection stack live in reused buffers).
//!
//! Planar curves (in any plane) use the signed curvature, spatial ones the guarded unsigned formula
//! ([`super::energy`]). Integration is span by span over the distinct knot spans (C''' jumps at knots, so no node ever sits
//! on a knot): each span gets the Gauss–Kronrod 15-point rule, and a span whose Kronrod and embedded
//! Gauss 7-point energies disagree by more than the tolerance is bisected adaptively. The tolerance is
//! `max(rel_tol · |E_sub|, abs · (width of sub-interval) / (width of domain))`, where
//! `abs = max(rel_tol · E₀, 1e-14 / L₀³)` uses the first-pass totals `E₀`, `L₀`; every quantity is
//! scale- and motion-invariant, so the refinement decisions are too. The accepted value is the Kronrod
//! one.

use super::energy::{mvc_point, plane_normal};
use crate::diffgeo::quadrature::gauss_kronrod_15;
use crate::nurbs::{NurbsCurve, Vec3};

/// Tuning of the adaptive integration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvaluatorOptions {
    /// Relative tolerance on the error estimate of each (sub)span's energy.
    pub rel_tol: f64,
    /// Maximum number of bisection levels of a knot span (0: one Gauss–Kronrod rule per span).
    pub max_depth: usize,
}

impl Default for EvaluatorOptions {
    fn default() -> Self {
        EvaluatorOptions {
            rel_tol: 1e-6,
            max_depth: 12,
        }
    }
}

/// Integrals over one distinct knot span `[u0, u1]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpanIntegrals {
    /// Start of the span.
    pub u0: f64,
    /// End of the span.
    pub u1: f64,
    /// Arc length `∫ ds`.
    pub length: f64,
    /// MVC energy `∫ (dκ/ds)² ds`.
    pub energy: f64,
    /// Bending energy `∫ κ² ds`.
    pub bending: f64,
}

/// One Kronrod evaluation of a (sub)interval: integrals and the energy error estimate.
#[derive(Clone, Copy, Debug, Default)]
struct Piece {
    length: f64,
    energy: f64,
    bending: f64,
    error: f64,
}

/// Reusable fairness evaluator; create once, call [`FairnessEvaluator::evaluate`] many times.
///
/// ```
/// use fairfit::nurbs::{NurbsCurve, Vec3, knots::uniform_clamped};
/// use fairfit::fair::FairnessEvaluator;
/// let pts: Vec<Vec3> = [(0., 0.), (1., 2.), (2., 3.), (3., 1.), (4., 0.), (5., 2.), (6., 1.)]
///     .iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
/// let c = NurbsCurve::bspline(3, uniform_clamped(3, 7), pts).unwrap();
/// let mut ev = FairnessEvaluator::new();
/// let (f, max_fj) = ev.evaluate(&c);
/// let mut fj = Vec::new();
/// let f2 = ev.span_fairness_into(&c, &mut fj);
/// assert_eq!(fj.len(), 4);
/// assert!((fj.iter().sum::<f64>() - f).abs() <= 1e-12 * f);
/// assert_eq!(f, f2);
/// assert!(max_fj <= f && max_fj > 0.0);
/// ```
#[derive(Clone, Debug)]
pub struct FairnessEvaluator {
    opts: EvaluatorOptions,
    rule: [(f64, f64, f64); 15],
    breaks: Vec<f64>,
    spans: Vec<SpanIntegrals>,
    errors: Vec<f64>,
    stack: Vec<(f64, f64, usize)>,
}

impl Default for FairnessEvaluator {
    fn default() -> Self {
        Self::new()
    }
}

impl FairnessEvaluator {
    /// An evaluator with the default options.
    pub fn new() -> Self {
        Self::with_options(EvaluatorOptions::default())
    }

    /// An evaluator with the given options.
    pub fn with_options(opts: EvaluatorOptions) -> Self {
        FairnessEvaluator {
            opts,
            rule: gauss_kronrod_15(),
            breaks: Vec::new(),
            spans: Vec::new(),
            errors: Vec::new(),
            stack: Vec::new(),
        }
    }

    /// `(F, max_j F_j)` of `curve`.
    pub fn evaluate(&mut self, curve: &NurbsCurve) -> (f64, f64) {
        let l3 = self.integrate_length_cubed(curve);
        let mut f = 0.0;
        let mut fmax = 0.0f64;
        for s in &self.spans {
            let fj = l3 * s.energy;
            f += fj;
            fmax = fmax.max(fj);
        }
        (f, fmax)
    }

    /// Writes `F_j` of every distinct knot span into `out` (cleared first) and returns `F = Σ F_j`.
    pub fn span_fairness_into(&mut self, curve: &NurbsCurve, out: &mut Vec<f64>) -> f64 {
        let l3 = self.integrate_length_cubed(curve);
        out.clear();
        let mut f = 0.0;
        for s in &self.spans {
            let fj = l3 * s.energy;
            f += fj;
            out.push(fj);
        }
        f
    }

    /// Integrates `curve` span by span and returns the per-span integrals (valid until the next call).
    pub fn integrate(&mut self, curve: &NurbsCurve) -> &[SpanIntegrals] {
        let planar = plane_normal(curve);
        self.fill_breaks(curve);
        self.spans.clear();
        self.errors.clear();
        let (mut l0, mut e0) = (0.0, 0.0);
        for i in 0..self.breaks.len().saturating_sub(1) {
            let (a, b) = (self.breaks[i], self.breaks[i + 1]);
            let p = self.kronrod(curve, planar, a, b);
            l0 += p.length;
            e0 += p.energy;
            self.spans.push(SpanIntegrals {
                u0: a,
                u1: b,
                length: p.length,
                energy: p.energy,
                bending: p.bending,
            });
            self.errors.push(p.error);
        }
        if self.spans.is_empty() || l0.is_nan() || l0 <= 0.0 {
            return &self.spans;
        }
        let width = self.breaks[self.breaks.len() - 1] - self.breaks[0];
        let abs = (self.opts.rel_tol * e0).max(1e-14 / (l0 * l0 * l0)) / width;
        for j in 0..self.spans.len() {
            let s = self.spans[j];
            if self.opts.max_depth == 0
                || self.accept(self.errors[j], s.energy, abs * (s.u1 - s.u0))
            {
                continue;
            }
            let refined = self.refine(curve, planar, s.u0, s.u1, abs);
            self.spans[j] = SpanIntegrals {
                u0: s.u0,
                u1: s.u1,
                ..refined
            };
        }
        &self.spans
    }

    /// The per-span integrals of the last call.
    pub fn span_integrals(&self) -> &[SpanIntegrals] {
        &self.spans
    }

    fn integrate_length_cubed(&mut self, curve: &NurbsCurve) -> f64 {
        self.integrate(curve);
        let l: f64 = self.spans.iter().map(|s| s.length).sum();
        l * l * l
    }

    #[inline]
    fn accept(&self, error: f64, energy: f64, abs_here: f64) -> bool {
        error <= (self.opts.rel_tol * energy.abs()).max(abs_here)
    }

    fn fill_breaks(&mut self, curve: &NurbsCurve) {
        self.breaks.clear();
        let (p, k) = (curve.degree(), curve.knots());
        let n1 = k.len() - p - 1;
        for &u in &k[p..=n1] {
            if self.breaks.last().is_none_or(|&l| u > l) {
                self.breaks.push(u);
            }
        }
    }

    /// Adaptive bisection of `[a, b]`, summing accepted pieces in a fixed (stack) order.
    fn refine(
        &mut self,
        curve: &NurbsCurve,
        planar: Option<Vec3>,
        a: f64,
        b: f64,
        abs: f64,
    ) -> SpanIntegrals {
        let mut total = SpanIntegrals::default();
        self.stack.clear();
        let m = 0.5 * (a + b);
        self.stack
            .push((m, b, self.opts.max_depth.saturating_sub(1)));
        self.stack
            .push((a, m, self.opts.max_depth.saturating_sub(1)));
        while let Some((x, y, depth)) = self.stack.pop() {
            let p = self.kronrod(curve, planar, x, y);
            let mid = 0.5 * (x + y);
            if depth == 0 || mid <= x || mid >= y || self.accept(p.error, p.energy, abs * (y - x)) {
                total.length += p.length;
                total.energy += p.energy;
                total.bending += p.bending;
            } else {
                self.stack.push((mid, y, depth - 1));
                self.stack.push((x, mid, depth - 1));
            }
        }
        total
    }

    /// Gauss–Kronrod 15 on `[a, b]`.
    #[inline]
    fn kronrod(&self, curve: &NurbsCurve, planar: Option<Vec3>, a: f64, b: f64) -> Piece {
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
        let mut d = [Vec3::ZERO; 4];
        let mut fe = [0.0; 15];
        let (mut len, mut ek, mut eg, mut bend) = (0.0, 0.0, 0.0, 0.0);
        for (i, &(x, wk, wg)) in self.rule.iter().enumerate() {
            curve.derivatives_into(c + h * x, 3, &mut d);
            let m = mvc_point(&d, planar);
            let e = m.energy_density();
            fe[i] = e;
            len += wk * m.speed;
            ek += wk * e;
            eg += wg * e;
            bend += wk * m.bending_density();
        }
        // QUADPACK qk15 error estimate: |K15 − G7| scaled by the integrand's variation `resasc`
        let mean = 0.5 * ek;
        let resasc: f64 = self
            .rule
            .iter()
            .zip(&fe)
            .map(|(&(_, wk, _), &e)| wk * (e - mean).abs())
            .sum::<f64>()
            * h;
        let mut error = ((ek - eg) * h).abs();
        if resasc > 0.0 && error > 0.0 {
            error = resasc * (200.0 * error / resasc).powf(1.5).min(1.0);
        }
        Piece {
            length: len * h,
            energy: ek * h,
            bending: bend * h,
            error,
        }
    }
}
