//! IGES reader for entity 126 (rational B-spline curve) and 128 (rational B-spline surface), and for
//! the conics 100 (circular arc) and 104 (conic arc: ellipse, parabola, hyperbola) as exact rational
//! quadratic B-splines ([`super::cad_conic`]): circles and ellipses counter-clockwise in their
//! definition plane `z = ZT` from the start to the end point (the whole conic when they coincide),
//! parabola and hyperbola arcs from the start to the end point, then moved by their 124 as OpenCASCADE moves a conic (centre mapped, plane normal the matrix's third
//! column, semi-axes kept), alone and as members of a 102.
//!
//! Hand-written, like the writer ([`super::iges`]): no maintained small Rust crate parses IGES (the
//! readers that exist live inside whole B-rep kernels). Read: the fixed 80-column ASCII form with its
//! Start, Global, Directory Entry, Parameter Data and Terminate sections (CR LF line ends, short lines
//! padded); the Global section's delimiters, model space scale (field 13; the standard defines it as
//! model / real-world size, so coordinates are divided by it: folded into the unit factor. OpenCASCADE
//! ignores this field; nearly every writer puts 1.0) and unit flag (field 14, and the unit name of
//! field 15 for flag 3); free-format parameters with Hollerith strings (`3Habc`), empty fields
//! (defaults), `D` exponents (`1.5D-3`) and blanks inside numbers; a transformation matrix (entity 124,
//! DE field 7, chained) applied to the control points; the parameter range `V(0), V(1)` of a 126 that
//! trims the knot domain (the curve is cut there exactly by knot insertion). Curves flagged as
//! parameter-space curves (entity use 05) or referenced as such by a 142 (directly or as members of a
//! 102 composite curve) are skipped. Errors
//! ([`Error::Cad`]) name the section line or the DE.

use super::cad_conic::{arc_between, bezier_arc, Conic};
use super::cad_read::{CadContents, CadUnit};
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use std::collections::BTreeSet;

/// One field of a free-format parameter record.
#[derive(Clone, Debug, PartialEq)]
enum Field {
    /// Empty: the default applies.
    Empty,
    /// A Hollerith string.
    Text(String),
    /// Anything else, blanks removed (a number or a pointer).
    Token(String),
}

/// Splits free-format text into fields up to the record delimiter (or the end).
fn fields(text: &str, pd: char, rd: char) -> Result<Vec<Field>> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    loop {
        while i < chars.len() && chars[i] == ' ' {
            i += 1;
        }
        if i >= chars.len() {
            return Ok(out);
        }
        if chars[i] == pd || chars[i] == rd {
            out.push(Field::Empty);
            if chars[i] == rd {
                return Ok(out);
            }
            i += 1;
            continue;
        }
        // a Hollerith string: digits, 'H', then that many characters
        let mut j = i;
        while j < chars.len() && chars[j].is_ascii_digit() {
            j += 1;
        }
        let field = if j > i && j < chars.len() && chars[j] == 'H' {
            let n: usize = chars[i..j].iter().collect::<String>().parse().unwrap_or(0);
            let start = j + 1;
            if start + n > chars.len() {
                return Err(Error::Cad(format!(
                    "a Hollerith string of {n} characters runs past the end of its record"
                )));
            }
            i = start + n;
            Field::Text(chars[start..start + n].iter().collect())
        } else {
            let start = i;
            while i < chars.len() && chars[i] != pd && chars[i] != rd {
                i += 1;
            }
            let t: String = chars[start..i].iter().filter(|c| **c != ' ').collect();
            if t.is_empty() {
                Field::Empty
            } else {
                Field::Token(t)
            }
        };
        out.push(field);
        while i < chars.len() && chars[i] == ' ' {
            i += 1;
        }
        match chars.get(i) {
            None => return Ok(out),
            Some(&c) if c == rd => return Ok(out),
            Some(&c) if c == pd => i += 1,
            Some(&c) => {
                return Err(Error::Cad(format!(
                    "unexpected '{c}' after a field (expected '{pd}' or '{rd}')"
                )))
            }
        }
    }
}

/// A real in IGES syntax (`1.`, `1.5D-3`, `-.5E2`, `3`).
fn real(t: &str) -> Option<f64> {
    let mut s = t.replace(['D', 'd'], "E");
    if let Some(i) = s.find(".E").or_else(|| s.find(".e")) {
        s.insert(i + 1, '0');
    }
    if s.ends_with('.') {
        s.push('0');
    }
    s.parse().ok().filter(|x: &f64| x.is_finite())
}

