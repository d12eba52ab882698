use super::deviation::{is_flat, project, project_planar_any};
use super::power_form::{power_span, power_span_from};
use super::*;

fn circle_data(n: usize, radius: f64) -> FitData {
    let points: Vec<Vec3> = (0..n)
        .map(|i| {
            let t = std::f64::consts::FRAC_PI_2 * i as f64 / (n - 1) as f64;
            Vec3([radius * t.cos(), radius * t.sin(), 0.0])
        })
        .collect();
    let params = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
    FitData {
        points,
        params,
        degree: 3,
        planar: true,
        corrections: 0,
        ends: Default::default(),
        bands: Default::default(),
    }
}

#[test]
fn reproduces_a_cubic_exactly_with_zero_deviation() {
    // data sampled from a known cubic B-spline with the same knots: LSQ must reproduce it
    let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0];
    let ctrl = vec![
        Vec3([0.0, 0.0, 0.0]),
        Vec3([1.0, 2.0, 0.0]),
        Vec3([2.0, -1.0, 0.0]),
        Vec3([3.0, 3.0, 0.0]),
        Vec3([4.0, 0.5, 0.0]),
        Vec3([5.0, 1.0, 0.0]),
    ];
    let params: Vec<f64> = (0..41).map(|i| i as f64 / 40.0).collect();
    let mut d = [Vec3::default(); 4];
    let points = params
        .iter()
        .map(|&u| {
            bspline_ders(&knots, &ctrl, 3, u, 0, &mut d);
            d[0]
        })
        .collect();
    let data = FitData {
        points,
        params,
        degree: 3,
        planar: true,
        corrections: 0,
        ends: Default::default(),
        bands: Default::default(),
    };
    let mut ws = EvalWorkspace::default();
    set_knots(3, &[0.3, 0.7], &mut ws);
    let ev = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
    assert!(ev.solved);
    assert!(ev.max_deviation < 1e-12, "{}", ev.max_deviation);
    for (a, b) in ws.ctrl.iter().zip(&ctrl) {
        assert!((*a - *b).norm() < 1e-10);
    }
}

#[test]
fn quarter_circle_deviation_and_fairness_are_small_and_scale_free() {
    // a cubic with 6 control points approximates a quarter circle within ~1e-4 of the radius;
    // the circle has F = 0, so F of the fit is small (0.15), and identical for radius 1 and 1000
    let mut ws = EvalWorkspace::default();
    set_knots(3, &[1.0 / 3.0, 2.0 / 3.0], &mut ws);
    let e1 = evaluate_candidate(&circle_data(60, 1.0), f64::NEG_INFINITY, &mut ws);
    let e2 = evaluate_candidate(&circle_data(60, 1000.0), f64::NEG_INFINITY, &mut ws);
    assert!(
        e1.max_deviation < 3e-4 && e1.max_deviation > 1e-7,
        "{}",
        e1.max_deviation
    );
    assert!(e1.fairness < 0.5, "{}", e1.fairness);
    assert!((e2.max_deviation / 1000.0 - e1.max_deviation).abs() < 1e-12);
    assert!((e2.fairness - e1.fairness).abs() < 1e-9 * e1.fairness.max(1e-12));
    // per-span parts add up to F
    let s: f64 = ws.span_fairness.iter().sum();
    assert!((s - e2.fairness).abs() <= 1e-12 * e2.fairness);
}

#[test]
fn every_projection_arm_gives_the_feet_of_the_spatial_projection() {
    // planar B-splines of degree 3 to 6 (each arm of `with_projection!`: constant degrees 3, 4,
    // 5 and a run-time degree), fitted exactly from points on them; points offset by a known
    // distance δ along the normal at known parameters must project back to that foot at
    // distance δ, bit for bit as the spatial `project` does, from a start 0.01 off
    let delta = 1e-3;
    for p in 3..=6 {
        let interior = [0.25, 0.5, 0.75];
        let mut knots = vec![0.0; p + 1];
        knots.extend_from_slice(&interior);
        knots.extend(std::iter::repeat_n(1.0, p + 1));
        let n = knots.len() - p - 1;
        let ctrl: Vec<Vec3> = (0..n)
            .map(|i| {
                let x = i as f64 / (n - 1) as f64;
                Vec3([x, 0.2 * (5.0 * x).sin(), 0.0])
            })
            .collect();
        let params: Vec<f64> = (0..61).map(|i| i as f64 / 60.0).collect();
        let mut d = [Vec3::default(); 4];
        let on = |u: f64, d: &mut [Vec3; 4]| bspline_ders(&knots, &ctrl, p, u, 1, d);
        let points = params
            .iter()
            .map(|&u| {
                on(u, &mut d);
                d[0]
            })
            .collect();
        let data = FitData {
            points,
            params: params.clone(),
            degree: p,
            planar: true,
            corrections: 0,
            ends: Default::default(),
            bands: Default::default(),
        };
        let mut ws = EvalWorkspace::default();
        set_knots(p, &interior, &mut ws);
        let ev = evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws);
        assert!(ev.solved && ev.max_deviation < 1e-12, "{p}: {ev:?}");
        assert!(is_flat(&data, &ws));
        // the offset points, alternating sides of the curve
        let offset: Vec<Vec3> = params
            .iter()
            .enumerate()
            .map(|(k, &u)| {
                on(u, &mut d);
                let t = d[1] / d[1].norm();
                let side = if k % 2 == 0 { 1.0 } else { -1.0 };
                d[0] + Vec3([-t.y(), t.x(), 0.0]) * (side * delta)
            })
            .collect();
        let query = FitData {
            points: offset,
            ..data
        };
        let start: Vec<f64> = params.iter().map(|&u| (u + 0.01).clamp(0.0, 1.0)).collect();
        let feet = with_projection!(&query, &ws, |proj| {
            let mut hint = 0;
            (1..params.len() - 1)
                .map(|k| proj(k, start[k], &ws, &mut hint))
                .collect::<Vec<_>>()
        });
        let mut hint = 0;
        for (k, &(d2, u)) in (1..params.len() - 1).zip(&feet) {
            let spatial = project(&query, k, start[k], &ws, &mut hint);
            assert_eq!(
                (d2.to_bits(), u.to_bits()),
                (spatial.0.to_bits(), spatial.1.to_bits())
            );
            assert!((d2.sqrt() - delta).abs() < 1e-9, "{p} {k}: {}", d2.sqrt());
            assert!((u - params[k]).abs() < 1e-6, "{p} {k}: {u}");
        }
    }
}

