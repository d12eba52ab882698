//! Small dense linear solvers for the surface module: Cholesky for the (small, symmetric positive definite)
//! normal equations of section fitting and LU with partial pivoting for the skinning interpolation systems.
//!
//! The systems are at most about a hundred unknowns (control points of one section, or one control
//! column) in a dense matrix. The Cholesky factor comes from the fitting side's envelope solver
//! ([`crate::fit::banded::EnvelopeCholesky`]) on the matrix's own envelope; LU is a plain dense
//! factorisation with explicit pivot checks (the skinning systems are small and solved once).

#![allow(clippy::needless_range_loop)]

use crate::errors::{Error, Result};
use crate::fit::banded::EnvelopeCholesky;

/// A dense row-major square matrix.
#[derive(Clone, Debug)]
pub(crate) struct Dense {
    pub n: usize,
    pub a: Vec<f64>,
    /// After [`cholesky`]: per row, the first column of its envelope (the factor is zero left of it).
    first: Vec<usize>,
}

impl Dense {
    pub fn zeros(n: usize) -> Self {
        Dense {
            n,
            a: vec![0.0; n * n],
            first: Vec::new(),
        }
    }
    #[inline]
    pub fn at(&mut self, i: usize, j: usize) -> &mut f64 {
        &mut self.a[i * self.n + j]
    }
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.n + j]
    }
}

/// Cholesky factorisation in place (lower triangle); fails when the matrix is not positive definite.
///
/// The factor is [`EnvelopeCholesky`]'s (the fitting side's envelope solver): the factor of a symmetric
/// matrix keeps the envelope of its lower triangle (row `i` is zero left of its first nonzero), so only
/// products inside the envelopes are formed. The normal matrices of the section fits are banded (open
/// fits) or banded with `p` full rows at the end (periodic fits): `O(n p²)` instead of `O(n³)`. The
/// skipped terms are exact zeros, so the result is the dense factorisation's, bit for bit.
pub(crate) fn cholesky(m: &mut Dense) -> Result<()> {
    let n = m.n;
    let first: Vec<usize> = (0..n)
        .map(|i| (0..i).find(|&j| m.get(i, j) != 0.0).unwrap_or(i))
        .collect();
    let mut env = EnvelopeCholesky::new();
    env.reset_envelope(&first);
    for i in 0..n {
        for j in first[i]..=i {
            *env.entry_mut(i, j) = m.get(i, j);
        }
    }
    env.factor()?;
    for i in 0..n {
        for j in first[i]..=i {
            *m.at(i, j) = env.get(i, j);
        }
    }
    m.first = first;
    Ok(())
}

/// Solves `L Lᵀ x = b` for several right-hand sides stored as `b[i][c]` (in place), `l` from
/// [`cholesky`].
pub(crate) fn cholesky_solve<const C: usize>(l: &Dense, b: &mut [[f64; C]]) {
    let n = l.n;
    let first = |i: usize| l.first.get(i).copied().unwrap_or(0);
    for i in 0..n {
        for k in first(i)..i {
            let lik = l.get(i, k);
            for c in 0..C {
                b[i][c] -= lik * b[k][c];
            }
        }
        let d = l.get(i, i);
        for v in b[i].iter_mut() {
            *v /= d;
        }
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            if first(k) > i {
                continue;
            }
            let lki = l.get(k, i);
            for c in 0..C {
                b[i][c] -= lki * b[k][c];
            }
        }
        let d = l.get(i, i);
        for v in b[i].iter_mut() {
            *v /= d;
        }
    }
}

