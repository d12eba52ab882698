//! Generated scan-like data: dense, noisy and spiky point sequences with known truths (the noise σ,
//! the corner positions, the spike indices), for the screening stages' tests.

use super::rng;
use super::xorshift::Xorshift;
use fairfit::nurbs::Vec3;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A standard normal sample (Box–Muller).
pub fn gauss(r: &mut ChaCha8Rng) -> f64 {
    let (a, b): (f64, f64) = (r.random::<f64>().max(1e-300), r.random());
    (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
}

/// A planar spiral of size about 2 (`r = 0.4 + 0.15 t`, `t ∈ [0, 4]`), `n` points even in `t`, with
/// Gaussian noise of standard deviation `sigma` along its normal.
pub fn noisy_spiral(n: usize, sigma: f64, seed: u64) -> Vec<Vec3> {
    let mut g = rng(seed);
    (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64 * 4.0;
            let r = 0.4 + 0.15 * t;
            let p = Vec3::new(r * t.cos(), r * t.sin(), 0.0);
            let d = Vec3::new(
                0.15 * t.cos() - r * t.sin(),
                0.15 * t.sin() + r * t.cos(),
                0.0,
            );
            p + Vec3::new(-d[1], d[0], 0.0) / d.norm() * (sigma * gauss(&mut g))
        })
        .collect()
}

/// Two straight legs of length 1 meeting at `(1, 0)` with a turn of `turn_deg`, `n` points even in
/// arc length (the corner is point `n / 2`), isotropic Gaussian noise `sigma`.
pub fn noisy_corner(n: usize, turn_deg: f64, sigma: f64, seed: u64) -> Vec<Vec3> {
    let mut g = rng(seed);
    let a = turn_deg.to_radians();
    let h = n / 2;
    (0..n)
        .map(|i| {
            let s = i as f64 / h as f64;
            let p = if i <= h {
                Vec3::new(s, 0.0, 0.0)
            } else {
                Vec3::new(1.0 + (s - 1.0) * a.cos(), (s - 1.0) * a.sin(), 0.0)
            };
            p + Vec3::new(gauss(&mut g), gauss(&mut g), 0.0) * sigma
        })
        .collect()
}

/// Largest side of the bounding box (the unit of relative tolerances).
pub fn extent(pts: &[Vec3]) -> f64 {
    fairfit::fit::points::bounding_box_extent(pts)
}

/// Tolerance of the noisy rings (absolute; the ellipse is 4 × 2).
pub const RING_TOL: f64 = 4e-3;

/// `n` points on the ellipse of semi-axes 2 and 1 around (3, −2), noise σ = `RING_TOL / 10` in x and
/// y; the first `n − drop` of them kept, and the last of those moved to `gap_tol · RING_TOL` from the
/// first along the line between them (the ring's ends, not repeated).
pub fn noisy_ring(n: usize, drop: usize, gap_tol: f64) -> Vec<Vec3> {
    let sigma = RING_TOL / 10.0;
    let mut rng = Xorshift(0x2545_f491_4f6c_dd1d);
    let mut v: Vec<Vec3> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let (ex, ey) = (sigma * rng.normal(), sigma * rng.normal());
            Vec3([3.0 + 2.0 * t.cos() + ex, -2.0 + t.sin() + ey, 0.0])
        })
        .collect();
    v.truncate(n - drop);
    let last = v.len() - 1;
    let d = v[last] - v[0];
    v[last] = v[0] + d * (gap_tol * RING_TOL / d.norm());
    v
}
