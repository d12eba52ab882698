//! Clamped least squares of a closed section whose seam is smooth, when the shared knot vector must stay
//! clamped (some other section is open, e.g. a blade's round root next to its blunt-edged airfoils): the
//! end derivatives up to order `k` are tied, `C^(j)(0) = C^(j)(1)` for `j = 1..=k`, so the closed section
//! is `C^k` across its seam instead of creased.
//!
//! The ties are linear in the control points and involve only the first and last `p + 1` of them; each
//! is solved for one of the last `k` inner control points (`P_{N−1−k} … P_{N−2}`, a triangular system),
//! which are eliminated: `P = T x + o` with `x` the remaining inner control points and `o` carrying the
//! interpolated end points. The normal equations `Tᵀ (BᵀB + λG) T x = Tᵀ (Bᵀd − (BᵀB + λG) o)` are dense
//! (a few dozen control points), like [`super::section_fit`]'s.
//!
//! Because the ties depend only on the knot vector, skinning sections that all satisfy them gives a
//! surface whose iso-curves at those sections are `C^k` across the seam.

#![allow(clippy::needless_range_loop)]

use super::linalg::{cholesky, cholesky_solve, constrain_solution, Dense};
use super::section_fit::{bending_gram, Pin};
use crate::errors::{Error, Result};
use crate::nurbs::basis::{basis_funs_into, ders_basis_funs_into};
use crate::nurbs::knots::find_span;

/// The seam tie order used for a smooth closed section on a clamped knot vector of degree `p`:
/// `C^(p−1)` like a periodic fit, at most `C^2`.
pub(crate) fn tie_order(degree: usize) -> usize {
    degree.saturating_sub(1).min(2)
}

/// Rows `j = 1..=k` of the tie `C^(j)(a) − C^(j)(b) = Σ_i c_ji P_i` on clamped `knots` (`n` control
/// points).
fn tie_rows(degree: usize, knots: &[f64], n: usize, k: usize) -> Vec<Vec<f64>> {
    let p = degree;
    let p1 = p + 1;
    let (mut left, mut right) = (vec![0.0; p1], vec![0.0; p1]);
    let (mut ndu, mut a) = (vec![0.0; p1 * p1], vec![0.0; 2 * p1]);
    let mut start = vec![0.0; (k + 1) * p1];
    let mut end = vec![0.0; (k + 1) * p1];
    // end derivatives from inside the first and last spans (the clamped ends are span ends, never
    // interior knots)
    ders_basis_funs_into(
        p, knots[p], p, k, knots, &mut left, &mut right, &mut ndu, &mut a, &mut start,
    );
    ders_basis_funs_into(
        n - 1,
        knots[n],
        p,
        k,
        knots,
        &mut left,
        &mut right,
        &mut ndu,
        &mut a,
        &mut end,
    );
    (1..=k)
        .map(|j| {
            let mut row = vec![0.0; n];
            for i in 0..p1 {
                row[i] += start[j * p1 + i];
                row[n - p1 + i] -= end[j * p1 + i];
            }
            row
        })
        .collect()
}

