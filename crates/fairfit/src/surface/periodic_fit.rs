//! Periodic least squares of one closed section on a shared periodic knot vector
//! ([`crate::fit::lsq::periodic_knots`] of the breakpoints `0 = b_0 < … < b_{n_u} = 1`): `n_u` distinct
//! control points, the last `p` of the `n_u + p` written repeating the first, so the curve is
//! `C^(p−1)` across the seam. Nothing is interpolated; the closing point (the section's last point,
//! parameter 1, repeating the first) is left out so the seam point counts once. The bending term is the
//! open fit's Gram matrix with its columns wrapped onto the distinct control points.

#![allow(clippy::needless_range_loop)]

use super::linalg::{cholesky, cholesky_solve, constrain_solution, Dense};
use super::section_fit::{bending_gram, Pin};
use crate::errors::{Error, Result};
use crate::nurbs::basis::basis_funs_into;
use crate::nurbs::knots::find_span;

/// Periodic least-squares control points (`C` coordinates) of a degree-`degree` B-spline on the
/// periodic knot vector `knots` through the closed `data` at `params` (last point = first, parameter
/// 1); `smoothing` as in the open fit; with `pin` the curve passes through the pinned point exactly.
/// Returns all `n_u + p` control points (the last `p` repeat the first).
pub(crate) fn lsq_periodic_control_points<const C: usize>(
    data: &[[f64; C]],
    params: &[f64],
    degree: usize,
    knots: &[f64],
    smoothing: f64,
    pin: Option<&Pin<C>>,
) -> Result<Vec<[f64; C]>> {
    let p = degree;
    let n_ctrl = knots.len() - p - 1;
    let m = data.len();
    if n_ctrl < 2 * p + 1 {
        return Err(Error::Fit(format!(
            "a periodic fit of degree {p} needs at least {} knot spans",
            p + 1
        )));
    }
    let nu = n_ctrl - p;
    // as in the open fit, spans without data are kept well posed by the bending term only
    if m < 3 || params.len() != m {
        return Err(Error::Fit(format!(
            "a periodic fit needs at least 3 points with parameters, got {m}"
        )));
    }
    let mut ntn = Dense::zeros(nu);
    let mut rhs = vec![[0.0; C]; nu];
    let (mut left, mut right, mut nb) = (vec![0.0; p + 1], vec![0.0; p + 1], vec![0.0; p + 1]);
    for k in 0..m - 1 {
        let u = params[k];
        let span = find_span(n_ctrl - 1, p, u, knots);
        basis_funs_into(span, u, p, knots, &mut left, &mut right, &mut nb);
        let first = span - p;
        for (j, &nj) in nb.iter().enumerate() {
            let a = (first + j) % nu;
            for c in 0..C {
                rhs[a][c] += nj * data[k][c];
            }
            for (l, &nl) in nb.iter().enumerate() {
                *ntn.at(a, (first + l) % nu) += nj * nl;
            }
        }
    }
    if smoothing > 0.0 {
        let g = bending_gram(p, knots, n_ctrl);
        let lam = smoothing * m as f64;
        for i in 0..n_ctrl {
            for j in 0..n_ctrl {
                let gij = g.get(i, j);
                if gij != 0.0 {
                    *ntn.at(i % nu, j % nu) += lam * gij;
                }
            }
        }
    }
    cholesky(&mut ntn)?;
    cholesky_solve(&ntn, &mut rhs);
    if let Some(pin) = pin {
        // the constraint's row wrapped onto the distinct control points like the data rows
        let (first, nb) = pin.basis(p, knots, n_ctrl);
        let mut row = vec![0.0; nu];
        for (j, &nj) in nb.iter().enumerate() {
            row[(first + j) % nu] += nj;
        }
        constrain_solution(&ntn, &mut rhs, &row, pin.point);
    }
    let mut ctrl = rhs;
    for i in 0..p {
        ctrl.push(ctrl[i]);
    }
    Ok(ctrl)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::lsq::periodic_knots;
    use crate::nurbs::{NurbsCurve, Vec3};

    #[test]
    fn reproduces_a_periodic_cubic_on_its_own_knots() {
        let breaks = [0.0, 0.15, 0.4, 0.5, 0.8, 1.0];
        let knots = periodic_knots(&breaks, 3);
        let distinct = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.7, 0.9, 0.1),
            Vec3::new(-0.4, 1.1, 0.0),
            Vec3::new(-1.2, -0.2, -0.1),
            Vec3::new(0.1, -1.0, 0.2),
        ];
        let mut ctrl = distinct.to_vec();
        ctrl.extend_from_slice(&distinct[..3]);
        let truth = NurbsCurve::bspline(3, knots.clone(), ctrl.clone()).unwrap();
        let us: Vec<f64> = (0..=50).map(|k| (k as f64 / 50.0).powf(1.2)).collect();
        let data: Vec<[f64; 3]> = truth.points(&us).iter().map(|p| p.0).collect();
        let got = lsq_periodic_control_points(&data, &us, 3, &knots, 0.0, None).unwrap();
        assert_eq!(got.len(), ctrl.len());
        for (g, c) in got.iter().zip(&ctrl) {
            assert!((Vec3(*g) - *c).norm() < 1e-12, "{g:?} vs {c:?}");
        }
        // a bending term keeps a span without data well posed
        let sparse: Vec<usize> = (0..=50).filter(|&k| !(20..=30).contains(&k)).collect();
        let d2: Vec<[f64; 3]> = sparse.iter().map(|&k| data[k]).collect();
        let u2: Vec<f64> = sparse.iter().map(|&k| us[k]).collect();
        assert!(lsq_periodic_control_points(&d2, &u2, 3, &knots, 1e-6, None).is_ok());
    }
}
