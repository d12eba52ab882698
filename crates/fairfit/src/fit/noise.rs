//! The noise of ordered points, measured before any fit.
//!
//! The points are grouped into bins of `r` consecutive points (`r = 1` first) and each bin is replaced
//! by its mean. Every bin mean is compared with the quintic through its three neighbours on each side
//! (Lagrange interpolation in the frame of the seven-mean stencil's chord, across the chord: the
//! in-plane normal for planar data, both normal directions otherwise). The residual is divided by
//! its own standard deviation for unit noise, `√((1 + Σ ℓ_j²) / r)` with `ℓ_j` the four Lagrange
//! weights, so that for Gaussian noise of standard deviation `σ` across the curve every standardised
//! residual has standard deviation `σ`; `σ` is the median absolute standardised residual divided by
//! `Φ⁻¹(3/4) ≈ 0.6745` (the MAD of a normal law).
//!
//! `σ` is the root-mean-square distance of the noise across the curve, for planar and space curves
//! alike. Across a planar curve that is the one in-plane normal component, Gaussian for Gaussian
//! noise, hence the MAD. Across a space curve the residual is a vector in the normal plane, and how
//! the noise shares itself between the two normal directions is unknown (along one random normal
//! per point, as a scan's noise along its beam; or independent per coordinate): the MAD of the
//! pooled components depends on that sharing (0.73 of the true σ for noise along one random
//! normal). So for space curves `σ²` is the mean of the squared residual vector's length over the
//! stencils, which does not depend on the sharing, over the stencils within
//! [`SPACE_TRIM`] times the median length (spikes and stencils that cannot follow a corner are
//! left out; a Gaussian along one normal loses 0.07 % of its stencils there, 1 % of `σ²`, and an
//! isotropic one none).
//!
//! Why this form:
//! - a quintic through the nearest neighbours follows the curve's curvature and its changes; what
//!   is left on clean data is a sixth-order term over six spacings, far below any tolerance on an
//!   airfoil table of a hundred points (a cubic over five points left 0.4 tol on a thick 95-point
//!   table);
//! - the median ignores the few stencils where a cubic cannot follow (a leading edge, a corner) and
//!   the ones holding a spike;
//! - `r` doubles while the stencils are shorter than [`FRAME_SIGMAS`] `σ`: at a density where the
//!   noise is larger than the point spacing, a short stencil is a blob of noise with no direction,
//!   and its frame would be noise too. Each try is one O(n) pass, so the estimate is O(n log n) at
//!   worst.
//!
//! - the same measure is taken again at twice the spacing (each stencil over every second bin mean,
//!   at the final bin size) as a consistency check: for white noise the standardised residual does
//!   not depend on the spacing, so both give the same `σ`. A residual of shape (a clean but sparse
//!   table, where the sixth-order term is what is left) grows like `h⁶`, 64 times per doubling; a
//!   point-to-point alternation (tables whose odd and even points were made apart) vanishes at twice
//!   the spacing. When the two differ by more than [`RESOLVED_RATIO`] either way, the residual is not
//!   white noise and the 5 σ rule of [`super::screening`] (the largest of `n` Gaussian deviations)
//!   does not apply: the estimate is flagged unresolved ([`NoiseEstimate::resolved`]).
//!
//! The estimate is scale-free (a scaled input gives a scaled `σ`) and deterministic.

use crate::nurbs::Vec3;

/// Fewest points measured (fewer give `σ = 0`); also the fewest bins at any bin size.
pub const MIN_POINTS: usize = 16;

/// A stencil's chord must be at least this many `σ` for its frame to follow the curve, not the noise.
pub const FRAME_SIGMAS: f64 = 30.0;

/// The estimate is resolved (white noise) while `σ` at twice the spacing stays within this factor of
/// `σ`, either way: white noise gives a ratio near 1 (a few per cent of sampling scatter on dense
/// data, up to about ±30 % on the fewest bins), a residual of shape about 64 (`h⁶`), an alternation
/// about 0; 2 sits between with a wide margin on both sides.
pub const RESOLVED_RATIO: f64 = 2.0;

/// Space curves: stencils whose residual is longer than this many times the median length are left
/// out of the mean square (module doc).
pub const SPACE_TRIM: f64 = 5.0;

/// `Φ⁻¹(3/4)`: the median absolute value of a standard normal variable.
const MAD_NORMAL: f64 = 0.674_489_750_196_081_7;

/// The measured noise of a point sequence.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NoiseEstimate {
    /// Standard deviation of the noise across the curve, in the points' units (0 when too few points).
    pub sigma: f64,
    /// Points per stencil at which it was measured (six bin spacings): the shortest run of consecutive
    /// points whose chord reaches [`FRAME_SIGMAS`] `σ` (the scale below which the data's direction is
    /// noise).
    pub block: usize,
    /// Whether `σ` is white noise: `false` when the residual changes with the spacing (it grows for
    /// shape, vanishes for an odd/even alternation; module doc), so that `σ` is not the deviation of
    /// independent noise. `true` for too few points.
    pub resolved: bool,
}

