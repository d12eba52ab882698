//! Compatible section curves: ONE clamped knot vector shared by all sections, each section fitted by
//! least squares on it (approximate compatibility by multiple curve refitting, Park et al. 2000;
//! method reconstruction §4).
//!
//! Deterministic search: every section gets normalised chord-length parameters; candidate knot vectors
//! equidistribute a blend of the uniform density and the sections' averaged turning-angle density (so
//! knots gather where any section bends sharply, e.g. airfoil leading edges). The number of control
//! points grows geometrically until the worst section's orthogonal deviation is within tolerance, then is
//! bisected down to the smallest count that passes; among the passing candidates of that count the one
//! with the smallest worst-span fairness `max_{k,j} F_{k,j}` over all sections is kept.
//!
//! Matching inner corners of the sections are held as knots of multiplicity `p` that the search never
//! moves or removes, with piecewise chord-length parameters ([`super::section_corners`]). With
//! [`CompatibleOptions::split_at_le`] every airfoil section's leading edge is pinned to one common
//! parameter, without a knot ([`super::leading_edge`]).

use super::leading_edge::{find_leading_edges, split_params, LeadingEdges, LEADING_EDGE_PARAMETER};
use super::orient::Section;
use super::seam::{periodic_seam, smooth_at_seam};
use super::seam_tie::tie_order;
use super::section_corners::{piecewise_params, plan_corners, CornerFreedom, HeldCorners};
use super::section_fit::{chord_length_params, fit_section_with, SectionFit};
use crate::errors::{Error, Result};
use crate::fair::FairnessEvaluator;
use crate::fit::lsq::periodic_knots;
use crate::nurbs::NurbsCurve;
use rayon::prelude::*;

/// Options of [`make_compatible`].
#[derive(Clone, Debug)]
pub struct CompatibleOptions {
    /// Degree of the section curves (3 = cubic).
    pub degree: usize,
    /// Largest allowed orthogonal distance of a section point from its curve.
    pub tolerance: f64,
    /// Upper bound on the number of control points per section.
    pub max_control_points: usize,
    /// Parameter-correction passes per fit.
    pub corrections: usize,
    /// Weight of the bending term `∫|C''|² du` against the mean squared residual during the knot search
    /// (a small value keeps spans with little data from folding; 0 = pure least squares).
    pub smoothing: f64,
    /// Parameters of the section points (one increasing list in `[0, 1]` per section, first 0, last 1),
    /// e.g. from design data; `None` uses normalised chord lengths.
    pub section_params: Option<Vec<Vec<f64>>>,
    /// Fairing weights tried, largest first, for each section on the final knot vector: each section keeps
    /// the largest weight that still meets the tolerance (none: keep the search fit).
    pub fairing_weights: Vec<f64>,
    /// Blends of uniform and curvature-driven knot density tried for each control-point count
    /// (1 = uniform knots).
    pub uniform_blends: Vec<f64>,
    /// Fit closed sections that are smooth at their seams periodically (one periodic knot vector,
    /// `C^(p−1)` across the seam, see [`super::seam`]); when some section is open the knot vector stays
    /// clamped and each smooth closed section gets its seam tied (`C^(p−1)`, at most `C^2`, see
    /// the private `seam_tie` module). `false` keeps the plain clamped fit (C0 seams).
    pub periodic_closed: bool,
    /// Turning angle (degrees) above which a point is a corner, judged at the tolerance's scale: next to
    /// a seam it keeps the seam C0; inside the sections it is held as a C0 knot when
    /// [`Self::hold_corners`] allows ([`super::section_corners`]).
    pub corner_angle_deg: f64,
    /// Hold matching inner corners of the sections as C0 knot lines (`false`: they are smoothed over
    /// like any other point).
    pub hold_corners: bool,
    /// Airfoil sections: pin every section's leading edge (the point farthest from the midpoint of its
    /// first and last points) to the common parameter 0.5 ([`super::leading_edge`], the convention of
    /// `fairfit curve --split-at-le`); each section curve passes through it there exactly. Conflicts
    /// with [`Self::section_params`] ([`crate::Error::InvalidOption`]); a section whose leading edge
    /// would be an end point, or is a held corner, is an [`crate::Error::InvalidData`] naming it.
    pub split_at_le: bool,
}

impl Default for CompatibleOptions {
    fn default() -> Self {
        CompatibleOptions {
            degree: 3,
            tolerance: 1e-3,
            max_control_points: 60,
            corrections: 8,
            smoothing: 1e-11,
            fairing_weights: vec![1e-7, 1e-8, 1e-9, 1e-10],
            section_params: None,
            uniform_blends: vec![0.5, 0.25],
            periodic_closed: true,
            corner_angle_deg: crate::fit::shape::DEFAULT_CORNER_ANGLE_DEG,
            hold_corners: true,
            split_at_le: false,
        }
    }
}

