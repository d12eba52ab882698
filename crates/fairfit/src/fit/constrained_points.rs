//! Which points a fit under weights and points to interpolate ([`super::point_constraints`]) runs
//! on, and where they came from: the points of weight 0 dropped before anything else (so the fit
//! is the fit of the data without them, bit for bit), then the spikes the screening
//! ([`super::screening`]) excluded, except the points to interpolate (a point the user pins is
//! never an outlier). Each step keeps the index of every kept point among the points it was
//! given, so reports name the caller's points.
//!
//! The CLI (`fairfit curve`) and the Python package both fit this way.

use super::point_constraints::PointConstraints;
use crate::nurbs::Vec3;

/// Points of non-zero weight and their constraints, re-indexed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Weighted {
    /// The kept points.
    pub points: Vec<Vec3>,
    /// Their constraints (weights of the kept points; indices into [`Self::points`]).
    pub constraints: PointConstraints,
    /// For each kept point, its index among the points given.
    pub original: Vec<usize>,
    /// The indices of the points of weight 0 among the points given.
    pub ignored: Vec<usize>,
}

/// Drops the points of weight 0 (the constraints already validated: not all 0, none to
/// interpolate). Without weights every point is kept, in order.
///
/// ```
/// use fairfit::fit::constrained_points::without_ignored;
/// use fairfit::fit::point_constraints::PointConstraints;
/// use fairfit::Vec3;
/// let pts: Vec<Vec3> = (0..4).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
/// let pc = PointConstraints { weights: Some(vec![1.0, 0.0, 2.0, 1.0]), interpolate: vec![3] };
/// let w = without_ignored(&pts, &pc);
/// assert_eq!((w.original, w.ignored), (vec![0, 2, 3], vec![1]));
/// assert_eq!(w.constraints.interpolate, vec![2]);
/// assert_eq!(w.constraints.weights, Some(vec![1.0, 2.0, 1.0]));
/// ```
pub fn without_ignored(points: &[Vec3], pc: &PointConstraints) -> Weighted {
    let Some(w) = &pc.weights else {
        return Weighted {
            points: points.to_vec(),
            constraints: pc.clone(),
            original: (0..points.len()).collect(),
            ignored: Vec::new(),
        };
    };
    let original: Vec<usize> = (0..w.len()).filter(|&i| w[i] > 0.0).collect();
    let ignored = (0..w.len()).filter(|&i| w[i] == 0.0).collect();
    let pos = |k: usize| original.binary_search(&k).ok();
    Weighted {
        points: original.iter().map(|&i| points[i]).collect(),
        constraints: PointConstraints {
            weights: Some(original.iter().map(|&i| w[i]).collect()),
            interpolate: pc.interpolate.iter().filter_map(|&k| pos(k)).collect(),
        },
        original,
        ignored,
    }
}

/// Which of `points` the screening kept: not among `outliers` (indices into `points`), or to be
/// interpolated; with the constraints of the kept points (re-indexed) and each kept point's index
/// among `points`.
///
/// ```
/// use fairfit::fit::constrained_points::kept_after_screening;
/// use fairfit::fit::point_constraints::PointConstraints;
/// use fairfit::Vec3;
/// let pts: Vec<Vec3> = (0..5).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
/// let pc = PointConstraints { weights: None, interpolate: vec![1, 4] };
/// // points 1 and 2 were screened out as spikes: 1 is kept, as a point to interpolate
/// let (kept, kc, index) = kept_after_screening(&pts, &[1, 2], &pc);
/// assert_eq!((kept.len(), index), (4, vec![0, 1, 3, 4]));
/// assert_eq!(kc.interpolate, vec![1, 3]);
/// ```
pub fn kept_after_screening(
    points: &[Vec3],
    outliers: &[usize],
    pc: &PointConstraints,
) -> (Vec<Vec3>, PointConstraints, Vec<usize>) {
    let mask = |ids: &[usize]| {
        let mut m = vec![false; points.len()];
        for &i in ids {
            if let Some(x) = m.get_mut(i) {
                *x = true;
            }
        }
        m
    };
    let (spike, pinned) = (mask(outliers), mask(&pc.interpolate));
    let index: Vec<usize> = (0..points.len())
        .filter(|&i| !spike[i] || pinned[i])
        .collect();
    let constraints = PointConstraints {
        weights: pc
            .weights
            .as_ref()
            .map(|w| index.iter().map(|&i| w[i]).collect()),
        interpolate: index
            .iter()
            .enumerate()
            .filter(|&(_, &i)| pinned[i])
            .map(|(j, _)| j)
            .collect(),
    };
    (
        index.iter().map(|&i| points[i]).collect(),
        constraints,
        index,
    )
}
