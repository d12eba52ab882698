//! The reduction stage (`fairfit::optim::stages::reduce`) through `fit_integrated`, without corner
//! detection, on a noisy spiral (size about 2.2, noise tol/20): the dense fit meets the tolerance on
//! every input point (an independent whole-curve projection) and stays within 1.1 tol of the
//! noise-free spiral; a burst of 100:1 density gives the count of even sampling; the data scaled
//! by 1000 give the same knots (12,000 points whose normalised coordinates differ in the last
//! place, one of them across the pipeline's 2^-36 snap grid); 10 times fewer points (two or three
//! to a bin) give the count within one; a noisy stretch of otherwise clean data costs at most one
//! control point; a noisy airfoil (examples/data/fx77w343.csv densified, noise tol/10) at 10^4
//! and 10^5 points gets counts within one (its fits are repaired at their own count).

use fairfit::diffgeo::projection::CurveProjector;
use fairfit::optim::{fit_integrated, IntegratedOptions, IntegratedResult, Tolerance};
use fairfit::Vec3;

/// The noise-free spiral at `t ∈ [0, 1]`.
fn spiral(t: f64) -> Vec3 {
    let a = 7.2 * t;
    let r = 0.4 + 1.125 * t;
    Vec3::new(r * a.cos(), r * a.sin(), 0.0)
}

/// A deterministic standard normal stream (xorshift and Box–Muller).
struct Gauss(u64);