/// Sections fitted on one shared knot vector.
#[derive(Clone, Debug)]
pub struct CompatibleSections {
    /// The shared knot vector: clamped, or periodic when [`Self::periodic`].
    pub knots: Vec<f64>,
    /// True when the closed sections were fitted periodically (smooth seam): the knot vector is
    /// unclamped and every curve's last `p` control points repeat its first.
    pub periodic: bool,
    /// One fit per section, in input order.
    pub fits: Vec<SectionFit>,
    /// Worst orthogonal deviation over all sections.
    pub max_deviation: f64,
    /// Worst per-span fairness `F_j` over all sections.
    pub max_span_fairness: f64,
    /// True when `max_deviation <= tolerance`.
    pub within_tolerance: bool,
    /// Number of candidate knot vectors evaluated.
    pub candidates_tried: usize,
    /// The weight of the bending term the search ended with: [`CompatibleOptions::smoothing`], or
    /// less when no knot vector met the tolerance with it (it is then relaxed, at most twice, by a
    /// factor of 100 each time).
    pub smoothing: f64,
    /// The sections' inner corners and whether they are held as C0 knots of multiplicity `p`
    /// ([`super::section_corners`]).
    pub corners: HeldCorners,
    /// With [`CompatibleOptions::split_at_le`]: the sections' leading edges at their common parameter
    /// and how far each fit is from its leading-edge point there (`None` without).
    pub leading_edges: Option<LeadingEdges>,
}

impl CompatibleSections {
    /// The section curves.
    pub fn curves(&self) -> Vec<NurbsCurve> {
        self.fits.iter().map(|f| f.curve.clone()).collect()
    }
}

/// Cumulative turning-angle density of one section sampled on a uniform grid of `grid + 1` parameters.
fn turning_cdf(points: &[crate::nurbs::Vec3], params: &[f64], grid: usize) -> Vec<f64> {
    let m = points.len();
    let mut w = vec![0.0; m];
    for k in 1..m.saturating_sub(1) {
        let a = points[k] - points[k - 1];
        let b = points[k + 1] - points[k];
        let (na, nb) = (a.norm(), b.norm());
        if na > 0.0 && nb > 0.0 {
            let c = (a.dot(b) / (na * nb)).clamp(-1.0, 1.0);
            // softened: sqrt of the turning angle spreads knots over the whole bend
            w[k] = c.acos().sqrt();
        }
    }
    let total: f64 = w.iter().sum();
    let mut cdf = vec![0.0; grid + 1];
    if total.is_nan() || total <= 0.0 {
        for (g, v) in cdf.iter_mut().enumerate() {
            *v = g as f64 / grid as f64;
        }
        return cdf;
    }
    let mut acc = 0.0;
    let mut k = 0;
    for (g, v) in cdf.iter_mut().enumerate() {
        let u = g as f64 / grid as f64;
        while k < m && params[k] <= u {
            acc += w[k];
            k += 1;
        }
        *v = acc / total;
    }
    cdf
}

/// Interior knots equidistributing `blend * u + (1 - blend) * cdf(u)` into `spans` spans.
fn knots_from_density(cdf: &[f64], blend: f64, degree: usize, n_ctrl: usize) -> Vec<f64> {
    let grid = cdf.len() - 1;
    let h: Vec<f64> = cdf
        .iter()
        .enumerate()
        .map(|(g, &c)| blend * g as f64 / grid as f64 + (1.0 - blend) * c)
        .collect();
    let spans = n_ctrl - degree;
    let mut knots = vec![0.0; degree + 1];
    let mut g = 0;
    for i in 1..spans {
        let target = i as f64 / spans as f64;
        while g + 1 < grid && h[g + 1] < target {
            g += 1;
        }
        let (h0, h1) = (h[g], h[g + 1]);
        let t = if h1 > h0 {
            (target - h0) / (h1 - h0)
        } else {
            0.5
        };
        let u = (g as f64 + t.clamp(0.0, 1.0)) / grid as f64;
        knots.push(u);
    }
    // keep knots strictly increasing and away from the ends
    let min_gap = 1e-6;
    for i in degree + 1..knots.len() {
        let lo = knots[i - 1] + min_gap;
        if knots[i] < lo {
            knots[i] = lo;
        }
    }
    knots.extend(std::iter::repeat_n(1.0, degree + 1));
    knots
}

/// Clamped or periodic shared knot vectors, built from their interior knots (the breakpoints strictly
/// inside `(0, 1)`; both forms hold them at indices `p + 1 .. len − p − 1`). A clamped form may hold
/// corner knots of multiplicity `p` ([`super::section_corners`]): they are added by [`Self::full`] and
/// left out by [`Self::interior`], so the knot search only ever inserts and removes the free knots.
#[derive(Clone, Copy)]
struct KnotForm<'a> {
    degree: usize,
    periodic: bool,
    corners: &'a [f64],
}

