//! Tests of `fairfit::optim::stages`, one file (or folder) per stage.

mod degree_search;
mod own_count_search;
mod reduce;
mod release_ends;
