//! Whether open-looking data are a closed curve, judged at the tolerance's scale.
//!
//! Data whose last point repeats the first (within [`CLOSED_REL_GAP`](super::shape::CLOSED_REL_GAP) of the extent,
//! [`looks_closed`]) are closed whatever their tangents: a sharp trailing edge is a closed loop with
//! a corner at the seam. Otherwise the data are closed across the *gap* from their last point to
//! their first ([`Closure::Gap`]) when all three hold:
//!
//! 1. the gap is at most the tolerance `tol`: at the fit's scale the ends meet;
//! 2. the gap is at most [`GAP_SPACINGS`] times the data's own spacing at each end (the median of the
//!    [`END_CHORDS`] chords there): the gap is one more step of the sampling, not a missing arc. A
//!    C-shaped curve whose opening is smaller than the tolerance but many spacings wide stays open;
//! 3. the data continue smoothly through the gap: the tangent arriving at the last point and the
//!    tangent leaving the first, each estimated over a window of arc length
//!    [`CornerScale::measure`]`(points, tol, angle).window` ([`seam_turn`]), turn by at most the
//!    corner angle. The seam would not be a corner at the tolerance's scale, so closing it adds no
//!    feature the data do not show. A blunt trailing edge (the tangents reverse) stays open.
//!
//! Every quantity is a length compared with a length or an angle with an angle: scaling the points
//! and the tolerance together gives the same decision. The cost is O(1) for data whose gap exceeds
//! the tolerance (most open data); otherwise one noise estimate and two window sweeps.

use super::corners::{seam_turn, CornerScale};
use super::shape::looks_closed;
use crate::nurbs::Vec3;

/// How many of the data's spacings at an end a closing gap may span (rule 2 of the module doc).
pub const GAP_SPACINGS: f64 = 4.0;

/// The chords at each end whose median is the data's spacing there (fewer for short data).
pub const END_CHORDS: usize = 15;

/// The shape of data at their ends.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Closure {
    /// Open: two free ends.
    #[default]
    Open,
    /// Closed: the last point repeats the first, or the caller said so.
    Closed,
    /// Closed across the gap of this length (the points' units) from the last point to the first,
    /// by the rule of the module doc; the points are fitted as a loop as they are.
    Gap(f64),
}

impl Closure {
    /// Whether the data are fitted as a closed curve.
    pub fn is_closed(self) -> bool {
        !matches!(self, Closure::Open)
    }

    /// The gap closed by the rule of the module doc, if it was.
    pub fn gap(self) -> Option<f64> {
        match self {
            Closure::Gap(g) => Some(g),
            _ => None,
        }
    }
}

/// The closure of `points` at tolerance `tol` (the points' units) and corner angle `angle_deg`
/// (module doc).
///
/// ```
/// use fairfit::fit::closure::{closure_at_tolerance, Closure};
/// use fairfit::nurbs::Vec3;
/// // a circle of 400 points, the last one step before the first: closed across one step
/// let ring: Vec<Vec3> = (0..400)
///     .map(|i| {
///         let t = std::f64::consts::TAU * i as f64 / 400.0;
///         Vec3::new(t.cos(), t.sin(), 0.0)
///     })
///     .collect();
/// let step = ring[0].distance(ring[399]);
/// assert_eq!(closure_at_tolerance(&ring, 2e-2, 60.0), Closure::Gap(step));
/// // the tolerance below the gap (one step is 1.6e-2): open
/// assert_eq!(closure_at_tolerance(&ring, 1e-2, 60.0), Closure::Open);
/// // an arc of ten steps missing: open though within the tolerance
/// assert_eq!(closure_at_tolerance(&ring[..390], 0.2, 60.0), Closure::Open);
/// ```
pub fn closure_at_tolerance(points: &[Vec3], tol: f64, angle_deg: f64) -> Closure {
    let n = points.len();
    if n < 3 {
        return Closure::Open;
    }
    if looks_closed(points) {
        return Closure::Closed;
    }
    let gap = points[0].distance(points[n - 1]);
    if !(tol.is_finite() && tol > 0.0 && gap.is_finite() && gap <= tol) {
        return Closure::Open;
    }
    let k = END_CHORDS.min((n - 1) / 2).max(1);
    let spacing = median_chord(&points[..=k]).min(median_chord(&points[n - 1 - k..]));
    if !(spacing.is_finite() && gap <= GAP_SPACINGS * spacing) {
        return Closure::Open;
    }
    let scale = CornerScale::measure(points, tol, angle_deg);
    if seam_turn(points, &scale) <= angle_deg.to_radians() {
        Closure::Gap(gap)
    } else {
        Closure::Open
    }
}

/// The median length of the chords of `points` (at least two points).
fn median_chord(points: &[Vec3]) -> f64 {
    let mut d: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}
