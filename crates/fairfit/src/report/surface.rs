//! The `--report` JSON of a surface fit ([`surface_report`]): the tolerance and whether it was met,
//! the net, the deviation, the iso-curve fairness, the shared knots, and one row per section; with
//! `relaxed_smoothing` when the knot search relaxed its bending term
//! ([`crate::surface::SurfaceReconstruction::relaxed_smoothing`]).
//!
//! Key names are a public contract (scripts read them); a new key may be added, none renamed.

use crate::surface::cad_skin::ExactSkin;
use crate::surface::chain::Gap;
use crate::surface::SurfaceReconstruction;
use serde_json::{json, Value};

/// What the input side knows of the sections of a surface fit, for its report.
#[derive(Clone, Debug, Default)]
pub struct SectionNotes {
    /// A name per section (file name, or `plane at H` for a slice), in the order fitted.
    pub names: Vec<String>,
    /// Gaps found while chaining slices into sections.
    pub gaps: Vec<Gap>,
    /// The offsets of slicing planes that cut nothing.
    pub empty_planes: Vec<f64>,
    /// Per section: the chains of its slice dropped as too small.
    pub dropped_chains: Vec<usize>,
}

/// The report of the surface `r` fitted at the absolute tolerance `tol`, with `notes` on its
/// sections and, for CAD sections, `exact` (how far the exact section curves are from the surface).
///
/// `within_tolerance` holds when every section point and, with `exact`, every exact section is
/// within `tol` (the meaningful tolerance of noisy dense sections when `tol` is below their noise;
/// `dense` then says so, [`crate::surface::DenseSummary`]).
pub fn surface_report(
    r: &SurfaceReconstruction,
    tol: f64,
    notes: &SectionNotes,
    exact: Option<&ExactSkin>,
) -> Value {
    let (nu, nv) = r.surface.net_size();
    let within = r.deviation.max <= r.tolerance_used(tol) && exact.is_none_or(|e| e.met);
    let sections: Vec<Value> = r
        .sections
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let mut row = json!({
                "name": notes.names.get(k),
                "points": s.points.len(),
                "closed": s.closed,
                "reversed": r.alignment[k].0,
                "seam_shift": r.alignment[k].1,
                "v": r.v_params[k],
                "max_deviation": r.section_deviation[k],
                "exact_max_deviation": exact.map(|e| e.section_max_deviation[k]),
                "dropped_chains": notes.dropped_chains.get(k),
                "corners_held": if r.compatible.corners.held {
                    r.compatible.corners.per_section.get(k).copied().unwrap_or(0)
                } else {
                    0
                },
            });
            // only for a section closed across a gap: other reports keep their bytes
            if let (Some(Some(g)), Some(obj)) = (r.closed_by_gap.get(k), row.as_object_mut()) {
                obj.insert("closed_by_gap".into(), json!(g));
            }
            row
        })
        .collect();
    let mut report = json!({
        "tolerance": tol,
        "within_tolerance": within,
        "net": [nu, nv],
        "degree": [r.surface.degree_u(), r.surface.degree_v()],
        "deviation": r.deviation,
        "section_fit_max_deviation": r.compatible.max_deviation,
        "section_max_span_fairness": r.compatible.max_span_fairness,
        "iso_fairness": r.fairness,
        "knots_u": r.compatible.knots,
        "periodic_u": r.compatible.periodic,
        "corners": r.compatible.corners,
        "seam": r.seam,
        "v_params": r.v_params,
        "candidates_tried": r.compatible.candidates_tried,
        "sections": sections,
        "gaps": notes.gaps,
        "empty_planes": notes.empty_planes,
        "exact_sections": exact.map(exact_json),
    });
    // only when the sections were dense: the plain pipeline's report keeps its bytes
    if let (Some(d), Some(obj)) = (&r.dense, report.as_object_mut()) {
        obj.insert("dense".into(), json!(d));
    }
    // only when the leading edges were pinned (split_at_le), for the same reason
    if let (Some(le), Some(obj)) = (&r.compatible.leading_edges, report.as_object_mut()) {
        obj.insert("split_at_le".into(), json!(le));
    }
    // only when the knot search had to relax its smoothing, for the same reason
    if let (Some(w), Some(obj)) = (r.relaxed_smoothing, report.as_object_mut()) {
        obj.insert("relaxed_smoothing".into(), json!(w));
    }
    // only when v end tangents were asked, for the same reason
    if let (Some(t), Some(obj)) = (&r.v_end_tangents, report.as_object_mut()) {
        obj.insert("v_end_tangents".into(), json!(t));
    }
    report
}

/// The report's `exact_sections`: how far the exact CAD sections are from the surface.
fn exact_json(e: &ExactSkin) -> Value {
    json!({
        "max_deviation": e.max_deviation,
        "within_tolerance": e.met,
        "checked_points": e.checked,
        "first_max_deviation": e.first_max_deviation,
        "refits": e.refits,
        "fit_tolerance": e.fit_tolerance,
        "added_points": e.added,
    })
}
