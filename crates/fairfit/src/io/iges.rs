//! IGES 5.3 writer: entity 126 (rational B-spline curve) and 128 (rational B-spline surface).
//!
//! Hand-written (no maintained Rust crate writes IGES). The file has the five fixed-format sections:
//! Start, Global (Hollerith strings, `,` parameter and `;` record delimiters, unit flag), Directory Entry
//! (two 80-column lines per entity), Parameter Data (64 columns of data, the DE back-pointer, sequence
//! numbers) and Terminate (section line counts). Knots are written in full (IGES has no multiplicity
//! form); reals in shortest round-trip form, so the file holds the geometry bit for bit.

use super::cad_common::{
    format_real, max_coordinate, utc_now, validate_curve, validate_surface, LengthUnit,
};
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use std::fmt::Write as _;
use std::path::Path;

/// Options of the IGES writer.
#[derive(Clone, Debug)]
pub struct IgesOptions {
    /// Length unit declared in the Global section (unit flag 2 = mm, 6 = m).
    pub unit: LengthUnit,
    /// File name recorded in the Global section (ASCII; other characters become `_`).
    pub name: String,
    /// Minimum user-intended resolution, in the file's unit.
    pub resolution: f64,
}

impl Default for IgesOptions {
    fn default() -> Self {
        IgesOptions {
            unit: LengthUnit::Millimetre,
            name: "fairfit.igs".into(),
            resolution: 1e-7,
        }
    }
}