/// One Directory Entry (the fields fairfit uses).
#[derive(Clone, Debug)]
struct Entry {
    kind: u32,
    pd_start: usize,
    transform: usize,
    use_flag: u32,
    pd_lines: usize,
}

/// The sections of an IGES file.
struct Iges {
    global: Vec<Field>,
    entries: Vec<Entry>,
    /// Parameter data columns 1-64 by line.
    params: Vec<String>,
    pd: char,
    rd: char,
}

fn de_field(line: &str, k: usize) -> &str {
    line.get(8 * k..8 * k + 8).unwrap_or("").trim()
}

fn split(text: &str) -> Result<Iges> {
    let (mut start, mut global, mut de, mut pd) = (0, String::new(), Vec::new(), Vec::new());
    let mut terminate = false;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim_end_matches('\r');
        if line.trim().is_empty() {
            continue;
        }
        if line.chars().count() < 73 {
            return Err(Error::Cad(if i == 0 {
                "not an IGES file (no section letter S in column 73 of the first line)".into()
            } else {
                format!(
                    "line {} ends before column 73, where its section letter belongs: the file is \
                     truncated or not fixed-format IGES",
                    i + 1
                )
            }));
        }
        let padded = format!("{line:<80}");
        let section = padded.chars().nth(72).unwrap_or(' ');
        let body: String = padded.chars().take(72).collect();
        match section {
            'S' => start += 1,
            'G' => global.push_str(&body),
            'D' => de.push(body),
            'P' => pd.push(padded.chars().take(64).collect::<String>()),
            'T' => terminate = true,
            'C' if i == 0 => {
                return Err(Error::Cad(
                    "compressed IGES is not supported; re-export as fixed-format ASCII IGES".into(),
                ))
            }
            _ if i == 0 => {
                return Err(Error::Cad(
                    "not an IGES file (no section letter S in column 73 of the first line)".into(),
                ))
            }
            other => {
                return Err(Error::Cad(format!(
                    "line {}: unknown section letter '{}' in column 73 (expected S, G, D, P or T)",
                    i + 1,
                    other.escape_default()
                )))
            }
        }
    }
    if start == 0 && global.is_empty() {
        return Err(Error::Cad(
            "not an IGES file (no Start or Global section)".into(),
        ));
    }
    if !terminate {
        return Err(Error::Cad(
            "no Terminate section (T in column 73 of the last line): the file is truncated".into(),
        ));
    }
    if de.len() % 2 != 0 {
        return Err(Error::Cad(format!(
            "the Directory Entry section has {} lines, not an even number (truncated?)",
            de.len()
        )));
    }
    // delimiters: field 1 and 2 of the Global section, `1H,` / `1H;` or empty (defaults , and ;)
    let g: Vec<char> = global.chars().collect();
    let (mut pdelim, mut rdelim, mut at) = (',', ';', 0);
    if g.len() >= 3 && g[0] == '1' && g[1] == 'H' {
        pdelim = g[2];
        at = 4;
    } else {
        at += 1;
    }
    if g.len() >= at + 3 && g[at] == '1' && g[at + 1] == 'H' {
        rdelim = g[at + 2];
    }
    let global_fields =
        fields(&global, pdelim, rdelim).map_err(|e| Error::Cad(format!("Global section: {e}")))?;
    let mut entries = Vec::with_capacity(de.len() / 2);
    for (k, pair) in de.chunks(2).enumerate() {
        let seq = 2 * k + 1;
        let int = |s: &str, what: &str| -> Result<usize> {
            if s.is_empty() {
                return Ok(0);
            }
            s.parse::<usize>()
                .map_err(|_| Error::Cad(format!("DE {seq}: {what} '{s}' is not a whole number")))
        };
        let status = de_field(&pair[0], 8);
        let status = format!("{status:0>8}");
        entries.push(Entry {
            kind: int(de_field(&pair[0], 0), "the entity type")? as u32,
            pd_start: int(de_field(&pair[0], 1), "the parameter data pointer")?,
            transform: int(de_field(&pair[0], 6), "the transformation matrix pointer")?,
            use_flag: status.get(4..6).and_then(|s| s.parse().ok()).unwrap_or(0),
            pd_lines: int(de_field(&pair[1], 3), "the parameter line count")?,
        });
    }
    Ok(Iges {
        global: global_fields,
        entries,
        params: pd,
        pd: pdelim,
        rd: rdelim,
    })
}

impl Iges {
    fn entry(&self, de: usize) -> Option<&Entry> {
        (de % 2 == 1).then(|| self.entries.get(de / 2)).flatten()
    }

