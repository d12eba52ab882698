//! Corners inside the sections (`src/surface/section_corners.rs`): blunt-trailing-edge airfoils closed by
//! a straight trailing-edge segment have a corner at the seam and one at the other end of that segment;
//! the inner one is held as a C0 knot line of multiplicity `p` shared by all sections, so the loft meets
//! the tolerance. Sections with different numbers of corners are fitted as before.

use fairfit::nurbs::Vec3;
use fairfit::surface::{
    reconstruct_surface, CompatibleOptions, Section, SurfaceOptions, SurfaceReconstruction,
};

/// NACA 4-digit camber `m` (max camber), `p` (its position), thickness `t`: the upper and lower
/// surface points at chord position `x` (the standard open trailing edge, 0.2 % thick at 12 %).
pub(super) fn naca(m: f64, p: f64, t: f64, x: f64) -> (Vec3, Vec3) {
    let yt = 5.0
        * t
        * (0.2969 * x.sqrt() - 0.126 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
            - 0.1015 * x.powi(4));
    let (yc, dy) = if m == 0.0 {
        (0.0, 0.0)
    } else if x < p {
        (
            m / (p * p) * (2.0 * p * x - x * x),
            2.0 * m / (p * p) * (p - x),
        )
    } else {
        let q = (1.0 - p) * (1.0 - p);
        (
            m / q * ((1.0 - 2.0 * p) + 2.0 * p * x - x * x),
            2.0 * m / q * (p - x),
        )
    };
    let th = dy.atan();
    (
        Vec3::new(x - yt * th.sin(), yc + yt * th.cos(), 0.0),
        Vec3::new(x + yt * th.sin(), yc - yt * th.cos(), 0.0),
    )
}

/// Section `k` of a twisted, tapering loft: a NACA 4-digit airfoil from the upper trailing edge round
/// the leading edge to the lower trailing edge (101 cosine-spaced points per side), closed by a
/// straight trailing-edge segment of `te` chords back to the start; 207 points with `te = 6`. The
/// two trailing-edge points are corners (turns of about 90°). Returns the section and its two
/// trailing-edge corner points.
pub(super) fn blunt_airfoil(k: usize, te: usize) -> (Section, [Vec3; 2]) {
    blunt_airfoil_n(k, te, 100)
}

/// [`blunt_airfoil`] with `n + 1` points per side.
fn blunt_airfoil_n(k: usize, te: usize, n: usize) -> (Section, [Vec3; 2]) {
    let (m, p, t) = [
        (0.04, 0.4, 0.12),
        (0.03, 0.4, 0.14),
        (0.02, 0.4, 0.16),
        (0.0, 0.4, 0.18),
    ][k];
    let (chord, twist, z) = (
        1.0 - 0.1 * k as f64,
        (6.0 * k as f64).to_radians(),
        0.6 * k as f64,
    );
    let x = |i: usize, up: bool| {
        let c = (std::f64::consts::PI * i as f64 / n as f64).cos();
        0.5 * if up { 1.0 + c } else { 1.0 - c }
    };
    let mut pts: Vec<Vec3> = (0..=n).map(|i| naca(m, p, t, x(i, true)).0).collect();
    pts.extend((1..=n).map(|i| naca(m, p, t, x(i, false)).1));
    let (a, b) = (pts[pts.len() - 1], pts[0]);
    pts.extend((1..te).map(|j| a + (b - a) * (j as f64 / te as f64)));
    pts.push(pts[0]);
    let (c, s) = (twist.cos(), twist.sin());
    let place = |q: Vec3| {
        let (x, y) = ((q.x() - 0.3) * chord, q.y() * chord);
        Vec3::new(c * x - s * y, s * x + c * y, z)
    };
    let pts: Vec<Vec3> = pts.into_iter().map(place).collect();
    (Section::from_points(pts), [place(b), place(a)])
}

fn options(tol: f64, hold: bool) -> SurfaceOptions {
    SurfaceOptions {
        sections: CompatibleOptions {
            tolerance: tol,
            hold_corners: hold,
            ..Default::default()
        },
        iso_curves: 5,
        ..Default::default()
    }
}

const TOL: f64 = 1e-4;

/// Four blunt-trailing-edge NACA sections (4412 to 0018, chord 1 to 0.7, twisted by 18°), 207 points
/// each, tolerance 1e-4 (1e-4 of the chord). Before the corners were held the inner trailing-edge
/// corner was rounded: the search ran out of knots at 37 control points with the surface 6.67e-4
/// (6.7 tol) away from the corner; held, the loft meets the tolerance with 23 control points.
/// Smoothed over, it now meets it too, with the search's smoothing relaxed and more control points.
#[test]
fn blunt_trailing_edges_are_held_as_c0_knot_lines() {
    let (secs, tes): (Vec<Section>, Vec<[Vec3; 2]>) = (0..4).map(|k| blunt_airfoil(k, 6)).unzip();
    assert!(secs.iter().all(|s| s.closed && s.points.len() == 207));
    let r = reconstruct_surface(secs.clone(), &options(TOL, true)).unwrap();
    let c = &r.compatible.corners;
    println!(
        "held: net {:?}, max deviation {:.4e} ({:.3} tol), corners {c:?}",
        r.surface.net_size(),
        r.deviation.max,
        r.deviation.max / TOL
    );
    assert!(c.held && c.reason.is_none(), "{c:?}");
    assert_eq!(c.per_section, vec![1; 4]);
    assert_eq!(c.params.len(), 1);
    assert!(r.deviation.max <= TOL, "{}", r.deviation.max);
    assert!(r.compatible.within_tolerance);
    check_corner_line(&r, &tes, c.params[0]);

    assert_eq!(
        r.compatible.smoothing,
        CompatibleOptions::default().smoothing
    );

    // the same loft with the corners smoothed over: the search's bending term binds at the
    // corner (with it, the search ran out of knots at 37 control points, 6.7 tol from the corner),
    // so it is relaxed and the loft meets the tolerance, with more control points than held
    let smoothed = reconstruct_surface(secs, &options(TOL, false)).unwrap();
    println!(
        "smoothed: net {:?}, max deviation {:.4e} ({:.3} tol), smoothing {:e}",
        smoothed.surface.net_size(),
        smoothed.deviation.max,
        smoothed.deviation.max / TOL,
        smoothed.compatible.smoothing
    );
    assert!(!smoothed.compatible.corners.held);
    assert!(smoothed.deviation.max <= TOL, "{}", smoothed.deviation.max);
    assert!(smoothed.compatible.smoothing < 1e-2 * CompatibleOptions::default().smoothing);
    assert_eq!(
        smoothed.relaxed_smoothing,
        Some(smoothed.compatible.smoothing)
    );
    assert_eq!(r.relaxed_smoothing, None);
    assert!(r.surface.net_size().0 < smoothed.surface.net_size().0);
}

