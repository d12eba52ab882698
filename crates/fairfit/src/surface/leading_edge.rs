//! Airfoil sections split at their leading edges (`fairfit surface --split-at-le`,
//! [`super::CompatibleOptions::split_at_le`]): every section's leading edge is pinned to the common
//! parameter `u_LE` = [`LEADING_EDGE_PARAMETER`] (0.5, as `fairfit curve --split-at-le` writes it),
//! so the skinned surface's iso-curve `u = u_LE` is the blade's leading edge.
//!
//! - The leading edge of a section is [`crate::fit::airfoil::leading_edge`] of its points (as
//!   oriented and seam-aligned by [`super::orient`]): the point farthest from the midpoint of its first
//!   and last points, the first point of a closed section. A section whose leading edge would be an end
//!   point is refused, naming it.
//! - The parameters are piecewise chord length with the leading edge as one more break point: the
//!   points up to it on `[0, u_LE]`, the rest on `[u_LE, 1]`. Held corners
//!   ([`super::section_corners`]) keep their C0 knots; their common parameters are then the
//!   sections' averaged chord positions within their half, so every corner stays on its side of
//!   `u_LE`. A leading edge that is a held corner, or corners on different sides of the leading edge in
//!   different sections, are refused, naming the section.
//! - Dense sections ([`super::dense`]) are fitted through representatives of tolerance-sized arcs;
//!   the arc holding the data's leading edge is represented by that point itself, so the point
//!   pinned is the data's.
//! - The leading edge is NOT a knot: the sections share one knot vector anyway, so pinning adds no
//!   knot per section. The leading edge's parameter is held through the parameter correction, and
//!   every section fit passes through its leading-edge point exactly at `u_LE` (one equality
//!   constraint on the least squares, in the open, periodic and tied-seam solvers alike,
//!   [`super::section_fit`]).

use super::orient::Section;
use super::section_corners::{cumulative_chords, piecewise_params, CornerPlan};
use super::section_fit::SectionFit;
use crate::errors::{Error, Result};
use crate::fit::airfoil::leading_edge;
pub use crate::fit::airfoil::LEADING_EDGE_PARAMETER;
use crate::nurbs::{NurbsSurface, Vec3};
use serde::Serialize;

/// One section's leading edge and how far the fit is from it (the report's `split_at_le.sections`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SectionLeadingEdge {
    /// The section (input order).
    pub index: usize,
    /// The leading edge's point index in the section as fitted (after orientation and seam alignment).
    pub point_index: usize,
    /// The leading-edge point.
    pub point: Vec3,
    /// `|C(u_LE) − point|` on the section curve (0 up to rounding: the fit passes through it).
    pub distance: f64,
    /// `|S(u_LE, v) − point|` on the surface at the section's `v` (`None` before skinning).
    pub surface_distance: Option<f64>,
}

/// The sections' leading edges pinned to one parameter (the report's `split_at_le`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LeadingEdges {
    /// The common parameter `u_LE` of the leading edges.
    pub parameter: f64,
    /// One row per section, in input order.
    pub sections: Vec<SectionLeadingEdge>,
    /// The largest [`SectionLeadingEdge::distance`].
    pub max_distance: f64,
    /// The largest [`SectionLeadingEdge::surface_distance`]: how far the surface's iso-curve
    /// `u = u_LE` passes from the leading-edge points (`None` before skinning).
    pub surface_max_distance: Option<f64>,
}

impl LeadingEdges {
    /// The fitted section curves' distances from their leading-edge points at `u_LE`.
    pub(crate) fn measure(sections: &[Section], les: &[usize], fits: &[SectionFit]) -> Self {
        let u = LEADING_EDGE_PARAMETER;
        let rows: Vec<SectionLeadingEdge> = sections
            .iter()
            .zip(les)
            .zip(fits)
            .enumerate()
            .map(|(index, ((s, &i), f))| SectionLeadingEdge {
                index,
                point_index: i,
                point: s.points[i],
                distance: (f.curve.point(u) - s.points[i]).norm(),
                surface_distance: None,
            })
            .collect();
        LeadingEdges {
            parameter: u,
            max_distance: rows.iter().map(|r| r.distance).fold(0.0, f64::max),
            sections: rows,
            surface_max_distance: None,
        }
    }

