//! Scale-free preparation of the data for the knot search, and the least-squares baseline knots.
//!
//! Points are translated to their bounding-box minimum, divided by the bounding box's largest side and
//! snapped to a grid of `2^-36` (about 1.5e-11 of that side). The snapping makes the normalised data
//! of inputs that differ only by a scale factor or a translation bit-identical, except where a
//! coordinate's last-place difference after the division crosses a grid line (about one coordinate
//! in 10^4 on a 12,000-point spiral scaled by 1000): tables of a few hundred points are almost always
//! exactly scale-invariant, and dense data get their scale invariance from the reduction's coarser
//! grid (`fit::reduce`, `ReduceTuning::grid`), which is what the search sees there.
//! Parameters are centripetal (increments `|ΔQ|^½`: denser at a leading edge, where a fair curve
//! needs its knots; on the benchmark curves it gave lower F than chord length, 6 % in the geometric
//! mean); the
//! baseline knots are the averaging knots of the NURBS Book
//! (eq. 9.68). These two are small private stand-ins for the least-squares module's own
//! parameterisation and knot placement.

use super::objective::FitData;
use crate::errors::{Error, Result};
use crate::nurbs::Vec3;

const SNAP: f64 = 1.0 / (1u64 << 36) as f64;

/// Normalised data and the map back to the input's coordinates (`x = origin + scale · x̂`).
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Normalised points, parameters, degree, planarity.
    pub data: FitData,
    /// Bounding-box minimum of the input.
    pub origin: Vec3,
    /// Largest side of the input's bounding box.
    pub scale: f64,
}

impl Prepared {
    /// Maps a normalised point back to input coordinates.
    pub fn denormalise(&self, p: Vec3) -> Vec3 {
        self.origin + p * self.scale
    }
}

/// Normalises `points` and computes centripetal parameters.
pub fn prepare(points: &[Vec3], degree: usize) -> Result<Prepared> {
    if points.len() < degree + 1 || points.len() < 3 {
        return Err(Error::InvalidData(format!(
            "{} points are too few for a degree-{degree} curve (need at least {})",
            points.len(),
            (degree + 1).max(3)
        )));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(Error::InvalidData(format!("point {i} is not finite")));
    }
    let mut lo = points[0];
    let mut hi = points[0];
    for p in points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    // the largest side of the bounding box: the unit of relative tolerances across fairfit
    let scale = (hi - lo).max_abs();
    if !scale.is_finite() {
        return Err(Error::InvalidData(
            "the points are too far apart to measure (coordinates near the floating-point limit): rescale the data".into(),
        ));
    }
    if scale.is_nan() || scale <= 0.0 {
        return Err(Error::InvalidData("all points coincide".into()));
    }
    let snapped: Vec<Vec3> = points
        .iter()
        .map(|p| {
            let q = (*p - lo) / scale;
            Vec3([
                (q[0] / SNAP).round() * SNAP,
                (q[1] / SNAP).round() * SNAP,
                (q[2] / SNAP).round() * SNAP,
            ])
        })
        .collect();
    let planar = snapped.iter().all(|p| p[2] == 0.0);
    let mut params = Vec::with_capacity(snapped.len());
    let mut acc = 0.0;
    params.push(0.0);
    for (i, w) in snapped.windows(2).enumerate() {
        let d = (w[1] - w[0]).norm();
        if d <= 1e-9 {
            return Err(Error::InvalidData(format!(
                "points {} and {} coincide; remove duplicate points",
                i,
                i + 1
            )));
        }
        acc += d.sqrt();
        params.push(acc);
    }
    for u in &mut params {
        *u /= acc;
    }
    if let Some(last) = params.last_mut() {
        *last = 1.0;
    }
    Ok(Prepared {
        data: FitData {
            points: snapped,
            params,
            degree,
            planar,
            corrections: 1,
            ends: Default::default(),
            bands: Default::default(),
        },
        origin: lo,
        scale,
    })
}

/// The `n_ctrl − degree − 1` interior averaging knots (NURBS Book eq. 9.68) for `params`.
pub(crate) fn averaging_interior_knots(params: &[f64], degree: usize, n_ctrl: usize) -> Vec<f64> {
    let m = params.len() - 1;
    let k = n_ctrl.saturating_sub(degree + 1);
    if k == 0 {
        return Vec::new();
    }
    if n_ctrl == m + 1 {
        // interpolation: averages of `degree` consecutive parameters
        return (1..=k)
            .map(|j| params[j..j + degree].iter().sum::<f64>() / degree as f64)
            .collect();
    }
    let d = (m + 1) as f64 / (n_ctrl - degree) as f64;
    (1..=k)
        .map(|j| {
            let jd = j as f64 * d;
            let i = (jd.floor() as usize).clamp(1, m);
            let a = jd - i as f64;
            (1.0 - a) * params[i - 1] + a * params[i]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalisation_is_bit_identical_under_scaling_and_translation() {
        let pts: Vec<Vec3> = (0..50)
            .map(|i| {
                let t = i as f64 * 0.07;
                Vec3([t.cos() * 0.37, (1.3 * t).sin() * 0.21, 0.0])
            })
            .collect();
        let big: Vec<Vec3> = pts
            .iter()
            .map(|p| *p * 1000.0 + Vec3([5.0, -3.0, 0.0]))
            .collect();
        let (a, b) = (prepare(&pts, 3).unwrap(), prepare(&big, 3).unwrap());
        assert!(a.data.planar);
        for (p, q) in a.data.points.iter().zip(&b.data.points) {
            assert_eq!(p.0.map(f64::to_bits), q.0.map(f64::to_bits));
        }
        assert_eq!(
            a.data
                .params
                .iter()
                .map(|u| u.to_bits())
                .collect::<Vec<_>>(),
            b.data
                .params
                .iter()
                .map(|u| u.to_bits())
                .collect::<Vec<_>>()
        );
        assert!((b.scale / a.scale - 1000.0).abs() < 1e-9);
        // duplicates are an error naming the points
        let mut dup = pts.clone();
        dup.insert(3, pts[3]);
        let e = prepare(&dup, 3).unwrap_err().to_string();
        assert!(e.contains("points 3 and 4"), "{e}");
    }

    #[test]
    fn averaging_knots_for_uniform_parameters_are_uniform() {
        // 13 uniform parameters, 7 control points, degree 3: d = 13/4, knots at 3.25/12, 6.5/12, 9.75/12
        let params: Vec<f64> = (0..13).map(|i| i as f64 / 12.0).collect();
        let k = averaging_interior_knots(&params, 3, 7);
        let want = [2.25 / 12.0, 5.5 / 12.0, 8.75 / 12.0];
        for (a, b) in k.iter().zip(want) {
            assert!((a - b).abs() < 1e-15, "{k:?}");
        }
    }
}
