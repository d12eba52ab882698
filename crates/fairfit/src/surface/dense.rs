//! Dense sections (scans, mesh and cloud slices of 10^3-10^5 points each): screened and reduced the
//! way dense curves are, so that the shared knot search costs what the shapes and the tolerance
//! need, not what the point count is; the tolerance is then verified on every kept point.
//!
//! # When it applies
//!
//! The sections are *dense* when their reduced forms ([`crate::fit::reduce`]) together at least halve
//! their points ([`ReduceTuning::min_points_per_bin`] over all sections, as for one curve). Otherwise
//! the plain pipeline runs untouched (every clean table, the blade, whose small tip section alone
//! would reduce, and the sliced bunny: byte-identical results). When they are, every section takes
//! the path below; a section whose own reduction would not halve it is its own reduced form (one
//! bin per point, spread 0) and is not screened.
//!
//! # Steps
//!
//! 1. **Screening** of every dense section ([`crate::fit::screening::screen`], as for curves): the
//!    noise `σ` is measured, isolated spikes are excluded ([`DenseOptions::outliers`]) and listed in
//!    [`DenseSummary`], and a tolerance below what the noise allows is raised to the meaningful one
//!    (the largest over the sections, [`DenseSummary::tolerance_used`]; said so, never silent).
//! 2. **Reduction**: representatives of tolerance-sized arcs, each bin's spread (noise plus
//!    sagitta) recorded ([`crate::fit::reduce`], the same tuning as curves).
//! 3. **Compatible fit** of the representatives ([`super::compatible`]), each within its own
//!    bin's *share* of the tolerance, `tol − spread` of the widest spread among its bin and its two
//!    neighbours (at least `tol/4`), as for curves: a curve within that of every representative is
//!    within `tol` of its bin's points. The shares reach the shared knot search as per-point
//!    deviation factors, so a bin of large spread (a thin trailing edge's sagitta, the noise's
//!    extreme) tightens the fit there and nowhere else; held to the tightest share everywhere, the
//!    sections of noisy cloud slices were held to a quarter of the tolerance and took up to 1.6
//!    times the control points (the vase clouds of `bench/dense_surface.py`).
//! 4. **Verification on every kept point**: each point is projected onto its section curve by
//!    Newton from the previous point's foot, by the local sampled search when Newton lands beyond
//!    the tolerance, and a remaining violation is confirmed by the whole-curve search. Bins holding
//!    a point beyond the tolerance are cut in two and the search runs again
//!    ([`ReduceTuning::repair_rounds`] times at most); then every share is tightened by twice the
//!    largest excess ([`ReduceTuning::tighten_rounds`] times at most).
//! 5. The skinned surface's deviation of every kept point is measured by a projection started at
//!    the point's section parameters ([`super::measure::surface_deviation_near`]): a local search,
//!    not a scan of the whole sample grid per point.
//!
//! Every step is a pure function of the sections, and the parallel loops collect in input order:
//! the result does not depend on the thread count.

use super::compatible::{make_compatible_held_to, CompatibleOptions, CompatibleSections};
use super::orient::Section;
use super::section_fit::newton_from;
use crate::diffgeo::CurveProjector;
use crate::errors::Result;
use crate::fit::outliers::Outlier;
use crate::fit::reduce::{bin_points, reduce, refine, Bin, ReduceTuning, Reduced};
use crate::fit::screening::{screen, OutlierMode, Screening};
use crate::nurbs::Vec3;
use rayon::prelude::*;
use serde::Serialize;

/// How dense sections are treated (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct DenseOptions {
    /// Take the dense path when some section is dense (`false`: always the plain pipeline, e.g. for
    /// the samples of exact CAD curves, which are refined point by point). Default `true`.
    pub enabled: bool,
    /// Spikes of dense sections: excluded (`Auto`, the default, as for curves) or kept (`Off`).
    pub outliers: OutlierMode,
    /// The reduction's thresholds (the curves' defaults).
    pub reduce: ReduceTuning,
}

