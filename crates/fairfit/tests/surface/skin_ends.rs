//! v end tangents of skinned surfaces (`surface::skin_ends`) against analytic truths: sections of a
//! translational surface `S(u, t) = C(u) + γ(t)`, whose `∂S/∂t = γ'(t)` is one direction along a whole
//! section. The surface's `∂S/∂v` is measured by a one-sided 5-point finite difference of surface
//! points (not by the library's derivative evaluation, which is checked against it), and the sections
//! are checked to be interpolated.

use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use fairfit::surface::{
    max_v_tangent_angle, reconstruct_surface, skin, CompatibleOptions, Section, Skin, SkinOptions,
    SurfaceOptions, VParams,
};

/// The spine of the translational surface.
fn gamma(t: f64) -> Vec3 {
    Vec3::new(0.4 * (1.5 * t).sin(), 0.2 * (1.0 - t.cos()), 2.0 * t)
}

/// γ'(t), analytic.
fn gamma_d(t: f64) -> Vec3 {
    Vec3::new(0.6 * (1.5 * t).cos(), 0.2 * t.sin(), 2.0)
}

/// The spine parameters of the sections (unevenly spaced).
fn spine_params(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let s = k as f64 / (n - 1) as f64;
            1.3 * (s + 0.15 * s * (1.0 - s))
        })
        .collect()
}

/// A wavy cubic B-spline profile in the plane z = 0.
fn profile() -> NurbsCurve {
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.55, 0.8, 1.0, 1.0, 1.0, 1.0];
    let pts: Vec<Vec3> = (0..7)
        .map(|i| {
            let x = i as f64;
            Vec3::new(x, 0.5 * (0.9 * x).sin() + 0.1 * x, 0.0)
        })
        .collect();
    NurbsCurve::bspline(3, knots, pts).unwrap()
}

/// `curve` moved by `by` (weights kept).
fn translated(curve: &NurbsCurve, by: Vec3) -> NurbsCurve {
    let pts: Vec<Vec3> = curve.control_points().iter().map(|&p| p + by).collect();
    let w = curve.is_rational().then(|| curve.weights().to_vec());
    NurbsCurve::new(curve.degree(), curve.knots().to_vec(), pts, w).unwrap()
}

/// The angle between two vectors (radians).
fn angle(a: Vec3, b: Vec3) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// `∂S/∂v (u, v)` at an end by a one-sided 5-point difference (exact for polynomials of degree 4;
/// `h` is kept inside the end knot span, so exact for a polynomial skin of degree ≤ 4 in v).
fn sv_fd(s: &NurbsSurface, u: f64, at_start: bool, h: f64) -> Vec3 {
    let (v0, v1) = s.domain_v();
    let (v, h) = if at_start { (v0, h) } else { (v1, -h) };
    let f = |k: f64| s.point(u, v + k * h);
    (f(0.0) * -25.0 + f(1.0) * 48.0 - f(2.0) * 36.0 + f(3.0) * 16.0 - f(4.0) * 3.0) / (12.0 * h)
}

/// The worst angle at an end, by finite differences and by the library's derivatives, over 401 u;
/// checks the two agree.
fn worst_angles(s: &NurbsSurface, at_start: bool, dir: Vec3) -> (f64, f64) {
    let kv = s.knots_v();
    let q = s.degree_v();
    // a step well inside the end knot span
    let span = if at_start {
        kv[q + 1] - kv[q]
    } else {
        kv[kv.len() - q - 1] - kv[kv.len() - q - 2]
    };
    let h = 1e-3 * span;
    let v = if at_start {
        s.domain_v().0
    } else {
        s.domain_v().1
    };
    let mut fd_worst = 0.0f64;
    for i in 0..=400 {
        let u = i as f64 / 400.0;
        let fd = sv_fd(s, u, at_start, h);
        let an = s.derivatives(u, v, 1)[1];
        assert!(
            (fd - an).norm() <= 1e-7 * an.norm(),
            "u {u}: finite difference {fd:?} vs derivative {an:?}"
        );
        fd_worst = fd_worst.max(angle(fd, dir));
    }
    (fd_worst, max_v_tangent_angle(s, v, dir, 1001))
}

/// Largest distance of `S(u, v_k)` from section `k` over 201 u, relative to the surface's extent.
fn interpolation_error(sk: &Skin, sections: &[NurbsCurve]) -> f64 {
    let size = 8.0;
    let mut worst = 0.0f64;
    for (c, &v) in sections.iter().zip(&sk.v_params) {
        for i in 0..=200 {
            let u = i as f64 / 200.0;
            worst = worst.max(sk.surface.point(u, v).distance(c.point(u)) / size);
        }
    }
    worst
}

