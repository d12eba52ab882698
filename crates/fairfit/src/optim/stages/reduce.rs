//! Reduction of dense data: the stage before every other, so that the knot search, the count search
//! and the band fairing cost what the shape and the tolerance need, not what the point count is.
//!
//! # The reduced form: representative points of tolerance-sized arcs
//!
//! The points are cut, in their order, into *bins*: runs of consecutive points that stay within
//! `h = bin_tolerances · tol` of the bin's first point (a bin also closes where the path turns back
//! towards its first point by more than a quarter of `h`: measured along the bin's direction: a hairpin's two sides never share more
//! than that).
//! Each bin is replaced by its mean (of the polyline between its fractional boundaries, so that
//! the representatives lie `h` apart even where a bin holds two or three points; `crate::fit::reduce`);
//! the first and the last point stay as they are (the curve's ends interpolate them). Why this
//! form rather than moments or a pre-fit:
//!
//! - **It is the same kind of data.** Every later stage (corners, closure, centripetal
//!   parameters, knot search, band fairing, polish) runs unchanged on the representatives, so the
//!   method's policy is the one measured on the clean tables.
//! - **It is even in arc length.** A bin holds an arc of length about `h` however many points were
//!   sampled on it: a burst of 100:1 density gives the same representatives as even sampling
//!   (least squares on the raw burst would weight it 100 times), a gap simply has none.
//! - **It averages the noise.** A representative of `m` points carries `σ/√m` of noise; a
//!   centripetal parameterisation of raw dense noisy points is dominated by the noise instead.
//! - **Its error is bounded by the shape.** The centroid of an arc of length `h` and curvature `κ`
//!   lies within `κh²/24` of the arc (the mean sagitta): with `h = 4 tol` that is below `tol/15`
//!   wherever the radius of curvature is at least `10 tol`, less than any feature a tolerance-`tol`
//!   fit can resolve. It is scale-free: `h` is a multiple of the tolerance.
//!
//! # Certificate and repair
//!
//! Every bin records its *spread*: how far its points lie from the line through its centroid along
//! the bin's direction (noise plus sagitta). Each representative is held within its own *share*
//! of the tolerance, `tol − spread` of the widest spread among its bin and the two neighbouring
//! ones (the curve between two representatives passes the points of both bins): a curve within
//! that of the representative, and following the bin's line, is within `tol` of the bin's points.
//! The shares reach the search as per-point deviation factors (`PointBands`, the mechanism of
//! per-point weights), so a bin of large spread (the noise's extreme, a leading edge's sagitta)
//! tightens the fit there and nowhere else: held to the tightest share everywhere, a fit of
//! 10^6 noisy points was held to about half the tolerance and needed two control points more than
//! the same shape at 10^4 points.
//!
//! The fit is then measured on **every input point** (in the normalised units, like the
//! fit itself, so that a scaled input gives the same result) by exact foot-point projection
//! ([`crate::diffgeo::projection::CurveProjector`]). Where a point is still outside `tol` (the
//! curve bends away between representatives, typically by a few per cent of the tolerance), the
//! fit is repaired. The **search repair**: the bins of the missing points are cut in two (`h/2`
//! there) and the reduced data fitted again ([`ReduceTuning::repair_rounds`] times at most), then
//! every share is tightened by twice the largest excess ([`ReduceTuning::tighten_rounds`] times at
//! most) until every point is within `tol`. Each of these fits searches the count anew, and the
//! count search on representatives that barely meet their shares has a spread of several control
//! points: the count would depend on whether, and how often, the data needed a repair, not on
//! the shape. So where the search repair ends above the first fit's count (or with a point still
//! outside), the **count-keeping repair** is tried: the first fit has shown that its count meets
//! the representatives' shares, and a miss between representatives is local, so the shares of
//! the representatives around every bin whose points miss (the bin and its two neighbours, the
//! ones the curve passes there) are taken in by twice that bin's excess, nowhere else, and the
//! first fit's representatives fitted again at its degree and count
//! ([`ReduceTuning::keep_count_rounds`] times at most). Its result replaces the search repair's
//! when every point is within `tol`. So a repair never returns more control points than the
//! first fit where that count can be kept, and every result is measured on every input point.
//!
//! # Scale
//!
//! The result does not depend on the input's units: the points are divided by their bounding box's
//! largest side (the tolerance too), and everything the search sees, the representatives and the
//! inner tolerance, is rounded to a grid of [`ReduceTuning::grid`] (`2^-30`) of that side. A
//! rescaled input's normalised points differ by a few units in the last place (the scale factor's
//! rounding); the centroids average that to about `1e-16`, which crosses a `2^-30` grid line with
//! probability about `1e-7` per coordinate, so the reduced data are bit-identical and the knots the
//! same. (Rounding every input point to a grid instead, as the pipeline's own normalisation does,
//! flips about one point in `10^4` at `2^-36`, and the swarm turns that one representative's shift
//! into other knots.) The grid is `10^-6` of a relative tolerance of `10^-3`, far below any
//! tolerance; the spread is rounded up and every share down, so the certificate holds.
//!
//! # When it applies
//!
//! Only when the bins at least halve the points ([`ReduceTuning::min_points_per_bin`]): data whose
//! typical tolerance-sized arc holds one point are already their own reduced form and go to the
//! pipeline untouched (all the clean tables, 60-400 points with spacings of several tolerances,
//! give byte-identical results).

