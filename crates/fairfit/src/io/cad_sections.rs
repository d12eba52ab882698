//! Sections for a surface from a CAD file (`fairfit surface part.step`): each B-spline curve of the
//! file is one section, or the v-iso-curves of one B-spline surface are, so that skinning them again
//! re-fairs the surface.
//!
//! Curves: every curve of the file (in file order, in millimetres, see [`super::cad_read`]) is sampled
//! as `fairfit curve` samples a CAD curve for re-fitting ([`crate::fit::sampling::sample_curve`]); a composite curve is one
//! section, its segments sampled in order ([`crate::fit::sampling::sample_chain`]). Surface: the sections are
//! the curves `u ↦ S(u, v_k)` at [`iso_section_count`] parameters `v_k` spread evenly over every
//! non-empty v knot span, each sampled the same way. Every section keeps its exact curve, which
//! [`crate::surface::cad_skin::skin_to_exact`] holds the skinned surface to.

use super::cad_read::{
    curve_chains, read_contents, segments_in_mm, select, CadContents, CadKind, CadUnit,
};
use super::json::Geometry;
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsSurface, Vec3};
use crate::surface::cad_skin::ExactSection;
use std::path::Path;

/// Sections read from a CAD file, in millimetres.
#[derive(Clone, Debug)]
pub struct CadSections {
    /// Each section's name (`#12`, `DE 7`, `#30 at v = 0.25`) and its points, in file order (curves) or
    /// in increasing v (a surface's iso-curves).
    pub sections: Vec<(String, Vec<Vec3>)>,
    /// The file's unit (coordinates were converted from it to millimetres).
    pub unit: CadUnit,
    /// For a re-faired surface: its source (`#30`), index and the count of surfaces in the file.
    pub surface: Option<(String, usize, usize)>,
    /// Every section's exact curve (in millimetres) and its samples (the points of
    /// [`CadSections::sections`]), in the same order: what [`crate::surface::cad_skin::skin_to_exact`] holds the
    /// surface to.
    pub exact: Vec<ExactSection>,
}

/// How many v-iso-curves re-fair a surface: `q_v + 1` per non-empty v knot span, plus the last one
/// (at least 4), so that skinning them again with a cubic across reproduces a polynomial piece of
/// degree up to 3 in v and follows every span of the original.
pub fn iso_section_count(s: &NurbsSurface) -> usize {
    let kv = s.knots_v();
    let (a, b) = s.domain_v();
    let spans = kv
        .windows(2)
        .filter(|w| w[1].min(b) > w[0].max(a))
        .count()
        .max(1);
    (spans * (s.degree_v() + 1) + 1).max(4)
}

/// The parameters `v_k` of the re-fairing sections: [`iso_section_count`] values, the ends included,
/// `q_v + 1` equal steps in every non-empty v knot span.
pub fn iso_section_params(s: &NurbsSurface) -> Vec<f64> {
    let (a, b) = s.domain_v();
    let spans: Vec<(f64, f64)> = s
        .knots_v()
        .windows(2)
        .map(|w| (w[0].max(a), w[1].min(b)))
        .filter(|(u0, u1)| u1 > u0)
        .collect();
    let m = s.degree_v() + 1;
    let mut out = Vec::new();
    for (u0, u1) in &spans {
        out.extend((0..m).map(|j| u0 + (u1 - u0) * j as f64 / m as f64));
    }
    out.push(b);
    // too few spans: subdivide evenly instead
    if out.len() < 4 {
        out = (0..4).map(|j| a + (b - a) * j as f64 / 3.0).collect();
    }
    out
}

/// The sections of one B-spline surface: its v-iso-curves at [`iso_section_params`], sampled densely.
pub fn surface_sections(s: &NurbsSurface, source: &str) -> Result<Vec<(String, Vec<Vec3>)>> {
    Ok(exact_surface_sections(s, source)?
        .into_iter()
        .map(|(name, e)| (name, e.points()))
        .collect())
}

/// [`surface_sections`] with every iso-curve, the exact section.
pub(crate) fn exact_surface_sections(
    s: &NurbsSurface,
    source: &str,
) -> Result<Vec<(String, ExactSection)>> {
    iso_section_params(s)
        .into_iter()
        .map(|v| {
            let c = s.iso_curve_v(v)?;
            Ok((
                format!("{source} at v = {v}"),
                ExactSection::sampled(vec![c]),
            ))
        })
        .collect()
}

/// Names and points of `exact`, and the exact sections.
fn split(named: Vec<(String, ExactSection)>) -> (Vec<(String, Vec<Vec3>)>, Vec<ExactSection>) {
    named
        .into_iter()
        .map(|(name, e)| ((name, e.points()), e))
        .unzip()
}