/// The affine map `P = T x + o`: `T` is `n × free` (row-major), `o` the offsets (end points and the
/// eliminated points' constant parts), for the tie rows `rows` and the fixed ends `first`, `last`.
fn elimination<const C: usize>(
    rows: &[Vec<f64>],
    n: usize,
    first: [f64; C],
    last: [f64; C],
) -> Option<(Vec<f64>, usize, Vec<[f64; C]>)> {
    let k = rows.len();
    // free inner points 1..n-1-k, eliminated n-1-k..n-1
    let free = n.checked_sub(2 + k)?;
    if free < k + 1 {
        return None;
    }
    let dep: Vec<usize> = (n - 1 - k..n - 1).collect();
    // solve rows restricted to dep: cd (k × k) d = −(c_free x + c_0 P_0 + c_{n−1} P_{n−1})
    let mut cd = vec![0.0; k * k];
    for (r, row) in rows.iter().enumerate() {
        for (c, &d) in dep.iter().enumerate() {
            cd[r * k + c] = row[d];
        }
    }
    // rhs columns: the free variables, then the C offset coordinates
    let width = free + C;
    let mut rhs = vec![0.0; k * width];
    for (r, row) in rows.iter().enumerate() {
        for f in 0..free {
            rhs[r * width + f] = -row[1 + f];
        }
        for c in 0..C {
            rhs[r * width + free + c] = -(row[0] * first[c] + row[n - 1] * last[c]);
        }
    }
    // Gaussian elimination with partial pivoting on the k × k block (k <= 2)
    let scale = cd.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for col in 0..k {
        let piv =
            (col..k).max_by(|&a, &b| cd[a * k + col].abs().total_cmp(&cd[b * k + col].abs()))?;
        if cd[piv * k + col].abs() <= 1e-12 * scale {
            return None;
        }
        if piv != col {
            for j in 0..k {
                cd.swap(col * k + j, piv * k + j);
            }
            for j in 0..width {
                rhs.swap(col * width + j, piv * width + j);
            }
        }
        for r in 0..k {
            if r == col {
                continue;
            }
            let f = cd[r * k + col] / cd[col * k + col];
            if f == 0.0 {
                continue;
            }
            for j in 0..k {
                cd[r * k + j] -= f * cd[col * k + j];
            }
            for j in 0..width {
                rhs[r * width + j] -= f * rhs[col * width + j];
            }
        }
    }
    let mut t = vec![0.0; n * free];
    let mut o = vec![[0.0; C]; n];
    o[0] = first;
    o[n - 1] = last;
    for f in 0..free {
        t[(1 + f) * free + f] = 1.0;
    }
    for (r, &d) in dep.iter().enumerate() {
        let piv = cd[r * k + r];
        for f in 0..free {
            t[d * free + f] = rhs[r * width + f] / piv;
        }
        for c in 0..C {
            o[d][c] = rhs[r * width + free + c] / piv;
        }
    }
    Some((t, free, o))
}

