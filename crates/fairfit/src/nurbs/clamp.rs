//! Clamping: an unclamped (floating) knot vector turned into a clamped one with the same geometry on
//! the domain, by inserting the domain ends up to multiplicity `p` (A5.1) and dropping the control
//! points that no longer influence the domain.

use super::curve::NurbsCurve;
use super::insert::{insert_knot_hom, Hom};
use super::knots::is_clamped;
use crate::errors::Result;

/// Clamps the knot vector of degree `p` with homogeneous points `cw` (returned unchanged if already
/// clamped).
pub(crate) fn clamp_hom(p: usize, knots: &[f64], cw: &[Hom]) -> Result<(Vec<f64>, Vec<Hom>)> {
    if is_clamped(knots, p) {
        return Ok((knots.to_vec(), cw.to_vec()));
    }
    let n1 = cw.len();
    let (a, b) = (knots[p], knots[n1]);
    // start: a needs multiplicity p among the knots from index 1 on
    let s_a = knots.iter().filter(|&&k| k == a).count().min(p);
    let (mut k, mut c) = insert_knot_hom(p, knots, cw, a, p - s_a)?;
    // keep p + 1 knots up to the last copy of a (index L): drop L - p knots and control points
    let below = k.iter().take_while(|&&x| x < a).count();
    let last_a = below + k.iter().filter(|&&x| x == a).count() - 1;
    let drop = last_a - p;
    k.drain(..drop);
    c.drain(..drop);
    k[..p].fill(a);
    let s_b = k.iter().filter(|&&x| x == b).count().min(p);
    let (mut k, mut c) = insert_knot_hom(p, &k, &c, b, p - s_b)?;
    // the first copy of b sits at index F; F control points remain, F + p + 1 knots
    let first_b = k.iter().take_while(|&&x| x < b).count();
    k.truncate(first_b + p + 1);
    c.truncate(first_b);
    let len = k.len();
    k[len - p - 1..].fill(b);
    Ok((k, c))
}

impl NurbsCurve {
    /// The same curve on its domain with a clamped knot vector (end knots of multiplicity `p + 1`), so
    /// it starts and ends at its end control points. Returns a copy when already clamped.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let pts: Vec<Vec3> = (0..6).map(|i| Vec3::new(i as f64, (i * i) as f64, 0.0)).collect();
    /// let c = NurbsCurve::bspline(3, (0..10).map(|i| i as f64).collect(), pts).unwrap();
    /// let d = c.clamped().unwrap();
    /// assert_eq!(d.domain(), (3.0, 6.0));
    /// assert!((d.control_points()[0] - c.point(3.0)).norm() < 1e-13);
    /// assert!((d.point(4.2) - c.point(4.2)).norm() < 1e-13);
    /// ```
    pub fn clamped(&self) -> Result<NurbsCurve> {
        let (knots, cw) = clamp_hom(self.degree(), self.knots(), self.homogeneous_points())?;
        Ok(self.with_homogeneous(knots, &cw))
    }
}
