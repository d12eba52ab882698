//! The whole section-to-surface pipeline: orientation and seam alignment, compatible fair section curves
//! on one shared knot vector, skinning, and the surface measures of the result. Dense sections are
//! screened and reduced first, and the tolerance verified on every point ([`super::dense`]).

use super::compatible::{make_compatible_with_progress, CompatibleOptions, CompatibleSections};
use super::dense::{DenseOptions, DenseSummary};
use super::measure::{surface_deviation, surface_deviation_near, Deviation};
use super::orient::{align_sections, extent, Section};
use super::seam::{seam_continuity, seam_continuity_at, SeamContinuity};
use super::skin_ends::VEndTangents;
use super::skinning::{skin, SkinOptions};

/// Iso-curves `v = const` at which the seam continuity is measured (ends included: one more).
const SEAM_SAMPLES: usize = 40;
use crate::errors::{Error, Result};
use crate::fair::{surface_fairness, SurfaceFairness};
use crate::nurbs::NurbsSurface;

/// Options of [`reconstruct_surface`].
#[derive(Clone, Debug, Default)]
pub struct SurfaceOptions {
    /// Section fitting (degree in u, tolerance, ...).
    pub sections: CompatibleOptions,
    /// Skinning (degree in v, parameterisation, approximation).
    pub skin: SkinOptions,
    /// Number of iso-curves per direction for the fairness report.
    pub iso_curves: usize,
    /// Dense sections: screening and reduction ([`super::dense`]).
    pub dense: DenseOptions,
    /// Keep open sections open. By default an open section whose ends meet at the tolerance's
    /// scale and which continues smoothly through the gap is closed first
    /// ([`Section::close_at_tolerance`], the rule of `fairfit curve`), and the gap reported
    /// ([`SurfaceReconstruction::closed_by_gap`]).
    pub open_sections: bool,
}

/// Progress stages reported by [`reconstruct_surface_with_progress`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Candidate knot vectors evaluated so far.
    Compatible(usize),
    /// Skinning done.
    Skinned,
    /// Measures done.
    Measured,
}

/// A reconstructed surface with its measures.
#[derive(Clone, Debug)]
pub struct SurfaceReconstruction {
    /// The skinned surface.
    pub surface: NurbsSurface,
    /// The compatible section fits (after alignment) and the shared knot vector.
    pub compatible: CompatibleSections,
    /// The aligned sections that were fitted.
    pub sections: Vec<Section>,
    /// Per section: (reversed, seam shift in points) applied by the alignment.
    pub alignment: Vec<(bool, usize)>,
    /// v parameter of each section on the surface.
    pub v_params: Vec<f64>,
    /// Orthogonal deviation of every section point from the surface.
    pub deviation: Deviation,
    /// Per section: largest orthogonal deviation from its fitted curve.
    pub section_deviation: Vec<f64>,
    /// Fairness of iso-curves in both directions (`u_iso`: across the sections).
    pub fairness: SurfaceFairness,
    /// When every section is closed: the surface's continuity across its u seam (tangent angle and
    /// curvature jump, ~0 when the sections were fitted periodically, see [`super::seam`]), over
    /// equally spaced iso-curves. When only some are closed: the same at those sections (~0 where their
    /// seams were tied, see the private `seam_tie` module). `None` when no section is closed.
    pub seam: Option<SeamContinuity>,
    /// What the dense path found and did (`None`: no section was dense, the plain pipeline ran).
    /// Then `sections` hold the kept points (spikes excluded), and the fits in `compatible` are of
    /// the representatives while its `max_deviation` is that of every kept point.
    pub dense: Option<DenseSummary>,
    /// With v end tangents asked ([`SkinOptions::start_tangent_v`], `end_tangent_v`): the largest
    /// angle between `∂S/∂v` and each asked direction over a dense u sampling; `None` without.
    pub v_end_tangents: Option<VEndTangents>,
    /// Per section (input order): the gap it was closed across ([`SurfaceOptions::open_sections`]),
    /// `None` when it was not.
    pub closed_by_gap: Vec<Option<f64>>,
    /// The knot search's smoothing when it was relaxed below [`CompatibleOptions::smoothing`] (no
    /// knot vector met the tolerance with it, [`CompatibleSections::smoothing`]); `None` when not.
    pub relaxed_smoothing: Option<f64>,
}

