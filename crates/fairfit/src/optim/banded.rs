//! A small banded Cholesky solver for the symmetric positive definite normal equations of the knot
//! search's inner least-squares solve (bandwidth = degree).
//!
//! Written here rather than taken from a crate because the hot loop needs an allocation-free solve on
//! reused buffers with three right-hand sides; dense crates (faer) would factor the full matrix.
//! It is a private stand-in for the least-squares module's solver, kept small on purpose.

/// Lower band storage of an `n × n` symmetric matrix with half bandwidth `b`:
/// `band[i * (b + 1) + d] = A[i][i - d]` for `d = 0..=b`.
#[derive(Clone, Debug, Default)]
pub(crate) struct BandedSpd {
    pub n: usize,
    pub b: usize,
    pub band: Vec<f64>,
}

impl BandedSpd {
    /// Resizes to `n × n` with half bandwidth `b` and zeroes the entries (no allocation when it fits).
    pub fn reset(&mut self, n: usize, b: usize) {
        self.n = n;
        self.b = b;
        self.band.clear();
        self.band.resize(n * (b + 1), 0.0);
    }

    /// Adds `v` to `A[i][j]` for `j <= i`, `i - j <= b`.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(j <= i && i - j <= self.b);
        self.band[i * (self.b + 1) + (i - j)] += v;
    }

    /// The diagonal entry `A[i][i]`.
    #[inline]
    pub fn diag(&self, i: usize) -> f64 {
        self.band[i * (self.b + 1)]
    }

    /// In-place Cholesky `A = L Lᵀ`; false if a pivot is not positive (relative to `pivot_floor`).
    pub fn factor(&mut self, pivot_floor: f64) -> bool {
        let (n, b) = (self.n, self.b);
        let w = b + 1;
        for i in 0..n {
            let j0 = i.saturating_sub(b);
            for j in j0..=i {
                let mut s = self.band[i * w + (i - j)];
                let k0 = j0.max(j.saturating_sub(b));
                for k in k0..j {
                    s -= self.band[i * w + (i - k)] * self.band[j * w + (j - k)];
                }
                if j == i {
                    if s.is_nan() || s <= pivot_floor {
                        return false;
                    }
                    self.band[i * w] = s.sqrt();
                } else {
                    self.band[i * w + (i - j)] = s / self.band[j * w];
                }
            }
        }
        true
    }

    /// Solves `L Lᵀ x = rhs` in place for three right-hand sides stored as `[f64; 3]` rows.
    pub fn solve3(&self, rhs: &mut [[f64; 3]]) {
        let (n, b) = (self.n, self.b);
        let w = b + 1;
        for i in 0..n {
            let mut s = rhs[i];
            for k in i.saturating_sub(b)..i {
                let l = self.band[i * w + (i - k)];
                for c in 0..3 {
                    s[c] -= l * rhs[k][c];
                }
            }
            let d = self.band[i * w];
            rhs[i] = [s[0] / d, s[1] / d, s[2] / d];
        }
        for i in (0..n).rev() {
            let mut s = rhs[i];
            for k in i + 1..(i + b + 1).min(n) {
                let l = self.band[k * w + (k - i)];
                for c in 0..3 {
                    s[c] -= l * rhs[k][c];
                }
            }
            let d = self.band[i * w];
            rhs[i] = [s[0] / d, s[1] / d, s[2] / d];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_pentadiagonal_system_exactly() {
        // A = tridiagonal-squared style SPD matrix with half bandwidth 2; x known
        let n = 7;
        let mut dense = vec![vec![0.0; n]; n];
        for i in 0..n {
            dense[i][i] = 6.0 + i as f64;
            if i >= 1 {
                dense[i][i - 1] = -2.0;
                dense[i - 1][i] = -2.0;
            }
            if i >= 2 {
                dense[i][i - 2] = 0.5;
                dense[i - 2][i] = 0.5;
            }
        }
        let x: Vec<[f64; 3]> = (0..n)
            .map(|i| [i as f64, 1.0 - i as f64 * 0.3, (i * i) as f64])
            .collect();
        let mut rhs: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let mut s = [0.0; 3];
                for j in 0..n {
                    for c in 0..3 {
                        s[c] += dense[i][j] * x[j][c];
                    }
                }
                s
            })
            .collect();
        let mut a = BandedSpd::default();
        a.reset(n, 2);
        for i in 0..n {
            for j in i.saturating_sub(2)..=i {
                a.add(i, j, dense[i][j]);
            }
        }
        assert!(a.factor(0.0));
        a.solve3(&mut rhs);
        for i in 0..n {
            for c in 0..3 {
                assert!((rhs[i][c] - x[i][c]).abs() < 1e-12);
            }
        }
        // an indefinite matrix is refused
        a.reset(2, 1);
        a.add(0, 0, 1.0);
        a.add(1, 0, 2.0);
        a.add(1, 1, 1.0);
        assert!(!a.factor(0.0));
    }
}