impl Gauss {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The spiral at parameters `ts` with Gaussian noise `sigma` on each coordinate.
fn noisy(ts: &[f64], sigma: f64, seed: u64) -> Vec<Vec3> {
    let mut g = Gauss(seed);
    ts.iter()
        .map(|&t| spiral(t) + Vec3::new(sigma * g.next(), sigma * g.next(), 0.0))
        .collect()
}

fn even(n: usize) -> Vec<f64> {
    (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
}

fn fit(points: &[Vec3]) -> IntegratedResult {
    let opts = IntegratedOptions::new(Tolerance::Relative(1e-3)).corner_angle(None);
    fit_integrated(points, &opts).unwrap()
}

/// Tolerance of the spiral data (relative 1e-3 of the bounding box's largest side).
fn tolerance(points: &[Vec3]) -> f64 {
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    1e-3 * (hi - lo).max_abs()
}

const SIGMA: f64 = 1.1e-4;

#[test]
fn a_dense_noisy_spiral_meets_the_tolerance_on_every_point_and_averages_the_noise() {
    let dense = noisy(&even(20_000), SIGMA, 7);
    let tol = tolerance(&dense);
    let r = fit(&dense);
    assert!(r.met, "max deviation {} > {tol}", r.quality.max_deviation);
    assert!((r.tolerance / tol - 1.0).abs() < 1e-12);
    let proj = CurveProjector::new(&r.curve, 16);
    let worst = dense
        .iter()
        .map(|&q| proj.project(q).distance)
        .fold(0.0, f64::max);
    assert!(worst <= tol * (1.0 + 1e-9), "{worst} > {tol}");
    assert!((worst / r.quality.max_deviation - 1.0).abs() < 1e-6);
    // the noise-free spiral (which the noise hides) within 1.1 tol of the fit
    let truth = (0..=4000)
        .map(|i| proj.project(spiral(i as f64 / 4000.0)).distance)
        .fold(0.0, f64::max);
    assert!(truth <= 1.1 * tol, "{truth} from the noise-free spiral");
    let a = r.curve.n_control_points();
    assert!(a < 40, "{a} control points follow the noise");
}

#[test]
fn ten_times_fewer_points_give_the_count_within_one() {
    let dense = fit(&noisy(&even(20_000), SIGMA, 7));
    let sparse = fit(&noisy(&even(2_000), SIGMA, 11));
    let (a, b) = (
        dense.curve.n_control_points(),
        sparse.curve.n_control_points(),
    );
    assert!(a.abs_diff(b) <= 1, "{a} vs {b} control points");
}

#[test]
fn a_noisy_stretch_tightens_the_fit_there_and_nowhere_else() {
    // 20,000 points of the spiral, noise-free but for 4 % of them (noise tol/5 on each coordinate:
    // its bins' spread is most of the tolerance): every representative is held to its own bin's
    // share of the tolerance, so the count is within one of the noise-free spiral's. (Held to the
    // tightest share everywhere, a quarter of the tolerance, the fit took 13 control points
    // against 11.)
    let ts = even(20_000);
    let clean: Vec<Vec3> = ts.iter().map(|&t| spiral(t)).collect();
    let tol = tolerance(&clean);
    let mut g = Gauss(13);
    let stretch: Vec<Vec3> = ts
        .iter()
        .map(|&t| {
            let s = tol / 5.0 * f64::from(u8::from((0.48..0.52).contains(&t)));
            spiral(t) + Vec3::new(s * g.next(), s * g.next(), 0.0)
        })
        .collect();
    let (a, b) = (fit(&clean), fit(&stretch));
    assert!(a.met && b.met);
    let proj = CurveProjector::new(&b.curve, 16);
    let worst = stretch
        .iter()
        .map(|&q| proj.project(q).distance)
        .fold(0.0, f64::max);
    assert!(worst <= tol * (1.0 + 1e-9), "{worst} > {tol}");
    let (na, nb) = (a.curve.n_control_points(), b.curve.n_control_points());
    assert!(
        nb <= na + 1,
        "{nb} control points with the noisy stretch, {na} without"
    );
}

#[test]
fn scaled_dense_data_give_the_same_knots() {
    let dense = noisy(&even(12_000), SIGMA, 3);
    let scaled: Vec<Vec3> = dense.iter().map(|&p| p * 1000.0).collect();
    let (a, b) = (fit(&dense), fit(&scaled));
    assert_eq!(a.curve.n_control_points(), b.curve.n_control_points());
    assert_eq!(a.curve.knots(), b.curve.knots());
    assert_eq!(a.met, b.met);
}

#[test]
fn a_burst_of_density_gives_the_count_of_even_sampling() {
    // even sampling at 12,000 points, and the same with two stretches 100 times denser
    let base = even(12_000);
    let mut burst = Vec::new();
    for w in base.windows(2) {
        let dense = (0.2..0.3).contains(&w[0]) || (0.6..0.65).contains(&w[0]);
        let k = if dense { 100 } else { 1 };
        for j in 0..k {
            burst.push(w[0] + (w[1] - w[0]) * j as f64 / k as f64);
        }
    }
    burst.push(1.0);
    assert!(burst.len() > 6 * base.len());
    // the fairness too, over three noise draws: one draw's F moves 5-15 % with the draw alone
    // (even sampling, seeds 1-4: 561-646), so the means are compared (measured: 10, 11, 10 control
    // points evenly and 11 with bursts, mean F 656 and 655)
    let (mut fa, mut fb) = (0.0, 0.0);
    for seed in [5, 6, 7] {
        let (a, b) = (
            fit(&noisy(&base, SIGMA, seed)),
            fit(&noisy(&burst, SIGMA, seed)),
        );
        assert!(a.met && b.met);
        let (na, nb) = (a.curve.n_control_points(), b.curve.n_control_points());
        assert!(na.abs_diff(nb) <= 1, "{na} evenly vs {nb} with bursts");
        fa += a.quality.fairness / 3.0;
        fb += b.quality.fairness / 3.0;
    }
    assert!(
        (fb / fa - 1.0).abs() <= 0.1,
        "mean F {fa} evenly vs {fb} with bursts"
    );
}

#[test]
fn gaps_give_the_count_and_fairness_of_even_sampling() {
    // even sampling at 12,000 points, and the same with two stretches of about 16 tol left out
    let base = even(12_000);
    let gaps: Vec<f64> = base
        .iter()
        .copied()
        .filter(|t| !((0.3..0.305).contains(t) || (0.7..0.706).contains(t)))
        .collect();
    assert_eq!(base.len() - gaps.len(), 132);
    let (a, b) = (fit(&noisy(&base, SIGMA, 5)), fit(&noisy(&gaps, SIGMA, 5)));
    assert!(a.met && b.met);
    let (na, nb) = (a.curve.n_control_points(), b.curve.n_control_points());
    assert!(na.abs_diff(nb) <= 1, "{na} evenly vs {nb} with gaps");
    // measured: 11 and 11 control points, F 639 and 583 (the gaps leave the fit freer there)
    let (fa, fb) = (a.quality.fairness, b.quality.fairness);
    assert!(
        (fb / fa - 1.0).abs() <= 0.15,
        "F {fa} evenly vs {fb} with gaps"
    );
    // the noise-free spiral across the gaps within 1.1 tol of the fit
    let tol = tolerance(&noisy(&gaps, SIGMA, 5));
    let proj = CurveProjector::new(&b.curve, 16);
    let truth = (0..=4000)
        .map(|i| proj.project(spiral(i as f64 / 4000.0)).distance)
        .fold(0.0, f64::max);
    assert!(
        truth <= 1.1 * tol,
        "{} tol from the noise-free spiral",
        truth / tol
    );
}

#[test]
fn a_tolerance_below_the_noise_is_fitted_to_the_meaningful_tolerance_and_stays_on_the_shape() {
    // σ = tol/3 at 10^4 points: the noise alone puts points 4.3 σ ≈ 1.4 tol off the spiral
    let n = 10_000;
    let tol = tolerance(&noisy(&even(n), 0.0, 1));
    let sigma = tol / 3.0;
    let pts = noisy(&even(n), sigma, 13);
    let asked = tolerance(&pts);
    let r = fit(&pts);
    let s = &r.screening;
    assert!(
        (s.noise_sigma / sigma - 1.0).abs() < 0.25,
        "σ {}",
        s.noise_sigma / sigma
    );
    // 10^4 planar points: the floor of 5 σ (the 1 % level of the largest deviation is 4.9 σ)
    let t = s.noise_limited.expect("noise limited");
    assert!(
        (t / s.noise_sigma - 5.0).abs() < 1e-12,
        "{}",
        t / s.noise_sigma
    );
    assert!((s.tolerance / asked - 1.0).abs() < 1e-12);
    assert!(r.met && r.tolerance == t, "{} vs {t}", r.tolerance);
    let proj = CurveProjector::new(&r.curve, 16);
    let worst = pts
        .iter()
        .map(|&q| proj.project(q).distance)
        .fold(0.0, f64::max);
    assert!(
        worst <= t * (1.0 + 1e-9) && worst > asked,
        "{worst}: {t}, {asked}"
    );
    // it averages the noise: closer to the noise-free spiral than the asked tolerance, with no
    // more than twice the count of a fit at a tenth of the noise (measured: 17 and 11; the bins'
    // spread of about 4 σ leaves the representatives 0.4 tol)
    let truth = (0..=4000)
        .map(|i| proj.project(spiral(i as f64 / 4000.0)).distance)
        .fold(0.0, f64::max);
    assert!(
        truth <= asked,
        "{} tol from the noise-free spiral",
        truth / asked
    );
    let calm = fit(&noisy(&even(n), sigma / 10.0, 13));
    let (a, b) = (r.curve.n_control_points(), calm.curve.n_control_points());
    assert!(a <= 2 * b, "{a} control points at σ = tol/3, {b} at tol/30");
}

/// The airfoil table `examples/data/fx77w343.csv` densified to `n` points evenly in chord length
/// along its Catmull–Rom spline, each moved along the spline's normal by Gaussian noise of
/// `sigma_tol` tolerances (the tolerance: relative 1e-3 of the table's bounding box).
fn noisy_airfoil(n: usize, sigma_tol: f64, seed: u64) -> Vec<Vec3> {
    use crate::common::example_data::read_csv;
    use crate::common::xorshift::Xorshift;
    let t = read_csv("fx77w343.csv");
    let sigma = sigma_tol * tolerance(&t);
    let m = t.len();
    let at = |i: isize| t[i.clamp(0, m as isize - 1) as usize];
    // the spline on segment i at u in [0, 1] and its derivative
    let seg = |i: usize, u: f64| {
        let i = i as isize;
        let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
        let (u2, u3) = (u * u, u * u * u);
        let p = (p1 * 2.0
            + (p2 - p0) * u
            + (p0 * 2.0 - p1 * 5.0 + p2 * 4.0 - p3) * u2
            + (p1 * 3.0 - p0 - p2 * 3.0 + p3) * u3)
            * 0.5;
        let d = ((p2 - p0)
            + (p0 * 2.0 - p1 * 5.0 + p2 * 4.0 - p3) * (2.0 * u)
            + (p1 * 3.0 - p0 - p2 * 3.0 + p3) * (3.0 * u2))
            * 0.5;
        (p, d)
    };
    let mut cum = vec![0.0];
    for w in t.windows(2) {
        cum.push(cum[cum.len() - 1] + (w[1] - w[0]).norm());
    }
    let total = cum[m - 1];
    let mut g = Xorshift(seed);
    let mut i = 0;
    (0..n)
        .map(|k| {
            let s = total * k as f64 / (n - 1) as f64;
            while i + 2 < m && cum[i + 1] < s {
                i += 1;
            }
            let u = ((s - cum[i]) / (cum[i + 1] - cum[i])).clamp(0.0, 1.0);
            let (p, d) = seg(i, u);
            let normal = Vec3::new(-d[1], d[0], 0.0) / d.norm();
            p + normal * (sigma * g.normal())
        })
        .collect()
}

#[test]
fn a_noisy_airfoil_at_ten_times_the_density_keeps_its_count() {
    // 10^4 and 10^5 points of one airfoil with noise tol/10: the first reduced fits miss the
    // tolerance between representatives by a few per cent; a repair that only searched the count
    // anew would draw another count at each density (16 and 20 here), one that can keep the first
    // fit's count keeps it
    let fits: Vec<IntegratedResult> = [10_000, 100_000]
        .into_iter()
        .map(|n| {
            let pts = noisy_airfoil(n, 0.1, 1);
            let r = fit(&pts);
            assert!(
                r.met,
                "{n} points: max deviation {}",
                r.quality.max_deviation
            );
            let proj = CurveProjector::new(&r.curve, 16);
            let tol = r.tolerance;
            let worst = pts
                .iter()
                .step_by(n / 10_000)
                .map(|&q| proj.project(q).distance)
                .fold(0.0, f64::max);
            assert!(worst <= tol * (1.0 + 1e-9), "{n} points: {worst} > {tol}");
            r
        })
        .collect();
    let (a, b) = (
        fits[0].curve.n_control_points(),
        fits[1].curve.n_control_points(),
    );
    assert!(a.abs_diff(b) <= 1, "{a} vs {b} control points");
}
