//! Surface reconstruction against known truths: sections sampled from a known bicubic surface, exact
//! interpolation of skinning, the blade sections at the tolerance.

use fairfit::nurbs::SurfaceWorkspace;
use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use fairfit::surface::{
    reconstruct_surface, skin, CompatibleOptions, Section, SkinOptions, SurfaceOptions,
    SurfaceProjector, VParams,
};

/// A bicubic Bézier patch (4 x 4 control points), curved in both directions.
fn bicubic() -> NurbsSurface {
    let net: Vec<Vec<Vec3>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, z) = (i as f64, 1.5 * j as f64);
                    let y = 0.6 * ((i * 7 + j * 3) % 5) as f64 - 0.3 * (i as f64 - 1.5).powi(2);
                    Vec3::new(x + 0.2 * j as f64, y, z)
                })
                .collect()
        })
        .collect();
    let k = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    NurbsSurface::new(3, 3, k.clone(), k, net, None).unwrap()
}

#[test]
fn sections_of_a_bicubic_surface_are_reproduced_to_1e_8() {
    let truth = bicubic();
    let vs = [0.0, 0.3, 0.65, 1.0];
    // non-uniform sampling in u, different per section; the design parameters are known
    let us: Vec<Vec<f64>> = (0..4)
        .map(|s| {
            (0..60)
                .map(|k| {
                    let t = k as f64 / 59.0;
                    let a = 0.2 * s as f64;
                    (1.0 - a) * t + a * t * t * (3.0 - 2.0 * t)
                })
                .collect()
        })
        .collect();
    let sections: Vec<Section> = vs
        .iter()
        .zip(&us)
        .map(|(&v, u)| Section::from_points(u.iter().map(|&u| truth.point(u, v)).collect()))
        .collect();
    let opts = SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: 1e-9,
            smoothing: 0.0,
            fairing_weights: vec![],
            corrections: 0,
            section_params: Some(us.clone()),
            ..Default::default()
        },
        skin: SkinOptions {
            degree_v: 3,
            params: VParams::Given(vs.to_vec()),
            ..Default::default()
        },
        iso_curves: 3,
        ..Default::default()
    };
    let r = reconstruct_surface(sections, &opts).unwrap();
    assert!(
        r.compatible.within_tolerance,
        "{} {:?} {:?} {:?}",
        r.compatible.max_deviation, r.alignment, r.section_deviation, r.compatible.knots
    );
    assert!(r.deviation.max < 1e-8, "{}", r.deviation.max);
    // the whole surface, not only the sections: dense samples of the truth lie on the reconstruction
    let proj = SurfaceProjector::new(&r.surface, 8);
    let mut ws = SurfaceWorkspace::new(&r.surface, 2);
    let mut worst = 0.0f64;
    for a in 0..=20 {
        for b in 0..=20 {
            let (u, v) = (a as f64 / 20.0, b as f64 / 20.0);
            let d = proj
                .project(truth.point(u, v), Some((u, v)), &mut ws)
                .distance;
            worst = worst.max(d);
        }
    }
    assert!(worst < 1e-8, "surface reproduced to {worst:e}");
    // without the design parameters (chord lengths + foot-point correction) the knot search still meets a
    // tolerance of 1e-5 on every section point
    let mut chord = opts.clone();
    chord.sections.section_params = None;
    chord.sections.tolerance = 1e-5;
    chord.sections.corrections = 30;
    chord.skin.params = VParams::ChordLength;
    let sections: Vec<Section> = vs
        .iter()
        .zip(&us)
        .map(|(&v, u)| Section::from_points(u.iter().map(|&u| truth.point(u, v)).collect()))
        .collect();
    let r = reconstruct_surface(sections, &chord).unwrap();
    assert!(
        r.compatible.within_tolerance && r.deviation.max <= 1e-5,
        "{}",
        r.deviation.max
    );
}