/// The held corner `tc`: a knot of multiplicity `p` in u, each section's corner point keeps `tc` as
/// its parameter and lies on the surface's iso-curve at `tc` within the tolerance (one of that
/// section's trailing-edge points), and the surface is creased along the knot line.
fn check_corner_line(r: &SurfaceReconstruction, tes: &[[Vec3; 2]], tc: f64) {
    let p = r.surface.degree_u();
    let mult = r.surface.knots_u().iter().filter(|&&u| u == tc).count();
    assert_eq!(mult, p, "{:?}", r.surface.knots_u());
    for (k, (s, fit)) in r.sections.iter().zip(&r.compatible.fits).enumerate() {
        let i = fit
            .params
            .iter()
            .position(|&u| u == tc)
            .expect("held parameter");
        let q = s.points[i];
        assert!(
            tes[k].iter().any(|&te| te.distance(q) < 1e-12),
            "section {k}: corner {q:?} is not a trailing-edge point {:?}",
            tes[k]
        );
        let on = r.surface.point(tc, r.v_params[k]);
        let miss = on.distance(q);
        println!("section {k}: corner off the knot line by {miss:.3e}");
        assert!(miss <= TOL, "section {k}: {miss:e}");
        // a crease: the u tangents either side of the knot line turn by about the corner's 90°
        let (a, b) = (
            r.surface.derivatives(tc - 1e-9, r.v_params[k], 1)[2],
            r.surface.derivatives(tc + 1e-9, r.v_params[k], 1)[2],
        );
        let angle = a.cross(b).norm().atan2(a.dot(b));
        assert!(angle > 1.0, "section {k}: {angle}");
    }
}

/// One section without a closing trailing-edge segment (open: its trailing-edge points are its ends,
/// no inner corner) among three with one inner corner: counts differ, nothing is held, the sections
/// are fitted as with holding switched off (bit for bit), without an error.
#[test]
fn different_corner_counts_fit_as_before() {
    let mut secs: Vec<Section> = (0..4).map(|k| blunt_airfoil(k, 6).0).collect();
    let open: Vec<Vec3> = secs[1].points[..201].to_vec();
    secs[1] = Section::from_points(open);
    assert!(!secs[1].closed);
    let tol = 5e-4;
    let r = reconstruct_surface(secs.clone(), &options(tol, true)).unwrap();
    let off = reconstruct_surface(secs, &options(tol, false)).unwrap();
    let c = &r.compatible.corners;
    println!(
        "mixed counts: {c:?}, net {:?}, max deviation {:.4e}",
        r.surface.net_size(),
        r.deviation.max
    );
    assert!(!c.held && c.params.is_empty(), "{c:?}");
    assert_eq!(c.per_section, vec![1, 0, 1, 1]);
    assert!(c.reason.as_deref().is_some_and(|m| m.contains("different")));
    assert_eq!(r.surface, off.surface);
    assert_eq!(r.compatible.knots, off.compatible.knots);
}

/// The same four sections at 3,061 points each with Gaussian noise of 0.05 tol on each coordinate (a
/// deterministic stream): held as a C0 knot line the inner corner does not let the sections meet the
/// tolerance (7.3 tol with 43 control points), so they are fitted again with it smoothed over, and the
/// result is the loft without holding (also 7.3 tol: noisy blunt trailing edges are not solved), with
/// the reason in the report.
#[test]
fn noisy_sections_that_miss_with_held_corners_fall_back_to_smoothed_ones() {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut gauss = || {
        let mut u = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let (a, b) = (u(), u());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    };
    let secs: Vec<Section> = (0..4)
        .map(|k| {
            let mut pts = blunt_airfoil_n(k, 60, 1500).0.points;
            let last = pts.len() - 1;
            for q in &mut pts[..last] {
                *q += Vec3::new(0.05 * TOL * gauss(), 0.05 * TOL * gauss(), 0.0);
            }
            pts[last] = pts[0];
            Section::from_points(pts)
        })
        .collect();
    let r = reconstruct_surface(secs.clone(), &options(TOL, true)).unwrap();
    let c = &r.compatible.corners;
    if r.compatible.within_tolerance {
        // held and within the tolerance: nothing to fall back from
        assert!(c.held, "{c:?}");
        return;
    }
    assert!(!c.held, "{c:?}");
    let reason = c.reason.as_deref().unwrap_or("");
    assert!(reason.contains("smoothed over"), "{reason}");
    let plain = reconstruct_surface(secs, &options(TOL, false)).unwrap();
    assert_eq!(plain.compatible.knots, r.compatible.knots);
    assert_eq!(plain.deviation.max, r.deviation.max);
}