    /// The parameter fields of the entity at DE `de` (the entity type first).
    fn params(&self, de: usize) -> Result<Vec<Field>> {
        let e = self
            .entry(de)
            .ok_or_else(|| Error::Cad(format!("DE {de} does not exist")))?;
        let (a, n) = (e.pd_start, e.pd_lines.max(1));
        if a == 0 || a + n - 1 > self.params.len() {
            return Err(Error::Cad(format!(
                "DE {de}: parameter lines {a}..{} are missing (truncated?)",
                a + n - 1
            )));
        }
        let text: String = self.params[a - 1..a - 1 + n].concat();
        let f = fields(&text, self.pd, self.rd).map_err(|m| Error::Cad(format!("DE {de}: {m}")))?;
        match f.first() {
            Some(Field::Token(t)) if t.parse::<u32>().ok() == Some(e.kind) => Ok(f),
            _ => Err(Error::Cad(format!(
                "DE {de}: its parameter data does not start with entity type {}",
                e.kind
            ))),
        }
    }
}

/// Reads numbered parameters of one entity, with errors naming the DE.
struct Params {
    f: Vec<Field>,
    de: usize,
    next: usize,
}

impl Params {
    fn real(&mut self, what: &str) -> Result<f64> {
        let i = self.next;
        self.next += 1;
        match self.f.get(i) {
            Some(Field::Token(t)) => real(t)
                .ok_or_else(|| Error::Cad(format!("DE {}: {what} '{t}' is not a number", self.de))),
            Some(Field::Empty) => Ok(0.0),
            Some(Field::Text(_)) => Err(Error::Cad(format!("DE {}: {what} is a string", self.de))),
            None => Err(Error::Cad(format!(
                "DE {}: the parameters end before {what} (truncated?)",
                self.de
            ))),
        }
    }
    fn int(&mut self, what: &str) -> Result<usize> {
        let x = self.real(what)?;
        if x >= 0.0 && x.fract() == 0.0 && x < 1e8 {
            Ok(x as usize)
        } else {
            Err(Error::Cad(format!(
                "DE {}: {what} {x} is not a count",
                self.de
            )))
        }
    }
    fn reals(&mut self, n: usize, what: &str) -> Result<Vec<f64>> {
        (0..n).map(|_| self.real(what)).collect()
    }
    fn points(&mut self, n: usize) -> Result<Vec<Vec3>> {
        (0..n)
            .map(|_| {
                Ok(Vec3::new(
                    self.real("a control point")?,
                    self.real("a control point")?,
                    self.real("a control point")?,
                ))
            })
            .collect()
    }
}

/// A rotation (or any 3 x 3 matrix) and a translation: `x -> R x + t`.
type Affine = ([[f64; 3]; 3], [f64; 3]);

/// The affine map of the transformation matrix at DE `de` (entity 124), chained through its own DE
/// field 7; `None` for pointer 0.
fn transform(g: &Iges, de: usize, depth: usize) -> Result<Option<Affine>> {
    if de == 0 {
        return Ok(None);
    }
    if depth > 16 {
        return Err(Error::Cad(format!(
            "DE {de}: transformation matrices form a cycle"
        )));
    }
    let e = g
        .entry(de)
        .ok_or_else(|| Error::Cad(format!("transformation matrix DE {de} does not exist")))?;
    if e.kind != 124 {
        return Err(Error::Cad(format!(
            "DE {de} is entity {}, not a transformation matrix (124)",
            e.kind
        )));
    }
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let mut r = [[0.0; 3]; 3];
    let mut t = [0.0; 3];
    for (row, tk) in r.iter_mut().zip(t.iter_mut()) {
        for entry in row.iter_mut() {
            *entry = p.real("a matrix entry")?;
        }
        *tk = p.real("a translation")?;
    }
    match transform(g, e.transform, depth + 1)? {
        None => Ok(Some((r, t))),
        Some((r2, t2)) => {
            // outer (r2, t2) after inner (r, t)
            let mut rr = [[0.0; 3]; 3];
            let mut tt = t2;
            for i in 0..3 {
                for j in 0..3 {
                    rr[i][j] = (0..3).map(|k| r2[i][k] * r[k][j]).sum();
                }
                tt[i] += (0..3).map(|k| r2[i][k] * t[k]).sum::<f64>();
            }
            Ok(Some((rr, tt)))
        }
    }
}

fn apply(m: &Option<Affine>, p: Vec3) -> Vec3 {
    match m {
        None => p,
        Some((r, t)) => Vec3(std::array::from_fn(|i| {
            r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + t[i]
        })),
    }
}