/// Takes the sections of `contents` (see the module documentation): `kind` [`CadKind::Any`] re-fairs a
/// surface when the file holds one, else takes the curves; `index` chooses the surface (it is refused
/// for curves, which are all taken). `file` names the file in errors.
pub fn cad_sections(
    contents: CadContents,
    kind: CadKind,
    index: Option<usize>,
    file: &str,
) -> Result<CadSections> {
    let surface = match kind {
        CadKind::Any => !contents.surfaces.is_empty(),
        CadKind::Surface => true,
        CadKind::Curve => false,
    };
    let unit = contents.unit.clone();
    if surface {
        let g = select(contents, CadKind::Surface, index.unwrap_or(0), file)?;
        let Geometry::Surface(s) = &g.geometry else {
            return Err(Error::Cad(format!(
                "{file}: internal: a surface was asked for"
            )));
        };
        let (sections, exact) = split(exact_surface_sections(s, &g.source)?);
        return Ok(CadSections {
            sections,
            unit,
            surface: Some((g.source, g.index, g.count)),
            exact,
        });
    }
    if index.is_some() {
        return Err(Error::InvalidOption(format!(
            "--index chooses a B-spline surface to re-fair; {file} is read as sections, and every \
             B-spline curve of it is one section"
        )));
    }
    let n = contents.curves.len() + contents.composites.len();
    if n < 2 {
        let held = match (n, contents.composites.len()) {
            (0, _) => "no B-spline curve",
            (_, 0) => "1 B-spline curve",
            _ => "1 composite curve",
        };
        return Err(Error::Cad(format!(
            "{file} holds {held}: a surface needs at least 2 sections; export every section as a \
             B-spline (NURBS) curve into one file, or give a B-spline surface to re-fair"
        )));
    }
    let f = unit.mm_per_unit;
    let named = curve_chains(contents.curves, contents.composites)
        .into_iter()
        .map(|(src, segments)| {
            let segments = segments_in_mm(segments, f, file)?;
            Ok((src, ExactSection::sampled(segments)))
        })
        .collect::<Result<Vec<_>>>()?;
    let (sections, exact) = split(named);
    Ok(CadSections {
        sections,
        unit,
        surface: None,
        exact,
    })
}

/// Reads the sections of a STEP or IGES file (see [`cad_sections`]).
pub fn read_cad_sections(
    path: impl AsRef<Path>,
    kind: CadKind,
    index: Option<usize>,
) -> Result<CadSections> {
    let path = path.as_ref();
    cad_sections(
        read_contents(path)?,
        kind,
        index,
        &path.display().to_string(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::NurbsCurve;

    fn arc(z: f64, r: f64) -> NurbsCurve {
        let pts = vec![
            Vec3::new(r, 0.0, z),
            Vec3::new(r, r, z),
            Vec3::new(0.0, r, z),
        ];
        let w = std::f64::consts::FRAC_1_SQRT_2;
        NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            pts,
            Some(vec![1.0, w, 1.0]),
        )
        .unwrap()
    }

    #[test]
    fn curves_become_sections_in_file_order_in_mm() {
        let contents = CadContents {
            curves: vec![("#5".into(), arc(0.0, 1.0)), ("#9".into(), arc(2.0, 1.5))],
            unit: CadUnit::from_mm_per_unit(25.4),
            ..CadContents::default()
        };
        let s = cad_sections(contents, CadKind::Any, None, "f.step").unwrap();
        assert_eq!(s.sections.len(), 2);
        assert_eq!(
            (s.sections[0].0.as_str(), s.sections[1].0.as_str()),
            ("#5", "#9")
        );
        for (k, (r, z)) in [(25.4, 0.0), (38.1, 50.8)].into_iter().enumerate() {
            let pts = &s.sections[k].1;
            assert!(pts.len() > 20);
            for p in pts {
                let rho = (p.x() * p.x() + p.y() * p.y()).sqrt();
                assert!(
                    (rho - r).abs() < 1e-12 && (p.z() - z).abs() < 1e-12,
                    "{p:?}"
                );
            }
        }
    }

    #[test]
    fn too_few_curves_and_an_index_are_refused() {
        let one = CadContents {
            curves: vec![("#5".into(), arc(0.0, 1.0))],
            ..CadContents::default()
        };
        let e = cad_sections(one.clone(), CadKind::Any, None, "f.step")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("f.step holds 1 B-spline curve: a surface needs at least 2 sections"),
            "{e}"
        );
        let e = cad_sections(one, CadKind::Curve, Some(0), "f.step").unwrap_err();
        assert!(matches!(e, Error::InvalidOption(_)), "{e}");
    }

    #[test]
    fn iso_sections_follow_the_v_spans() {
        let net: Vec<Vec<Vec3>> = (0..4)
            .map(|i| {
                (0..5)
                    .map(|j| Vec3::new(i as f64, j as f64, (i * j) as f64 * 0.1))
                    .collect()
            })
            .collect();
        let kv = vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
        let ku = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let s = NurbsSurface::new(3, 3, ku, kv, net, None).unwrap();
        assert_eq!(iso_section_count(&s), 9);
        let v = iso_section_params(&s);
        assert_eq!(
            v,
            vec![0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0]
        );
        let sec = surface_sections(&s, "#3").unwrap();
        assert_eq!(sec.len(), 9);
        assert_eq!(sec[2].0, "#3 at v = 0.25");
        for (u, p) in [(0.0, sec[2].1[0]), (1.0, *sec[2].1.last().unwrap())] {
            assert!((p - s.point(u, 0.25)).norm() < 1e-14);
        }
    }
}