/// Free knots closer than this to a corner knot are dropped (the density's smallest knot gap).
const CORNER_GAP: f64 = 1e-6;

/// How often the knot search is run again with [`CompatibleOptions::smoothing`] relaxed when no knot
/// vector met the tolerance (each time by [`SMOOTHING_RELAXATION`]; from the default 1e-11 down to
/// 1e-15, still enough to keep a span without data well posed).
const SMOOTHING_RELAXATIONS: usize = 2;

/// The factor of each relaxation of the smoothing.
const SMOOTHING_RELAXATION: f64 = 1e-2;

/// A refinement gives up after this many insertion rounds in a row that did not lower its smallest
/// worst deviation below [`STALL_GAIN`] times itself: knots are then being inserted where they do
/// not help (the bending term binds, or the worst point cannot be reached), and the control-point
/// cap would only be reached at great cost.
const STALL_ROUNDS: usize = 4;

/// The fraction of the smallest worst deviation a round must reach to count as progress.
const STALL_GAIN: f64 = 0.99;

impl KnotForm<'_> {
    fn full(self, interior: &[f64]) -> Vec<f64> {
        let p = self.degree;
        if !self.corners.is_empty() {
            let mut all: Vec<f64> = interior
                .iter()
                .copied()
                .filter(|t| self.corners.iter().all(|c| (t - c).abs() > CORNER_GAP))
                .collect();
            for &c in self.corners {
                all.extend(std::iter::repeat_n(c, p));
            }
            all.sort_by(f64::total_cmp);
            let mut k = vec![0.0; p + 1];
            k.extend(all);
            k.extend(std::iter::repeat_n(1.0, p + 1));
            return k;
        }
        if self.periodic {
            let mut b = Vec::with_capacity(interior.len() + 2);
            b.push(0.0);
            b.extend_from_slice(interior);
            b.push(1.0);
            periodic_knots(&b, p)
        } else {
            let mut k = vec![0.0; p + 1];
            k.extend_from_slice(interior);
            k.extend(std::iter::repeat_n(1.0, p + 1));
            k
        }
    }

    /// The free interior knots (corner knots left out).
    fn interior(self, knots: &[f64]) -> Vec<f64> {
        let inner = &knots[self.degree + 1..knots.len() - self.degree - 1];
        if self.corners.is_empty() {
            return inner.to_vec();
        }
        inner
            .iter()
            .copied()
            .filter(|t| !self.corners.contains(t))
            .collect()
    }

    /// Distinct control points (a periodic curve repeats `p` of them).
    fn distinct(self, knots: &[f64]) -> usize {
        let n = knots.len() - self.degree - 1;
        if self.periodic {
            n - self.degree
        } else {
            n
        }
    }

    /// Fewest interior knots: a periodic knot vector needs `p + 1` spans.
    fn min_interior(self) -> usize {
        if self.periodic {
            self.degree
        } else {
            0
        }
    }

    /// The form's knot vector with `n_ctrl` distinct control points from [`knots_from_density`].
    fn by_density(self, cdf: &[f64], blend: f64, n_ctrl: usize) -> Vec<f64> {
        let p = self.degree;
        if self.periodic {
            let k = knots_from_density(cdf, blend, p, n_ctrl.max(p + 1) + p);
            self.full(&self.interior(&k))
        } else if !self.corners.is_empty() {
            let k = knots_from_density(cdf, blend, p, n_ctrl);
            let free = KnotForm {
                corners: &[],
                ..self
            }
            .interior(&k);
            self.full(&free)
        } else {
            knots_from_density(cdf, blend, p, n_ctrl)
        }
    }
}

/// What every fit of a section keeps whatever the knots: its seam tie order ([`seam_ties`]), its
/// held corner parameters (`(point index, parameter)`, empty when no corner is held), its pinned
/// leading edge (`(point index, u_LE)`, empty without [`CompatibleOptions::split_at_le`]) and its
/// points' deviation factors ([`make_compatible_held_to`]; empty: all 1).
struct Fixed<'a> {
    ties: Vec<usize>,
    held: Vec<Vec<(usize, f64)>>,
    pins: Vec<(usize, f64)>,
    factors: &'a [Vec<f64>],
}

impl Fixed<'_> {
    fn held(&self, k: usize) -> &[(usize, f64)] {
        self.held.get(k).map_or(&[], Vec::as_slice)
    }

    /// Section `k`'s deviation of point `i` as the search measures it (times its factor).
    fn measured(&self, k: usize, i: usize, d: f64) -> f64 {
        self.factors
            .get(k)
            .and_then(|f| f.get(i))
            .map_or(d, |f| f * d)
    }

    /// Section `k`'s largest measured deviation of `fit`.
    fn max_measured(&self, k: usize, fit: &SectionFit) -> f64 {
        if self.factors.is_empty() {
            return fit.max_deviation;
        }
        fit.deviations
            .iter()
            .enumerate()
            .map(|(i, &d)| self.measured(k, i, d))
            .fold(0.0, f64::max)
    }

    /// The largest measured deviation over all sections' `fits` (in section order).
    fn worst(&self, fits: &[SectionFit]) -> f64 {
        fits.iter()
            .enumerate()
            .map(|(k, f)| self.max_measured(k, f))
            .fold(0.0, f64::max)
    }

    fn pin(&self, k: usize) -> Option<(usize, f64)> {
        self.pins.get(k).copied()
    }
}