/// Measures the noise of `points` (module doc). Fewer than [`MIN_POINTS`] points give `σ = 0`.
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
    if n < MIN_POINTS {
        return NoiseEstimate {
            sigma: 0.0,
            block: 1,
            resolved: true,
        };
    }
    let planar = points.iter().all(|p| p[2] == points[0][2]);
    let mut scratch = Vec::with_capacity(if planar { n } else { 2 * n });
    let mut r = 1;
    loop {
        let q = bin_means(points, r);
        let (sigma, chord) = stencil_sigma(&q, 1, r, planar, &mut scratch);
        if chord >= FRAME_SIGMAS * sigma || 2 * r * MIN_POINTS > n {
            let (wide, _) = stencil_sigma(&q, 2, r, planar, &mut scratch);
            return NoiseEstimate {
                sigma,
                block: 6 * r,
                resolved: wide <= RESOLVED_RATIO * sigma && sigma <= RESOLVED_RATIO * wide,
            };
        }
        r *= 2;
    }
}

/// The means of consecutive bins of `r` points (a last, partial bin is dropped).
fn bin_means(points: &[Vec3], r: usize) -> Vec<Vec3> {
    points
        .chunks_exact(r)
        .map(|c| c.iter().fold(Vec3::new(0.0, 0.0, 0.0), |a, &p| a + p) / r as f64)
        .collect()
}

/// `σ` and the median stencil chord over the bin means `q` of `r` points each, every stencil made of
/// every `stride`-th mean (module doc).
fn stencil_sigma(
    q: &[Vec3],
    stride: usize,
    r: usize,
    planar: bool,
    res: &mut Vec<f64>,
) -> (f64, f64) {
    res.clear();
    let span = 6 * stride;
    let mut chords = Vec::with_capacity(q.len().saturating_sub(span));
    for i in 0..q.len().saturating_sub(span) {
        let w: [Vec3; 7] = std::array::from_fn(|k| q[i + k * stride]);
        chords.push((w[6] - w[0]).norm());
        stencil_residual(&w, planar, r, res);
    }
    let sigma = if planar {
        median(res) / MAD_NORMAL
    } else {
        // the residual vectors' lengths: the mean square of those within SPACE_TRIM medians
        let cut = SPACE_TRIM * median(res);
        let (sum, k) = res
            .iter()
            .filter(|&&m| m <= cut)
            .fold((0.0, 0usize), |(s, k), &m| (s + m * m, k + 1));
        if k == 0 {
            0.0
        } else {
            (sum / k as f64).sqrt()
        }
    };
    (sigma, median(&mut chords))
}

/// Pushes the standardised residual of the middle of seven bin means `w` from the quintic
/// through the other six (in their chord's frame) onto `out`: the residual's length across the
/// curve (its in-plane normal component for planar data) over the standard deviation
/// `σ √((1 + Σ ℓ_j²) / r)` of each component (`ℓ_j` the Lagrange weights, `r` points per mean).
fn stencil_residual(w: &[Vec3], planar: bool, r: usize, out: &mut Vec<f64>) {
    let d = w[6] - w[0];
    let len = d.norm();
    if len.is_nan() || len <= 0.0 {
        return;
    }
    let u = d / len;
    let x: Vec<f64> = w.iter().map(|&p| (p - w[0]).dot(u) / len).collect();
    let nodes = [0usize, 1, 2, 4, 5, 6];
    let mut weights = [0.0; 6];
    for (k, &a) in nodes.iter().enumerate() {
        let mut l = 1.0;
        for &b in &nodes {
            if b != a {
                let den = x[a] - x[b];
                if den.abs() < 1e-9 {
                    return;
                }
                l *= (x[3] - x[b]) / den;
            }
        }
        weights[k] = l;
    }
    let var = (1.0 + weights.iter().map(|l| l * l).sum::<f64>()) / r as f64;
    let normals: Vec<Vec3> = if planar {
        let h = u[0].hypot(u[1]);
        if h.is_nan() || h <= 0.0 {
            return;
        }
        vec![Vec3::new(-u[1] / h, u[0] / h, 0.0)]
    } else {
        let (v, n2) = perpendicular_pair(u);
        vec![v, n2]
    };
    // planar: the in-plane normal component; space: the length of the residual vector across
    // the curve (module doc)
    let across = |nrm: Vec3| {
        let y = |i: usize| (w[i] - w[0]).dot(nrm);
        let pred: f64 = nodes.iter().zip(&weights).map(|(&i, l)| l * y(i)).sum();
        y(3) - pred
    };
    let r = match normals[..] {
        [n1] => across(n1).abs(),
        _ => normals
            .iter()
            .map(|&n| across(n).powi(2))
            .sum::<f64>()
            .sqrt(),
    };
    out.push(r / var.sqrt());
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
