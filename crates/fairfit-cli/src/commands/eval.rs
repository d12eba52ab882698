//! `fairfit eval`: a curve or surface JSON file evaluated at given parameters, printed as a JSON array
//! (points, derivatives, curvature, torsion and dκ/ds for curves; partials and Gaussian/mean curvature
//! for surfaces).

use super::{print_json, CliError, CmdResult};
use clap::Args;
use fairfit::diffgeo::{differentials, surface_curvature_from};
use fairfit::io::Geometry;
use fairfit::nurbs::scale::{normalising_factor, scaled_surface};
use fairfit::nurbs::{NurbsCurve, NurbsSurface, SurfaceWorkspace, Vec3};
use serde_json::{json, Value};
use std::path::PathBuf;

/// Arguments of `fairfit eval`.
#[derive(Args, Debug)]
pub struct EvalArgs {
    /// The curve or surface file (JSON, STEP or IGES).
    pub input: PathBuf,
    /// Entity choice for STEP/IGES input.
    #[command(flatten)]
    pub cad: super::cad_input::CadInputArgs,
    /// Parameters: `U1,U2,...` for a curve, `U1:V1,U2:V2,...` for a surface.
    #[arg(long, allow_hyphen_values = true)]
    pub at: String,
}

/// Runs `fairfit eval`.
pub fn run(args: EvalArgs) -> CmdResult {
    let geometry = super::cad_input::read_input(&args.input, &args.cad)?;
    let out = match geometry {
        Geometry::Curve(c) => eval_curve(&c, &parse_curve_params(&args.at)?)?,
        Geometry::Surface(s) => eval_surface(&s, &parse_surface_params(&args.at)?)?,
    };
    print_json(&Value::Array(out))
}

/// One number of the `--at` list.
fn parse_number(text: &str) -> Result<f64, CliError> {
    let t = text.trim();
    match t.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(CliError::usage(format!(
            "--at: `{t}` is not a finite number (expected e.g. --at 0,0.5,1 or --at 0.2:0.3,0.5:0.5)"
        ))),
    }
}

/// The entries of a comma-separated `--at` list (none empty).
fn entries(at: &str) -> Result<Vec<&str>, CliError> {
    let items: Vec<&str> = at.split(',').map(str::trim).collect();
    if items.iter().any(|s| s.is_empty()) {
        return Err(CliError::usage(format!(
            "--at: empty entry in `{at}`; give comma-separated parameters like 0,0.5,1"
        )));
    }
    Ok(items)
}

/// `U1,U2,...` for curves.
fn parse_curve_params(at: &str) -> Result<Vec<f64>, CliError> {
    entries(at)?
        .into_iter()
        .map(|s| {
            if s.contains(':') {
                Err(CliError::usage(format!(
                    "--at: `{s}` is a surface parameter pair, but the file holds a curve"
                )))
            } else {
                parse_number(s)
            }
        })
        .collect()
}

/// `U1:V1,U2:V2,...` for surfaces.
fn parse_surface_params(at: &str) -> Result<Vec<(f64, f64)>, CliError> {
    entries(at)?
        .into_iter()
        .map(|s| match s.split_once(':') {
            Some((u, v)) if !v.contains(':') => {
                if u.trim().is_empty() || v.trim().is_empty() {
                    return Err(CliError::usage(format!(
                        "--at: `{s}` lacks its {} value (expected U:V pairs like 0.2:0.3)",
                        if u.trim().is_empty() { "U" } else { "V" }
                    )));
                }
                Ok((parse_number(u)?, parse_number(v)?))
            }
            _ => Err(CliError::usage(format!(
                "--at: `{s}` is not a U:V pair (the file holds a surface)"
            ))),
        })
        .collect()
}

/// A number as the user would write it: plain when short, else in exponent form (`1e300`, not 301
/// digits).
fn short(x: f64) -> String {
    let plain = x.to_string();
    if plain.len() <= 12 {
        plain
    } else {
        format!("{x:e}")
    }
}