impl Default for DenseOptions {
    fn default() -> Self {
        DenseOptions {
            enabled: true,
            outliers: OutlierMode::Auto,
            reduce: ReduceTuning::default(),
        }
    }
}

/// What the dense path found and did, per section and overall (the report's `dense`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DenseSummary {
    /// The tolerance the surface is held to: the one asked for, or the meaningful tolerance of the
    /// noisiest section when the asked one is below its noise.
    pub tolerance_used: f64,
    /// The tolerance the representatives were fitted within (`tolerance_used` less the spread,
    /// tightened by the repair).
    pub fit_tolerance: f64,
    /// Bin-cutting rounds and tolerance tightenings of the repair (0 when the first fit held).
    pub repair_rounds: usize,
    /// One row per section, in the order fitted.
    pub sections: Vec<DenseSection>,
}

/// One section on the dense path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DenseSection {
    /// Points read (before the excluded spikes).
    pub points: usize,
    /// Representatives fitted (bins of the reduced form).
    pub representatives: usize,
    /// The noise `σ` measured across the section (0 when it was not screened: not dense).
    pub noise_sigma: f64,
    /// The section's meaningful tolerance when the asked one is below its noise.
    pub noise_limited: Option<f64>,
    /// Excluded spikes (indices into the section's points as read, after the alignment).
    pub outliers: Vec<Outlier>,
}

impl DenseSummary {
    /// The one-line warning when the tolerance asked for, `tol`, was below the noise.
    pub fn noise_warning(&self, tol: f64) -> Option<String> {
        let worst = self
            .sections
            .iter()
            .filter(|s| s.noise_limited.is_some())
            .max_by(|a, b| a.noise_sigma.total_cmp(&b.noise_sigma))?;
        Some(format!(
            "warning: the tolerance {tol:.3e} is below the noise of the sections (σ ≈ {:.3e}): fitted to {:.3e} instead, the smallest tolerance that does not follow the noise",
            worst.noise_sigma, self.tolerance_used
        ))
    }
}

/// Dense sections screened and reduced, ready for the compatible fit.
pub(crate) struct Prepared {
    /// The kept points of every section (spikes excluded).
    pub sections: Vec<Section>,
    reduced: Vec<Reduced>,
    rows: Vec<DenseSection>,
    tol: f64,
}

/// A section's points as their own reduced form (one bin per point).
fn identity(points: &[Vec3]) -> Reduced {
    Reduced {
        bins: points
            .iter()
            .enumerate()
            .map(|(i, &p)| Bin {
                first: i,
                last: i,
                point: p,
                spread: 0.0,
            })
            .collect(),
    }
}

/// Screens and reduces `sections` at tolerance `tol` (module doc, steps 1-2), or `None` when no
/// section is dense (the plain pipeline then runs).
pub(crate) fn prepare(sections: &[Section], tol: f64, opts: &DenseOptions) -> Option<Prepared> {
    if !opts.enabled {
        return None;
    }
    let h = opts.reduce.bin_tolerances * tol;
    let bins: usize = sections
        .par_iter()
        .map(|s| match s.points.len() {
            n if n < 3 => n,
            _ => bin_points(&s.points, h, &opts.reduce).bins.len(),
        })
        .sum();
    let points: usize = sections.iter().map(|s| s.points.len()).sum();
    if bins as f64 * opts.reduce.min_points_per_bin > points as f64 {
        return None;
    }
    let dense: Vec<bool> = sections
        .par_iter()
        .map(|s| reduce(&s.points, tol, &opts.reduce).is_some())
        .collect();
    let screened: Vec<(Section, Option<Screening>)> = sections
        .par_iter()
        .zip(&dense)
        .map(|(s, &d)| {
            if !d {
                return (s.clone(), None);
            }
            let (found, kept) = screen(&s.points, tol, opts.outliers);
            let mut points = kept.unwrap_or_else(|| s.points.clone());
            if s.closed && points.first() != points.last() {
                if let Some(&f) = points.first() {
                    points.push(f);
                }
            }
            (
                Section {
                    points,
                    closed: s.closed,
                },
                Some(found),
            )
        })
        .collect();
    let used = screened
        .iter()
        .filter_map(|(_, f)| f.as_ref().map(|f| f.tolerance_used(tol)))
        .fold(tol, f64::max);
    let (kept, screenings): (Vec<Section>, Vec<Option<Screening>>) = screened.into_iter().unzip();
    let reduced: Vec<Reduced> = kept
        .par_iter()
        .map(|s| reduce(&s.points, used, &opts.reduce).unwrap_or_else(|| identity(&s.points)))
        .collect();
    let rows = sections
        .iter()
        .zip(&reduced)
        .zip(screenings)
        .map(|((s, r), f)| DenseSection {
            points: s.points.len(),
            representatives: r.bins.len(),
            noise_sigma: f.as_ref().map_or(0.0, |f| f.noise_sigma),
            noise_limited: f.as_ref().and_then(|f| f.noise_limited),
            outliers: f.map(|f| f.outliers).unwrap_or_default(),
        })
        .collect();
    Some(Prepared {
        sections: kept,
        reduced,
        rows,
        tol: used,
    })
}