struct Candidate {
    knots: Vec<f64>,
    fits: Vec<SectionFit>,
    max_dev: f64,
}

fn evaluate(
    sections: &[Section],
    params: &[Vec<f64>],
    knots: Vec<f64>,
    opts: &CompatibleOptions,
    global: bool,
    fixed: &Fixed,
) -> Option<Candidate> {
    let fits: Result<Vec<SectionFit>> = sections
        .par_iter()
        .zip(params.par_iter())
        .enumerate()
        .map(|(k, (s, t))| {
            fit_section_with(
                &s.points,
                t,
                opts.degree,
                &knots,
                opts.smoothing,
                opts.corrections,
                global,
                fixed.ties[k],
                fixed.held(k),
                fixed.pin(k),
            )
        })
        .collect();
    let fits = fits.ok()?;
    let max_dev = fixed.worst(&fits);
    Some(Candidate {
        knots,
        fits,
        max_dev,
    })
}

/// Where to insert the next knots: in the (at most `count`) spans with the largest deviation over all
/// sections above `tol`, at the worst point of that span, or at the span's middle when that point lies
/// close to a knot.
fn insertion_knots(c: &Candidate, fixed: &Fixed, p: usize, tol: f64, count: usize) -> Vec<f64> {
    let k = &c.knots;
    let n1 = k.len() - p - 1;
    // per span: (largest deviation, its parameter)
    let mut worst: Vec<(f64, f64)> = vec![(0.0, 0.0); n1];
    for (sec, f) in c.fits.iter().enumerate() {
        for (i, (&t, &d)) in f.params.iter().zip(&f.deviations).enumerate() {
            let d = fixed.measured(sec, i, d);
            let span = crate::nurbs::knots::find_span(n1 - 1, p, t, k);
            if d > worst[span].0 {
                worst[span] = (d, t);
            }
        }
    }
    let mut spans: Vec<usize> = (p..n1).filter(|&s| worst[s].0 > tol).collect();
    spans.sort_by(|&a, &b| worst[b].0.total_cmp(&worst[a].0));
    spans.truncate(count);
    let mut out = Vec::new();
    for s in spans {
        let (a, b) = (k[s], k[s + 1]);
        if b - a <= 1e-9 {
            continue;
        }
        let t = worst[s].1;
        let min_gap = 0.2 * (b - a);
        let t = if t - a < min_gap || b - t < min_gap {
            0.5 * (a + b)
        } else {
            t
        };
        out.push(t);
    }
    out.sort_by(|a, b| a.total_cmp(b));
    out
}

/// Per section, the largest fairing weight whose fit (global projection) still meets the tolerance.
fn fair_per_section(
    sections: &[Section],
    params: &[Vec<f64>],
    mut c: Candidate,
    opts: &CompatibleOptions,
    fixed: &Fixed,
) -> Candidate {
    if opts.fairing_weights.is_empty() {
        return c;
    }
    let improved: Vec<Option<SectionFit>> = sections
        .par_iter()
        .zip(params.par_iter())
        .enumerate()
        .map(|(k, (s, t))| {
            opts.fairing_weights.iter().find_map(|&w| {
                fit_section_with(
                    &s.points,
                    t,
                    opts.degree,
                    &c.knots,
                    w,
                    opts.corrections,
                    true,
                    fixed.ties[k],
                    fixed.held(k),
                    fixed.pin(k),
                )
                .ok()
                .filter(|f| fixed.max_measured(k, f) <= opts.tolerance)
            })
        })
        .collect();
    for (fit, new) in c.fits.iter_mut().zip(improved) {
        if let Some(n) = new {
            *fit = n;
        }
    }
    c.max_dev = fixed.worst(&c.fits);
    c
}

fn worst_span_fairness(fits: &[SectionFit]) -> f64 {
    let per: Vec<f64> = fits
        .par_iter()
        .map_init(FairnessEvaluator::new, |ev, f| {
            let spans = ev.integrate(&f.curve);
            let l: f64 = spans.iter().map(|s| s.length).sum();
            spans.iter().map(|s| s.energy).fold(0.0, f64::max) * l * l * l
        })
        .collect();
    per.into_iter().fold(0.0, f64::max)
}

