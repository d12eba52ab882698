//! The three curve-fitting methods a front end offers, and which method-specific options each one
//! honours: the one table the command-line tool and the Python package check their options
//! against, so that an option the chosen method would ignore is refused, never silently dropped.
//!
//! - [`Method::Lsq`]: least squares with a tolerance-driven knot count ([`crate::fit`]);
//! - [`Method::FitThenFair`]: least squares, then fairing within the same tolerance;
//! - [`Method::Integrated`]: the integrated fitting-and-fairing method ([`crate::optim`]).
//!
//! Invariant: every [`MethodOption`] is honoured by the integrated method or by both least-squares
//! methods, never by a mix ([`MethodOption::used_by`]).
//!
//! ```
//! use fairfit::fit::method::{Method, MethodOption};
//! let given = [MethodOption::SpanFairness, MethodOption::Knots];
//! assert_eq!(Method::Lsq.first_ignored(given), Some(MethodOption::SpanFairness));
//! assert_eq!(Method::Integrated.first_ignored(given), Some(MethodOption::Knots));
//! assert_eq!(Method::Integrated.first_ignored([MethodOption::SpanFairness]), None);
//! ```

use std::fmt;
use std::str::FromStr;

/// A curve-fitting method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Least squares with a tolerance-driven knot count.
    Lsq,
    /// The integrated fitting-and-fairing method (knots by particle swarm optimisation).
    Integrated,
    /// Least squares, then fairing of the fitted curve within the same tolerance.
    FitThenFair,
}

impl Method {
    /// The method's name as both front ends spell it (`lsq`, `integrated`, `fit-then-fair`).
    pub fn name(self) -> &'static str {
        match self {
            Method::Lsq => "lsq",
            Method::Integrated => "integrated",
            Method::FitThenFair => "fit-then-fair",
        }
    }

    /// The first option of `given` that this method ignores (the order of `given` is kept).
    pub fn first_ignored(
        self,
        given: impl IntoIterator<Item = MethodOption>,
    ) -> Option<MethodOption> {
        given.into_iter().find(|o| !o.used_by(self))
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    /// `lsq`, `integrated`, `fit-then-fair` (or `fit_then_fair`).
    fn from_str(text: &str) -> Result<Method, String> {
        match text {
            "integrated" => Ok(Method::Integrated),
            "lsq" => Ok(Method::Lsq),
            "fit-then-fair" | "fit_then_fair" => Ok(Method::FitThenFair),
            _ => Err(format!(
                "expected `integrated`, `lsq` or `fit-then-fair`, got `{text}`"
            )),
        }
    }
}

/// An option that only some methods honour (named here by its library meaning; each front end
/// spells it as its flag or keyword).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodOption {
    /// The knot placement rule of least squares.
    Knots,
    /// The parameterisation of least squares.
    Param,
    /// Parameter-correction rounds of least squares.
    CorrectionRounds,
    /// The smoothing weight of least squares.
    Smoothing,
    /// The derivative order the smoothing term penalises.
    SmoothingOrder,
    /// The integrated method's bound on every span's fairness `F_j`.
    SpanFairness,
    /// The integrated method's Pareto front of deviation against fairness.
    Pareto,
    /// The curves of that Pareto front.
    ParetoCurves,
    /// Switching off the integrated method's band fairing.
    BandFairing,
}

impl MethodOption {
    /// Whether `method` honours this option: the least-squares options by `lsq` and
    /// `fit-then-fair`, the others by `integrated` only.
    pub fn used_by(self, method: Method) -> bool {
        let least_squares = matches!(
            self,
            MethodOption::Knots
                | MethodOption::Param
                | MethodOption::CorrectionRounds
                | MethodOption::Smoothing
                | MethodOption::SmoothingOrder
        );
        least_squares != (method == Method::Integrated)
    }

    /// The methods that honour this option, as a front end names them in an error
    /// (`lsq or fit-then-fair`, or `integrated`).
    pub fn methods(self) -> &'static [Method] {
        if self.used_by(Method::Integrated) {
            &[Method::Integrated]
        } else {
            &[Method::Lsq, Method::FitThenFair]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [MethodOption; 9] = [
        MethodOption::Knots,
        MethodOption::Param,
        MethodOption::CorrectionRounds,
        MethodOption::Smoothing,
        MethodOption::SmoothingOrder,
        MethodOption::SpanFairness,
        MethodOption::Pareto,
        MethodOption::ParetoCurves,
        MethodOption::BandFairing,
    ];

    #[test]
    fn every_option_belongs_to_the_integrated_method_or_to_both_least_squares_methods() {
        let integrated = 5..9;
        for (i, o) in ALL.into_iter().enumerate() {
            let (i_uses, l, f) = (
                o.used_by(Method::Integrated),
                o.used_by(Method::Lsq),
                o.used_by(Method::FitThenFair),
            );
            assert_eq!(i_uses, integrated.contains(&i), "{o:?}");
            assert_eq!((l, f), (!i_uses, !i_uses), "{o:?}");
            assert!(o.methods().iter().all(|&m| o.used_by(m)), "{o:?}");
        }
    }

    #[test]
    fn names_round_trip() {
        for m in [Method::Lsq, Method::Integrated, Method::FitThenFair] {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
        }
        assert_eq!("fit_then_fair".parse::<Method>(), Ok(Method::FitThenFair));
        assert!("splprep".parse::<Method>().unwrap_err().contains("splprep"));
    }
}
