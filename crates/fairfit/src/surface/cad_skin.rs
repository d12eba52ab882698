//! Skinning the sections of a CAD file within the tolerance of the exact section curves, not only of
//! their samples.
//!
//! `fairfit surface part.step` fits dense samples of every exact section curve (a B-spline, conic or
//! composite of the file, or an iso-curve of a re-faired surface) and skins the fits; between the
//! samples the exact curve can stray a little farther from the surface's iso-curve than the tolerance.
//! [`skin_to_exact`] measures every exact section against the skinned surface's iso-curve at that
//! section's `v` ([`crate::fit::cad_fit::exact_deviation`]: samples, quarter points and midpoints of every
//! sample interval, and a parabola peak) and, while some exact section lies farther than the
//! tolerance, adds the offending checked points to that section's samples and skins again, the
//! sections fitted at a tolerance tightened by the measured excess (from the second refit on), at most
//! [`crate::fit::cad_fit::MAX_REFITS`] times. It keeps the surface with the smallest exact deviation (the
//! first one that meets the tolerance, so a surface that met it at once is returned unchanged).

use crate::errors::{Error, Result};
use crate::fit::cad_fit::{exact_deviation, with_added, MAX_REFITS, TIGHTENING_MARGIN};
use crate::fit::sampling::ChainSample;
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use crate::surface::{
    reconstruct_surface_with_progress, Section, Stage, SurfaceOptions, SurfaceReconstruction,
};

/// One exact section: its curve (the segments of a chain, one for a single curve), in millimetres,
/// and the samples of it that are fitted.
#[derive(Clone, Debug)]
pub struct ExactSection {
    /// The segments, oriented along the chain.
    pub segments: Vec<NurbsCurve>,
    /// The samples ([`crate::fit::sampling::sample_chain_params`]), in chain order.
    pub samples: Vec<ChainSample>,
}

impl ExactSection {
    /// The section sampled as `fairfit surface` samples a CAD curve
    /// ([`crate::fit::sampling::sample_chain_params`]).
    pub fn sampled(segments: Vec<NurbsCurve>) -> Self {
        let samples = crate::fit::sampling::sample_chain_params(&segments);
        ExactSection { segments, samples }
    }

    /// The sample points.
    pub fn points(&self) -> Vec<Vec3> {
        self.samples.iter().map(|s| s.point).collect()
    }
}

/// A surface skinned through CAD sections, checked against the exact section curves.
#[derive(Clone, Debug)]
pub struct ExactSkin {
    /// The reconstruction kept (its sections are the samples with the checked points added).
    pub reconstruction: SurfaceReconstruction,
    /// The tolerance asked for (absolute).
    pub tolerance: f64,
    /// The section tolerance the kept surface was fitted at (the tolerance, or tighter after refits).
    pub fit_tolerance: f64,
    /// The largest distance of an exact section from the surface's iso-curve at its `v`.
    pub max_deviation: f64,
    /// The same per section, in input order.
    pub section_max_deviation: Vec<f64>,
    /// Whether [`ExactSkin::max_deviation`] is within [`ExactSkin::tolerance`].
    pub met: bool,
    /// How many points of the exact sections were measured against the kept surface.
    pub checked: usize,
    /// How many refits ran after the first skinning.
    pub refits: usize,
    /// How many checked points the kept surface's sections have beyond the first samples.
    pub added: usize,
    /// The exact deviation of the first surface (before any refit).
    pub first_max_deviation: f64,
}