/// A Hollerith string (`nH...`), ASCII, at most 60 characters so it fits one Global line.
fn hollerith(s: &str) -> String {
    let s: String = s
        .chars()
        .take(60)
        .map(|c| {
            if c.is_ascii_graphic() || c == ' ' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{}H{}", s.len(), s)
}

/// Packs delimited tokens into lines of at most `width` columns without splitting a token.
fn pack(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for t in tokens {
        let fits = lines.last().is_some_and(|l| l.len() + t.len() <= width);
        if !fits && !lines.last().is_some_and(|l| l.is_empty()) {
            lines.push(String::new());
        }
        if let Some(l) = lines.last_mut() {
            l.push_str(t);
        }
    }
    lines
}

/// Turns parameter values into tokens: each followed by `,`, the last by `;`.
fn delimit(values: Vec<String>) -> Vec<String> {
    let n = values.len();
    values
        .into_iter()
        .enumerate()
        .map(|(i, v)| format!("{v}{}", if i + 1 == n { ';' } else { ',' }))
        .collect()
}

/// One entity's directory label, type and parameter values.
struct Entity {
    kind: u32,
    label: &'static str,
    params: Vec<String>,
}

fn assemble(entities: &[Entity], opts: &IgesOptions, max_coord: f64) -> String {
    let (y, mo, d, h, mi, s) = utc_now();
    let stamp = hollerith(&format!("{y:04}{mo:02}{d:02}.{h:02}{mi:02}{s:02}"));
    let (flag, unit_name) = match opts.unit {
        LengthUnit::Millimetre => (2, "MM"),
        LengthUnit::Metre => (6, "M"),
    };
    let version = format!("fairfit {}", env!("CARGO_PKG_VERSION"));
    let global = vec![
        "1H,".into(),
        "1H;".into(),
        hollerith(&opts.name),
        hollerith(&opts.name),
        hollerith("fairfit"),
        hollerith(&version),
        "32".into(),
        "38".into(),
        "6".into(),
        "308".into(),
        "15".into(),
        hollerith(&opts.name),
        "1.".into(),
        flag.to_string(),
        hollerith(unit_name),
        "1".into(),
        "1.".into(),
        stamp.clone(),
        format_real(opts.resolution),
        format_real(max_coord),
        hollerith("fairfit"),
        hollerith("fairfit"),
        "11".into(),
        "0".into(),
        stamp,
    ];
    let mut out = String::new();
    let line = |out: &mut String, text: &str, letter: char, seq: usize| {
        let _ = writeln!(out, "{text:<72}{letter}{seq:>7}");
    };
    let start: Vec<u8> = format!(
        "fairfit NURBS geometry (IGES 5.3): {}",
        hollerith(&opts.name)
    )
    .into_bytes();
    let start_lines: Vec<String> = start
        .chunks(72)
        .map(|c| String::from_utf8_lossy(c).into_owned())
        .collect();
    for (i, l) in start_lines.iter().enumerate() {
        line(&mut out, l, 'S', i + 1);
    }
    let global_lines = pack(&delimit(global), 72);
    for (i, l) in global_lines.iter().enumerate() {
        line(&mut out, l, 'G', i + 1);
    }
    let mut pd_lines = Vec::new();
    let mut de_text = String::new();
    for (k, e) in entities.iter().enumerate() {
        let de_seq = 2 * k + 1;
        let first_pd = pd_lines.len() + 1;
        let mut tokens = vec![e.kind.to_string()];
        tokens.extend(e.params.iter().cloned());
        let lines = pack(&delimit(tokens), 64);
        let count = lines.len();
        for l in lines {
            pd_lines.push((l, de_seq));
        }
        let _ = writeln!(
            de_text,
            "{:>8}{first_pd:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{de_seq:>7}",
            e.kind, 0, 1, 0, 0, 0, 0, "00000000"
        );
        let _ = writeln!(
            de_text,
            "{:>8}{:>8}{:>8}{count:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            e.kind,
            0,
            0,
            0,
            "",
            "",
            e.label,
            0,
            de_seq + 1
        );
    }
    out.push_str(&de_text);
    for (i, (l, de)) in pd_lines.iter().enumerate() {
        let _ = writeln!(out, "{l:<64} {de:>7}P{:>7}", i + 1);
    }
    let counts = format!(
        "S{:07}G{:07}D{:07}P{:07}",
        start_lines.len(),
        global_lines.len(),
        2 * entities.len(),
        pd_lines.len()
    );
    line(&mut out, &counts, 'T', 1);
    out
}

fn xyz(params: &mut Vec<String>, p: Vec3) {
    params.extend(p.0.iter().map(|&c| format_real(c)));
}

fn curve_entity(c: &NurbsCurve) -> Entity {
    let pts = c.control_points();
    let (n, p) = (pts.len(), c.degree());
    let planar = pts.iter().all(|q| q.z() == pts[0].z());
    let closed = pts.first() == pts.last();
    let mut params: Vec<String> = [n - 1, p, planar as usize, closed as usize]
        .iter()
        .map(|v| v.to_string())
        .collect();
    params.push(if c.is_rational() { "0" } else { "1" }.into());
    params.push("0".into());
    params.extend(c.knots().iter().map(|&k| format_real(k)));
    params.extend(c.weights().iter().map(|&w| format_real(w)));
    for &q in pts {
        xyz(&mut params, q);
    }
    let (a, b) = c.domain();
    params.push(format_real(a));
    params.push(format_real(b));
    xyz(
        &mut params,
        Vec3::new(0.0, 0.0, if planar { 1.0 } else { 0.0 }),
    );
    Entity {
        kind: 126,
        label: "BSPLCRV",
        params,
    }
}

fn surface_entity(s: &NurbsSurface) -> Entity {
    let (n_u, n_v) = s.net_size();
    let row_eq =
        |a: usize, b: usize| (0..n_v).all(|j| s.control_point(a, j) == s.control_point(b, j));
    let col_eq =
        |a: usize, b: usize| (0..n_u).all(|i| s.control_point(i, a) == s.control_point(i, b));
    // closed: the end rows coincide, or periodic (the last p rows repeat the first, see
    // NurbsSurface::is_periodic_u), which readers then rebuild as periodic
    let (per_u, per_v) = (s.is_periodic_u(), s.is_periodic_v());
    let flags = [
        n_u - 1,
        n_v - 1,
        s.degree_u(),
        s.degree_v(),
        (per_u || row_eq(0, n_u - 1)) as usize,
        (per_v || col_eq(0, n_v - 1)) as usize,
        (!s.is_rational()) as usize,
        per_u as usize,
        per_v as usize,
    ];
    let mut params: Vec<String> = flags.iter().map(|v| v.to_string()).collect();
    params.extend(s.knots_u().iter().map(|&k| format_real(k)));
    params.extend(s.knots_v().iter().map(|&k| format_real(k)));
    // IGES orders the net with the first (u) index varying fastest.
    for j in 0..n_v {
        params.extend((0..n_u).map(|i| format_real(s.weight(i, j))));
    }
    for j in 0..n_v {
        for i in 0..n_u {
            xyz(&mut params, s.control_point(i, j));
        }
    }
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    params.extend([u0, u1, v0, v1].map(format_real));
    Entity {
        kind: 128,
        label: "BSPLSRF",
        params,
    }
}

/// The IGES text of a curve (one entity 126).
///
/// ```
/// use fairfit::{NurbsCurve, Vec3};
/// use fairfit::io::iges::{curve_to_iges, IgesOptions};
/// let c = NurbsCurve::bspline(1, vec![0., 0., 1., 1.], vec![Vec3::ZERO, Vec3::new(1., 0., 0.)]).unwrap();
/// let text = curve_to_iges(&c, &IgesOptions::default()).unwrap();
/// assert!(text.lines().all(|l| l.len() == 80));
/// ```
pub fn curve_to_iges(c: &NurbsCurve, opts: &IgesOptions) -> Result<String> {
    validate_curve(c)?;
    let max = max_coordinate(c.control_points());
    Ok(assemble(&[curve_entity(c)], opts, max))
}

/// The IGES text of a surface (one entity 128).
pub fn surface_to_iges(s: &NurbsSurface, opts: &IgesOptions) -> Result<String> {
    validate_surface(s)?;
    let max = max_coordinate(s.control_points_flat());
    Ok(assemble(&[surface_entity(s)], opts, max))
}

/// Validates and writes a curve to an IGES file atomically (nothing is written on error).
pub fn write_curve_iges(path: impl AsRef<Path>, c: &NurbsCurve, opts: &IgesOptions) -> Result<()> {
    let text = curve_to_iges(c, opts)?;
    super::write_atomic(path, text.as_bytes())
}

/// Validates and writes a surface to an IGES file atomically (nothing is written on error).
pub fn write_surface_iges(
    path: impl AsRef<Path>,
    s: &NurbsSurface,
    opts: &IgesOptions,
) -> Result<()> {
    let text = surface_to_iges(s, opts)?;
    super::write_atomic(path, text.as_bytes())
}
