//! Per-point weights and interpolated points of a least-squares solve ([`super::LsqSolver::set_point_terms`]).
//!
//! **What.** With weights `w_k`, the data term is `Σ_k w_k² |C(ū_k) − Q_k|²` (a point of weight 2
//! counts as four); with points to interpolate `K`, the minimum is taken under the linear
//! equalities `C(ū_k) = Q_k`, `k ∈ K` (each coordinate).
//!
//! **How.** The weights scale each point's rows of the normal equations `N x = b`. The equalities
//! `A x = c` (one row per point of `K`, its `p + 1` basis values on the unknown columns; the fixed
//! columns moved into `c`) are met by the KKT system's Schur complement: with `x₀ = N⁻¹ b` and
//! `Y = N⁻¹ Aᵀ` (solved with the factor of `N` already at hand, three columns per solve),
//! `(A Y) λ = c − A x₀` and `x = x₀ + Y λ`. `A Y` is small (one row per point to interpolate) and
//! symmetric positive definite while the rows are independent; a rank-deficient one (more points
//! to interpolate in a few spans than those spans have unknowns, or a point whose row holds only
//! fixed columns but misses them) is refused, naming `interpolate`.
//!
//! Invariant: with no weights and no equalities, the solve is bit for bit the unweighted one.

use super::super::banded::EnvelopeCholesky;
use super::super::dense::{cholesky, cholesky_solve};
use crate::errors::{Error, Result};
use crate::nurbs::Vec3;

/// The weights and equalities held for the next solves, with the Schur complement's buffers.
#[derive(Clone, Debug, Default)]
pub(super) struct PointTerms {
    /// Squared weight of every point (empty: all 1).
    pub weights2: Vec<f64>,
    /// Indices of the points to interpolate.
    pub equal: Vec<usize>,
    /// Per equality row: its `(unknown, coefficient)` entries (flattened, `rows` delimits them).
    entries: Vec<(usize, f64)>,
    rows: Vec<usize>,
    /// `c − A x₀` per row.
    rhs: Vec<Vec3>,
    /// `Y = N⁻¹ Aᵀ`, one column of `n_unknown` per row.
    y: Vec<f64>,
    pack: Vec<Vec3>,
    schur: Vec<f64>,
    lambda: Vec<f64>,
}

impl PointTerms {
    /// The factor of point `k`'s term (`w_k²`, 1 without weights).
    #[inline]
    pub fn weight2(&self, k: usize) -> f64 {
        if self.weights2.is_empty() {
            1.0
        } else {
            self.weights2[k]
        }
    }

    /// Starts the equality rows of a solve.
    pub fn clear_rows(&mut self) {
        self.entries.clear();
        self.rows.clear();
        self.rhs.clear();
    }

    /// Adds the row of one point to interpolate: its `(unknown, coefficient)` entries and the
    /// target `c_k` (the point less the fixed columns' part). A row without entries must already
    /// hold (`Err` naming `interpolate` otherwise; `tol` is the absolute slack).
    pub fn push_row(
        &mut self,
        k: usize,
        entries: impl Iterator<Item = (usize, f64)>,
        target: Vec3,
        tol: f64,
    ) -> Result<()> {
        let before = self.entries.len();
        self.entries.extend(entries.filter(|e| e.1 != 0.0));
        if self.entries.len() == before {
            if target.norm() > tol {
                return Err(dependent(k));
            }
            return Ok(());
        }
        self.rows.push(self.entries.len());
        self.rhs.push(target);
        Ok(())
    }

    /// The entries of row `r`.
    fn row(&self, r: usize) -> &[(usize, f64)] {
        let a = if r == 0 { 0 } else { self.rows[r - 1] };
        &self.entries[a..self.rows[r]]
    }

    /// Moves the unconstrained solution `x` (`N x = b`, `mat` holding the factor of `N`) onto the
    /// rows' equalities (module docs).
    pub fn apply(&mut self, mat: &EnvelopeCholesky, x: &mut [Vec3]) -> Result<()> {
        let m = self.rows.len();
        if m == 0 {
            return Ok(());
        }
        let nu = x.len();
        // residuals c − A x₀
        for r in 0..m {
            let mut ax = Vec3::ZERO;
            for &(u, a) in self.row(r) {
                ax += x[u] * a;
            }
            self.rhs[r] -= ax;
        }
        // Y = N⁻¹ Aᵀ, three columns per solve
        self.y.clear();
        self.y.resize(m * nu, 0.0);
        for g in (0..m).step_by(3) {
            self.pack.clear();
            self.pack.resize(nu, Vec3::ZERO);
            for c in 0..3.min(m - g) {
                let (a, b) = (
                    if g + c == 0 { 0 } else { self.rows[g + c - 1] },
                    self.rows[g + c],
                );
                for &(u, v) in &self.entries[a..b] {
                    self.pack[u][c] += v;
                }
            }
            mat.solve_vec3(&mut self.pack);
            for c in 0..3.min(m - g) {
                for u in 0..nu {
                    self.y[(g + c) * nu + u] = self.pack[u][c];
                }
            }
        }
        // S = A Y, symmetric positive definite for independent rows
        self.schur.clear();
        self.schur.resize(m * m, 0.0);
        for r in 0..m {
            for s in 0..m {
                let ys = &self.y[s * nu..(s + 1) * nu];
                self.schur[r * m + s] = self.row(r).iter().map(|&(u, a)| a * ys[u]).sum();
            }
        }
        if !cholesky(&mut self.schur, m) {
            return Err(dependent(self.equal.first().copied().unwrap_or(0)));
        }
        for c in 0..3 {
            self.lambda.clear();
            self.lambda.extend(self.rhs.iter().map(|v| v[c]));
            cholesky_solve(&self.schur, m, &mut self.lambda);
            for (r, &l) in self.lambda.iter().enumerate() {
                for (u, xu) in x.iter_mut().enumerate() {
                    xu[c] += self.y[r * nu + u] * l;
                }
            }
        }
        Ok(())
    }
}

fn dependent(k: usize) -> Error {
    Error::InvalidSetting {
        option: "interpolate",
        reason: format!(
            "point {k} cannot be interpolated on these knots: the points to interpolate are more than the spans around them have free control points"
        ),
    }
}