/// Per-section exact deviations of `sections` from the iso-curves of `surface` at `v_params`:
/// `(max per section, checked points, points beyond limit per section)`.
#[allow(clippy::type_complexity)]
fn measure(
    sections: &[ExactSection],
    surface: &NurbsSurface,
    v_params: &[f64],
    limit: f64,
) -> Result<(Vec<f64>, usize, Vec<Vec<(usize, ChainSample)>>)> {
    if v_params.len() != sections.len() {
        return Err(Error::InvalidData(format!(
            "{} sections were skinned at {} parameters",
            sections.len(),
            v_params.len()
        )));
    }
    let mut max = Vec::with_capacity(sections.len());
    let mut beyond = Vec::with_capacity(sections.len());
    let mut checked = 0;
    for (s, &v) in sections.iter().zip(v_params) {
        let iso = surface.iso_curve_v(v)?;
        let d = exact_deviation(&s.segments, &s.samples, &iso, limit)?;
        max.push(d.max);
        checked += d.checked;
        beyond.push(d.beyond);
    }
    Ok((max, checked, beyond))
}

/// Skins `sections` with `opts` (its section tolerance is the tolerance the exact sections are held
/// to) and refits while an exact section strays beyond the tolerance from the surface (see the module
/// documentation). The first surface is returned unchanged when the exact sections are within the
/// tolerance, or when it did not meet the tolerance on its own samples (fitting tighter cannot help
/// then). Errors of the reconstruction are returned as they are; `progress` sees every skinning.
pub fn skin_to_exact(
    mut sections: Vec<ExactSection>,
    opts: &SurfaceOptions,
    progress: &mut dyn FnMut(Stage),
) -> Result<ExactSkin> {
    let tol = opts.sections.tolerance;
    if tol.is_nan() || tol <= 0.0 {
        return Err(Error::InvalidOption(format!(
            "the tolerance must be positive, got {tol}"
        )));
    }
    let n0: usize = sections.iter().map(|s| s.samples.len()).sum();
    let run = |sections: &[ExactSection],
               fit_tol: f64,
               progress: &mut dyn FnMut(Stage)|
     -> Result<SurfaceReconstruction> {
        let mut o = opts.clone();
        o.sections.tolerance = fit_tol;
        // the samples of exact curves are refined point by point: never reduced
        o.dense.enabled = false;
        let input = sections
            .iter()
            .map(|s| Section::from_points(s.points()))
            .collect();
        reconstruct_surface_with_progress(input, &o, progress)
    };
    let first = run(&sections, tol, progress)?;
    let (dev, checked, mut beyond) = measure(&sections, &first.surface, &first.v_params, tol)?;
    let worst = dev.iter().copied().fold(0.0, f64::max);
    let reachable = first.deviation.max <= tol;
    let mut best = ExactSkin {
        met: worst <= tol,
        max_deviation: worst,
        first_max_deviation: worst,
        section_max_deviation: dev,
        checked,
        reconstruction: first,
        tolerance: tol,
        fit_tolerance: tol,
        refits: 0,
        added: 0,
    };
    if best.met || !reachable {
        return Ok(best);
    }
    let (mut worst, mut fit_tol) = (worst, tol);
    for refit in 1..=MAX_REFITS {
        for (s, b) in sections.iter_mut().zip(&beyond) {
            if !b.is_empty() {
                s.samples = with_added(&s.samples, b);
            }
        }
        if refit > 1 {
            // the exact sections strayed worst / fit_tol of the fitting tolerance: ask that much less
            fit_tol *= (tol / worst).min(1.0) * (1.0 - TIGHTENING_MARGIN);
        }
        if fit_tol.is_nan() || fit_tol <= 0.0 {
            break;
        }
        let next = run(&sections, fit_tol, progress)?;
        let (dev, checked, b) = measure(&sections, &next.surface, &next.v_params, tol)?;
        beyond = b;
        worst = dev.iter().copied().fold(0.0, f64::max);
        if worst < best.max_deviation {
            let added = sections.iter().map(|s| s.samples.len()).sum::<usize>() - n0;
            best = ExactSkin {
                met: worst <= tol,
                max_deviation: worst,
                section_max_deviation: dev,
                checked,
                reconstruction: next,
                fit_tolerance: fit_tol,
                refits: refit,
                added,
                ..best
            };
        }
        best.refits = refit;
        if best.met {
            break;
        }
    }
    Ok(best)
}