/// Weights that are all equal describe a polynomial spline: they become 1 (exactly the same curve).
fn normalised(w: Vec<f64>) -> Option<Vec<f64>> {
    // equal positive weights are a polynomial B-spline; equal zero or negative weights are kept, so
    // that the curve's or surface's validation refuses them (weights must be finite and > 0)
    let all_equal = w.iter().all(|&x| x == w[0]) && w.first().is_some_and(|&x| x > 0.0);
    (!all_equal).then_some(w)
}

fn curve(g: &Iges, de: usize) -> Result<NurbsCurve> {
    let e = &g.entries[de / 2];
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let k = p.int("the upper index K")?;
    let m = p.int("the degree M")?;
    let _props: Vec<f64> = p.reals(4, "a PROP flag")?;
    let knots = p.reals(k + m + 2, "a knot")?;
    let weights = p.reals(k + 1, "a weight")?;
    let xf = transform(g, e.transform, 0)?;
    let pts: Vec<Vec3> = p
        .points(k + 1)?
        .into_iter()
        .map(|q| apply(&xf, q))
        .collect();
    let (v0, v1) = (p.real("V(0)")?, p.real("V(1)")?);
    let c = NurbsCurve::new(m, knots, pts, normalised(weights))
        .map_err(|e| Error::Cad(format!("DE {de} (entity 126): {e}")))?;
    super::cad_read::trimmed(c, v0, v1)
        .map_err(|e| Error::Cad(format!("DE {de} (entity 126): V(0), V(1): {e}")))
}

fn surface(g: &Iges, de: usize) -> Result<NurbsSurface> {
    let e = &g.entries[de / 2];
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let k1 = p.int("the upper index K1")?;
    let k2 = p.int("the upper index K2")?;
    let m1 = p.int("the degree M1")?;
    let m2 = p.int("the degree M2")?;
    let _props = p.reals(5, "a PROP flag")?;
    let ku = p.reals(k1 + m1 + 2, "a u knot")?;
    let kv = p.reals(k2 + m2 + 2, "a v knot")?;
    let (n_u, n_v) = (k1 + 1, k2 + 1);
    // the net is ordered with the u index varying fastest
    let w_flat = p.reals(n_u * n_v, "a weight")?;
    let xf = transform(g, e.transform, 0)?;
    let pts_flat: Vec<Vec3> = p
        .points(n_u * n_v)?
        .into_iter()
        .map(|q| apply(&xf, q))
        .collect();
    let net = (0..n_u)
        .map(|i| (0..n_v).map(|j| pts_flat[i + j * n_u]).collect())
        .collect();
    let weights = normalised(w_flat.clone()).map(|w| {
        (0..n_u)
            .map(|i| (0..n_v).map(|j| w[i + j * n_u]).collect())
            .collect()
    });
    NurbsSurface::new(m1, m2, ku, kv, net, weights)
        .map_err(|e| Error::Cad(format!("DE {de} (entity 128): {e}")))
}

/// A line (entity 110) as a B-spline of degree 1, moved by its transformation matrix.
fn line(g: &Iges, de: usize) -> Result<NurbsCurve> {
    let e = &g.entries[de / 2];
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let xf = transform(g, e.transform, 0)?;
    let pts = p.points(2)?.into_iter().map(|q| apply(&xf, q)).collect();
    NurbsCurve::bspline(1, vec![0.0, 0.0, 1.0, 1.0], pts)
        .map_err(|e| Error::Cad(format!("DE {de} (entity 110): {e}")))
}

/// `c` with every control point mapped by `f` (knots and weights kept).
fn mapped(c: NurbsCurve, f: impl Fn(Vec3) -> Vec3) -> Result<NurbsCurve> {
    let pts = c.control_points().iter().map(|&q| f(q)).collect();
    NurbsCurve::new(
        c.degree(),
        c.knots().to_vec(),
        pts,
        c.is_rational().then(|| c.weights().to_vec()),
    )
}

/// `c` with its control points moved by `xf` (exact: B-splines are invariant under affine maps).
fn moved(c: NurbsCurve, xf: &Option<Affine>) -> Result<NurbsCurve> {
    if xf.is_none() {
        return Ok(c);
    }
    mapped(c, |q| apply(xf, q))
}

/// The conic `c` of a definition plane moved by the transformation `xf` as OpenCASCADE moves it: the
/// centre mapped, the plane's normal the matrix's third column (turned for a reflection), the first
/// axis the mapped one made orthogonal to the normal, the semi-axes kept (a 124 matrix is a rotation,
/// written to 10 digits or so: this keeps a circle a circle of the written radius).
fn conic_moved(c: &Conic, xf: &Option<Affine>, de: usize) -> Result<Conic> {
    let Some(f) = rigid_frame(xf, c.x, de)? else {
        return Ok(*c);
    };
    Conic::new(apply(xf, c.centre), f.x, f.y, c.a, c.b)
        .map_err(|e| Error::Cad(format!("DE {de}: {e}")))
}

