//! `fairfit info`: a summary of a curve or surface JSON file as a JSON object on stdout. Curves: size,
//! knots, domain, length and every fairness measure of `fairfit::fair::curve_fairness` (its
//! `curvature_extrema` counts at the benchmark measurer's 192 samples per span;
//! `curvature_extrema_exact` is `fairfit::fair::count_extrema_exact`, from the roots of `dκ/ds`, which
//! also sees wiggles narrower than the samples, for rational and spatial curves too; `inflections_exact`
//! likewise counts the sign changes of a planar curve's signed curvature from the roots of its
//! numerator, `fairfit::fair::count_inflections_exact`; both made in one pass by
//! `fairfit::fair::count_shape_exact`); surfaces: net
//! size, degrees, domains and the fairness of iso-parametric curves in both directions: `along_u` holds
//! the curves `u ↦ S(u, v_k)` (the section curves of a skinned surface), `along_v` the curves
//! `v ↦ S(u_k, v)`, as in the `iso_fairness` of the `fairfit surface` report (same count by default).
//! For a STEP or IGES input, `source` says what was read: format, entity, kind, index among the
//! entities of its kind and their count, and the unit (`mm_per_unit`: the factor applied to reach mm).

use super::{print_json, CliError, CmdResult};
use clap::Args;
use fairfit::diffgeo::differentials;
use fairfit::fair::span_hodograph::speed_critical_points;
use fairfit::fair::{surface_fairness, try_curve_fairness, DEFAULT_ISO_CURVES};
use fairfit::io::Geometry;
use fairfit::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use fairfit::report::curve::exact_shape_json;
use serde_json::{json, Value};
use std::path::PathBuf;

/// Arguments of `fairfit info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Input file(s), JSON, STEP or IGES: one prints a JSON object, several print an array of objects.
    #[arg(required = true)]
    pub input: Vec<PathBuf>,
    /// Entity choice for STEP/IGES input.
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// Number of iso-parametric curves per direction for surfaces (ends included; the default is the
    /// count of the `fairfit surface` report).
    #[arg(long, default_value_t = DEFAULT_ISO_CURVES as u64, allow_hyphen_values = true,
          value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub iso: u64,
}

/// Runs `fairfit info`.
pub fn run(args: InfoArgs) -> CmdResult {
    let mut out = Vec::with_capacity(args.input.len());
    for path in &args.input {
        let (geometry, source) = super::cad_input::read_input_with_source(path, &args.cad)?;
        super::work::check_spans(&geometry, path)?;
        let mut v = match geometry {
            Geometry::Curve(c) => curve_info(&c)?,
            Geometry::Surface(s) => surface_info(&s, args.iso as usize)?,
        };
        if let (Some(src), Value::Object(m)) = (source, &mut v) {
            m.insert("source".into(), src);
        }
        if args.input.len() > 1 {
            if let Value::Object(m) = &mut v {
                m.insert("file".into(), json!(path.display().to_string()));
            }
        }
        out.push(v);
    }
    match out.len() {
        1 => print_json(&out[0]),
        _ => print_json(&Value::Array(out)),
    }
}

/// The first parameter where `c` is not regular (its speed vanishes, decided scale-free by
/// [`fairfit::diffgeo::CurveDifferentials::regular`]), with an unbounded curvature when `unbounded`
/// (see [`unbounded_curvature_at`]), searched at the knots (where coinciding control points put such
/// points) and where the speed is stationary inside a span
/// ([`fairfit::fair::span_hodograph::speed_critical_points`], exact roots, not samples): a zero of
/// the speed inside a span is a minimum of it.
fn first_irregular_parameter(c: &NurbsCurve, unbounded: bool) -> Option<f64> {
    let (a, b) = c.domain();
    let mut candidates: Vec<f64> = c
        .knots()
        .iter()
        .copied()
        .filter(|&k| (a..=b).contains(&k))
        .chain(speed_critical_points(c))
        .collect();
    candidates.sort_by(f64::total_cmp);
    candidates.dedup();
    candidates.into_iter().find(|&u| {
        if unbounded {
            unbounded_curvature_at(c, u)
        } else {
            !differentials(c, u).regular
        }
    })
}

