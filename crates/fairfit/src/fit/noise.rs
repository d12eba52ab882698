//! The noise of ordered points, measured before any fit.
//!
//! The points are cut into consecutive blocks of `m` points. In each block a cubic `y(x)` is fitted by
//! least squares in the block's own frame (`x` along the block, from the mean of its first half to the
//! mean of its second half; `y` across it: the in-plane normal for planar data, both normal directions
//! otherwise). Each residual is divided by `√(1 - h_ii)` (its leverage), so that for Gaussian noise of
//! standard deviation `σ` across the curve every standardised residual has standard deviation `σ`
//! exactly; `σ` is then the median absolute standardised residual over all blocks divided by
//! `Φ⁻¹(3/4) ≈ 0.6745` (the MAD of a normal law).
//!
//! Why this form:
//! - a cubic over a block follows the curve's curvature and its change, so clean data (an airfoil
//!   table) report `σ` far below any tolerance: the residuals are the curve's fourth-order terms;
//! - the median ignores the few blocks where a cubic cannot follow (a leading edge, a corner) and the
//!   blocks holding a spike;
//! - `m` starts at [`MIN_BLOCK`] points and doubles while the blocks are shorter than
//!   [`FRAME_SIGMAS`] `σ`: at a density where the noise is larger than the point spacing, a short block
//!   is a blob of noise with no direction, and its frame would be noise too. Each try is one O(n) pass,
//!   so the whole estimate is O(n log n) at worst.
//!
//! The estimate is scale-free (a scaled input gives a scaled `σ`) and deterministic.

use crate::nurbs::Vec3;

/// Fewest points in a block (a cubic has 4 coefficients: 4 degrees of freedom are left).
pub const MIN_BLOCK: usize = 8;

/// A block's chord must be at least this many `σ` for its frame to follow the curve, not the noise.
pub const FRAME_SIGMAS: f64 = 30.0;

/// `Φ⁻¹(3/4)`: the median absolute value of a standard normal variable.
const MAD_NORMAL: f64 = 0.674_489_750_196_081_7;

/// The measured noise of a point sequence.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NoiseEstimate {
    /// Standard deviation of the noise across the curve, in the points' units (0 when too few points).
    pub sigma: f64,
    /// Points per block at which it was measured: the shortest run of consecutive points whose chord
    /// reaches [`FRAME_SIGMAS`] `σ` (the scale below which the data's direction is noise).
    pub block: usize,
}

/// Measures the noise of `points` (module doc). Fewer than `2 ·` [`MIN_BLOCK`] points give `σ = 0`.
///
/// ```
/// use fairfit::fit::noise::estimate_noise;
/// use fairfit::nurbs::Vec3;
/// // a clean circle arc: no noise, whatever its curvature
/// let pts: Vec<Vec3> = (0..500)
///     .map(|i| {
///         let a = i as f64 / 499.0 * 3.0;
///         Vec3::new(a.cos(), a.sin(), 0.0)
///     })
///     .collect();
/// assert!(estimate_noise(&pts).sigma < 1e-9);
/// ```
pub fn estimate_noise(points: &[Vec3]) -> NoiseEstimate {
    let n = points.len();
    let mut block = MIN_BLOCK;
    if n < 2 * MIN_BLOCK {
        return NoiseEstimate {
            sigma: 0.0,
            block: 1,
        };
    }
    let planar = points.iter().all(|p| p[2] == points[0][2]);
    let mut scratch = Vec::with_capacity(if planar { n } else { 2 * n });
    loop {
        let (sigma, chord) = blocks_sigma(points, block, planar, &mut scratch);
        if chord >= FRAME_SIGMAS * sigma || 2 * block > n / 2 {
            return NoiseEstimate { sigma, block };
        }
        block *= 2;
    }
}

/// `σ` and the median block chord at block size `m` (module doc).
fn blocks_sigma(points: &[Vec3], m: usize, planar: bool, res: &mut Vec<f64>) -> (f64, f64) {
    res.clear();
    let nb = points.len() / m;
    let mut chords = Vec::with_capacity(nb);
    for b in 0..nb {
        // the last block takes the remainder
        let end = if b + 1 == nb {
            points.len()
        } else {
            (b + 1) * m
        };
        let blk = &points[b * m..end];
        chords.push((blk[blk.len() - 1] - blk[0]).norm());
        block_residuals(blk, planar, res);
    }
    (median(res) / MAD_NORMAL, median(&mut chords))
}

