//! Helpers shared by the integration tests: random test geometry here (seeded, so every run is
//! identical), and in submodules the example data, independent deviation checks, CAD fixtures, the
//! Python peers, the CLI's default integrated options and an allocation counter.
#![allow(dead_code)]

pub mod alloc_counter;
pub mod cad_fixtures;
pub mod degree_auto;
pub mod example_data;
pub mod python;
pub mod sampled;
pub mod scan_data;
pub mod xorshift;

use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A seeded RNG.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A random knot vector of degree `p` for `n` control points: clamped or not, with interior knots of
/// multiplicity up to `max_mult` on a random domain.
pub fn random_knots(
    r: &mut ChaCha8Rng,
    p: usize,
    n: usize,
    clamped: bool,
    max_mult: usize,
) -> Vec<f64> {
    let m = n + p + 1;
    let start = r.random_range(-2.0..2.0);
    let len = r.random_range(0.5..4.0);
    loop {
        let mut k: Vec<f64> = Vec::with_capacity(m);
        if clamped {
            k.extend(std::iter::repeat_n(start, p + 1));
            while k.len() < m - p - 1 {
                let v = start + len * r.random_range(0.02..0.98);
                let mult = r.random_range(1..=max_mult.max(1)).min(m - p - 1 - k.len());
                k.extend(std::iter::repeat_n(v, mult));
            }
            k.extend(std::iter::repeat_n(start + len, p + 1));
        } else {
            while k.len() < m {
                let v = start + len * r.random_range(0.0..1.0);
                let mult = r.random_range(1..=max_mult.max(1)).min(m - k.len());
                k.extend(std::iter::repeat_n(v, mult));
            }
        }
        k.sort_by(f64::total_cmp);
        // accept only vectors whose domain spans are not tiny and multiplicities stay legal
        let ok_mult = k
            .windows(p + 1)
            .enumerate()
            .all(|(i, w)| w[0] != w[p] || i == 0 || i + p + 1 == m);
        if k[n] - k[p] > 0.1 * len && ok_mult {
            return k;
        }
    }
}

/// A random 3D point with coordinates in `[-s, s]`.
pub fn random_point(r: &mut ChaCha8Rng, s: f64) -> Vec3 {
    Vec3::new(
        r.random_range(-s..s),
        r.random_range(-s..s),
        r.random_range(-s..s),
    )
}

/// A random rational curve of degree `p` with `n` control points.
pub fn random_curve(
    r: &mut ChaCha8Rng,
    p: usize,
    n: usize,
    clamped: bool,
    max_mult: usize,
) -> NurbsCurve {
    let knots = random_knots(r, p, n, clamped, max_mult);
    let pts = (0..n).map(|_| random_point(r, 5.0)).collect();
    let w = (0..n).map(|_| r.random_range(0.3..3.0)).collect();
    NurbsCurve::new(p, knots, pts, Some(w)).expect("valid random curve")
}

/// A random rational surface.
pub fn random_surface(
    r: &mut ChaCha8Rng,
    p: usize,
    q: usize,
    nu: usize,
    nv: usize,
    clamped: bool,
) -> NurbsSurface {
    let ku = random_knots(r, p, nu, clamped, p);
    let kv = random_knots(r, q, nv, clamped, q);
    let net = (0..nu)
        .map(|_| (0..nv).map(|_| random_point(r, 5.0)).collect())
        .collect();
    let w = (0..nu)
        .map(|_| (0..nv).map(|_| r.random_range(0.3..3.0)).collect())
        .collect();
    NurbsSurface::new(p, q, ku, kv, net, Some(w)).expect("valid random surface")
}

/// `count` evenly spread parameters over `[a, b]`, both ends included.
pub fn samples(a: f64, b: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| a + (b - a) * i as f64 / (count - 1) as f64)
        .collect()
}

/// Largest control-point coordinate magnitude (the length scale for tolerances).
pub fn scale(c: &NurbsCurve) -> f64 {
    c.control_points()
        .iter()
        .fold(1.0f64, |m, p| m.max(p.max_abs()))
}

/// Largest distance between the two curves over 1000 parameters of the first one's domain.
pub fn max_deviation(a: &NurbsCurve, b: &NurbsCurve) -> f64 {
    let (u0, u1) = a.domain();
    let us = samples(u0, u1, 1000);
    a.points(&us)
        .iter()
        .zip(b.points(&us))
        .map(|(p, q)| (*p - q).norm())
        .fold(0.0, f64::max)
}