#[test]
fn hinted_span_search_agrees_with_binary_search() {
    let breaks = [0.0, 0.1, 0.25, 0.5, 0.9];
    for hint in 0..7 {
        for i in 0..=100 {
            let u = i as f64 / 100.0;
            assert_eq!(
                power_span_from(&breaks, u, hint),
                power_span(&breaks, u),
                "{u} {hint}"
            );
        }
    }
}

#[test]
fn a_move_measured_in_part_equals_the_full_measurement() {
    // wavy data, 9 control points; moving P_4 and re-measuring only its spans must give the
    // deviations and F of a full re-measurement from the same feet
    let m = 80;
    let points: Vec<Vec3> = (0..m)
        .map(|i| {
            let x = i as f64 / (m - 1) as f64;
            Vec3([x, 0.3 * (3.0 * x).sin(), 0.0])
        })
        .collect();
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let data = FitData {
        points,
        params,
        degree: 3,
        planar: true,
        corrections: 1,
        ends: Default::default(),
        bands: Default::default(),
    };
    let mut ws = EvalWorkspace::default();
    set_knots(3, &[0.2, 0.35, 0.5, 0.65, 0.8], &mut ws);
    assert!(evaluate_candidate(&data, f64::NEG_INFINITY, &mut ws).solved);
    let feet = ws.foot_params.clone();
    let before = measure_current(&data, &feet, &mut ws);
    let feet = ws.foot_params.clone();
    let mut saved = MeasureState::default();
    ws.save_state(&mut saved);
    ws.ctrl[4] += Vec3([0.0, 0.01, 0.0]);
    let part = measure_move(&data, 4, &feet, true, &mut ws);
    let full = measure_current(&data, &feet, &mut ws);
    assert!(part.fairness != before.fairness);
    assert!((part.fairness - full.fairness).abs() <= 1e-12 * full.fairness);
    assert!((part.max_span_fairness - full.max_span_fairness).abs() <= 1e-12 * full.fairness);
    assert!((part.max_deviation - full.max_deviation).abs() <= 1e-12);
    assert!((part.rms_deviation - full.rms_deviation).abs() <= 1e-12);
    assert!(part.max_deviation > before.max_deviation + 1e-3);
    // undoing restores the earlier measurement exactly
    ws.ctrl[4] -= Vec3([0.0, 0.01, 0.0]);
    ws.load_state(&saved);
    let again = measure_move(&data, 4, &feet, true, &mut ws);
    assert!((again.fairness - before.fairness).abs() <= 1e-12 * before.fairness);
    assert!((again.max_deviation - before.max_deviation).abs() <= 1e-12);
}

#[test]
fn fairness_matches_closed_form_for_a_parabola() {
    // C(u) = (u, u²): κ = 2/(1+4u²)^{3/2}; exactly representable as a cubic B-spline (Bézier)
    // F = L³ ∫ (dκ/ds)² ds computed by dense trapezoid quadrature as independent truth
    let ctrl = vec![
        Vec3([0.0, 0.0, 0.0]),
        Vec3([1.0 / 3.0, 0.0, 0.0]),
        Vec3([2.0 / 3.0, 1.0 / 3.0, 0.0]),
        Vec3([1.0, 1.0, 0.0]),
    ];
    let mut ws = EvalWorkspace::default();
    set_knots(3, &[], &mut ws);
    ws.ctrl = ctrl;
    let data = FitData {
        points: vec![],
        params: vec![],
        degree: 3,
        planar: true,
        corrections: 0,
        ends: Default::default(),
        bands: Default::default(),
    };
    build_power_form(3, &mut ws);
    let (f, _) = fairness(&data, &mut ws);
    let n = 200_000;
    let (mut len, mut e) = (0.0, 0.0);
    for i in 0..n {
        let u = (i as f64 + 0.5) / n as f64;
        let s = (1.0 + 4.0 * u * u).sqrt();
        let dk_du = -24.0 * u / s.powi(5);
        len += s / n as f64;
        e += dk_du * dk_du / s / n as f64;
    }
    let truth = len * len * len * e;
    // one span over the whole curve: 8-point Gauss–Legendre is good to ~1e-4 here
    assert!((f - truth).abs() < 2e-4 * truth, "{f} vs {truth}");
    // the 3D formula agrees on a planar curve
    let data3 = FitData {
        planar: false,
        ..data
    };
    let (f3, _) = fairness(&data3, &mut ws);
    assert!((f3 - f).abs() < 1e-9 * truth);
}