/// Fits all `sections` on one shared knot vector (see the module documentation).
///
/// ```
/// use fairfit::surface::{make_compatible, CompatibleOptions, Section};
/// use fairfit::Vec3;
/// // three ellipses of different size: one shared cubic knot vector fits all within 1e-4
/// let sections: Vec<Section> = (0..3)
///     .map(|k| {
///         let a = 1.0 + 0.5 * k as f64;
///         Section::from_points((0..=60).map(|i| {
///             let t = std::f64::consts::TAU * i as f64 / 60.0;
///             Vec3::new(a * t.cos(), 0.5 * t.sin(), k as f64)
///         }).collect())
///     })
///     .collect();
/// let opts = CompatibleOptions { tolerance: 1e-4, ..Default::default() };
/// let c = make_compatible(&sections, &opts).unwrap();
/// assert!(c.within_tolerance && c.max_deviation <= 1e-4);
/// assert!(c.fits.iter().all(|f| f.curve.knots() == c.knots.as_slice()));
/// ```
pub fn make_compatible(
    sections: &[Section],
    opts: &CompatibleOptions,
) -> Result<CompatibleSections> {
    make_compatible_with_progress(sections, opts, &mut |_| {})
}

/// [`make_compatible`] reporting the number of candidates evaluated so far to `progress`.
///
/// Held corners are kept only when they let every section meet the tolerance: otherwise (a corner
/// the detector placed a point off on noisy sections, where the held fit runs to the control-point
/// cap and still misses) the sections are fitted again with the corners smoothed over, as without
/// holding, and the report's `corners.reason` says why.
pub(crate) fn make_compatible_with_progress(
    sections: &[Section],
    opts: &CompatibleOptions,
    progress: &mut dyn FnMut(usize),
) -> Result<CompatibleSections> {
    make_compatible_held_to(sections, opts, &[], progress)
}

/// [`make_compatible_with_progress`] with every point `i` of section `k` held within
/// `tolerance / factors[k][i]` instead of the tolerance (factors at most 1; empty: all 1): the
/// search, the fairing and `max_deviation` measure `factors[k][i] · d_i` against the tolerance.
/// The dense path's representatives use it, each within its bin's share ([`super::dense`]).
pub(crate) fn make_compatible_held_to(
    sections: &[Section],
    opts: &CompatibleOptions,
    factors: &[Vec<f64>],
    progress: &mut dyn FnMut(usize),
) -> Result<CompatibleSections> {
    let held = fit_once(sections, opts, factors, progress)?;
    if held.within_tolerance || !held.corners.held {
        return Ok(held);
    }
    let free = CompatibleOptions {
        hold_corners: false,
        ..opts.clone()
    };
    let mut plain = fit_once(sections, &free, factors, progress)?;
    plain.corners = HeldCorners {
        held: false,
        params: Vec::new(),
        reason: Some(format!(
            "held as C0 knot lines the sections missed the tolerance ({:.3} of it, {} control points); fitted with the corners smoothed over",
            held.max_deviation / opts.tolerance,
            held.knots.len().saturating_sub(opts.degree + 1)
        )),
        ..held.corners
    };
    plain.candidates_tried += held.candidates_tried;
    Ok(plain)
}

