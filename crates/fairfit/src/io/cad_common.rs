//! Helpers shared by the CAD writers ([`super::step`], [`super::iges`]): the length unit, full-precision
//! real formatting, knot compression to distinct values + multiplicities, the validation every writer
//! runs before producing a byte, and a UTC timestamp without a date-time crate.

use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};

/// The length unit declared in a CAD file. Coordinates are written as they are (no scaling).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LengthUnit {
    /// Millimetres.
    #[default]
    Millimetre,
    /// Metres.
    Metre,
}

impl std::str::FromStr for LengthUnit {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "mm" => Ok(LengthUnit::Millimetre),
            "m" => Ok(LengthUnit::Metre),
            other => Err(Error::InvalidOption(format!(
                "unknown length unit \"{other}\", expected \"mm\" or \"m\""
            ))),
        }
    }
}

/// A real number in the shortest form that reads back to the same `f64`, in the syntax STEP and IGES
/// both accept: always a decimal point, exponent letter `E` (`1.`, `0.25`, `1.5E-7`, `-3.E20`).
pub(crate) fn format_real(x: f64) -> String {
    let s = format!("{:?}", super::numbers::unsigned_zero(x));
    let (mantissa, exponent) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), Some(e.to_string())),
        None => (s, None),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').to_string()
    } else {
        format!("{mantissa}.")
    };
    match exponent {
        Some(e) => format!("{mantissa}E{e}"),
        None => mantissa,
    }
}

/// Distinct knot values and their multiplicities (exact equality: fairfit knots are stored exactly).
pub(crate) fn compress_knots(knots: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut values: Vec<f64> = Vec::new();
    let mut mults: Vec<usize> = Vec::new();
    for &k in knots {
        match values.last() {
            Some(&last) if last == k => {
                if let Some(m) = mults.last_mut() {
                    *m += 1;
                }
            }
            _ => {
                values.push(k);
                mults.push(1);
            }
        }
    }
    (values, mults)
}

/// Checks a knot vector for a CAD writer: valid for the degree and no interior knot of multiplicity
/// above the degree (CAD kernels reject such discontinuous splines).
fn check_knots(knots: &[f64], degree: usize, n_ctrl: usize, what: &str) -> Result<()> {
    crate::nurbs::knots::validate_knots(knots, degree, n_ctrl, what)?;
    let (values, mults) = compress_knots(knots);
    for (i, (&v, &m)) in values.iter().zip(&mults).enumerate() {
        let interior = i > 0 && i + 1 < values.len();
        if interior && m > degree {
            return Err(Error::InvalidKnots(format!(
                "{what}: interior knot {v} has multiplicity {m} > degree {degree}; \
                 a CAD file cannot hold a discontinuous spline (split it first)"
            )));
        }
    }
    Ok(())
}

fn check_points(points: &[Vec3], weights: &[f64]) -> Result<()> {
    if let Some(i) = points
        .iter()
        .position(|p| p.0.iter().any(|c| !c.is_finite()))
    {
        return Err(Error::InvalidControlPoints(format!(
            "control point {i} is not finite ({:?})",
            points[i].0
        )));
    }
    if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(Error::InvalidWeights(format!(
            "weight {i} = {} is not positive and finite",
            weights[i]
        )));
    }
    Ok(())
}

/// Validates a curve before it is written (finite data, a knot vector a CAD kernel accepts).
pub fn validate_curve(c: &NurbsCurve) -> Result<()> {
    check_points(c.control_points(), c.weights())?;
    check_knots(c.knots(), c.degree(), c.n_control_points(), "curve")
}

/// Validates a surface before it is written (finite data, knot vectors a CAD kernel accepts).
pub fn validate_surface(s: &NurbsSurface) -> Result<()> {
    check_points(s.control_points_flat(), s.weights_flat())?;
    let (n_u, n_v) = s.net_size();
    check_knots(s.knots_u(), s.degree_u(), n_u, "u direction")?;
    check_knots(s.knots_v(), s.degree_v(), n_v, "v direction")
}

/// The largest absolute coordinate of a set of points (IGES global field 20).
pub(crate) fn max_coordinate(points: &[Vec3]) -> f64 {
    points
        .iter()
        .flat_map(|p| p.0)
        .fold(0.0_f64, |m, c| m.max(c.abs()))
}

/// The current UTC date and time as `(year, month, day, hour, minute, second)`.
pub(crate) fn utc_now() -> (i64, u32, u32, u32, u32, u32) {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    let (h, m, s) = (rem / 3600, (rem % 3600) / 60, rem % 60);
    (year, month, day, h as u32, m as u32, s as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_read_back_exactly_in_cad_syntax() {
        for (x, want) in [
            (1.0, "1."),
            (0.25, "0.25"),
            (-3.0e20, "-3.E20"),
            (1.5e-7, "1.5E-7"),
            (0.1, "0.1"),
        ] {
            assert_eq!(format_real(x), want);
        }
        for x in [
            std::f64::consts::PI,
            1.0 / 3.0,
            -2.2250738585072014e-308,
            12345.678e9,
        ] {
            let s = format_real(x);
            assert!(s.contains('.'), "{s}");
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
        }
    }

    #[test]
    fn knots_compress_to_values_and_multiplicities() {
        let (v, m) = compress_knots(&[0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0]);
        assert_eq!(v, vec![0.0, 0.5, 1.0]);
        assert_eq!(m, vec![3, 2, 3]);
    }

    #[test]
    fn a_discontinuous_interior_knot_is_rejected() {
        let pts = (0..6).map(|i| Vec3::new(i as f64, 0.0, 0.0)).collect();
        let knots = vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
        let c = NurbsCurve::bspline(2, knots, pts).unwrap();
        let e = validate_curve(&c).unwrap_err().to_string();
        assert!(e.contains("multiplicity 3"), "{e}");
    }

    #[test]
    fn utc_now_is_a_plausible_date() {
        let (y, mo, d, h, mi, s) = utc_now();
        assert!((2024..2200).contains(&y));
        assert!((1..=12).contains(&mo) && (1..=31).contains(&d));
        assert!(h < 24 && mi < 60 && s < 60);
    }
}
