//! `fairfit curve --method integrated` (`src/commands/curve_optim.rs`): the default method, the
//! degree search, end conditions, closed data and data with corners.

mod closed;
mod degree;
mod dense;
mod ends;
mod integrated;
