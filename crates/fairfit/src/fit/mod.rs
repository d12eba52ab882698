//! Least-squares fitting of ordered points: point input, parameterisation, knot placement, banded
//! least squares with optional smoothing, parameter correction, closed curves, corners and
//! tolerance-driven knot counts.