    /// Adds the distances of the surface's iso-curve `u = u_LE` from the leading-edge points, each at
    /// its section's `v` (`v_params`, in section order).
    pub(crate) fn measure_surface(&mut self, surface: &NurbsSurface, v_params: &[f64]) {
        let mut max = 0.0f64;
        for (row, &v) in self.sections.iter_mut().zip(v_params) {
            let d = (surface.point(self.parameter, v) - row.point).norm();
            row.surface_distance = Some(d);
            max = max.max(d);
        }
        self.surface_max_distance = Some(max);
    }
}

/// Every section's leading-edge point index; a section without one (its farthest point from the
/// trailing edge is an end point) is an [`Error::InvalidData`] naming it.
pub(crate) fn find_leading_edges(sections: &[Section]) -> Result<Vec<usize>> {
    sections
        .iter()
        .enumerate()
        .map(|(k, s)| {
            leading_edge(&s.points).ok_or_else(|| {
                Error::InvalidData(format!(
                    "section {k}: no leading edge to split at: the point farthest from the trailing \
                     edge (the midpoint of its first and last points) is an end point"
                ))
            })
        })
        .collect()
}

/// The sections' point parameters with each leading edge (`les`) at `u_LE` (module doc): piecewise
/// chord length with the leading edge and the held corners of `plan` as break points. The plan's
/// corner parameters are replaced by the sections' averaged chord positions within their half.
pub(crate) fn split_params(
    sections: &[Section],
    les: &[usize],
    plan: Option<&mut CornerPlan>,
) -> Result<Vec<Vec<f64>>> {
    let u_le = LEADING_EDGE_PARAMETER;
    let no_corners: Vec<Vec<usize>> = vec![Vec::new(); sections.len()];
    let corner_idx = plan.as_ref().map_or(&no_corners, |p| &p.indices);
    let n_corners = corner_idx.first().map_or(0, Vec::len);
    let mut sums = vec![0.0; n_corners];
    let mut before: Option<Vec<bool>> = None;
    for (k, ((s, &le), idx)) in sections.iter().zip(les).zip(corner_idx).enumerate() {
        let c = cumulative_chords(&s.points);
        let (to_le, total) = (c[le], c[c.len() - 1]);
        if !(to_le > 0.0 && total - to_le > 0.0) {
            return Err(Error::InvalidData(format!(
                "section {k}: one side of its leading edge (point {le}) has zero length"
            )));
        }
        if idx.contains(&le) {
            return Err(Error::InvalidData(format!(
                "section {k}: its leading edge (point {le}) is a held corner: smooth the corners \
                 over or do not split at the leading edge"
            )));
        }
        let sides: Vec<bool> = idx.iter().map(|&i| i < le).collect();
        if before.as_ref().is_some_and(|b| *b != sides) {
            return Err(Error::InvalidData(format!(
                "section {k}: its held corners lie on other sides of its leading edge than in \
                 section 0: smooth the corners over or do not split at the leading edge"
            )));
        }
        for (sum, &i) in sums.iter_mut().zip(idx) {
            *sum += if i < le {
                u_le * c[i] / to_le
            } else {
                u_le + (1.0 - u_le) * (c[i] - to_le) / (total - to_le)
            };
        }
        before = Some(sides);
    }
    let corner_params: Vec<f64> = sums.iter().map(|s| s / sections.len() as f64).collect();
    let params: Vec<Vec<f64>> = sections
        .iter()
        .zip(les)
        .zip(corner_idx)
        .map(|((s, &le), idx)| {
            let mut breaks: Vec<(usize, f64)> = idx
                .iter()
                .copied()
                .zip(corner_params.iter().copied())
                .collect();
            breaks.push((le, u_le));
            breaks.sort_by_key(|&(i, _)| i);
            let (at_idx, at): (Vec<usize>, Vec<f64>) = breaks.into_iter().unzip();
            piecewise_params(&s.points, &at_idx, &at)
        })
        .collect();
    if let Some(k) = params.iter().position(|t| t.iter().any(|u| !u.is_finite())) {
        return Err(Error::InvalidData(format!(
            "section {k}: a piece between its leading edge and a held corner has zero length"
        )));
    }
    if let Some(plan) = plan {
        plan.params = corner_params;
    }
    Ok(params)
}
