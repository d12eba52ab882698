//! A surface skinned through CAD sections held to the tolerance of the exact section curves
//! (`fairfit::surface::cad_skin`): wiggly spatial cubics stacked into a blade-like surface, and circles of a
//! cone. Truth: every exact section at 3001 parameters that are not sampled, projected onto the
//! skinned surface's iso-curve at the section's `v`; the surface must hold them within the tolerance
//! (1.0 x, no slack), and the exact deviation the library reports must be the largest found (to 1e-4).

use fairfit::diffgeo::CurveProjector;
use fairfit::surface::cad_skin::{skin_to_exact, ExactSection, ExactSkin};
use fairfit::surface::{Stage, SurfaceOptions};
use fairfit::NurbsCurve;

use crate::common::cad_fixtures;
use cad_fixtures::wiggly;

/// The largest distance of every exact section, at 3001 parameters, from the surface's iso-curve at
/// its `v`.
fn truth(sections: &[NurbsCurve], e: &ExactSkin) -> f64 {
    let r = &e.reconstruction;
    sections
        .iter()
        .zip(&r.v_params)
        .map(|(c, &v)| {
            let iso = r.surface.iso_curve_v(v).unwrap();
            let proj = CurveProjector::new(&iso, 64);
            let (a, b) = c.domain();
            (0..=3000)
                .map(|i| {
                    proj.project(c.point(a + (b - a) * i as f64 / 3000.0))
                        .distance
                })
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

fn skin(curves: &[NurbsCurve], tol: f64) -> ExactSkin {
    let mut opts = SurfaceOptions::default();
    opts.sections.tolerance = tol;
    opts.sections.max_control_points = 120;
    opts.iso_curves = 10;
    let sections = curves
        .iter()
        .map(|c| ExactSection::sampled(vec![c.clone()]))
        .collect();
    let mut stages = 0;
    let e = skin_to_exact(sections, &opts, &mut |s: Stage| {
        stages += usize::from(s == Stage::Measured)
    })
    .unwrap();
    assert_eq!(stages, e.refits + 1);
    e
}

#[test]
fn wiggly_sections_are_held_to_the_exact_curves() {
    for (rel, scales) in [(1e-4, [1.0, 0.9, 0.8, 0.7]), (3e-5, [1.0, 0.95, 0.85, 0.8])] {
        let curves: Vec<NurbsCurve> = scales
            .iter()
            .enumerate()
            .map(|(k, &s)| wiggly(s, 20.0 * k as f64))
            .collect();
        let tol = rel * 110.0;
        let e = skin(&curves, tol);
        let t = truth(&curves, &e);
        println!(
            "rel {rel:e}: first {:.4} of the tolerance, kept {:.4} ({} refits, {} points added, fit \
             tolerance {:.4}); truth {:.4}",
            e.first_max_deviation / tol,
            e.max_deviation / tol,
            e.refits,
            e.added,
            e.fit_tolerance / tol,
            t / tol
        );
        assert!(e.met && e.max_deviation <= tol, "{}", e.max_deviation / tol);
        assert!(t <= tol, "{} of the tolerance", t / tol);
        // the checks find the largest distance of the 3001 parameters, or more
        assert!(
            e.max_deviation >= t * (1.0 - 1e-4),
            "{} < {t}",
            e.max_deviation
        );
        assert_eq!(e.section_max_deviation.len(), curves.len());
    }
}