/// Pushes the standardised residuals (absolute values) of one block's cubic onto `out`.
fn block_residuals(blk: &[Vec3], planar: bool, out: &mut Vec<f64>) {
    let m = blk.len();
    let mean = |s: &[Vec3]| s.iter().fold(Vec3::new(0.0, 0.0, 0.0), |a, &p| a + p) / s.len() as f64;
    let (a, b) = (mean(&blk[..m / 2]), mean(&blk[m / 2..]));
    let d = b - a;
    if !(d.norm() > 0.0) {
        return;
    }
    let u = d / d.norm();
    let c = (a + b) * 0.5;
    let half = 0.5
        * blk
            .iter()
            .map(|&p| (p - c).dot(u).abs())
            .fold(0.0, f64::max)
            .max(1e-300);
    let xs: Vec<f64> = blk.iter().map(|&p| (p - c).dot(u) / half).collect();
    let Some(ginv) = inverse_gram(&xs) else {
        return;
    };
    let normals: Vec<Vec3> = if planar {
        vec![Vec3::new(-u[1], u[0], 0.0) / (u[0].hypot(u[1])).max(1e-300)]
    } else {
        let (v, w) = perpendicular_pair(u);
        vec![v, w]
    };
    for nrm in normals {
        let ys: Vec<f64> = blk.iter().map(|&p| (p - c).dot(nrm)).collect();
        let mut rhs = [0.0; 4];
        for (&x, &y) in xs.iter().zip(&ys) {
            let phi = [1.0, x, x * x, x * x * x];
            for k in 0..4 {
                rhs[k] += phi[k] * y;
            }
        }
        let coef = mat_vec(&ginv, &rhs);
        for (&x, &y) in xs.iter().zip(&ys) {
            let phi = [1.0, x, x * x, x * x * x];
            let fit: f64 = (0..4).map(|k| coef[k] * phi[k]).sum();
            let g = mat_vec(&ginv, &phi);
            let lev: f64 = (0..4).map(|k| g[k] * phi[k]).sum();
            if lev < 0.99 {
                out.push((y - fit).abs() / (1.0 - lev).sqrt());
            }
        }
    }
}

/// Two unit vectors perpendicular to the unit `u` and to each other.
fn perpendicular_pair(u: Vec3) -> (Vec3, Vec3) {
    let e = if u[0].abs() < 0.6 {
        Vec3::new(1.0, 0.0, 0.0)
    } else {
        Vec3::new(0.0, 1.0, 0.0)
    };
    let v = u.cross(e);
    let v = v / v.norm();
    (v, u.cross(v))
}

fn mat_vec(a: &[[f64; 4]; 4], v: &[f64; 4]) -> [f64; 4] {
    let mut o = [0.0; 4];
    for (oi, row) in o.iter_mut().zip(a) {
        *oi = (0..4).map(|k| row[k] * v[k]).sum();
    }
    o
}

/// The inverse of the cubic's Gram matrix `Σ φ φᵀ` (Gauss–Jordan with pivoting); `None` if singular.
fn inverse_gram(xs: &[f64]) -> Option<[[f64; 4]; 4]> {
    let mut g = [[0.0; 8]; 4];
    for &x in xs {
        let phi = [1.0, x, x * x, x * x * x];
        for i in 0..4 {
            for j in 0..4 {
                g[i][j] += phi[i] * phi[j];
            }
        }
    }
    for (i, row) in g.iter_mut().enumerate() {
        row[4 + i] = 1.0;
    }
    let scale = g[0][0].max(1.0);
    for col in 0..4 {
        let piv = (col..4).max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))?;
        if g[piv][col].abs() < 1e-12 * scale {
            return None;
        }
        g.swap(col, piv);
        let d = g[col][col];
        g[col].iter_mut().for_each(|v| *v /= d);
        for r in 0..4 {
            if r != col {
                let f = g[r][col];
                let src = g[col];
                g[r].iter_mut().zip(src).for_each(|(v, s)| *v -= f * s);
            }
        }
    }
    let mut inv = [[0.0; 4]; 4];
    for i in 0..4 {
        inv[i].copy_from_slice(&g[i][4..]);
    }
    Some(inv)
}

/// The median of `v` (reordered; 0 for an empty slice).
pub(crate) fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let k = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(k, f64::total_cmp);
    *m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic standard normal samples (xorshift + Box–Muller).
    pub(crate) fn gauss(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        move || {
            let (a, b) = (next(), next());
            (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
        }
    }

    fn noisy_spiral(n: usize, sigma: f64, seed: u64) -> Vec<Vec3> {
        let mut g = gauss(seed);
        (0..n)
            .map(|i| {
                let t = i as f64 / (n - 1) as f64 * 4.0;
                let r = 0.4 + 0.15 * t;
                let (p, d) = (
                    Vec3::new(r * t.cos(), r * t.sin(), 0.0),
                    Vec3::new(
                        0.15 * t.cos() - r * t.sin(),
                        0.15 * t.sin() + r * t.cos(),
                        0.0,
                    ),
                );
                let nrm = Vec3::new(-d[1], d[0], 0.0) / d.norm();
                p + nrm * (sigma * g())
            })
            .collect()
    }

    #[test]
    fn sigma_within_a_quarter_on_noisy_spirals() {
        for (n, rel) in [
            (1000, 1e-2),
            (1000, 1.0 / 3.0),
            (20_000, 0.1),
            (20_000, 1e-2),
        ] {
            let tol = 1e-3 * 2.0;
            let s = estimate_noise(&noisy_spiral(n, rel * tol, 3));
            assert!(
                (s.sigma / (rel * tol) - 1.0).abs() < 0.25,
                "n {n} σ/tol {rel}: got {}",
                s.sigma / tol
            );
        }
    }

    #[test]
    fn clean_curve_reports_no_noise_and_scale_is_followed() {
        let clean = noisy_spiral(300, 0.0, 1);
        assert!(estimate_noise(&clean).sigma < 1e-6 * 2.0);
        let noisy = noisy_spiral(3000, 2e-4, 5);
        let big: Vec<Vec3> = noisy.iter().map(|&p| p * 1000.0).collect();
        let (a, b) = (estimate_noise(&noisy), estimate_noise(&big));
        assert_eq!(a.block, b.block);
        assert!((b.sigma / a.sigma / 1000.0 - 1.0).abs() < 1e-9);
    }
}
