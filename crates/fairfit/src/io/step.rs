//! STEP (ISO 10303-21, AP214 `AUTOMOTIVE_DESIGN`) writer for NURBS curves and surfaces.
//!
//! Hand-written because no maintained Rust crate writes STEP. A surface becomes one `ADVANCED_FACE`
//! bounded by its four exact iso-parametric boundary edges (a closed direction shares one seam edge),
//! in an `OPEN_SHELL` / `SHELL_BASED_SURFACE_MODEL` / `MANIFOLD_SURFACE_SHAPE_REPRESENTATION`; a curve
//! becomes a `GEOMETRIC_CURVE_SET` in a `GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION`. Both
//! sit in a full `PRODUCT` / `PRODUCT_DEFINITION` / `SHAPE_DEFINITION_REPRESENTATION` chain with the
//! caller's length unit. Rational geometry uses the complex-entity forms (`BOUNDED_CURVE`,
//! `B_SPLINE_CURVE`, ..., `RATIONAL_B_SPLINE_CURVE`). Knots are written as distinct values plus
//! multiplicities; reals in shortest round-trip form, so the file holds the geometry bit for bit.

use super::cad_common::{
    compress_knots, format_real, utc_now, validate_curve, validate_surface, LengthUnit,
};
use crate::errors::Result;
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use std::fmt::Write as _;
use std::path::Path;

/// Options of the STEP writer.
#[derive(Clone, Debug)]
pub struct StepOptions {
    /// Length unit declared in the file.
    pub unit: LengthUnit,
    /// Product name (ASCII; other characters become `_`).
    pub name: String,
    /// Distance accuracy declared in the geometric context, in the file's unit.
    pub uncertainty: f64,
}

impl Default for StepOptions {
    fn default() -> Self {
        StepOptions {
            unit: LengthUnit::Millimetre,
            name: "fairfit".into(),
            uncertainty: 1e-7,
        }
    }
}

/// Accumulates numbered entity instances.
struct Data {
    lines: Vec<String>,
}

impl Data {
    fn add(&mut self, body: impl Into<String>) -> usize {
        self.lines.push(body.into());
        self.lines.len()
    }
    fn point(&mut self, p: Vec3) -> usize {
        let [x, y, z] = p.0.map(format_real);
        self.add(format!("CARTESIAN_POINT('',({x},{y},{z}))"))
    }
    fn direction(&mut self, d: [f64; 3]) -> usize {
        let [x, y, z] = d.map(format_real);
        self.add(format!("DIRECTION('',({x},{y},{z}))"))
    }
}

fn step_string(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '\'' => "''".to_string(),
            '\\' => "\\\\".to_string(),
            c if c.is_ascii_graphic() || c == ' ' => c.to_string(),
            _ => "_".to_string(),
        })
        .collect()
}

fn refs(ids: &[usize]) -> String {
    let v: Vec<String> = ids.iter().map(|i| format!("#{i}")).collect();
    format!("({})", v.join(","))
}

fn reals(xs: &[f64]) -> String {
    let v: Vec<String> = xs.iter().map(|&x| format_real(x)).collect();
    format!("({})", v.join(","))
}

fn ints(xs: &[usize]) -> String {
    let v: Vec<String> = xs.iter().map(|x| x.to_string()).collect();
    format!("({})", v.join(","))
}

/// Writes the curve entity (plain or rational complex form); returns its id.
fn curve_entity(d: &mut Data, c: &NurbsCurve) -> usize {
    let pts: Vec<usize> = c.control_points().iter().map(|&p| d.point(p)).collect();
    let (values, mults) = compress_knots(c.knots());
    let p = c.degree();
    let (pts, mults, values) = (refs(&pts), ints(&mults), reals(&values));
    if c.is_rational() {
        let w = reals(c.weights());
        d.add(format!(
            "( BOUNDED_CURVE() B_SPLINE_CURVE({p},{pts},.UNSPECIFIED.,.F.,.F.) \
             B_SPLINE_CURVE_WITH_KNOTS({mults},{values},.UNSPECIFIED.) CURVE() \
             GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE({w}) REPRESENTATION_ITEM('') )"
        ))
    } else {
        d.add(format!(
            "B_SPLINE_CURVE_WITH_KNOTS('',{p},{pts},.UNSPECIFIED.,.F.,.F.,{mults},{values},.UNSPECIFIED.)"
        ))
    }
}