/// A rigid frame ([`rigid_frame`]): an origin and three orthonormal axes.
struct RigidFrame {
    origin: Vec3,
    x: Vec3,
    y: Vec3,
    n: Vec3,
}

/// The rotation of the 124 `xf` made exactly rigid as OpenCASCADE makes it: the image of the origin,
/// the unit image of the definition plane's direction `dx` made orthogonal to the plane's normal, that
/// normal's partner `n × x`, and the normal (the matrix's third column, turned for a reflection).
/// `None` without a matrix.
fn rigid_frame(xf: &Option<Affine>, dx: Vec3, de: usize) -> Result<Option<RigidFrame>> {
    let Some((r, _)) = xf else {
        return Ok(None);
    };
    let col = |k: usize| Vec3::new(r[0][k], r[1][k], r[2][k]);
    let det = col(0).dot(col(1).cross(col(2)));
    let n = col(2) * det.signum();
    let rx = Vec3(std::array::from_fn(|i| {
        r[i][0] * dx[0] + r[i][1] * dx[1] + r[i][2] * dx[2]
    }));
    let fail = || {
        Error::Cad(format!(
            "DE {de}: the transformation matrix is degenerate (not a rotation)"
        ))
    };
    let nn = n.norm();
    if !(nn > 1e-9 && nn.is_finite()) {
        return Err(fail());
    }
    let n = n * (1.0 / nn);
    let x = rx - n * rx.dot(n);
    let xn = x.norm();
    if !(xn > 1e-9 && xn.is_finite()) {
        return Err(fail());
    }
    let x = x * (1.0 / xn);
    Ok(Some(RigidFrame {
        origin: apply(xf, Vec3::ZERO),
        x,
        y: n.cross(x),
        n,
    }))
}

/// `c` (in a definition space) moved rigidly into `frame` ([`rigid_frame`]; unmoved for `None`).
fn moved_rigidly(c: NurbsCurve, frame: Option<&RigidFrame>) -> Result<NurbsCurve> {
    let Some(f) = frame else {
        return Ok(c);
    };
    mapped(c, |q| f.origin + f.x * q[0] + f.y * q[1] + f.n * q[2])
}

/// A circular arc (entity 100) as an exact rational quadratic B-spline, moved by its transformation
/// matrix, and its kind (`circular arc`, or `circle` when the start is the end).
fn circular_arc(g: &Iges, de: usize) -> Result<(NurbsCurve, &'static str)> {
    let e = &g.entries[de / 2];
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let v = p.reals(7, "a coordinate")?;
    let fail = |m: String| Error::Cad(format!("DE {de} (entity 100): {m}"));
    let centre = Vec3::new(v[1], v[2], v[0]);
    let (start, end) = (Vec3::new(v[3], v[4], v[0]), Vec3::new(v[5], v[6], v[0]));
    let r = (start - centre).norm();
    let conic = Conic::new(
        centre,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        r,
        r,
    )
    .map_err(|e| fail(e.to_string()))?;
    let re = (end - centre).norm();
    if (re - r).abs().is_nan() || (re - r).abs() > 1e-6 * r {
        return Err(fail(format!(
            "the end point is {re} from the centre, the start point {r}: not one circle"
        )));
    }
    let xf = transform(g, e.transform, 0)?;
    let conic = conic_moved(&conic, &xf, de)?;
    let (t0, t1) = (
        conic.angle_of(apply(&xf, start)).0,
        conic.angle_of(apply(&xf, end)).0,
    );
    let (c, full) = arc_between(&conic, t0, t1, true).map_err(|e| fail(e.to_string()))?;
    Ok((c, conic.kind(full)))
}