/// True where `c` is not regular at `u` and its curvature grows without bound there: near a zero of
/// `C'`, `C' ≈ C'' h` and `κ ≈ |C'' × C'''| / (2 |C''|³ h²)`, unbounded unless `C''` is parallel to
/// `C'''` (a straight piece with a repeated control point keeps κ = 0) or `C''` vanishes too (then
/// left as it was: not decided here).
fn unbounded_curvature_at(c: &NurbsCurve, u: f64) -> bool {
    let d = differentials(c, u);
    if d.regular {
        return false;
    }
    // C'' and C''' as unit vectors (divided by their largest coordinate first: on a curve 1e±200
    // in size their squares are beyond the floating-point range)
    let unit = |v: Vec3| {
        let m = v.max_abs();
        (m > 0.0 && m.is_finite()).then(|| {
            let w = v / m;
            w / w.norm()
        })
    };
    match (unit(d.d2), unit(d.d3)) {
        (Some(a), Some(b)) => a.cross(b).norm() > 1e-9,
        _ => false,
    }
}

fn curve_info(c: &NurbsCurve) -> Result<Value, CliError> {
    let f = try_curve_fairness(c)?;
    let (a, b) = c.domain();
    // with zero speed somewhere the curvature is unbounded there and F, the energies are undefined
    // (the quadrature gives a huge, meaningless number); a curve of length 0 is left as it was
    let irregular = (f.length > 0.0)
        .then(|| first_irregular_parameter(c, true))
        .flatten();
    let regular = first_irregular_parameter(c, false).is_none();
    super::finite("curve's length", f.length)?;
    if irregular.is_none() {
        for (what, x) in [
            ("curve's energy", f.energy),
            ("curve's fairness F", f.fairness),
            ("curve's largest span fairness", f.max_span_fairness),
            ("curve's bending energy", f.bending_energy),
        ] {
            super::finite(what, x)?;
        }
    }
    let (extrema_exact, inflections_exact) = exact_shape_json(c, f.length);
    let mut info = json!({
        "kind": "curve",
        "degree": c.degree(),
        "control_points": c.n_control_points(),
        "knots": c.knots().len(),
        "spans": f.span_fairness.len(),
        "rational": c.is_rational(),
        "domain": [a, b],
        "length": f.length,
        "regular": regular,
        "energy": f.energy,
        "fairness": f.fairness,
        "max_span_fairness": f.max_span_fairness,
        "span_fairness": f.span_fairness,
        "bending_energy": f.bending_energy,
        "curvature_extrema": f.curvature_extrema,
        "curvature_extrema_exact": extrema_exact,
        "inflections": f.inflections,
        "inflections_exact": inflections_exact,
    });
    if let (Some(u), Some(fields)) = (irregular, info.as_object_mut()) {
        fields.insert("regular".into(), Value::Bool(false));
        fields.insert("note".into(), json!(format!("the curve is not regular at u = {u} (its speed |C'| vanishes, e.g. where control points coincide): its curvature is unbounded there, so energy, fairness, span_fairness and bending_energy are undefined")));
        for key in [
            "energy",
            "fairness",
            "max_span_fairness",
            "span_fairness",
            "bending_energy",
        ] {
            fields.insert(key.into(), Value::Null);
        }
    }
    Ok(info)
}

fn surface_info(s: &NurbsSurface, n_iso: usize) -> Result<Value, CliError> {
    let f = surface_fairness(s, n_iso)?;
    super::finite("largest iso-curve fairness along u", f.max_fairness_v)?;
    super::finite("largest iso-curve fairness along v", f.max_fairness_u)?;
    let (n_u, n_v) = s.net_size();
    let iso = serde_json::to_value(&f).map_err(|e| CliError::new(format!("internal: {e}")))?;
    Ok(json!({
        "kind": "surface",
        "net_size": [n_u, n_v],
        "degree_u": s.degree_u(),
        "degree_v": s.degree_v(),
        "knots_u": s.knots_u().len(),
        "knots_v": s.knots_v().len(),
        "rational": s.is_rational(),
        "domain_u": [s.domain_u().0, s.domain_u().1],
        "domain_v": [s.domain_v().0, s.domain_v().1],
        "iso_curves_per_direction": f.iso_curves_per_direction,
        "max_fairness_along_u": f.max_fairness_v,
        "max_fairness_along_v": f.max_fairness_u,
        "iso_curves": iso,
    }))
}