/// One compatible fit of `sections` under `opts` (corners held when [`CompatibleOptions::hold_corners`]
/// and the sections allow it).
fn fit_once(
    sections: &[Section],
    opts: &CompatibleOptions,
    factors: &[Vec<f64>],
    progress: &mut dyn FnMut(usize),
) -> Result<CompatibleSections> {
    let p = opts.degree;
    let min_pts = validate(sections, opts)?;
    let mut params = section_params(sections, opts)?;
    let les = opts
        .split_at_le
        .then(|| find_leading_edges(sections))
        .transpose()?;
    let periodic =
        opts.periodic_closed && periodic_seam(sections, opts.corner_angle_deg, opts.tolerance);
    let (mut corners, mut plan) = plan_corners(
        sections,
        opts.corner_angle_deg,
        opts.tolerance,
        CornerFreedom {
            clamped: !periodic,
            params_given: opts.section_params.is_some(),
            switched_off: !opts.hold_corners,
        },
    );
    if let Some(les) = &les {
        params = split_params(sections, les, plan.as_mut())?;
        if let Some(plan) = &plan {
            corners.params.clone_from(&plan.params);
        }
    } else if let Some(plan) = &plan {
        params = sections
            .iter()
            .zip(&plan.indices)
            .map(|(s, idx)| piecewise_params(&s.points, idx, &plan.params))
            .collect();
    }
    let fixed = Fixed {
        ties: seam_ties(sections, opts, periodic),
        held: plan.as_ref().map(|c| c.held_params()).unwrap_or_default(),
        factors,
        pins: les
            .iter()
            .flatten()
            .map(|&i| (i, LEADING_EDGE_PARAMETER))
            .collect(),
    };
    let leading_edges = |fits: &[SectionFit]| {
        les.as_ref()
            .map(|l| LeadingEdges::measure(sections, l, fits))
    };
    let form = KnotForm {
        degree: p,
        periodic,
        corners: plan.as_ref().map_or(&[], |c| c.params.as_slice()),
    };
    let cdf = mean_turning_cdf(sections, &params);
    let n_max = max_control_points(sections, opts, min_pts);
    let mut finals: Vec<Candidate> = Vec::new();
    let mut best_fail: Option<Candidate> = None;
    let mut tried = 0;
    // the bending term only keeps spans without data well posed: when no knot vector meets the
    // tolerance with it (a corner at the tolerance's scale that no knot is held at), it is what binds,
    // so the search runs again at the next of these levels before the best failure is given back
    // (without a bending term there is one level)
    let levels: Vec<f64> =
        std::iter::successors(Some(opts.smoothing), |w| Some(w * SMOOTHING_RELAXATION))
            .take(if opts.smoothing == 0.0 {
                1
            } else {
                SMOOTHING_RELAXATIONS + 1
            })
            .collect();
    let mut used = opts.clone();
    let mut relaxed = 0;
    for (level, &w) in levels.iter().enumerate() {
        (used.smoothing, relaxed) = (w, level);
        let mut search = Search {
            sections,
            params: &params,
            opts: &used,
            fixed: &fixed,
            form,
            progress: &mut *progress,
            tried,
        };
        let last = level + 1 == levels.len();
        search.run(&cdf, n_max, !last, &mut finals, &mut best_fail);
        tried = search.tried;
        if !finals.is_empty() {
            break;
        }
    }
    let opts = &used;
    if finals.is_empty() {
        let c = best_fail.ok_or_else(|| {
            Error::Fit("no knot vector gave a well-posed fit for every section".into())
        })?;
        let c = evaluate(sections, &params, c.knots.clone(), opts, true, &fixed).unwrap_or(c);
        let msf = worst_span_fairness(&c.fits);
        return Ok(CompatibleSections {
            leading_edges: leading_edges(&c.fits),
            knots: c.knots,
            max_deviation: c.max_dev,
            fits: c.fits,
            max_span_fairness: msf,
            within_tolerance: false,
            candidates_tried: tried,
            smoothing: opts.smoothing,
            periodic,
            corners,
        });
    }
    let (msf, c) = fewest_then_fairest(finals)?;
    // final measurement with global projection (never larger than the search's estimate)
    let c = evaluate(sections, &params, c.knots.clone(), opts, true, &fixed).unwrap_or(c);
    // a relaxed smoothing is what some section needed: every other keeps the largest weight, down
    // to the levels the relaxation passed, that meets the tolerance
    let mut fairing = opts.clone();
    fairing.fairing_weights.extend(&levels[..relaxed]);
    let c = fair_per_section(sections, &params, c, &fairing, &fixed);
    let msf = worst_span_fairness(&c.fits).min(msf);
    Ok(CompatibleSections {
        leading_edges: leading_edges(&c.fits),
        knots: c.knots,
        within_tolerance: c.max_dev <= opts.tolerance,
        max_deviation: c.max_dev,
        fits: c.fits,
        max_span_fairness: msf,
        candidates_tried: tried,
        smoothing: opts.smoothing,
        periodic,
        corners,
    })
}

/// Checks the options and the sections (degree, finite non-negative weights, blends in `[0, 1]`,
/// a positive tolerance, at least `degree + 1` points per section); returns the fewest points of
/// any section.
fn validate(sections: &[Section], opts: &CompatibleOptions) -> Result<usize> {
    let p = opts.degree;
    if p == 0 || p > crate::nurbs::knots::MAX_DEGREE {
        return Err(Error::InvalidOption(format!(
            "section degree must be in 1..={}, got {p}",
            crate::nurbs::knots::MAX_DEGREE
        )));
    }
    let finite_non_negative = |x: &f64| x.is_finite() && *x >= 0.0;
    if !finite_non_negative(&opts.smoothing) {
        return Err(Error::InvalidOption(format!(
            "section smoothing must be finite and >= 0, got {}",
            opts.smoothing
        )));
    }
    if !opts.fairing_weights.iter().all(finite_non_negative) {
        return Err(Error::InvalidOption(format!(
            "fairing weights must be finite and >= 0, got {:?}",
            opts.fairing_weights
        )));
    }
    if !opts.uniform_blends.iter().all(|b| (0.0..=1.0).contains(b)) {
        return Err(Error::InvalidOption(format!(
            "uniform blends must lie in [0, 1], got {:?}",
            opts.uniform_blends
        )));
    }
    if opts.tolerance.is_nan() || opts.tolerance <= 0.0 || !opts.tolerance.is_finite() {
        return Err(Error::InvalidOption(format!(
            "tolerance must be positive, got {}",
            opts.tolerance
        )));
    }
    if opts.split_at_le && opts.section_params.is_some() {
        return Err(Error::InvalidOption(
            "split_at_le sets the section parameters (the leading edges at 0.5): it cannot be \
             combined with given section parameters"
                .into(),
        ));
    }
    if sections.is_empty() {
        return Err(Error::InvalidData("no sections given".into()));
    }
    let min_pts = sections.iter().map(|s| s.points.len()).min().unwrap_or(0);
    if min_pts < p + 1 {
        return Err(Error::InvalidData(format!(
            "every section needs at least {} points for degree {p}, one has {min_pts}",
            p + 1
        )));
    }
    Ok(min_pts)
}