/// Writes the surface entity (plain or rational complex form) with its closed flags; returns its id.
fn surface_entity(d: &mut Data, s: &NurbsSurface, closed_u: bool, closed_v: bool) -> usize {
    let flag = |c: bool| if c { ".T." } else { ".F." };
    let closed = format!("{},{}", flag(closed_u), flag(closed_v));
    let (n_u, n_v) = s.net_size();
    let rows: Vec<String> = (0..n_u)
        .map(|i| {
            let ids: Vec<usize> = (0..n_v).map(|j| d.point(s.control_point(i, j))).collect();
            refs(&ids)
        })
        .collect();
    let net = format!("({})", rows.join(","));
    let (ku, mu) = compress_knots(s.knots_u());
    let (kv, mv) = compress_knots(s.knots_v());
    let (pu, pv) = (s.degree_u(), s.degree_v());
    let knots = format!("{},{},{},{}", ints(&mu), ints(&mv), reals(&ku), reals(&kv));
    if s.is_rational() {
        let w: Vec<String> = s.weight_net().iter().map(|r| reals(r)).collect();
        let w = format!("({})", w.join(","));
        d.add(format!(
            "( BOUNDED_SURFACE() B_SPLINE_SURFACE({pu},{pv},{net},.UNSPECIFIED.,{closed},.F.) \
             B_SPLINE_SURFACE_WITH_KNOTS({knots},.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() \
             RATIONAL_B_SPLINE_SURFACE({w}) REPRESENTATION_ITEM('') SURFACE() )"
        ))
    } else {
        d.add(format!(
            "B_SPLINE_SURFACE_WITH_KNOTS('',{pu},{pv},{net},.UNSPECIFIED.,{closed},.F.,{knots},.UNSPECIFIED.)"
        ))
    }
}

/// Writes units, uncertainty and the geometric context; returns the context id.
fn context(d: &mut Data, opts: &StepOptions) -> usize {
    let prefix = match opts.unit {
        LengthUnit::Millimetre => ".MILLI.",
        LengthUnit::Metre => "$",
    };
    let len = d.add(format!(
        "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT({prefix},.METRE.) )"
    ));
    let ang = d.add("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )");
    let sol = d.add("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )");
    let unc = d.add(format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),#{len},'distance_accuracy_value','confusion accuracy')",
        format_real(opts.uncertainty)
    ));
    d.add(format!(
        "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{unc})) \
         GLOBAL_UNIT_ASSIGNED_CONTEXT((#{len},#{ang},#{sol})) REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY') )"
    ))
}

/// Writes the product chain pointing at shape representation `rep`.
fn product(d: &mut Data, name: &str, rep: usize) {
    let app = d.add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')");
    d.add(format!(
        "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
    ));
    let pc = d.add(format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    let prod = d.add(format!("PRODUCT('{name}','{name}','',(#{pc}))"));
    d.add(format!(
        "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{prod}))"
    ));
    let pdf = d.add(format!("PRODUCT_DEFINITION_FORMATION('','',#{prod})"));
    let pdc = d.add(format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
    ));
    let pd = d.add(format!("PRODUCT_DEFINITION('design','',#{pdf},#{pdc})"));
    let pds = d.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"));
    d.add(format!("SHAPE_DEFINITION_REPRESENTATION(#{pds},#{rep})"));
}

fn axis(d: &mut Data) -> usize {
    let o = d.point(Vec3::ZERO);
    let z = d.direction([0.0, 0.0, 1.0]);
    let x = d.direction([1.0, 0.0, 0.0]);
    d.add(format!("AXIS2_PLACEMENT_3D('',#{o},#{z},#{x})"))
}

fn finish(d: Data, opts: &StepOptions) -> String {
    let (y, mo, day, h, mi, s) = utc_now();
    let name = step_string(&opts.name);
    let mut out = String::with_capacity(d.lines.iter().map(|l| l.len() + 12).sum::<usize>() + 600);
    out.push_str("ISO-10303-21;\nHEADER;\n");
    out.push_str("FILE_DESCRIPTION(('fairfit NURBS geometry'),'2;1');\n");
    let _ = writeln!(
        out,
        "FILE_NAME('{name}','{y:04}-{mo:02}-{day:02}T{h:02}:{mi:02}:{s:02}',(''),(''),'fairfit {}','fairfit','');",
        env!("CARGO_PKG_VERSION")
    );
    out.push_str("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n");
    for (i, line) in d.lines.iter().enumerate() {
        let _ = writeln!(out, "#{}={};", i + 1, line);
    }
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    out
}

/// The STEP text of a curve, as an edge-free wireframe (`GEOMETRIC_CURVE_SET`).
///
/// ```
/// use fairfit::{NurbsCurve, Vec3};
/// use fairfit::io::step::{curve_to_step, StepOptions};
/// let c = NurbsCurve::bspline(1, vec![0., 0., 1., 1.], vec![Vec3::ZERO, Vec3::new(1., 0., 0.)]).unwrap();
/// let text = curve_to_step(&c, &StepOptions::default()).unwrap();
/// assert!(text.contains("B_SPLINE_CURVE_WITH_KNOTS('',1,"));
/// ```
pub fn curve_to_step(c: &NurbsCurve, opts: &StepOptions) -> Result<String> {
    validate_curve(c)?;
    let mut d = Data { lines: Vec::new() };
    let ctx = context(&mut d, opts);
    let ax = axis(&mut d);
    let curve = curve_entity(&mut d, c);
    let set = d.add(format!("GEOMETRIC_CURVE_SET('',(#{curve}))"));
    let rep = d.add(format!(
        "GEOMETRICALLY_BOUNDED_WIREFRAME_SHAPE_REPRESENTATION('',(#{ax},#{set}),#{ctx})"
    ));
    product(&mut d, &step_string(&opts.name), rep);
    Ok(finish(d, opts))
}