impl SurfaceReconstruction {
    /// The tolerance the surface is held to when `tol` was asked: `tol`, or the meaningful
    /// tolerance of noisy dense sections when `tol` is below their noise ([`DenseSummary`]).
    pub fn tolerance_used(&self, tol: f64) -> f64 {
        self.dense
            .as_ref()
            .map_or(tol, |d| d.tolerance_used.max(tol))
    }
}

/// Checks that sections can make a surface; the message names the offending section.
pub fn validate_sections(sections: &[Section], degree: usize) -> Result<()> {
    if degree == 0 || degree > crate::nurbs::knots::MAX_DEGREE {
        return Err(Error::InvalidOption(format!(
            "section degree must be in 1..={}, got {degree}",
            crate::nurbs::knots::MAX_DEGREE
        )));
    }
    if sections.len() < 2 {
        return Err(Error::InvalidData(format!(
            "a surface needs at least 2 sections, got {}",
            sections.len()
        )));
    }
    for (k, s) in sections.iter().enumerate() {
        if s.points.len() < degree + 1 || s.points.len() < 3 {
            return Err(Error::InvalidData(format!(
                "section {k} has {} points; at least {} are needed for degree {degree}",
                s.points.len(),
                (degree + 1).max(3)
            )));
        }
        if let Some(i) = s.points.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidData(format!(
                "section {k}, point {i} is not finite"
            )));
        }
        if extent(&s.points).is_nan() || extent(&s.points) <= 0.0 {
            return Err(Error::InvalidData(format!(
                "section {k} has all its points at one place"
            )));
        }
        // squared distances must neither overflow nor underflow: beyond these sizes the fit reads
        // points as coincident or returns deviations of 0
        let size = extent(&s.points);
        let reach = s
            .points
            .iter()
            .flat_map(|p| [p.x().abs(), p.y().abs(), p.z().abs()])
            .fold(0.0, f64::max);
        if !(MIN_SECTION_SIZE..=MAX_COORDINATE).contains(&size) || reach > MAX_COORDINATE {
            return Err(Error::InvalidData(format!(
                "section {k} is {size:.3e} across with coordinates up to {reach:.3e}; sections must be \
                 at least {MIN_SECTION_SIZE:e} across with coordinates up to {MAX_COORDINATE:e}: \
                 rescale the points (e.g. change their unit)"
            )));
        }
    }
    Ok(())
}

/// The smallest section size (largest bounding-box extent) [`validate_sections`] accepts.
pub(crate) const MIN_SECTION_SIZE: f64 = 1e-150;

/// The largest coordinate magnitude [`validate_sections`] accepts.
pub(crate) const MAX_COORDINATE: f64 = 1e150;

/// Sections to a fair skinned surface (see the module documentation).
pub fn reconstruct_surface(
    sections: Vec<Section>,
    opts: &SurfaceOptions,
) -> Result<SurfaceReconstruction> {
    reconstruct_surface_with_progress(sections, opts, &mut |_| {})
}

/// [`reconstruct_surface`] with a progress callback.
pub fn reconstruct_surface_with_progress(
    mut sections: Vec<Section>,
    opts: &SurfaceOptions,
    progress: &mut dyn FnMut(Stage),
) -> Result<SurfaceReconstruction> {
    validate_sections(&sections, opts.sections.degree)?;
    let closed_by_gap: Vec<Option<f64>> = sections
        .iter_mut()
        .map(|s| {
            if opts.open_sections {
                None
            } else {
                s.close_at_tolerance(opts.sections.tolerance, opts.sections.corner_angle_deg)
            }
        })
        .collect();
    let alignment = align_sections(&mut sections);
    let dense = match opts.sections.section_params {
        None => super::dense::prepare(&sections, opts.sections.tolerance, &opts.dense),
        Some(_) => None,
    };
    let fitted = match dense {
        Some(prepared) => {
            let kept = prepared.sections.clone();
            let f = super::dense::fit(prepared, &opts.sections, &opts.dense, &mut |n| {
                progress(Stage::Compatible(n))
            })?;
            Fitted {
                sections: kept,
                compatible: f.compatible,
                us: f.us,
                section_deviation: f.section_deviation,
                dense: Some(f.summary),
            }
        }
        None => {
            let compatible = make_compatible_with_progress(&sections, &opts.sections, &mut |n| {
                progress(Stage::Compatible(n))
            })?;
            Fitted {
                sections,
                us: compatible.fits.iter().map(|f| f.params.clone()).collect(),
                section_deviation: compatible.fits.iter().map(|f| f.max_deviation).collect(),
                compatible,
                dense: None,
            }
        }
    };
    let mut r = skinned(fitted, alignment, opts, progress)?;
    r.closed_by_gap = closed_by_gap;
    r.relaxed_smoothing =
        (r.compatible.smoothing < opts.sections.smoothing).then_some(r.compatible.smoothing);
    Ok(r)
}