/// A conic arc (entity 104) as an exact rational quadratic B-spline in its definition plane `z = ZT`,
/// moved by its transformation matrix, and its kind: an ellipse arc counter-clockwise from the start to
/// the end point (the whole ellipse when they coincide), or a parabola or hyperbola arc from the start
/// to the end point as one rational quadratic Bezier ([`super::cad_conic::bezier_arc`]). The kind is
/// told by the coefficients (`B² - 4AC`), not the form number.
fn conic_arc(g: &Iges, de: usize) -> Result<(NurbsCurve, &'static str)> {
    let e = &g.entries[de / 2];
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let v = p.reals(11, "a coefficient or coordinate")?;
    let fail = |m: String| Error::Cad(format!("DE {de} (entity 104): {m}"));
    let (a, b, c, d, ee, f, zt) = (v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
    let disc = b * b - 4.0 * a * c;
    let scale = (b * b).max((4.0 * a * c).abs());
    if disc.is_nan() {
        return Err(fail("the coefficients are not numbers".into()));
    }
    if disc >= -1e-12 * scale {
        // a parabola or a hyperbola: one exact rational quadratic Bezier arc from start to end
        let kind = if disc.abs() <= 1e-12 * scale {
            "parabolic arc"
        } else {
            "hyperbolic arc"
        };
        let xf = transform(g, e.transform, 0)?;
        // the ends as OpenCASCADE takes them: mapped by the matrix as written, then read in the rigid
        // frame the conic is moved by
        let frame = rigid_frame(&xf, Vec3::new(1.0, 0.0, 0.0), de)?;
        let end = |x: f64, y: f64| match &frame {
            None => (x, y),
            Some(fr) => {
                let q = apply(&xf, Vec3::new(x, y, zt)) - fr.origin;
                (q.dot(fr.x), q.dot(fr.y))
            }
        };
        let arc = bezier_arc(&[a, b, c, d, ee, f], end(v[7], v[8]), end(v[9], v[10]), zt)
            .map_err(|e| fail(format!("{kind}: {e}")))?;
        return Ok((moved_rigidly(arc, frame.as_ref())?, kind));
    }
    // centre: the gradient of A x² + B xy + C y² + D x + E y + F vanishes
    let det = 4.0 * a * c - b * b;
    let (cx, cy) = ((b * ee - 2.0 * c * d) / det, (b * d - 2.0 * a * ee) / det);
    let fc = f + 0.5 * (d * cx + ee * cy);
    // principal axes of [[A, B/2], [B/2, C]] (exactly the coordinate axes when B = 0)
    let (l1, l2, ux) = if b == 0.0 {
        (a, c, Vec3::new(1.0, 0.0, 0.0))
    } else {
        let m = 0.5 * (a + c);
        let h = (0.25 * (a - c) * (a - c) + 0.25 * b * b).sqrt();
        let (l1, l2) = (m + h, m - h);
        // eigenvector of l1: (B/2, l1 - A) or (l1 - C, B/2)
        let (v1, v2) = (
            Vec3::new(0.5 * b, l1 - a, 0.0),
            Vec3::new(l1 - c, 0.5 * b, 0.0),
        );
        let v = if v1.norm() >= v2.norm() { v1 } else { v2 };
        (l1, l2, v * (1.0 / v.norm()))
    };
    let (sa, sb) = ((-fc / l1).sqrt(), (-fc / l2).sqrt());
    let uy = Vec3::new(-ux[1], ux[0], 0.0);
    let conic = Conic::new(Vec3::new(cx, cy, zt), ux, uy, sa, sb)
        .map_err(|e| fail(format!("the coefficients describe no real ellipse ({e})")))?;
    let xf = transform(g, e.transform, 0)?;
    let conic = conic_moved(&conic, &xf, de)?;
    let size = sa.max(sb);
    let mut t = [0.0; 2];
    for (k, (x, y)) in [(v[7], v[8]), (v[9], v[10])].into_iter().enumerate() {
        let (ang, dist) = conic.angle_of(apply(&xf, Vec3::new(x, y, zt)));
        if dist.is_nan() || dist > 1e-6 * size {
            return Err(fail(format!(
                "the {} point lies {dist:.3e} off the ellipse (more than 1e-6 of its size)",
                ["start", "end"][k]
            )));
        }
        t[k] = ang;
    }
    let (arc, full) = arc_between(&conic, t[0], t[1], true).map_err(|e| fail(e.to_string()))?;
    Ok((arc, conic.kind(full)))
}

/// What a composite curve (entity 102) gives: its members as B-splines in order (126 curves, 110
/// lines, nested 102s) with their DEs, or the name of a member kind fairfit does not read.
enum Members {
    Read(Vec<NurbsCurve>, Vec<usize>),
    Unsupported(String),
}

fn composite(g: &Iges, de: usize, depth: usize) -> Result<Members> {
    if depth > 8 {
        return Err(Error::Cad(format!(
            "DE {de}: composite curves nested more than 8 deep"
        )));
    }
    let mut p = Params {
        f: g.params(de)?,
        de,
        next: 1,
    };
    let n = p.int("the member count N")?;
    let ptrs = (0..n)
        .map(|_| p.int("a member pointer"))
        .collect::<Result<Vec<_>>>()?;
    let xf = transform(g, g.entries[de / 2].transform, 0)?;
    let (mut segments, mut members) = (Vec::new(), Vec::new());
    for m in ptrs {
        let kind = g
            .entry(m)
            .ok_or_else(|| Error::Cad(format!("DE {de}: member DE {m} does not exist")))?
            .kind;
        members.push(m);
        match kind {
            126 => segments.push(curve(g, m)?),
            110 => segments.push(line(g, m)?),
            100 => segments.push(circular_arc(g, m)?.0),
            104 => segments.push(conic_arc(g, m)?.0),
            102 => match composite(g, m, depth + 1)? {
                Members::Read(s, inner) => {
                    segments.extend(s);
                    members.extend(inner);
                }
                unsupported => return Ok(unsupported),
            },
            other => {
                let name = other_name(other).map_or(format!("{other}"), |(n, _)| n.to_string());
                return Ok(Members::Unsupported(format!(
                    "102 (composite curve with a {name} member)"
                )));
            }
        }
    }
    if segments.is_empty() {
        return Err(Error::Cad(format!(
            "DE {de}: a composite curve without members"
        )));
    }
    if xf.is_some() {
        segments = segments
            .into_iter()
            .map(|c| moved(c, &xf))
            .collect::<Result<Vec<_>>>()?;
    }
    Ok(Members::Read(segments, members))
}

/// Millimetres per unit of IGES unit flag `flag` (field 14), or of the unit name (field 15) for flag 3.
fn unit_mm(flag: usize, name: &str) -> Option<f64> {
    let by_name = |n: &str| match n.trim().to_ascii_uppercase().as_str() {
        "IN" | "INCH" => Some(25.4),
        "MM" => Some(1.0),
        "FT" => Some(304.8),
        "MI" => Some(1_609_344.0),
        "M" => Some(1000.0),
        "KM" => Some(1e6),
        "MIL" => Some(0.0254),
        "UM" | "MICRON" => Some(1e-3),
        "CM" => Some(10.0),
        "UIN" => Some(2.54e-5),
        _ => None,
    };
    match flag {
        1 => Some(25.4),
        2 => Some(1.0),
        3 => by_name(name),
        4 => Some(304.8),
        5 => Some(1_609_344.0),
        6 => Some(1000.0),
        7 => Some(1e6),
        8 => Some(0.0254),
        9 => Some(1e-3),
        10 => Some(10.0),
        11 => Some(2.54e-5),
        _ => None,
    }
}

/// Names of the other curve and surface entity types, for "has no ..." errors.
fn other_name(kind: u32) -> Option<(&'static str, bool)> {
    Some(match kind {
        100 => ("100 (circular arc)", false),
        102 => ("102 (composite curve)", false),
        104 => ("104 (conic arc)", false),
        106 => ("106 (copious data)", false),
        110 => ("110 (line)", false),
        112 => ("112 (parametric spline curve)", false),
        130 => ("130 (offset curve)", false),
        108 => ("108 (plane)", true),
        114 => ("114 (parametric spline surface)", true),
        118 => ("118 (ruled surface)", true),
        120 => ("120 (surface of revolution)", true),
        122 => ("122 (tabulated cylinder)", true),
        140 => ("140 (offset surface)", true),
        190 | 192 | 194 | 196 | 198 => ("analytic surface (190-198)", true),
        _ => return None,
    })
}

/// Reads every entity 126 and 128 of an IGES text, in DE order, with the unit (coordinates as written;
/// the unit factor includes the division by the model space scale), and every model-space composite
/// curve (102) of 126 curves, 110 lines and nested 102s as its members in order (members that run
/// against the chain are turned, [`super::cad_chain::orient_segments`]); members are not read on their own.
pub fn contents(text: &str) -> Result<CadContents> {
    let g = split(text)?;
    let text_field = |i: usize| match g.global.get(i) {
        Some(Field::Text(s)) => s.clone(),
        _ => String::new(),
    };
    let num_field = |i: usize| match g.global.get(i) {
        Some(Field::Token(t)) => real(t),
        _ => None,
    };
    let scale = num_field(12).filter(|s| *s > 0.0).unwrap_or(1.0);
    let unit = match num_field(13) {
        None if scale == 1.0 => CadUnit::undeclared(),
        None => CadUnit::from_mm_per_unit(1.0 / scale),
        Some(f) => {
            let name = text_field(14);
            let mm = unit_mm(f as usize, &name).ok_or_else(|| {
                Error::Cad(format!(
                    "Global section: unit flag {f} (name '{name}') is not an IGES length unit"
                ))
            })?;
            CadUnit::from_mm_per_unit(if scale == 1.0 { mm } else { mm / scale })
        }
    };
    // parameter-space curves referenced by curves on surfaces (142: CRTN, SPTR, BPTR, ...), and the
    // members of a composite curve (102: N, DE1, ..., DEN) that BPTR points at
    let mut param_curves = BTreeSet::new();
    for (k, e) in g.entries.iter().enumerate() {
        if e.kind == 142 {
            if let Some(Field::Token(t)) = g.params(2 * k + 1)?.get(3) {
                if let Ok(ptr) = t.parse::<usize>() {
                    param_curves.insert(ptr);
                    if g.entry(ptr).is_some_and(|c| c.kind == 102) {
                        for f in g.params(ptr)?.iter().skip(2) {
                            if let Field::Token(t) = f {
                                param_curves.extend(t.parse::<usize>().ok());
                            }
                        }
                    }
                }
            }
        }
    }
    // composite curves in model space, and every member DE they hold (not read on their own)
    let mut composites = std::collections::BTreeMap::new();
    let mut members = BTreeSet::new();
    for (k, e) in g.entries.iter().enumerate() {
        let de = 2 * k + 1;
        if e.kind == 102 && e.use_flag != 5 && !param_curves.contains(&de) {
            let c = composite(&g, de, 0)?;
            if let Members::Read(_, m) = &c {
                members.extend(m.iter().copied());
            }
            composites.insert(de, c);
        }
    }
    composites.retain(|de, _| !members.contains(de));
    let mut out = CadContents {
        unit,
        ..CadContents::default()
    };
    for (k, e) in g.entries.iter().enumerate() {
        let de = 2 * k + 1;
        if let Some(c) = composites.remove(&de) {
            let read = match c {
                Members::Read(segments, _) => Ok(segments),
                Members::Unsupported(name) => Err(name),
            };
            out.push_composite(&format!("DE {de}"), read);
            continue;
        }
        if members.contains(&de) {
            continue;
        }
        match e.kind {
            126 if e.use_flag != 5 && !param_curves.contains(&de) => {
                out.curves.push((format!("DE {de}"), curve(&g, de)?));
            }
            100 if e.use_flag != 5 && !param_curves.contains(&de) => {
                let (c, kind) = circular_arc(&g, de)?;
                out.curves.push((format!("DE {de} ({kind})"), c));
            }
            104 if e.use_flag != 5 && !param_curves.contains(&de) => {
                let (c, kind) = conic_arc(&g, de)?;
                out.curves.push((format!("DE {de} ({kind})"), c));
            }
            128 => {
                out.surfaces.push((format!("DE {de}"), surface(&g, de)?));
            }
            kind => {
                if let Some((name, is_surface)) = other_name(kind) {
                    if is_surface {
                        out.other_surfaces.insert(name.into());
                    } else {
                        out.other_curves.insert(name.into());
                    }
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_with_hollerith_empties_and_d_exponents() {
        let f = fields("126,3Ha,b,,1.5D-3, 2 .5 ,-.5E1;junk", ',', ';').unwrap();
        assert_eq!(
            f,
            vec![
                Field::Token("126".into()),
                Field::Text("a,b".into()),
                Field::Empty,
                Field::Token("1.5D-3".into()),
                Field::Token("2.5".into()),
                Field::Token("-.5E1".into()),
            ]
        );
        assert_eq!(real("1.5D-3"), Some(1.5e-3));
        assert_eq!(real("1.E2"), Some(100.0));
        assert_eq!(real("-.5E1"), Some(-5.0));
        assert_eq!(real("3"), Some(3.0));
        assert!(fields("5Hab;", ',', ';').is_err());
    }

    #[test]
    fn equal_weights_become_polynomial_only_when_positive() {
        assert_eq!(normalised(vec![2.0, 2.0, 2.0]), None);
        assert_eq!(normalised(vec![0.0, 0.0, 0.0]), Some(vec![0.0; 3]));
        assert_eq!(normalised(vec![-1.0, -1.0]), Some(vec![-1.0; 2]));
        // so the curve's validation refuses zero weights instead of reading a polynomial curve
        let pts = vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0)];
        let e = NurbsCurve::new(1, vec![0.0, 0.0, 1.0, 1.0], pts, normalised(vec![0.0; 2]))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "invalid weights: weight 0 is 0; weights must be finite and > 0"
        );
    }

    #[test]
    fn units_by_flag_and_name() {
        assert_eq!(unit_mm(1, ""), Some(25.4));
        assert_eq!(unit_mm(2, ""), Some(1.0));
        assert_eq!(unit_mm(6, ""), Some(1000.0));
        assert_eq!(unit_mm(3, "IN"), Some(25.4));
        assert_eq!(unit_mm(12, ""), None);
    }
}