/// Each section's point parameters: chord length, or the caller's lists after checking that each
/// runs non-decreasing from 0 to 1 with one value per point.
fn section_params(sections: &[Section], opts: &CompatibleOptions) -> Result<Vec<Vec<f64>>> {
    Ok(match &opts.section_params {
        None => sections
            .iter()
            .map(|s| chord_length_params(&s.points))
            .collect::<Result<_>>()?,
        Some(given) => {
            if given.len() != sections.len() {
                return Err(Error::InvalidOption(format!(
                    "{} parameter lists given for {} sections",
                    given.len(),
                    sections.len()
                )));
            }
            for (k, (t, s)) in given.iter().zip(sections).enumerate() {
                let ok = t.len() == s.points.len()
                    && t.first() == Some(&0.0)
                    && t.last() == Some(&1.0)
                    && t.windows(2).all(|w| w[1] >= w[0]);
                if !ok {
                    return Err(Error::InvalidOption(format!(
                        "parameters of section {k} must be {} non-decreasing values from 0 to 1",
                        s.points.len()
                    )));
                }
            }
            given.clone()
        }
    })
}

/// The seam tie order per section: on a clamped knot vector, closed sections that are smooth at
/// the seam get their ends tied (C^(p-1), at most C^2) unless the user asked for C0 seams; 0 means
/// no tie.
fn seam_ties(sections: &[Section], opts: &CompatibleOptions, periodic: bool) -> Vec<usize> {
    let p = opts.degree;
    sections
        .iter()
        .map(|s| {
            let tie = !periodic
                && opts.periodic_closed
                && smooth_at_seam(s, opts.corner_angle_deg, opts.tolerance);
            if tie {
                tie_order(p)
            } else {
                0
            }
        })
        .collect()
}

/// The sections' turning-angle CDFs on a common grid of parameters, averaged (summed in section
/// order, then divided): the density knots are placed by.
fn mean_turning_cdf(sections: &[Section], params: &[Vec<f64>]) -> Vec<f64> {
    const GRID: usize = 2000;
    let cdfs: Vec<Vec<f64>> = sections
        .iter()
        .zip(params)
        .map(|(s, t)| turning_cdf(&s.points, t, GRID))
        .collect();
    (0..=GRID)
        .map(|g| cdfs.iter().map(|c| c[g]).sum::<f64>() / cdfs.len() as f64)
        .collect()
}

/// The most control points a candidate may have. Without smoothing a span needs data in it: at
/// most (points - 1) control points for the sparsest section; the bending term keeps spans without
/// data well posed, so then only the densest section bounds the count (a small top slice of a scan
/// must not cap the large ones). Never below `degree + 1`.
fn max_control_points(sections: &[Section], opts: &CompatibleOptions, min_pts: usize) -> usize {
    let p = opts.degree;
    let max_pts = sections.iter().map(|s| s.points.len()).max().unwrap_or(0);
    let cap_pts = if opts.smoothing > 0.0 {
        max_pts
    } else {
        min_pts
    };
    opts.max_control_points
        .max(p + 1)
        .min(cap_pts.saturating_sub(1).max(p + 1))
}

/// Of the passing candidates, those with the fewest control points, and of them the fairest
/// (smallest worst-span F over all sections; the first on ties); returns that F with it.
fn fewest_then_fairest(finals: Vec<Candidate>) -> Result<(f64, Candidate)> {
    let n_min = finals.iter().map(|c| c.knots.len()).min().unwrap_or(0);
    let mut best: Option<(f64, Candidate)> = None;
    for c in finals.into_iter().filter(|c| c.knots.len() == n_min) {
        let f = worst_span_fairness(&c.fits);
        if best.as_ref().is_none_or(|b| f < b.0) {
            best = Some((f, c));
        }
    }
    best.ok_or_else(|| Error::Fit("internal: lost the passing candidate".into()))
}

/// How one knot refinement ended ([`Search::refine`]).
enum Refined {
    /// Every section within tolerance.
    Passed(Candidate),
    /// No knot could be inserted within the control-point cap, or a fit failed.
    Failed,
    /// [`STALL_ROUNDS`] insertion rounds in a row brought no progress.
    Stalled,
}

