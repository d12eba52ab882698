//! Quadrature rules on `[-1, 1]` for integrals over knot spans: Gauss–Legendre of any order (nodes by
//! Newton's method on the Legendre three-term recurrence, the classic `gauleg` algorithm) and the
//! Gauss–Kronrod 7/15 pair of QUADPACK (`qk15`), whose difference `|K15 − G7|` is an error estimate for
//! adaptive bisection.
//!
//! Written here because the rules are a few lines and fairfit only needs these two; every node lies
//! strictly inside the interval, so integrands with jumps at the ends (C''' at knots) are never evaluated
//! on the jump.

/// A Gauss–Legendre rule: `∫_{-1}^{1} f ≈ Σ w_i f(x_i)`, exact for polynomials of degree `2n − 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// The `n`-point rule (`n >= 1`; `0` is treated as `1`). Nodes ascend.
    ///
    /// ```
    /// use fairfit::diffgeo::quadrature::GaussLegendre;
    /// let g = GaussLegendre::new(8);
    /// // ∫_0^2 x^15 dx = 2^16 / 16, exact for the 8-point rule
    /// let v = g.integrate(0.0, 2.0, |x| x.powi(15));
    /// assert!((v - 4096.0).abs() < 1e-9);
    /// ```
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let m = n.div_ceil(2);
        for i in 0..m {
            // Tricomi's initial guess for the i-th largest root
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre_and_derivative(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() <= 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre_and_derivative(n, x);
            if d.is_finite() {
                dp = d;
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        GaussLegendre { nodes, weights }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Always false (a rule has at least one node).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Nodes on `[-1, 1]`, ascending.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// Weights (sum 2).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// `∫_a^b f` by this rule.
    pub fn integrate(&self, a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a));
        let mut s = 0.0;
        for (x, w) in self.nodes.iter().zip(&self.weights) {
            s += w * f(c + h * x);
        }
        s * h
    }
}

/// `(P_n(x), P_n'(x))` by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

/// Kronrod nodes of the 15-point rule on `[0, 1)` (the negatives complete them; QUADPACK `qk15`).
/// Odd indices `1, 3, 5` and the centre `7` are the 7-point Gauss nodes.
#[allow(clippy::excessive_precision)] // the published QUADPACK digits
pub const GK15_NODES: [f64; 8] = [
    0.991_455_371_120_812_639_206_854_697_526_329,
    0.949_107_912_342_758_524_526_189_684_047_851,
    0.864_864_423_359_769_072_789_712_788_640_926,
    0.741_531_185_599_394_439_863_864_773_280_788,
    0.586_087_235_467_691_130_294_144_845_693_013,
    0.405_845_151_377_397_166_906_606_412_076_961,
    0.207_784_955_007_898_467_600_689_403_773_245,
    0.0,
];

/// Kronrod weights matching [`GK15_NODES`].
#[allow(clippy::excessive_precision)] // the published QUADPACK digits
pub(crate) const GK15_WEIGHTS: [f64; 8] = [
    0.022_935_322_010_529_224_963_732_008_058_970,
    0.063_092_092_629_978_553_290_700_663_189_204,
    0.104_790_010_322_250_183_839_876_322_541_518,
    0.140_653_259_715_525_918_745_189_590_510_238,
    0.169_004_726_639_267_902_826_583_426_598_550,
    0.190_350_578_064_785_409_913_256_402_421_014,
    0.204_432_940_075_298_892_414_161_999_234_649,
    0.209_482_141_084_727_828_012_999_174_891_714,
];

/// 7-point Gauss weights for the Gauss nodes `GK15_NODES[1], [3], [5], [7]`.
#[allow(clippy::excessive_precision)] // the published QUADPACK digits
pub(crate) const G7_WEIGHTS: [f64; 4] = [
    0.129_484_966_168_869_693_270_611_432_679_082,
    0.279_705_391_489_276_667_901_467_771_423_780,
    0.381_830_050_505_118_944_950_369_775_488_975,
    0.417_959_183_673_469_387_755_102_040_816_327,
];

/// The 15 Kronrod nodes on `[-1, 1]` in ascending order with their Kronrod weights and Gauss weights
/// (0 for the pure Kronrod nodes).
pub(crate) fn gauss_kronrod_15() -> [(f64, f64, f64); 15] {
    let mut out = [(0.0, 0.0, 0.0); 15];
    for i in 0..8 {
        let g = if i % 2 == 1 { G7_WEIGHTS[i / 2] } else { 0.0 };
        out[i] = (-GK15_NODES[i], GK15_WEIGHTS[i], g);
        out[14 - i] = (GK15_NODES[i], GK15_WEIGHTS[i], g);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in 1..=16 {
            let g = GaussLegendre::new(n);
            assert!((g.weights().iter().sum::<f64>() - 2.0).abs() < 1e-14);
            for k in 0..2 * n {
                let exact = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k as f64 + 1.0)
                };
                let v = g.integrate(-1.0, 1.0, |x| x.powi(k as i32));
                assert!((v - exact).abs() < 1e-14, "n={n} k={k}: {v} vs {exact}");
            }
            // and not exact one degree higher (the rule really has n points)
            if n <= 6 {
                let k = 2 * n;
                let v = g.integrate(-1.0, 1.0, |x| x.powi(k as i32));
                assert!((v - 2.0 / (k as f64 + 1.0)).abs() > 1e-9, "n={n}");
            }
        }
    }

    #[test]
    fn gauss_legendre_known_nodes() {
        // 2-point: ±1/√3; 3-point: 0, ±√(3/5) with weights 8/9, 5/9
        let g2 = GaussLegendre::new(2);
        assert!((g2.nodes()[1] - 1.0 / 3f64.sqrt()).abs() < 1e-15);
        let g3 = GaussLegendre::new(3);
        assert!((g3.nodes()[2] - 0.6f64.sqrt()).abs() < 1e-15);
        assert!((g3.weights()[1] - 8.0 / 9.0).abs() < 1e-15);
        assert!((g3.weights()[0] - 5.0 / 9.0).abs() < 1e-15);
        // smooth non-polynomial: ∫_0^π sin = 2
        let g = GaussLegendre::new(12);
        assert!((g.integrate(0.0, std::f64::consts::PI, f64::sin) - 2.0).abs() < 1e-14);
    }

    #[test]
    fn kronrod_15_exact_to_degree_22_and_gauss_7_to_13() {
        let rule = gauss_kronrod_15();
        for k in 0..=23 {
            let exact = if k % 2 == 1 {
                0.0
            } else {
                2.0 / (k as f64 + 1.0)
            };
            let kr: f64 = rule.iter().map(|(x, w, _)| w * x.powi(k)).sum();
            let ga: f64 = rule.iter().map(|(x, _, w)| w * x.powi(k)).sum();
            if k <= 22 {
                assert!((kr - exact).abs() < 1e-15, "K15 degree {k}");
            }
            if k <= 13 {
                assert!((ga - exact).abs() < 1e-15, "G7 degree {k}");
            } else if k % 2 == 0 {
                assert!((ga - exact).abs() > 1e-9, "G7 not exact at degree {k}");
            }
        }
        // the Gauss nodes are those of the 7-point Gauss–Legendre rule
        let g7 = GaussLegendre::new(7);
        for i in 0..4 {
            assert!((g7.nodes()[6 - i] - GK15_NODES[2 * i + 1]).abs() < 1e-15);
            assert!((g7.weights()[6 - i] - G7_WEIGHTS[i]).abs() < 1e-15);
        }
    }
}
