//! Tests of `fairfit::optim::fairing`: band fairing and the periodic fairing.

mod band;
mod periodic;