/// The knot search's fixed inputs and its running count of candidates evaluated (each reported to
/// `progress` before it is evaluated).
struct Search<'a> {
    sections: &'a [Section],
    params: &'a [Vec<f64>],
    opts: &'a CompatibleOptions,
    fixed: &'a Fixed<'a>,
    form: KnotForm<'a>,
    progress: &'a mut dyn FnMut(usize),
    tried: usize,
}

impl Search<'_> {
    /// Park-style refinement from each initial density: inserts a knot where the worst section is
    /// worst until every section is within tolerance, then greedily removes knots that are not
    /// needed. Passing candidates go to `finals` (the blends stop at the first), the smallest
    /// failure to `best_fail`. With `stop_on_stall` a stalled refinement ends the run (the caller
    /// relaxes the smoothing rather than trying the other blends).
    fn run(
        &mut self,
        cdf: &[f64],
        n_max: usize,
        stop_on_stall: bool,
        finals: &mut Vec<Candidate>,
        best_fail: &mut Option<Candidate>,
    ) {
        let (form, opts) = (self.form, self.opts);
        let p = opts.degree;
        let n0 = (p + 1 + 4).min(n_max);
        // a single span first: cheap, and exact when the sections are polynomial (open fits only)
        if !form.periodic {
            if let Some(c) = self.try_knots(form.full(&[])) {
                if c.max_dev <= opts.tolerance {
                    finals.push(c);
                }
            }
        }
        let blends = if opts.uniform_blends.is_empty() {
            vec![1.0]
        } else {
            opts.uniform_blends.clone()
        };
        for &b in &blends {
            if !finals.is_empty() {
                break;
            }
            let knots = form.by_density(cdf, b.clamp(0.0, 1.0), n0);
            match self.refine(knots, n_max, best_fail) {
                Refined::Passed(cur) => finals.push(self.remove_knots(cur)),
                Refined::Stalled if stop_on_stall => return,
                Refined::Stalled | Refined::Failed => {}
            }
        }
    }

    /// Counts, reports and evaluates one candidate knot vector (local projection).
    fn try_knots(&mut self, knots: Vec<f64>) -> Option<Candidate> {
        self.tried += 1;
        (self.progress)(self.tried);
        evaluate(
            self.sections,
            self.params,
            knots,
            self.opts,
            false,
            self.fixed,
        )
    }

    /// Knot insertion from `knots` until every section is within tolerance ([`Refined::Passed`]),
    /// until no knot can be inserted within `n_max` control points or a fit fails
    /// ([`Refined::Failed`]), or until [`STALL_ROUNDS`] rounds in a row bring no progress
    /// ([`Refined::Stalled`]). Keeps the candidate with the smallest deviation that failed in
    /// `best_fail`.
    fn refine(
        &mut self,
        mut knots: Vec<f64>,
        n_max: usize,
        best_fail: &mut Option<Candidate>,
    ) -> Refined {
        let (form, p, tol) = (self.form, self.opts.degree, self.opts.tolerance);
        let (mut best, mut stalled) = (f64::INFINITY, 0);
        loop {
            let Some(c) = self.try_knots(knots.clone()) else {
                return Refined::Failed;
            };
            if c.max_dev <= tol {
                return Refined::Passed(c);
            }
            if c.max_dev < STALL_GAIN * best {
                (best, stalled) = (c.max_dev, 0);
            } else {
                stalled += 1;
            }
            let n_ctrl = form.distinct(&knots);
            let room = n_max.saturating_sub(n_ctrl);
            let next = insertion_knots(&c, self.fixed, p, tol, room.min((n_ctrl / 6).max(1)));
            if best_fail.as_ref().is_none_or(|f| c.max_dev < f.max_dev) {
                *best_fail = Some(c);
            }
            if next.is_empty() {
                return Refined::Failed;
            }
            if stalled >= STALL_ROUNDS {
                return Refined::Stalled;
            }
            let mut interior = form.interior(&knots);
            for t in next {
                let pos = interior.partition_point(|&k| k <= t);
                interior.insert(pos, t);
            }
            knots = form.full(&interior);
        }
    }

    /// Greedy knot removal from a passing candidate, smallest spans first: drops each interior
    /// knot whose removal keeps every section within tolerance. The result still passes.
    fn remove_knots(&mut self, mut cur: Candidate) -> Candidate {
        let form = self.form;
        let mut i = 0;
        while i < form.interior(&cur.knots).len() {
            if form.interior(&cur.knots).len() <= form.min_interior() {
                break;
            }
            let mut interior = form.interior(&cur.knots);
            interior.remove(i);
            let k2 = form.full(&interior);
            match self.try_knots(k2) {
                Some(c) if c.max_dev <= self.opts.tolerance => cur = c,
                _ => i += 1,
            }
        }
        cur
    }
}
