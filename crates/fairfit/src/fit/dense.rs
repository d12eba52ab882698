//! Small dense symmetric positive definite solves: Cholesky factorisation in place with a rank test,
//! and the triangular solves. For the few-hundred-unknown systems of the point constraints
//! ([`super::point_constraints`]): their Gram and normal matrices are dense in the constraints, so
//! the banded solver of [`super::banded`] does not apply.
//!
//! Invariant: a factorisation that meets a pivot below `RANK_EPS` times the largest diagonal entry
//! fails (`false`): the matrix is singular to working precision, and the caller says which
//! constraint made it so.

/// Pivots below this fraction of the largest diagonal entry mean a rank-deficient matrix.
pub const RANK_EPS: f64 = 1e-12;

/// Factors the symmetric positive definite `n × n` row-major `a` as `L Lᵀ` in place (the lower
/// triangle holds `L`, the upper is left as it was). `false` when `a` is not positive definite to
/// working precision (see the module docs).
pub fn cholesky(a: &mut [f64], n: usize) -> bool {
    let scale = (0..n).map(|i| a[i * n + i]).fold(0.0f64, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return n == 0;
    }
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.is_nan() || d <= RANK_EPS * scale {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place for the factor `l` of [`cholesky`].
pub fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= l[k * n + i] * b[k];
        }
        b[i] = s / l[i * n + i];
    }
}
