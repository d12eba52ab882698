//! The stages of the pipelines, in pipeline order; each takes the fit's context
//! (`crate::optim::context::FitContext`), a curve kind (`crate::optim::kind::CurveKind`) where
//! the stage is shared by open and periodic curves, and an input, and returns an output.

pub mod baseline;
pub mod count_choice;
pub mod count_search;
pub mod degree_candidates;
pub mod degree_search;
pub mod descent;
pub mod own_count_search;
pub mod reduce;
pub mod release_ends;
pub mod warm_ends;
