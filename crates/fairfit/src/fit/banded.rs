//! Cholesky factorisation of symmetric positive-definite matrices stored by rows of their lower
//! triangle from a per-row first column (an *envelope* or profile). A band of half-width `p` is the
//! common case (open least-squares fits: row `i` starts at `i − p`); a periodic fit adds full bottom rows
//! (its wrapped columns), which the envelope keeps without fill-in outside it.
//!
//! Hand-written because faer has no banded or envelope solver: a dense solve would cost O(n³), this one
//! O(n p²) for a band, with storage reused between calls so repeated solves of the same size allocate
//! nothing (the least-squares solve is the knot optimiser's inner loop).

use crate::errors::{Error, Result};
use crate::nurbs::Vec3;

/// Pivots below this fraction of the largest diagonal entry count as singular.
const PIVOT_EPS: f64 = 1e-14;

/// An SPD matrix in envelope storage, factorised in place into `L` with `A = L Lᵀ`.
#[derive(Clone, Debug, Default)]
pub struct EnvelopeCholesky {
    n: usize,
    first: Vec<usize>,
    offset: Vec<usize>,
    data: Vec<f64>,
    max_diag: f64,
}

impl EnvelopeCholesky {
    /// An empty matrix; call [`EnvelopeCholesky::reset_band`] or [`EnvelopeCholesky::reset_envelope`].
    pub fn new() -> Self {
        Self::default()
    }

    /// Size `n`.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Zeroes the matrix and shapes it as a band of half-width `bw` (row `i` starts at `i − bw`).
    pub fn reset_band(&mut self, n: usize, bw: usize) {
        self.first.clear();
        self.first.extend((0..n).map(|i| i.saturating_sub(bw)));
        self.finish_shape(n);
    }

    /// Zeroes the matrix and shapes it with row `i` starting at column `first[i] <= i`.
    pub fn reset_envelope(&mut self, first: &[usize]) {
        self.first.clear();
        self.first
            .extend(first.iter().enumerate().map(|(i, &f)| f.min(i)));
        self.finish_shape(first.len());
    }

    /// Mutable access to the row starts before [`EnvelopeCholesky::reshape`]: lets callers build an
    /// envelope without a separate buffer.
    pub fn first_mut(&mut self, n: usize) -> &mut Vec<usize> {
        self.first.clear();
        self.first.extend(0..n);
        &mut self.first
    }

    /// Zeroes the matrix with the row starts set through [`EnvelopeCholesky::first_mut`].
    pub fn reshape(&mut self) {
        let n = self.first.len();
        for i in 0..n {
            self.first[i] = self.first[i].min(i);
        }
        self.finish_shape(n);
    }

    fn finish_shape(&mut self, n: usize) {
        self.n = n;
        self.offset.clear();
        let mut off = 0;
        for i in 0..n {
            self.offset.push(off);
            off += i - self.first[i] + 1;
        }
        self.data.clear();
        self.data.resize(off, 0.0);
        self.max_diag = 0.0;
    }

    /// First stored column of row `i`.
    #[inline]
    pub fn first(&self, i: usize) -> usize {
        self.first[i]
    }

