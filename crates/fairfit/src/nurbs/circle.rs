//! Exact circles and circular arcs as rational quadratic NURBS (NURBS Book §7.3 and A7.1), in a plane
//! parallel to xy. Handy as analytic test geometry: |C − centre| = r and κ = 1/r everywhere.

use super::curve::NurbsCurve;
use super::vec3::Vec3;
use crate::errors::{Error, Result};

impl NurbsCurve {
    /// The full circle of `radius` around `center` in the plane `z = center.z`, counter-clockwise from
    /// `center + (r, 0, 0)`: degree 2, 9 control points, weights `1, √2/2, 1, ...`, knots
    /// `[0,0,0, ¼,¼, ½,½, ¾,¾, 1,1,1]`.
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let c = NurbsCurve::circle(Vec3::new(1.0, -1.0, 0.5), 2.0).unwrap();
    /// let p = c.point(0.37);
    /// assert!(((p - Vec3::new(1.0, -1.0, 0.5)).norm() - 2.0).abs() < 1e-14);
    /// assert!((c.point(0.25) - Vec3::new(1.0, 1.0, 0.5)).norm() < 1e-15);
    /// ```
    pub fn circle(center: Vec3, radius: f64) -> Result<NurbsCurve> {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        check_radius(radius)?;
        let dirs = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
        ];
        let pts = dirs
            .iter()
            .map(|&(x, y)| center + Vec3::new(radius * x, radius * y, 0.0))
            .collect();
        let w = vec![1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0];
        let knots = vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ];
        NurbsCurve::new(2, knots, pts, Some(w))
    }

    /// The arc of `radius` around `center` (plane `z = center.z`) from angle `start` to `end` (radians,
    /// counter-clockwise, `0 < end − start <= 2π`), on the domain `[0, 1]` (NURBS Book A7.1: at most 90°
    /// per rational quadratic segment).
    ///
    /// ```
    /// use fairfit::nurbs::{NurbsCurve, Vec3};
    /// let c = NurbsCurve::arc(Vec3::ZERO, 3.0, 0.2, 2.5).unwrap();
    /// assert!((c.point(0.0) - Vec3::new(3.0 * 0.2f64.cos(), 3.0 * 0.2f64.sin(), 0.0)).norm() < 1e-14);
    /// assert!((c.point(0.6).norm() - 3.0).abs() < 1e-14);
    /// ```
    pub fn arc(center: Vec3, radius: f64, start: f64, end: f64) -> Result<NurbsCurve> {
        check_radius(radius)?;
        let theta = end - start;
        if !(theta.is_finite() && theta > 0.0 && theta <= 2.0 * std::f64::consts::PI + 1e-12) {
            return Err(Error::InvalidOption(format!(
                "arc angles: need 0 < end - start <= 2π, got start {start}, end {end}"
            )));
        }
        let narcs = ((theta / std::f64::consts::FRAC_PI_2) - 1e-12)
            .ceil()
            .max(1.0) as usize;
        let dtheta = theta / narcs as f64;
        let w1 = (dtheta / 2.0).cos();
        let on = |ang: f64| center + Vec3::new(radius * ang.cos(), radius * ang.sin(), 0.0);
        let mut pts = vec![on(start)];
        let mut w = vec![1.0];
        let mut knots = vec![0.0; 3];
        for i in 1..=narcs {
            let mid = start + (i as f64 - 0.5) * dtheta;
            // the tangent lines at both segment ends meet at distance r / cos(dθ/2) along the bisector
            pts.push(on(mid) + (on(mid) - center) * (1.0 / w1 - 1.0));
            w.push(w1);
            pts.push(on(start + i as f64 * dtheta));
            w.push(1.0);
            if i < narcs {
                let k = i as f64 / narcs as f64;
                knots.push(k);
                knots.push(k);
            }
        }
        knots.extend([1.0; 3]);
        NurbsCurve::new(2, knots, pts, Some(w))
    }
}

fn check_radius(radius: f64) -> Result<()> {
    if radius.is_finite() && radius > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidOption(format!(
            "circle radius must be finite and > 0, got {radius}"
        )))
    }
}