fn with_tangents(t: &[f64], base: SkinOptions) -> SkinOptions {
    SkinOptions {
        start_tangent_v: Some(gamma_d(t[0]) * 3.7),
        end_tangent_v: Some(gamma_d(t[t.len() - 1]) * 0.2),
        ..base
    }
}

#[test]
fn interpolated_skin_leaves_its_end_sections_along_the_asked_directions() {
    let t = spine_params(6);
    for rational in [false, true] {
        let base = if rational {
            NurbsCurve::circle(Vec3::ZERO, 1.5).unwrap()
        } else {
            profile()
        };
        assert_eq!(base.is_rational(), rational);
        let sections: Vec<NurbsCurve> = t.iter().map(|&x| translated(&base, gamma(x))).collect();
        for q in [2, 3, 4] {
            let opts = with_tangents(
                &t,
                SkinOptions {
                    degree_v: q,
                    ..Default::default()
                },
            );
            let sk = skin(&sections, &opts).unwrap();
            let (_, nv) = sk.surface.net_size();
            assert_eq!(nv, 6 + 2, "one more control point per end");
            assert_eq!(sk.surface.is_rational(), rational);
            for (at_start, tt) in [(true, t[0]), (false, t[5])] {
                let dir = gamma_d(tt);
                let (fd, lib) = worst_angles(&sk.surface, at_start, dir);
                assert!(
                    fd <= 1e-9,
                    "rational {rational} q {q} start {at_start}: {fd:e}"
                );
                assert!(
                    lib <= 1e-9,
                    "rational {rational} q {q} start {at_start}: {lib:e}"
                );
            }
            let e = interpolation_error(&sk, &sections);
            assert!(
                e <= 1e-9,
                "rational {rational} q {q}: sections missed by {e:e}"
            );
            // the magnitude is the method's: |S_v| = the mean column polygon length, for every u
            let speed = sk.v_tangent_speed.unwrap();
            for i in 0..=10 {
                let m = sk.surface.derivatives(i as f64 / 10.0, 0.0, 1)[1].norm();
                assert!((m - speed).abs() <= 1e-9 * speed, "{m} vs {speed}");
            }
        }
    }
}