    /// Adds `v` to entry `(i, j)`, `j <= i`, which must lie inside the envelope.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            j <= i && j >= self.first[i],
            "({i},{j}) outside the envelope"
        );
        self.data[self.offset[i] + j - self.first[i]] += v;
    }

    /// Mutable entry `(i, j)`, `j <= i`, which must lie inside the envelope.
    #[inline]
    pub fn entry_mut(&mut self, i: usize, j: usize) -> &mut f64 {
        debug_assert!(
            j <= i && j >= self.first[i],
            "({i},{j}) outside the envelope"
        );
        &mut self.data[self.offset[i] + j - self.first[i]]
    }

    /// Entry `(i, j)` with `j <= i` (0 outside the envelope).
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if j < self.first[i] || j > i {
            0.0
        } else {
            self.data[self.offset[i] + j - self.first[i]]
        }
    }

    /// Factorises in place. Fails when the matrix is not (numerically) positive definite.
    pub fn factor(&mut self) -> Result<()> {
        let n = self.n;
        self.max_diag = (0..n).map(|i| self.get(i, i).abs()).fold(0.0, f64::max);
        let floor = PIVOT_EPS * self.max_diag;
        for i in 0..n {
            let fi = self.first[i];
            let oi = self.offset[i];
            for j in fi..=i {
                let fj = self.first[j];
                let oj = self.offset[j];
                let k0 = fi.max(fj);
                let mut s = self.data[oi + j - fi];
                for k in k0..j {
                    s -= self.data[oi + k - fi] * self.data[oj + k - fj];
                }
                if j == i {
                    if s.is_nan() || s <= floor {
                        return Err(Error::Fit(format!(
                            "singular least-squares system (pivot {i} of {n}): some knot span holds too \
                             few data points"
                        )));
                    }
                    self.data[oi + i - fi] = s.sqrt();
                } else {
                    self.data[oi + j - fi] = s / self.data[oj + j - fj];
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place after [`EnvelopeCholesky::factor`], for three right-hand sides at once.
    pub fn solve_vec3(&self, b: &mut [Vec3]) {
        let n = self.n;
        // L y = b
        for i in 0..n {
            let fi = self.first[i];
            let oi = self.offset[i];
            let mut s = b[i];
            for (bk, l) in b[fi..i].iter().zip(&self.data[oi..oi + i - fi]) {
                s -= *bk * *l;
            }
            b[i] = s / self.data[oi + i - fi];
        }
        // Lᵀ x = y: column sweep
        for i in (0..n).rev() {
            let fi = self.first[i];
            let oi = self.offset[i];
            b[i] = b[i] / self.data[oi + i - fi];
            let bi = b[i];
            for (bk, l) in b[fi..i].iter_mut().zip(&self.data[oi..oi + i - fi]) {
                *bk -= bi * *l;
            }
        }
    }
}

/// The name the fitting code uses: a band is the common envelope.
pub type BandedCholesky = EnvelopeCholesky;

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense reference: A from the envelope, multiply back.
    fn check(first: &[usize], seed: u64) {
        let n = first.len();
        // random-ish SPD in the envelope: diagonally dominant
        let mut m = EnvelopeCholesky::new();
        m.reset_envelope(first);
        let mut dense = vec![0.0; n * n];
        let mut s = seed;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for i in 0..n {
            for j in m.first(i)..i {
                let v = rnd();
                m.add(i, j, v);
                dense[i * n + j] = v;
                dense[j * n + i] = v;
            }
        }
        for i in 0..n {
            let row: f64 = (0..n)
                .filter(|&j| j != i)
                .map(|j| dense[i * n + j].abs())
                .sum();
            m.add(i, i, row + 1.0);
            dense[i * n + i] = row + 1.0;
        }
        let x: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(i as f64, 1.0 - i as f64 * 0.5, (i * i) as f64 * 0.1))
            .collect();
        let mut b: Vec<Vec3> = (0..n)
            .map(|i| (0..n).fold(Vec3::ZERO, |acc, j| acc + x[j] * dense[i * n + j]))
            .collect();
        m.factor().unwrap();
        m.solve_vec3(&mut b);
        for (a, e) in b.iter().zip(&x) {
            assert!(
                (*a - *e).norm() < 1e-10 * (1.0 + e.norm()),
                "{a:?} vs {e:?}"
            );
        }
    }

    #[test]
    fn band_solve_matches_dense_product() {
        let first: Vec<usize> = (0..30).map(|i: usize| i.saturating_sub(3)).collect();
        check(&first, 1);
    }

    #[test]
    fn periodic_envelope_solve_matches_dense_product() {
        // cyclic band of half-width 3: the last 3 rows reach column 0
        let n = 25;
        let first: Vec<usize> = (0..n)
            .map(|i: usize| if i + 3 >= n { 0 } else { i.saturating_sub(3) })
            .collect();
        check(&first, 7);
    }

    #[test]
    fn singular_matrix_is_an_error() {
        let mut m = EnvelopeCholesky::new();
        m.reset_band(3, 1);
        m.add(0, 0, 1.0);
        m.add(1, 0, 1.0);
        m.add(1, 1, 1.0);
        m.add(2, 2, 1.0);
        assert!(m.factor().is_err());
    }
}