/// Fails with a one-line message when `x` lies outside `[a, b]` (with the library's 1e-12 relative
/// slack): `name` is the parameter's name (`u` or `v`).
fn check_in_domain(name: &str, x: f64, (a, b): (f64, f64)) -> Result<(), CliError> {
    let slack = 1e-12 * (b - a);
    if x < a - slack || x > b + slack {
        return Err(CliError::new(format!(
            "--at: parameter {name} = {} is outside the domain [{}, {}] of {name}",
            short(x),
            short(a),
            short(b)
        )));
    }
    Ok(())
}

fn arr(v: Vec3) -> Value {
    json!([v.x(), v.y(), v.z()])
}

fn eval_curve(c: &NurbsCurve, us: &[f64]) -> Result<Vec<Value>, CliError> {
    us.iter()
        .map(|&u| {
            check_in_domain("u", u, c.domain())?;
            c.check_parameter(u)?;
            let d = differentials(c, u);
            let point = arr(d.point);
            let derivatives = json!([arr(d.d1), arr(d.d2), arr(d.d3)]);
            if !d.regular {
                // zero speed: κ, τ and dκ/ds are undefined, not 0
                return Ok(json!({
                    "u": u,
                    "point": point,
                    "derivatives": derivatives,
                    "regular": false,
                    "curvature": null,
                    "torsion": null,
                    "dkappa_ds": null,
                    "note": "the curve is not regular at u: its speed |C'| vanishes (below 1e-10 of the control points' extent per unit of parameter, e.g. where control points coincide), so curvature, torsion and dkappa_ds are undefined",
                }));
            }
            for (what, x) in [
                ("curvature", d.curvature),
                ("torsion", d.torsion),
                ("dκ/ds", d.dkappa_ds),
            ] {
                super::finite(&format!("{what} at u = {}", short(u)), x)?;
            }
            Ok(json!({
                "u": u,
                "point": point,
                "derivatives": derivatives,
                "regular": true,
                "curvature": d.curvature,
                "torsion": d.torsion,
                "dkappa_ds": d.dkappa_ds,
            }))
        })
        .collect()
}

fn eval_surface(s: &NurbsSurface, uv: &[(f64, f64)]) -> Result<Vec<Value>, CliError> {
    let mut ws = SurfaceWorkspace::new(s, 2);
    let mut d = [Vec3::ZERO; 9];
    // far outside unit size the curvatures come from an exactly rescaled copy (fairfit::nurbs::scale)
    let f = normalising_factor(s.control_points_flat());
    let scaled = (f != 1.0).then(|| scaled_surface(s, f).ok()).flatten();
    let mut ws_scaled = scaled.as_ref().map(|t| SurfaceWorkspace::new(t, 2));
    let mut e = [Vec3::ZERO; 9];
    uv.iter()
        .map(|&(u, v)| {
            check_in_domain("u", u, s.domain_u())?;
            check_in_domain("v", v, s.domain_v())?;
            s.check_parameter(u, v)?;
            s.derivatives_with(u, v, 2, &mut ws, &mut d);
            // null curvatures where the normal is degenerate (poles, collapsed edges)
            let curv = match (&scaled, &mut ws_scaled) {
                (Some(t), Some(w)) => {
                    t.derivatives_with(u, v, 2, w, &mut e);
                    surface_curvature_from(e[3], e[1], e[6], e[4], e[2]).map(|mut c| {
                        c.gaussian *= f * f;
                        c.mean *= f;
                        c
                    })
                }
                _ => surface_curvature_from(d[3], d[1], d[6], d[4], d[2]),
            };
            if let Some(c) = curv {
                let at = format!("at (u, v) = ({}, {})", short(u), short(v));
                super::finite(&format!("Gaussian curvature {at}"), c.gaussian)?;
                super::finite(&format!("mean curvature {at}"), c.mean)?;
            }
            Ok(json!({
                "u": u,
                "v": v,
                "point": arr(d[0]),
                "du": arr(d[3]),
                "dv": arr(d[1]),
                "duu": arr(d[6]),
                "duv": arr(d[4]),
                "dvv": arr(d[2]),
                "gaussian_curvature": curv.map(|c| c.gaussian),
                "mean_curvature": curv.map(|c| c.mean),
            }))
        })
        .collect()
}
