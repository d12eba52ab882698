//! Knot refinement (NURBS Book A5.4): many knots inserted in one pass, on homogeneous control points.

use super::curve::NurbsCurve;
use super::insert::{lerp, Hom};
use super::knots::find_span;
use crate::errors::{Error, Result};

/// Checks that `x` is non-decreasing, strictly inside the domain `(U[p], U[n+1])`, and that no knot
/// ends up with multiplicity above `p`.
fn validate_refinement(p: usize, knots: &[f64], n_ctrl: usize, x: &[f64]) -> Result<()> {
    let (a, b) = (knots[p], knots[n_ctrl]);
    if let Some(v) = x.iter().find(|v| !v.is_finite() || **v <= a || **v >= b) {
        return Err(Error::KnotOperation(format!(
            "refinement knot {v} is not strictly inside the domain ({a}, {b})"
        )));
    }
    if let Some(i) = x.windows(2).position(|w| w[1] < w[0]) {
        return Err(Error::KnotOperation(format!(
            "refinement knots must not decrease, but {} > {}",
            x[i],
            x[i + 1]
        )));
    }
    let mut i = 0;
    while i < x.len() {
        let added = x[i..].iter().take_while(|&&v| v == x[i]).count();
        let total = added + knots.iter().filter(|&&k| k == x[i]).count();
        if total > p {
            return Err(Error::KnotOperation(format!(
                "knot {} would get multiplicity {total}, more than the degree {p}",
                x[i]
            )));
        }
        i += added;
    }
    Ok(())
}

/// Inserts all knots of the sorted slice `x` (NURBS Book A5.4); see [`NurbsCurve::refine_knots`].
pub(crate) fn refine_knots_hom(
    p: usize,
    knots: &[f64],
    cw: &[Hom],
    x: &[f64],
) -> Result<(Vec<f64>, Vec<Hom>)> {
    validate_refinement(p, knots, cw.len(), x)?;
    if x.is_empty() {
        return Ok((knots.to_vec(), cw.to_vec()));
    }
    let n = cw.len() - 1;
    let m = n + p + 1;
    let r = x.len() - 1;
    let a = find_span(n, p, x[0], knots);
    let b = find_span(n, p, x[r], knots) + 1;
    let mut qw = vec![[0.0; 4]; cw.len() + x.len()];
    let mut ub = vec![0.0; knots.len() + x.len()];
    qw[..=a - p].copy_from_slice(&cw[..=a - p]);
    for j in b - 1..=n {
        qw[j + r + 1] = cw[j];
    }
    ub[..=a].copy_from_slice(&knots[..=a]);
    for j in b + p..=m {
        ub[j + r + 1] = knots[j];
    }
    let mut i = b + p - 1;
    let mut k = b + p + r;
    for j in (0..=r).rev() {
        while x[j] <= knots[i] && i > a {
            qw[k - p - 1] = cw[i - p - 1];
            ub[k] = knots[i];
            k -= 1;
            i -= 1;
        }
        qw[k - p - 1] = qw[k - p];
        for l in 1..=p {
            let ind = k - p + l;
            let alfa = ub[k + l] - x[j];
            if alfa == 0.0 {
                qw[ind - 1] = qw[ind];
            } else {
                let alfa = alfa / (ub[k + l] - knots[i - p + l]);
                qw[ind - 1] = lerp(alfa, &qw[ind - 1], 1.0 - alfa, &qw[ind]);
            }
        }
        ub[k] = x[j];
        k -= 1;
    }
    Ok((ub, qw))
}

impl NurbsCurve {
    /// The same curve with every knot of `new_knots` inserted (NURBS Book A5.4). `new_knots` must be
    /// non-decreasing and strictly inside the domain, and no knot may end up with a multiplicity above
    /// the degree. The geometry is unchanged, rational curves included.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let c = NurbsCurve::circle(Vec3::new(1.0, 2.0, 0.0), 3.0).unwrap();
    /// let d = c.refine_knots(&[0.1, 0.1, 0.6, 0.9]).unwrap();
    /// assert_eq!(d.knots().len(), c.knots().len() + 4);
    /// for u in [0.0, 0.05, 0.33, 0.77, 1.0] {
    ///     assert!((d.point(u) - c.point(u)).norm() < 1e-13);
    /// }
    /// assert!(c.refine_knots(&[0.6, 0.1]).is_err()); // must be sorted
    /// ```
    pub fn refine_knots(&self, new_knots: &[f64]) -> Result<NurbsCurve> {
        let (knots, cw) = refine_knots_hom(
            self.degree(),
            self.knots(),
            self.homogeneous_points(),
            new_knots,
        )?;
        Ok(self.with_homogeneous(knots, &cw))
    }
}