/// The compatible fit of dense sections, verified on every kept point (module doc, steps 3-4).
pub(crate) struct DenseFit {
    /// The compatible curves (their fits' parameters are the representatives').
    pub compatible: CompatibleSections,
    /// Per section, the foot parameter of every kept point on its curve.
    pub us: Vec<Vec<f64>>,
    /// Per section, the largest distance of a kept point from its curve.
    pub section_deviation: Vec<f64>,
    /// What was found and done.
    pub summary: DenseSummary,
}

/// One section measured on every point: the foot parameters, the largest distance per bin and the
/// largest overall.
struct Checked {
    us: Vec<f64>,
    per_bin: Vec<f64>,
    max: f64,
}

/// Fits the representatives, verifies every kept point and repairs (module doc, steps 3-4).
pub(crate) fn fit(
    mut p: Prepared,
    sections: &CompatibleOptions,
    dense: &DenseOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<DenseFit> {
    let tuning = &dense.reduce;
    let tol = p.tol;
    let h = tuning.bin_tolerances * tol;
    let share = |spread: f64| (tol - spread).max(0.25 * tol);
    let tightest = |p: &Prepared| share(p.reduced.iter().map(Reduced::spread).fold(0.0, f64::max));
    // the tightest share; a tightening shrinks every share by the same factor
    let mut inner = tightest(&p);
    let (mut cuts, mut tightenings) = (0, 0);
    // a smoothing the search had to relax stays relaxed for the repair rounds
    let mut smoothing = sections.smoothing;
    loop {
        let reps: Vec<Section> = p
            .sections
            .iter()
            .zip(&p.reduced)
            .map(|(s, r)| Section {
                points: representatives(s, r, sections.split_at_le),
                closed: s.closed,
            })
            .collect();
        let t = tightest(&p);
        let factors: Vec<Vec<f64>> = p
            .reduced
            .iter()
            .map(|r| {
                let ns = r.neighbour_spreads();
                ns.into_iter().map(|s| t / share(s)).collect()
            })
            .collect();
        let mut o = sections.clone();
        o.tolerance = inner;
        o.smoothing = smoothing;
        let compatible = make_compatible_held_to(&reps, &o, &factors, progress)?;
        smoothing = compatible.smoothing;
        let checked: Vec<Checked> = p
            .sections
            .par_iter()
            .zip(&p.reduced)
            .zip(&compatible.fits)
            .map(|((s, r), f)| check(&s.points, r, f, compatible.periodic, tol))
            .collect::<Result<_>>()?;
        let max = checked.iter().map(|c| c.max).fold(0.0, f64::max);
        let done = max <= tol || !compatible.within_tolerance;
        if !done && cuts < tuning.repair_rounds {
            let mut changed = false;
            for ((s, r), c) in p.sections.iter().zip(&mut p.reduced).zip(&checked) {
                let cut: Vec<bool> = c.per_bin.iter().map(|&d| d > tol).collect();
                changed |= refine(&s.points, r, &cut, h, tuning);
            }
            if changed {
                cuts += 1;
                inner = inner.min(tightest(&p));
                continue;
            }
        }
        // the excess taken off the tightest share, twice over (a fit tightened by exactly the
        // excess lands on the tolerance's edge again)
        let tighter = inner - 2.0 * (max - tol);
        if done || tightenings == tuning.tighten_rounds || tighter <= 0.0 {
            return Ok(finished(
                p,
                compatible,
                checked,
                max,
                inner,
                cuts + tightenings,
            ));
        }
        inner = tighter;
        tightenings += 1;
    }
}

/// The representatives of section `s` reduced to `r`. With `split_at_le` the bin holding the
/// section's leading edge is represented by that data point itself, so the leading edge pinned on the
/// representatives ([`super::leading_edge`]) is the data's: the end bins hold the end points (the
/// same trailing edge), and a centroid is never farther from it than its bin's farthest point.
fn representatives(s: &Section, r: &Reduced, split_at_le: bool) -> Vec<Vec3> {
    let mut pts = r.points();
    if let Some(i) = split_at_le
        .then(|| crate::fit::airfoil::leading_edge(&s.points))
        .flatten()
    {
        if let Some(b) = r.bins.iter().position(|b| b.first <= i && i <= b.last) {
            pts[b] = s.points[i];
        }
    }
    pts
}

/// The fit's measures replaced by those of every kept point.
fn finished(
    p: Prepared,
    mut compatible: CompatibleSections,
    checked: Vec<Checked>,
    max: f64,
    inner: f64,
    rounds: usize,
) -> DenseFit {
    compatible.max_deviation = max;
    compatible.within_tolerance = max <= p.tol;
    let section_deviation = checked.iter().map(|c| c.max).collect();
    let mut rows = p.rows;
    for (row, r) in rows.iter_mut().zip(&p.reduced) {
        row.representatives = r.bins.len();
    }
    DenseFit {
        compatible,
        us: checked.into_iter().map(|c| c.us).collect(),
        section_deviation,
        summary: DenseSummary {
            tolerance_used: p.tol,
            fit_tolerance: inner,
            repair_rounds: rounds,
            sections: rows,
        },
    }
}

/// Every point of one section projected onto its fitted curve (module doc, step 4).
fn check(
    points: &[Vec3],
    r: &Reduced,
    f: &super::section_fit::SectionFit,
    periodic: bool,
    tol: f64,
) -> Result<Checked> {
    let clamped;
    let curve = if periodic {
        clamped = f.curve.clamped()?;
        &clamped
    } else {
        &f.curve
    };
    let proj = CurveProjector::new(curve, 8);
    let mut us = vec![0.0; points.len()];
    let mut per_bin = Vec::with_capacity(r.bins.len());
    let mut d3 = [Vec3::ZERO; 3];
    for (b, &u0) in r.bins.iter().zip(&f.params) {
        let mut u = u0;
        let mut worst = 0.0f64;
        let range = b.first..=b.last;
        for (&q, foot) in points[range.clone()].iter().zip(&mut us[range]) {
            let (mut nu, mut d) = newton_from(curve, q, u, &mut d3);
            if d > tol {
                let near = proj.project_near(q, u);
                if near.distance < d {
                    (nu, d) = (near.u, near.distance);
                }
            }
            if d > tol {
                let far = proj.project(q);
                if far.distance < d {
                    (nu, d) = (far.u, far.distance);
                }
            }
            *foot = nu;
            u = nu;
            worst = worst.max(d);
        }
        per_bin.push(worst);
    }
    let max = per_bin.iter().copied().fold(0.0, f64::max);
    Ok(Checked { us, per_bin, max })
}