#[test]
fn skinning_interpolates_every_section_exactly() {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.55, 1.0, 1.0, 1.0, 1.0];
    let sections: Vec<NurbsCurve> = (0..6)
        .map(|k| {
            let z = k as f64 * (1.0 + 0.3 * (k % 2) as f64);
            let pts: Vec<Vec3> = (0..6)
                .map(|i| {
                    let t = i as f64;
                    Vec3::new(t + 0.1 * k as f64, (t * 0.7 + k as f64).sin(), z + 0.05 * t)
                })
                .collect();
            let w: Vec<f64> = (0..6)
                .map(|i| 1.0 + 0.1 * (i % 3) as f64 + 0.02 * k as f64)
                .collect();
            NurbsCurve::new(3, knots.clone(), pts, Some(w)).unwrap()
        })
        .collect();
    for params in [VParams::ChordLength, VParams::Centripetal] {
        for q in [1, 2, 3, 5] {
            let sk = skin(
                &sections,
                &SkinOptions {
                    degree_v: q,
                    params: params.clone(),
                    ..Default::default()
                },
            )
            .unwrap_or_else(|e| panic!("q={q} {params:?}: {e}"));
            assert_eq!(sk.surface.degree_v(), q);
            for (c, &v) in sections.iter().zip(&sk.v_params) {
                for i in 0..=50 {
                    let u = i as f64 / 50.0;
                    let d = (sk.surface.point(u, v) - c.point(u)).norm();
                    assert!(d < 1e-10, "q={q} {params:?}: {d:e}");
                }
            }
        }
    }
    // degree above sections - 1 is lowered; one section or incompatible sections are errors
    let sk = skin(
        &sections[..3],
        &SkinOptions {
            degree_v: 5,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sk.surface.degree_v(), 2);
    assert!(skin(&sections[..1], &SkinOptions::default()).is_err());
    let other = NurbsCurve::bspline(
        3,
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
        vec![Vec3::ZERO; 4],
    )
    .unwrap();
    let e = skin(&[sections[0].clone(), other], &SkinOptions::default()).unwrap_err();
    assert!(e.to_string().contains("not compatible"), "{e}");
}

#[test]
fn approximation_across_many_noisy_sections_stays_close() {
    // 25 noisy circles on a cone: approximation in v with 8 control points and a smoothing term
    let sections = noisy_cone();
    let opts = SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: 1e-3,
            ..Default::default()
        },
        skin: SkinOptions {
            degree_v: 3,
            approximate_with: Some(8),
            smoothing: 1e-6,
            ..Default::default()
        },
        iso_curves: 5,
        ..Default::default()
    };
    let r = reconstruct_surface(sections, &opts).unwrap();
    assert_eq!(r.surface.net_size().1, 8);
    // the noise is +-0.01 in radius: the smooth surface stays within about that
    assert!(r.deviation.max < 0.015, "{}", r.deviation.max);
    // the fairness term makes the lines along the cone much fairer than interpolating the noise
    let mut interp = opts.clone();
    interp.skin.approximate_with = None;
    let ri = reconstruct_surface(noisy_cone(), &interp).unwrap();
    assert!(ri.deviation.max < 1e-3);
    assert!(
        r.fairness.max_fairness_u < 0.05 * ri.fairness.max_fairness_u,
        "{:?} vs {:?}",
        r.fairness.max_fairness_u,
        ri.fairness.max_fairness_u
    );
}

fn noisy_cone() -> Vec<Section> {
    (0..25)
        .map(|k| {
            let z = k as f64 * 0.2;
            let r = 1.0 + 0.1 * z + 0.002 * ((k * 37 % 11) as f64 - 5.0);
            Section::closed_loop(
                (0..80)
                    .map(|i| {
                        let t = std::f64::consts::TAU * i as f64 / 80.0;
                        Vec3::new(r * t.cos(), r * t.sin(), z)
                    })
                    .collect(),
            )
        })
        .collect()
}

#[test]
fn mismatched_inputs_are_errors_not_panics() {
    let line = |z: f64, n: usize| {
        Section::from_points((0..n).map(|i| Vec3::new(i as f64, 0.0, z)).collect())
    };
    let o = SurfaceOptions::default();
    let e = reconstruct_surface(vec![line(0.0, 10)], &o).unwrap_err();
    assert!(e.to_string().contains("at least 2 sections"), "{e}");
    let e = reconstruct_surface(vec![line(0.0, 10), line(1.0, 2)], &o).unwrap_err();
    assert!(e.to_string().contains("section 1 has 2 points"), "{e}");
    let e = reconstruct_surface(vec![], &o).unwrap_err();
    assert!(e.to_string().contains("got 0"), "{e}");
    let same = Section::from_points(vec![Vec3::new(1.0, 1.0, 1.0); 6]);
    let e = reconstruct_surface(vec![line(0.0, 10), same], &o).unwrap_err();
    assert!(e.to_string().contains("one place"), "{e}");
    // two identical sections: the v parameters cannot increase
    let e = reconstruct_surface(vec![line(0.0, 10), line(0.0, 10)], &o).unwrap_err();
    assert!(e.to_string().contains("coincide"), "{e}");
}
