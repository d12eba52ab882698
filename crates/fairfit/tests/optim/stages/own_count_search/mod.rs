//! The next degree's own count search in the degree search (`optim::stages::own_count_search`): its
//! triggers (wiggly curve, steep count gain, an unfair kept count), each on the curve that shows it.

mod count_gain;
mod unfair_count;
mod wiggly;