use super::super::context::tolerance_of;
use super::super::options::IntegratedOptions;
use super::super::result::{FitQuality, IntegratedResult};
use crate::diffgeo::projection::CurveProjector;
use crate::errors::Result;
use crate::fit::end_constraints::EndCurvature;
use crate::fit::reduce::{reduce, refine, ReduceTuning, Reduced};
use crate::nurbs::{NurbsCurve, Vec3};
use crate::optim::kind::periodic::distinct_control_points;
use crate::tolerance::Tolerance;
use rayon::prelude::*;

/// Dense data in their reduced form: the points and bins in normalised units (bounding-box minimum
/// `lo`, largest side `scale`). The pipeline fits the representatives in these units, at the
/// tolerance in these units, and the curve is mapped back to the input's units afterwards; what the
/// pipeline sees is rounded to [`ReduceTuning::grid`] (module doc, "Scale"), so that no rounding of
/// the input's units reaches its data or tolerance (a swarm search turns a last-bit difference into
/// another optimum).
pub(crate) struct Dense {
    normalised: Vec<Vec3>,
    red: Reduced,
    lo: Vec3,
    scale: f64,
    /// The tolerance in normalised units.
    tol: f64,
}

impl Dense {
    /// The reduced form of `points` under `opts`, or `None` when the points are their own reduced
    /// form (or unfit for one: the pipeline then says why).
    pub fn of(points: &[Vec3], opts: &IntegratedOptions, tuning: &ReduceTuning) -> Option<Dense> {
        let &first = points.first()?;
        let (mut lo, mut hi) = (first, first);
        for p in points {
            if !p.is_finite() {
                return None;
            }
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let scale = (hi - lo).max_abs();
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        let tol = tolerance_of(opts, scale);
        // not snapped: a rescaled input differs here by a few units in the last place, which the
        // centroids average and `grid` rounds away (a snap of every input point to a grid would
        // flip on about one in 10^4 of them, and move its representative)
        let normalised: Vec<Vec3> = points.iter().map(|&p| (p - lo) / scale).collect();
        let red = reduce(&normalised, tol, tuning)?;
        Some(Dense {
            normalised,
            red,
            lo,
            scale,
            tol,
        })
    }

    /// The representatives of `red` in normalised units, rounded to `grid`.
    fn points(red: &Reduced, grid: f64) -> Vec<Vec3> {
        let round = |x: f64| (x / grid).round() * grid;
        red.bins
            .iter()
            .map(|b| Vec3([round(b.point[0]), round(b.point[1]), round(b.point[2])]))
            .collect()
    }

    /// `opts` in normalised units: end points moved into the unit box, end curvatures scaled
    /// (tangent directions and everything else are scale-free).
    fn normalised_options(&self, opts: &IntegratedOptions) -> IntegratedOptions {
        let mut o = opts.clone();
        let (lo, s) = (self.lo, self.scale);
        for c in [&mut o.end_conditions.start, &mut o.end_conditions.end] {
            c.point = c.point.map(|p| (p - lo) / s);
            c.curvature = c.curvature.map(|k| match k {
                EndCurvature::Signed(k) => EndCurvature::Signed(k * s),
                EndCurvature::Vector(v) => EndCurvature::Vector(v * s),
            });
        }
        o
    }

    /// `r`, fitted in normalised units, in the input's units: control points mapped back,
    /// deviations and tolerance scaled (the fairness `F` is scale-free).
    fn to_input(&self, mut r: IntegratedResult) -> Result<IntegratedResult> {
        let c = &r.curve;
        let (lo, s) = (self.lo, self.scale);
        let pts: Vec<Vec3> = c.control_points().iter().map(|&p| lo + p * s).collect();
        r.curve = NurbsCurve::new(
            c.degree(),
            c.knots().to_vec(),
            pts,
            Some(c.weights().to_vec()),
        )?;
        r.quality.max_deviation *= s;
        r.quality.rms_deviation *= s;
        r.tolerance *= s;
        Ok(r)
    }

    /// The reduced data fitted by `fit`, every representative within its bin's share of the
    /// tolerance ([`Dense::factors`]), measured on every input point, and repaired while a point
    /// misses the tolerance (module doc, "Certificate and repair"). Everything runs in normalised
    /// units; the result is in the input's.
    pub fn fit(
        mut self,
        opts: &IntegratedOptions,
        tuning: &ReduceTuning,
        fit: &dyn Fn(&[Vec3], &IntegratedOptions) -> Result<IntegratedResult>,
    ) -> Result<IntegratedResult> {
        let h = tuning.bin_tolerances * self.tol;
        let tol = self.tol;
        let base = self.normalised_options(opts);
        let grid = tuning.grid;
        let on_grid = |t: f64| (t / grid).floor() * grid;
        let (mut cuts, mut tightenings) = (0, 0);
        // the first fit, when it missed: its bins, options, result and per-bin deviations
        let mut first: Option<(Reduced, IntegratedOptions, IntegratedResult, Vec<f64>)> = None;
        // the tightest share; a tightening shrinks every share by the same factor
        let mut inner = self.share(self.red.spread(), tuning);
        loop {
            let o = IntegratedOptions {
                tolerance: Tolerance::Absolute(inner),
                tolerance_factors: self.factors(tuning),
                ..base.clone()
            };
            let r = fit(&Dense::points(&self.red, grid), &o)?;
            let (max, rms, per_bin) = verify(&r.curve, &self.normalised, &self.red, tol);
            let done = max <= tol || !r.met;
            let cut: Vec<bool> = per_bin.iter().map(|&d| d > tol).collect();
            if !done && first.is_none() {
                first = Some((self.red.clone(), o.clone(), r.clone(), per_bin.clone()));
            }
            if !done
                && cuts < tuning.repair_rounds
                && refine(&self.normalised, &mut self.red, &cut, h, tuning)
            {
                cuts += 1;
                inner = inner.min(self.share(self.red.spread(), tuning));
                continue;
            }
            // the excess taken off the tightest share, twice over (a fit tightened by exactly
            // the excess lands on the tolerance's edge again)
            let tighter = on_grid(inner - 2.0 * (max - tol));
            if done || tightenings == tuning.tighten_rounds || tighter <= 0.0 {
                let searched = measured(r, max, rms, tol, opts.span_fairness);
                let kept = first.and_then(|(red, o, f, per_bin)| {
                    // the first fit's count kept where the new searches needed more (or failed)
                    let grew = !searched.met
                        || distinct_control_points(&searched.curve)
                            > distinct_control_points(&f.curve);
                    grew.then(|| self.keep_count(&red, &o, &f, &per_bin, tuning, fit))?
                });
                return self.to_input(match kept {
                    Some((k, max, rms)) => measured(k, max, rms, tol, opts.span_fairness),
                    None => searched,
                });
            }
            inner = tighter;
            tightenings += 1;
        }
    }

    /// The repair at the first fit's degree and count (module doc, "Certificate and repair"):
    /// `first` (fitted under `o` on the bins `red`) missed the tolerance on the points of the
    /// bins where `per_bin` exceeds it; the shares of each such bin and its two neighbours are
    /// taken in by twice its excess (cumulatively over the rounds, rounded down to the grid; the
    /// other shares stay), and the unchanged representatives fitted again at `first`'s degree
    /// and count. The first result within `tol` on every input point, with its `(max, rms)`;
    /// `None` when the count cannot be kept: a share would vanish, a fixed-count fit fails or
    /// misses the shares, or [`ReduceTuning::keep_count_rounds`] rounds leave a point outside.
    fn keep_count(
        &self,
        red: &Reduced,
        o: &IntegratedOptions,
        first: &IntegratedResult,
        per_bin: &[f64],
        tuning: &ReduceTuning,
        fit: &dyn Fn(&[Vec3], &IntegratedOptions) -> Result<IntegratedResult>,
    ) -> Option<(IntegratedResult, f64, f64)> {
        let (tol, grid) = (self.tol, tuning.grid);
        let kept = IntegratedOptions {
            degree: first.curve.degree(),
            max_degree: None,
            control_points: Some(distinct_control_points(&first.curve)),
            ..o.clone()
        };
        let mut shares: Vec<f64> = red
            .neighbour_spreads()
            .into_iter()
            .map(|s| self.share(s, tuning))
            .collect();
        let points = Dense::points(red, grid);
        let mut per_bin = per_bin.to_vec();
        for _ in 0..tuning.keep_count_rounds {
            // per representative, twice the largest excess among the bins it borders
            let mut take_in = vec![0.0f64; shares.len()];
            for (k, &d) in per_bin.iter().enumerate().filter(|x| *x.1 > tol) {
                let around = k.saturating_sub(1)..(k + 2).min(take_in.len());
                for c in &mut take_in[around] {
                    *c = c.max(2.0 * (d - tol));
                }
            }
            for (s, c) in shares.iter_mut().zip(&take_in) {
                *s = ((*s - c) / grid).floor() * grid;
            }
            // the tightest share is the inner tolerance, every factor at most 1 (`factors`)
            let inner = shares.iter().copied().fold(f64::INFINITY, f64::min);
            if inner <= 0.0 {
                return None;
            }
            let opts = IntegratedOptions {
                tolerance: Tolerance::Absolute(inner),
                tolerance_factors: shares.iter().map(|&s| inner / s).collect(),
                ..kept.clone()
            };
            let r = fit(&points, &opts).ok().filter(|r| r.met)?;
            let (max, rms, missed) = verify(&r.curve, &self.normalised, red, tol);
            if max <= tol {
                return Some((r, max, rms));
            }
            per_bin = missed;
        }
        None
    }

    /// A bin of spread `spread`'s share of the tolerance: the spread (rounded up to the grid)
    /// deducted, the share rounded down to it (so the certificate holds on the grid); never below
    /// a quarter of the tolerance (a spread beyond the tolerance is noise no fit within it can
    /// average: the verification says so).
    fn share(&self, spread: f64, tuning: &ReduceTuning) -> f64 {
        let grid = tuning.grid;
        let spread = (spread / grid).ceil() * grid;
        ((self.tol - spread).max(0.25 * self.tol) / grid).floor() * grid
    }

    /// The deviation factor of every representative: the tightest share over its own share, the
    /// share of the widest spread among the bin and its two neighbours (the curve between two
    /// representatives passes the points of both bins). Every factor is at most 1: a
    /// representative held within `inner / factor` is held within its share scaled by `inner`
    /// over the tightest share.
    fn factors(&self, tuning: &ReduceTuning) -> Vec<f64> {
        let tightest = self.share(self.red.spread(), tuning);
        self.red
            .neighbour_spreads()
            .into_iter()
            .map(|s| tightest / self.share(s, tuning))
            .collect()
    }
}

/// The deviation of every input point from `curve`: `(max, rms, per-bin max)` by exact foot-point
/// projection, the first and last point counted as zero like the pipeline does (the curve
/// interpolates them). Each point is projected by Newton from its predecessor's foot (the bin's
/// first from its representative's foot); a point whose Newton run does not converge, or lands
/// farther than `tol`, is projected again by the safeguarded search near that foot
/// ([`CurveProjector::project_near`]), so every reported violation is the exact distance.
pub fn verify(curve: &NurbsCurve, points: &[Vec3], r: &Reduced, tol: f64) -> (f64, f64, Vec<f64>) {
    let proj = CurveProjector::new(curve, 8);
    let n = points.len();
    let per_bin: Vec<(f64, f64)> = r
        .bins
        .par_iter()
        .map(|b| {
            let mut u = proj.project(b.point).u;
            let (mut worst, mut sum2) = (0.0f64, 0.0);
            let mut d3 = [Vec3::ZERO; 3];
            for k in b.first.max(1)..=b.last.min(n - 2) {
                let q = points[k];
                let (nu, mut d) = match newton(curve, q, u, &mut d3) {
                    Some(x) if x.1 <= tol => x,
                    _ => {
                        let f = proj.project_near(q, u);
                        (f.u, f.distance)
                    }
                };
                if d > tol {
                    // a violation is confirmed by the whole-curve search
                    d = d.min(proj.project(q).distance);
                }
                u = nu;
                worst = worst.max(d);
                sum2 += d * d;
            }
            (worst, sum2)
        })
        .collect();
    let max = per_bin.iter().map(|x| x.0).fold(0.0, f64::max);
    let sum2: f64 = per_bin.iter().map(|x| x.1).sum();
    (
        max,
        (sum2 / n as f64).sqrt(),
        per_bin.into_iter().map(|x| x.0).collect(),
    )
}

/// Foot parameter and distance of `q` by Newton on `C'·(C − q)` from `u` (inside the domain),
/// `None` unless it converges to a minimum within a few steps.
fn newton(curve: &NurbsCurve, q: Vec3, mut u: f64, d: &mut [Vec3; 3]) -> Option<(f64, f64)> {
    let (a, b) = curve.domain();
    for _ in 0..8 {
        curve.derivatives_into(u, 2, d);
        let diff = d[0] - q;
        let f = d[1].dot(diff);
        let fp = d[2].dot(diff) + d[1].norm_squared();
        if fp.is_nan() || fp <= 0.0 {
            return None;
        }
        let next = (u - f / fp).clamp(a, b);
        if (next - u).abs() <= 1e-12 * (b - a) {
            return Some((next, (curve.point(next) - q).norm()));
        }
        u = next;
    }
    None
}

/// `r` measured on the input points: its quality's deviations and `met` replaced by those of every
/// input point (`max`, `rms`) against the tolerance `tol` (input units), which becomes the result's.
pub fn measured(
    mut r: IntegratedResult,
    max: f64,
    rms: f64,
    tol: f64,
    span_fairness: Option<f64>,
) -> IntegratedResult {
    r.quality = FitQuality {
        max_deviation: max,
        rms_deviation: rms,
        ..r.quality
    };
    r.tolerance = tol;
    r.met = max <= tol && span_fairness.is_none_or(|t| r.quality.max_span_fairness <= t);
    r
}