/// Imposes one equality constraint `aᵀx = c` (per coordinate) on the solution `x` of the normal
/// equations `H x = b`, `l` the Cholesky factor of `H` from [`cholesky`]: the minimiser of the same
/// quadratic under the constraint is `x + H⁻¹a (c − aᵀx) / (aᵀH⁻¹a)` (the Schur complement of the
/// one-row KKT system), one more solve. Leaves `x` unchanged when `aᵀH⁻¹a` is not positive (`a` zero:
/// the constraint does not involve the unknowns).
pub(crate) fn constrain_solution<const C: usize>(
    l: &Dense,
    x: &mut [[f64; C]],
    a: &[f64],
    c: [f64; C],
) {
    let mut z: Vec<[f64; 1]> = a.iter().map(|&v| [v]).collect();
    cholesky_solve(l, &mut z);
    let s: f64 = a.iter().zip(&z).map(|(ai, zi)| ai * zi[0]).sum();
    if !(s > 0.0 && s.is_finite()) {
        return;
    }
    for k in 0..C {
        let ax: f64 = a.iter().zip(x.iter()).map(|(ai, xi)| ai * xi[k]).sum();
        let lambda = (c[k] - ax) / s;
        for (xi, zi) in x.iter_mut().zip(&z) {
            xi[k] += lambda * zi[0];
        }
    }
}