/// The boundary iso-curves `[v = v0, u = u1, v = v1, u = u0]` and whether u, v are closed.
fn boundary(s: &NurbsSurface) -> Result<([NurbsCurve; 4], bool, bool)> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let b0 = s.iso_curve_v(v0)?;
    let r = s.iso_curve_u(u1)?;
    let t = s.iso_curve_v(v1)?;
    let l = s.iso_curve_u(u0)?;
    let same = |a: &NurbsCurve, b: &NurbsCurve| {
        let scale = super::cad_common::max_coordinate(a.control_points()).max(1.0);
        a.homogeneous_points()
            .iter()
            .zip(b.homogeneous_points())
            .all(|(p, q)| (0..4).all(|k| (p[k] - q[k]).abs() <= 1e-12 * scale))
    };
    let (closed_u, closed_v) = (same(&l, &r), same(&b0, &t));
    Ok(([b0, r, t, l], closed_u, closed_v))
}

/// The STEP text of a surface, as one `ADVANCED_FACE` bounded by its exact boundary edges.
pub fn surface_to_step(s: &NurbsSurface, opts: &StepOptions) -> Result<String> {
    validate_surface(s)?;
    let ([bottom, right, top, left], closed_u, closed_v) = boundary(s)?;
    let mut d = Data { lines: Vec::new() };
    let ctx = context(&mut d, opts);
    let ax = axis(&mut d);
    let surf = surface_entity(&mut d, s, closed_u, closed_v);
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let vertex = |d: &mut Data, u: f64, v: f64| {
        let p = d.point(s.point(u, v));
        d.add(format!("VERTEX_POINT('',#{p})"))
    };
    let v00 = vertex(&mut d, u0, v0);
    let v10 = if closed_u {
        v00
    } else {
        vertex(&mut d, u1, v0)
    };
    let v01 = if closed_v {
        v00
    } else {
        vertex(&mut d, u0, v1)
    };
    let v11 = match (closed_u, closed_v) {
        (true, _) => v01,
        (false, true) => v10,
        _ => vertex(&mut d, u1, v1),
    };
    let edge = |d: &mut Data, c: &NurbsCurve, a: usize, b: usize| {
        let g = curve_entity(d, c);
        d.add(format!("EDGE_CURVE('',#{a},#{b},#{g},.T.)"))
    };
    let e_bottom = edge(&mut d, &bottom, v00, v10);
    let e_right = edge(&mut d, &right, v10, v11);
    let e_top = if closed_v {
        e_bottom
    } else {
        edge(&mut d, &top, v01, v11)
    };
    let e_left = if closed_u {
        e_right
    } else {
        edge(&mut d, &left, v00, v01)
    };
    let oriented: Vec<usize> = [(e_bottom, 'T'), (e_right, 'T'), (e_top, 'F'), (e_left, 'F')]
        .iter()
        .map(|&(e, o)| d.add(format!("ORIENTED_EDGE('',*,*,#{e},.{o}.)")))
        .collect();
    let lp = d.add(format!("EDGE_LOOP('',{})", refs(&oriented)));
    let bound = d.add(format!("FACE_OUTER_BOUND('',#{lp},.T.)"));
    let face = d.add(format!("ADVANCED_FACE('',(#{bound}),#{surf},.T.)"));
    let shell = d.add(format!("OPEN_SHELL('',(#{face}))"));
    let model = d.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
    let rep = d.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#{ax},#{model}),#{ctx})"
    ));
    product(&mut d, &step_string(&opts.name), rep);
    Ok(finish(d, opts))
}

/// Validates and writes a curve to a STEP file atomically (nothing is written on error).
pub fn write_curve_step(path: impl AsRef<Path>, c: &NurbsCurve, opts: &StepOptions) -> Result<()> {
    let text = curve_to_step(c, opts)?;
    super::write_atomic(path, text.as_bytes())
}

/// Validates and writes a surface to a STEP file atomically (nothing is written on error).
pub fn write_surface_step(
    path: impl AsRef<Path>,
    s: &NurbsSurface,
    opts: &StepOptions,
) -> Result<()> {
    let text = surface_to_step(s, opts)?;
    super::write_atomic(path, text.as_bytes())
}