/// Least-squares control points of a closed section (`data` starts and ends at the seam) on the clamped
/// `knots`, ends interpolated, the seam tied to order `k` (see the module documentation); `smoothing` as
/// in [`super::section_fit`]; with `pin` the curve passes through the pinned point exactly. `Ok(None)`
/// when there are too few control points to tie the seam (the caller falls back to the untied fit).
pub(crate) fn lsq_tied_control_points<const C: usize>(
    data: &[[f64; C]],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    k: usize,
    pin: Option<&Pin<C>>,
) -> Result<Option<Vec<[f64; C]>>> {
    let p = degree;
    let n = knots.len() - p - 1;
    let m = data.len();
    if m < 3 || params.len() != m {
        return Err(Error::Fit("least squares needs at least 3 points".into()));
    }
    if k == 0 {
        return Ok(None);
    }
    let rows = tie_rows(p, knots, n, k);
    let Some((t, free, o)) = elimination(&rows, n, data[0], data[m - 1]) else {
        return Ok(None);
    };
    // full normal matrix A = BᵀB (+ λG) and Bᵀd over the inner data points (the ends are interpolated)
    let mut a = Dense::zeros(n);
    let mut btd = vec![[0.0; C]; n];
    let (mut left, mut right, mut nb) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
    for q in 1..m - 1 {
        let u = params[q];
        let span = find_span(n - 1, p, u, knots);
        basis_funs_into(span, u, p, knots, &mut left, &mut right, &mut nb);
        let first = span - p;
        for (i, &ni) in nb.iter().enumerate() {
            for c in 0..C {
                btd[first + i][c] += ni * data[q][c];
            }
            for (j, &nj) in nb.iter().enumerate() {
                *a.at(first + i, first + j) += ni * nj;
            }
        }
    }
    if smoothing > 0.0 {
        let g = bending_gram(p, knots, n);
        let lam = smoothing * m as f64;
        for i in 0..n {
            for j in 0..n {
                *a.at(i, j) += lam * g.get(i, j);
            }
        }
    }
    // r = Bᵀd − A o, then the reduced system Tᵀ A T x = Tᵀ r
    let mut r = btd;
    for i in 0..n {
        for j in 0..n {
            let aij = a.get(i, j);
            if aij != 0.0 {
                for c in 0..C {
                    r[i][c] -= aij * o[j][c];
                }
            }
        }
    }
    // A T (n × free), then Tᵀ (A T)
    let mut at = vec![0.0; n * free];
    for i in 0..n {
        for j in 0..n {
            let aij = a.get(i, j);
            if aij == 0.0 {
                continue;
            }
            for f in 0..free {
                at[i * free + f] += aij * t[j * free + f];
            }
        }
    }
    let mut h = Dense::zeros(free);
    let mut rhs = vec![[0.0; C]; free];
    for i in 0..n {
        for f in 0..free {
            let tif = t[i * free + f];
            if tif == 0.0 {
                continue;
            }
            for g in 0..free {
                *h.at(f, g) += tif * at[i * free + g];
            }
            for c in 0..C {
                rhs[f][c] += tif * r[i][c];
            }
        }
    }
    cholesky(&mut h)?;
    cholesky_solve(&h, &mut rhs);
    if let Some(pin) = pin {
        // C(u) = Σ N_i(u) (T x + o)_i: the row Tᵀ N(u), the offsets' part moved to the target
        let (first, nb) = pin.basis(p, knots, n);
        let mut row = vec![0.0; free];
        let mut target = pin.point;
        for (j, &nj) in nb.iter().enumerate() {
            let i = first + j;
            for f in 0..free {
                row[f] += nj * t[i * free + f];
            }
            for c in 0..C {
                target[c] -= nj * o[i][c];
            }
        }
        constrain_solution(&h, &mut rhs, &row, target);
    }
    let mut ctrl = o;
    for i in 0..n {
        for f in 0..free {
            let tif = t[i * free + f];
            if tif != 0.0 {
                for c in 0..C {
                    ctrl[i][c] += tif * rhs[f][c];
                }
            }
        }
    }
    Ok(Some(ctrl))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::{NurbsCurve, Vec3};

    /// A closed, smooth but not circular loop sampled at chord-ish parameters.
    fn loop_data(m: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
        let data: Vec<[f64; 3]> = (0..=m)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / m as f64;
                [
                    2.0 * t.cos() + 0.3 * (2.0 * t).cos(),
                    t.sin() + 0.2 * (3.0 * t).sin(),
                    0.0,
                ]
            })
            .collect();
        let params = (0..=m).map(|i| i as f64 / m as f64).collect();
        (data, params)
    }

    fn knots() -> Vec<f64> {
        let mut k = vec![0.0; 4];
        k.extend([0.1, 0.25, 0.4, 0.5, 0.62, 0.75, 0.9]);
        k.extend([1.0; 4]);
        k
    }

    #[test]
    fn tied_seam_is_c2_and_the_fit_stays_close() {
        let (data, params) = loop_data(120);
        let k = knots();
        let ctrl = lsq_tied_control_points(&data, &params, 3, &k, 0.0, 2, None)
            .unwrap()
            .unwrap();
        let c = NurbsCurve::bspline(3, k.clone(), ctrl.into_iter().map(Vec3).collect()).unwrap();
        let (mut a, mut b) = ([Vec3::ZERO; 3], [Vec3::ZERO; 3]);
        c.derivatives_into(0.0, 2, &mut a);
        c.derivatives_into(1.0, 2, &mut b);
        let scale = a[1].norm();
        assert!((a[0] - b[0]).norm() < 1e-12);
        assert!(
            (a[1] - b[1]).norm() < 1e-12 * scale,
            "{:?} {:?}",
            a[1],
            b[1]
        );
        assert!(
            (a[2] - b[2]).norm() < 1e-11 * a[2].norm(),
            "{:?} {:?}",
            a[2],
            b[2]
        );
        // the untied clamped fit on the same knots has a crease; the tied one fits almost as well
        let free =
            crate::surface::section_fit::lsq_control_points(&data, &params, 3, &k, 0.0, None)
                .unwrap();
        let cf = NurbsCurve::bspline(3, k.clone(), free.into_iter().map(Vec3).collect()).unwrap();
        let (mut fa, mut fb) = ([Vec3::ZERO; 3], [Vec3::ZERO; 3]);
        cf.derivatives_into(0.0, 2, &mut fa);
        cf.derivatives_into(1.0, 2, &mut fb);
        let crease = fa[1].cross(fb[1]).norm().atan2(fa[1].dot(fb[1]));
        assert!(crease > 1e-3, "untied crease {crease}");
        let err = |c: &NurbsCurve| {
            data.iter()
                .zip(&params)
                .map(|(d, &u)| (c.point(u) - Vec3(*d)).norm())
                .fold(0.0, f64::max)
        };
        let (et, ef) = (err(&c), err(&cf));
        assert!(et < 1.5 * ef, "tied {et} vs free {ef}");
    }

    #[test]
    fn too_few_control_points_fall_back() {
        let (data, params) = loop_data(40);
        let k = vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
        assert!(lsq_tied_control_points(&data, &params, 3, &k, 0.0, 2, None)
            .unwrap()
            .is_none());
    }
}