/// Solves `A x = b` (several right-hand sides) by LU with partial pivoting; `A` is overwritten.
pub(crate) fn lu_solve<const C: usize>(m: &mut Dense, b: &mut [[f64; C]]) -> Result<()> {
    let n = m.n;
    let scale = m.a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    for k in 0..n {
        let (piv, pmax) = (k..n)
            .map(|i| (i, m.get(i, k).abs()))
            .fold((k, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
        if pmax.is_nan() || pmax <= 1e-14 * scale {
            return Err(Error::Fit(format!(
                "interpolation system is singular at pivot {k} of {n}"
            )));
        }
        if piv != k {
            for j in 0..n {
                m.a.swap(k * n + j, piv * n + j);
            }
            b.swap(k, piv);
        }
        let d = m.get(k, k);
        for i in k + 1..n {
            let f = m.get(i, k) / d;
            if f == 0.0 {
                continue;
            }
            for j in k..n {
                let v = m.get(k, j);
                *m.at(i, j) -= f * v;
            }
            let bk = b[k];
            for c in 0..C {
                b[i][c] -= f * bk[c];
            }
        }
    }
    for i in (0..n).rev() {
        for j in i + 1..n {
            let mij = m.get(i, j);
            let bj = b[j];
            for c in 0..C {
                b[i][c] -= mij * bj[c];
            }
        }
        let d = m.get(i, i);
        for v in b[i].iter_mut() {
            *v /= d;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constrained minimiser of `½ xᵀHx − bᵀx` under `aᵀx = c` meets the constraint and its
    /// gradient `Hx − b` is a multiple of `a` (the KKT conditions).
    #[test]
    fn constrained_solution_meets_the_kkt_conditions() {
        let n = 6;
        let mut h = Dense::zeros(n);
        for i in 0..n {
            for j in 0..n {
                *h.at(i, j) = if i == j {
                    4.0
                } else {
                    1.0 / (1.0 + (i + j) as f64)
                };
            }
        }
        let b: Vec<[f64; 2]> = (0..n).map(|i| [(i as f64).cos(), 1.0 - i as f64]).collect();
        let a: Vec<f64> = (0..n).map(|i| [0.0, 0.3, 0.5, 0.2, 0.0, 0.0][i]).collect();
        let c = [0.7, -2.0];
        let mut l = h.clone();
        cholesky(&mut l).unwrap();
        let mut x = b.clone();
        cholesky_solve(&l, &mut x);
        constrain_solution(&l, &mut x, &a, c);
        let aa: f64 = a.iter().map(|v| v * v).sum();
        for k in 0..2 {
            let ax: f64 = a.iter().zip(&x).map(|(ai, xi)| ai * xi[k]).sum();
            assert!((ax - c[k]).abs() < 1e-14, "{ax} vs {}", c[k]);
            let g: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| h.get(i, j) * x[j][k]).sum::<f64>() - b[i][k])
                .collect();
            let mu = g.iter().zip(&a).map(|(gi, ai)| gi * ai).sum::<f64>() / aa;
            for (gi, ai) in g.iter().zip(&a) {
                assert!((gi - mu * ai).abs() < 1e-13, "{gi} vs {}", mu * ai);
            }
        }
    }

    #[test]
    fn solvers_reproduce_a_known_solution() {
        // SPD matrix A = B Bᵀ + I with known x
        let n = 5;
        let mut a = Dense::zeros(n);
        for i in 0..n {
            for j in 0..n {
                let mut s = if i == j { 1.0 } else { 0.0 };
                for k in 0..n {
                    s += ((i + 2 * k) as f64).sin() * ((j + 2 * k) as f64).sin();
                }
                *a.at(i, j) = s;
            }
        }
        let x: Vec<[f64; 2]> = (0..n).map(|i| [i as f64 - 1.5, (i * i) as f64]).collect();
        let mut b = vec![[0.0; 2]; n];
        for i in 0..n {
            for j in 0..n {
                for c in 0..2 {
                    b[i][c] += a.get(i, j) * x[j][c];
                }
            }
        }
        let mut l = a.clone();
        cholesky(&mut l).unwrap();
        let mut b1 = b.clone();
        cholesky_solve(&l, &mut b1);
        let mut a2 = a.clone();
        let mut b2 = b.clone();
        lu_solve(&mut a2, &mut b2).unwrap();
        for i in 0..n {
            for c in 0..2 {
                assert!((b1[i][c] - x[i][c]).abs() < 1e-10);
                assert!((b2[i][c] - x[i][c]).abs() < 1e-10);
            }
        }
        let mut sing = Dense::zeros(2);
        assert!(lu_solve(&mut sing, &mut [[1.0], [1.0]]).is_err());
        assert!(cholesky(&mut Dense::zeros(2)).is_err());
    }

    /// The textbook dense Cholesky (all products, zeros included), for comparison.
    fn dense_cholesky(m: &mut Dense) {
        let n = m.n;
        for j in 0..n {
            let mut d = m.get(j, j);
            for k in 0..j {
                d -= m.get(j, k) * m.get(j, k);
            }
            let d = d.sqrt();
            *m.at(j, j) = d;
            for i in j + 1..n {
                let mut s = m.get(i, j);
                for k in 0..j {
                    s -= m.get(i, k) * m.get(j, k);
                }
                *m.at(i, j) = s / d;
            }
        }
    }

    #[test]
    fn envelope_cholesky_equals_the_dense_one_on_a_periodic_band() {
        // a periodic cubic's normal-matrix pattern: band of half-width 3 plus wrapped corners
        let (n, p) = (17, 3);
        let mut a = Dense::zeros(n);
        for i in 0..n {
            for d in 0..=p {
                let j = (i + d) % n;
                let v = if d == 0 {
                    4.0 + (i as f64).sin()
                } else {
                    0.3 / d as f64 + 0.05 * ((i * j) as f64).cos()
                };
                *a.at(i, j) = v;
                *a.at(j, i) = v;
            }
        }
        let (mut env, mut dense) = (a.clone(), a.clone());
        cholesky(&mut env).unwrap();
        dense_cholesky(&mut dense);
        for i in 0..n {
            for j in 0..=i {
                assert_eq!(
                    env.get(i, j).to_bits(),
                    dense.get(i, j).to_bits(),
                    "L[{i}][{j}]"
                );
            }
        }
        // the band rows only touch 3 columns left of the diagonal; the last p rows are full
        assert_eq!(env.first[8], 5);
        assert_eq!(env.first[n - 1], 0);
        // and the solve reproduces a known solution
        let x: Vec<[f64; 1]> = (0..n).map(|i| [1.0 + i as f64 * 0.25]).collect();
        let mut b = vec![[0.0; 1]; n];
        for i in 0..n {
            for j in 0..n {
                b[i][0] += a.get(i, j) * x[j][0];
            }
        }
        cholesky_solve(&env, &mut b);
        for i in 0..n {
            assert!(
                (b[i][0] - x[i][0]).abs() < 1e-12,
                "{} vs {}",
                b[i][0],
                x[i][0]
            );
        }
    }
}