#[test]
fn one_end_two_sections_and_the_free_end_unchanged() {
    let t = spine_params(5);
    let sections: Vec<NurbsCurve> = t
        .iter()
        .map(|&x| translated(&profile(), gamma(x)))
        .collect();
    // only the start: one more control point, the end free
    let opts = SkinOptions {
        start_tangent_v: Some(gamma_d(t[0])),
        ..Default::default()
    };
    let sk = skin(&sections, &opts).unwrap();
    assert_eq!(sk.surface.net_size().1, 6);
    let (fd, _) = worst_angles(&sk.surface, true, gamma_d(t[0]));
    assert!(fd <= 1e-9, "{fd:e}");
    assert!(interpolation_error(&sk, &sections) <= 1e-9);
    // the free end is not held: far from γ' there
    let (free, _) = worst_angles(&sk.surface, false, gamma_d(t[4]));
    assert!(free > 1e-6, "{free:e}");
    // two sections and both tangents: a cubic Hermite across them
    let two = [sections[0].clone(), sections[4].clone()];
    let sk = skin(
        &two,
        &SkinOptions {
            start_tangent_v: Some(gamma_d(t[0])),
            end_tangent_v: Some(gamma_d(t[4])),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sk.surface.degree_v(), 3);
    assert_eq!(sk.surface.net_size().1, 4);
    for (s, tt) in [(true, t[0]), (false, t[4])] {
        assert!(worst_angles(&sk.surface, s, gamma_d(tt)).0 <= 1e-9);
    }
    assert!(interpolation_error(&sk, &two) <= 1e-9);
}

#[test]
fn approximated_skin_holds_the_tangents_and_the_end_sections() {
    let t = spine_params(12);
    let sections: Vec<NurbsCurve> = t
        .iter()
        .map(|&x| translated(&profile(), gamma(x)))
        .collect();
    let opts = with_tangents(
        &t,
        SkinOptions {
            approximate_with: Some(7),
            smoothing: 1e-4,
            ..Default::default()
        },
    );
    let sk = skin(&sections, &opts).unwrap();
    assert_eq!(sk.surface.net_size().1, 7);
    for (s, tt) in [(true, t[0]), (false, t[11])] {
        let (fd, lib) = worst_angles(&sk.surface, s, gamma_d(tt));
        assert!(fd <= 1e-9 && lib <= 1e-9, "{fd:e} {lib:e}");
    }
    let ends = [sections[0].clone(), sections[11].clone()];
    let ends_skin = Skin {
        v_params: vec![0.0, 1.0],
        ..sk.clone()
    };
    assert!(interpolation_error(&ends_skin, &ends) <= 1e-9);
    // too few control points for both legs: a typed option error
    let e = skin(
        &sections,
        &SkinOptions {
            approximate_with: Some(3),
            ..opts.clone()
        },
    )
    .unwrap_err();
    assert!(
        matches!(e, fairfit::Error::InvalidOption(_)) && e.to_string().contains("at least 4"),
        "{e}"
    );
}

#[test]
fn bad_directions_and_degree_one_are_option_errors() {
    let t = spine_params(4);
    let sections: Vec<NurbsCurve> = t
        .iter()
        .map(|&x| translated(&profile(), gamma(x)))
        .collect();
    for d in [
        Vec3::ZERO,
        Vec3::new(f64::NAN, 0.0, 1.0),
        Vec3::new(f64::INFINITY, 0.0, 0.0),
    ] {
        for start in [true, false] {
            let opts = SkinOptions {
                start_tangent_v: start.then_some(d),
                end_tangent_v: (!start).then_some(d),
                ..Default::default()
            };
            let e = skin(&sections, &opts).unwrap_err();
            assert!(matches!(e, fairfit::Error::InvalidOption(_)), "{e}");
            assert!(e.to_string().contains("finite non-zero"), "{e}");
        }
    }
    let e = skin(
        &sections,
        &SkinOptions {
            degree_v: 1,
            start_tangent_v: Some(Vec3::new(0.0, 0.0, 1.0)),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("degree in v of at least 2"), "{e}");
}

#[test]
fn the_pipeline_reports_the_angles_and_leaves_the_default_untouched() {
    // sections sampled from a translational surface with circular profiles (closed: periodic in u)
    let t = spine_params(6);
    let sections = |_: ()| -> Vec<Section> {
        t.iter()
            .map(|&x| {
                Section::from_points(
                    (0..40)
                        .map(|i| {
                            let a = std::f64::consts::TAU * i as f64 / 40.0;
                            Vec3::new(1.5 * a.cos(), 1.0 * a.sin(), 0.0) + gamma(x)
                        })
                        .collect(),
                )
            })
            .collect()
    };
    let base = SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: 1e-4,
            ..Default::default()
        },
        iso_curves: 3,
        ..Default::default()
    };
    let plain = reconstruct_surface(sections(()), &base).unwrap();
    assert!(plain.v_end_tangents.is_none());
    let mut asked = base.clone();
    asked.skin.start_tangent_v = Some(gamma_d(t[0]));
    asked.skin.end_tangent_v = Some(gamma_d(t[5]));
    asked.skin.params = VParams::ChordLength;
    let r = reconstruct_surface(sections(()), &asked).unwrap();
    let tan = r.v_end_tangents.unwrap();
    let (s, e) = (tan.start.unwrap(), tan.end.unwrap());
    assert!(s.max_angle <= 1e-9 && e.max_angle <= 1e-9, "{tan:?}");
    assert_eq!(tan.u_samples, 1001);
    // the same net in u, one more row per end in v, the sections still within tolerance
    let (nu, nv) = plain.surface.net_size();
    assert_eq!(r.surface.net_size(), (nu, nv + 2));
    assert!(r.deviation.max <= 1e-4, "{}", r.deviation.max);
}

#[test]
fn sections_with_varying_weights_keep_the_direction_exact() {
    // rational sections whose weights change from section to section: the end derivative of the
    // weights is held at 0, so ∂S/∂v stays along the asked direction for every u
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
                .map(|i| 1.0 + 0.3 * (i % 3) as f64 + 0.1 * k as f64)
                .collect();
            NurbsCurve::new(3, knots.clone(), pts, Some(w)).unwrap()
        })
        .collect();
    let (d0, d1) = (Vec3::new(0.3, -0.2, 1.0), Vec3::new(-0.1, 0.4, 1.0));
    for approximate_with in [None, Some(5)] {
        let sk = skin(
            &sections,
            &SkinOptions {
                start_tangent_v: Some(d0),
                end_tangent_v: Some(d1),
                approximate_with,
                smoothing: 1e-5,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(sk.surface.is_rational());
        for (s, d) in [(true, d0), (false, d1)] {
            let (fd, lib) = worst_angles(&sk.surface, s, d);
            assert!(
                fd <= 1e-9 && lib <= 1e-9,
                "{approximate_with:?}: {fd:e} {lib:e}"
            );
        }
        if approximate_with.is_none() {
            let e = interpolation_error(&sk, &sections);
            assert!(e <= 1e-9, "{e:e}");
        }
    }
}