/// Sections fitted on one shared knot vector, with each point's parameter on its section curve.
struct Fitted {
    sections: Vec<Section>,
    compatible: CompatibleSections,
    us: Vec<Vec<f64>>,
    section_deviation: Vec<f64>,
    dense: Option<DenseSummary>,
}

/// The surface skinned through the fitted sections, and its measures: the deviation of every section
/// point (projected near its section parameters when the sections were dense), the iso-curve
/// fairness and the seam continuity.
fn skinned(
    f: Fitted,
    alignment: Vec<(bool, usize)>,
    opts: &SurfaceOptions,
    progress: &mut dyn FnMut(Stage),
) -> Result<SurfaceReconstruction> {
    let Fitted {
        sections,
        mut compatible,
        us,
        section_deviation,
        dense,
    } = f;
    let curves = compatible.curves();
    let sk = skin(&curves, &opts.skin)?;
    progress(Stage::Skinned);
    if let Some(le) = compatible.leading_edges.as_mut() {
        le.measure_surface(&sk.surface, &sk.v_params);
    }
    let mut pts = Vec::new();
    let mut hints = Vec::new();
    for ((s, us), &v) in sections.iter().zip(&us).zip(&sk.v_params) {
        for (p, &u) in s.points.iter().zip(us) {
            pts.push(*p);
            hints.push((u, v));
        }
    }
    let deviation = if dense.is_some() {
        surface_deviation_near(&sk.surface, &pts, &hints)
    } else {
        surface_deviation(&sk.surface, &pts, Some(&hints))
    };
    let fairness = surface_fairness(&sk.surface, opts.iso_curves.max(1))?;
    let closed_vs: Vec<f64> = sections
        .iter()
        .zip(&sk.v_params)
        .filter(|(s, _)| s.closed)
        .map(|(_, &v)| v)
        .collect();
    let seam = if closed_vs.len() == sections.len() {
        Some(seam_continuity(&sk.surface, SEAM_SAMPLES))
    } else if !closed_vs.is_empty() {
        Some(seam_continuity_at(&sk.surface, &closed_vs))
    } else {
        None
    };
    let v_end_tangents = sk.v_tangent_speed.and_then(|speed| {
        VEndTangents::measure(
            &sk.surface,
            opts.skin.start_tangent_v,
            opts.skin.end_tangent_v,
            speed,
        )
    });
    progress(Stage::Measured);
    Ok(SurfaceReconstruction {
        surface: sk.surface,
        section_deviation,
        compatible,
        sections,
        alignment,
        v_params: sk.v_params,
        deviation,
        fairness,
        seam,
        dense,
        v_end_tangents,
        closed_by_gap: Vec::new(),
        relaxed_smoothing: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::Vec3;

    /// Three ellipses 2s wide and s apart, scaled by `s`.
    fn ellipses(s: f64) -> Vec<Section> {
        (0..3)
            .map(|k| {
                Section::from_points(
                    (0..20)
                        .map(|i| {
                            let t = std::f64::consts::TAU * i as f64 / 20.0;
                            Vec3::new(s * t.cos(), 0.5 * s * t.sin(), s * k as f64)
                        })
                        .collect(),
                )
            })
            .collect()
    }

    #[test]
    fn sections_beyond_the_fittable_sizes_ask_for_rescaling() {
        for s in [1e-300, 1e-160, 1e160, 1e300] {
            let e = validate_sections(&ellipses(s), 3).unwrap_err().to_string();
            assert!(e.contains("section 0") && e.contains("rescale"), "{s}: {e}");
        }
        for s in [1e-140, 1.0, 1e140] {
            validate_sections(&ellipses(s), 3).unwrap();
        }
        // inside the range the fit is the unit fit scaled: deviation / size agrees to 1e-7 (the scaled
        // points round differently)
        let opts = SurfaceOptions::default();
        let fit = |s: f64| {
            let mut o = opts.clone();
            o.sections.tolerance = 1e-3 * s;
            reconstruct_surface(ellipses(s), &o).unwrap().deviation.max / s
        };
        let unit = fit(1.0);
        for s in [1e-140, 1e140] {
            assert!(
                (fit(s) - unit).abs() <= 1e-7 * unit,
                "{s:e}: {} vs {unit}",
                fit(s)
            );
        }
    }
}
