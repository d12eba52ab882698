//! The allowed maximum orthogonal deviation of a fit: the one tolerance type of the least-squares
//! method ([`crate::fit`]) and the integrated method ([`crate::optim`]).

/// The tolerance on the maximum orthogonal deviation of the fitted curve from the data.
///
/// ```
/// use fairfit::Tolerance;
/// // 1e-3 of the largest side of the data's bounding box, or 0.05 in the data's units
/// let rel = Tolerance::Relative(1e-3);
/// let abs = Tolerance::Absolute(0.05);
/// assert_ne!(rel, abs);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tolerance {
    /// A fraction of the largest side of the data's bounding box.
    Relative(f64),
    /// A distance in the data's units.
    Absolute(f64),
}
