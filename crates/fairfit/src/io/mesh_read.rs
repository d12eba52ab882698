//! Reading triangle meshes and point clouds: PLY (ascii and binary little-endian; vertices and faces,
//! other elements skipped), STL (ascii and binary; coincident corners welded so triangles share
//! vertices), OBJ (`v` and `f`, polygons fanned into triangles, negative indices allowed) and XYZ/CSV
//! point lists (no faces).
//!
//! Written here: the readers are small, the formats are stable, and fairfit needs typed one-line errors
//! naming the file and the place, which the general mesh crates do not give.

use super::limits::ReadLimits;
use super::sections::read_section_file;
use crate::errors::{Error, Result};
use crate::nurbs::Vec3;
use crate::surface::mesh::Mesh;
use std::collections::HashMap;
use std::path::Path;

fn bad(name: &str, msg: impl std::fmt::Display) -> Error {
    Error::InvalidData(format!("{name}: {msg}"))
}

/// Reads a mesh or point cloud, choosing the format by the file extension
/// (`ply`, `stl`, `obj`; anything else is read as an XYZ/CSV point list).
pub fn read_mesh(path: impl AsRef<Path>) -> Result<Mesh> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let whole = || super::limits::read_bounded(path);
    let mesh = match ext.as_str() {
        "ply" => parse_ply(&whole()?, &name)?,
        "stl" => parse_stl(&whole()?, &name)?,
        "obj" => parse_obj(
            &String::from_utf8_lossy(&super::limits::read_bounded_text(path)?),
            &name,
        )?,
        // a point cloud is streamed like a section file
        _ => Mesh {
            vertices: read_section_file(path)?,
            triangles: Vec::new(),
        },
    };
    ReadLimits::current().check_points(&name, mesh.vertices.len(), "vertices")?;
    if mesh.vertices.is_empty() {
        return Err(bad(&name, "no vertices"));
    }
    if let Some(i) = mesh.vertices.iter().position(|p| !p.is_finite()) {
        return Err(bad(&name, format!("vertex {i} is not finite")));
    }
    Ok(mesh)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn read(self, b: &[u8]) -> f64 {
        match self {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]),
        }
    }
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    /// `Some(count type)` for list properties.
    list: Option<Scalar>,
    ty: Scalar,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

/// A PLY file: its header parsed, then its elements read in order (vertices and faces kept).
fn parse_ply(bytes: &[u8], name: &str) -> Result<Mesh> {
    let (header, body) = ply_header(bytes, name)?;
    let mut reader: Box<dyn ValueReader> = if header.ascii {
        Box::new(AsciiValues::new(&bytes[body..]))
    } else {
        Box::new(BinaryValues {
            b: &bytes[body..],
            pos: 0,
        })
    };
    let mut mesh = Mesh::default();
    for el in &header.elements {
        read_element(el, reader.as_mut(), &mut mesh, name)?;
    }
    check_indices(&mesh, name)?;
    Ok(mesh)
}

/// What a PLY header declares: the encoding and the elements with their properties.
struct PlyHeader {
    /// `format ascii` (else `binary_little_endian`).
    ascii: bool,
    elements: Vec<Element>,
}

/// The header of a PLY file and the offset of its data (after the line end that follows `end_header`).
/// A vertex count is checked against the point limit here, before any data is read.
fn ply_header(bytes: &[u8], name: &str) -> Result<(PlyHeader, usize)> {
    let end = find_subslice(bytes, b"end_header")
        .ok_or_else(|| bad(name, "PLY header has no end_header"))?;
    let header = String::from_utf8_lossy(&bytes[..end]);
    let mut body = end + "end_header".len();
    // skip the line end after end_header
    while body < bytes.len() && (bytes[body] == b'\r' || bytes[body] == b'\n') {
        body += 1;
        if bytes[body - 1] == b'\n' {
            break;
        }
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (ln, line) in header.lines().enumerate() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first().copied() {
            Some("ply") | Some("comment") | Some("obj_info") | None => {}
            Some("format") => format = w.get(1).map(|s| s.to_string()),
            Some("element") => {
                let count = w.get(2).and_then(|c| c.parse().ok()).ok_or_else(|| {
                    bad(name, format!("header line {}: bad element count", ln + 1))
                })?;
                if w.get(1) == Some(&"vertex") {
                    ReadLimits::current().check_points(name, count, "vertices")?;
                }
                elements.push(Element {
                    name: w.get(1).unwrap_or(&"").to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let el = elements.last_mut().ok_or_else(|| {
                    bad(
                        name,
                        format!("header line {}: property before element", ln + 1),
                    )
                })?;
                el.props.push(ply_property(&w, ln, name)?);
            }
            Some(_) => {}
        }
    }
    let format = format.ok_or_else(|| bad(name, "PLY header has no format line"))?;
    let ascii = match format.as_str() {
        "ascii" => true,
        "binary_little_endian" => false,
        other => {
            return Err(bad(
                name,
                format!("PLY format {other} is not supported (ascii or binary_little_endian)"),
            ))
        }
    };
    Ok((PlyHeader { ascii, elements }, body))
}

/// A header's `property TYPE NAME` or `property list COUNT_TYPE TYPE NAME` line, split into words `w`
/// (`ln` is its 0-based line number).
fn ply_property(w: &[&str], ln: usize, name: &str) -> Result<Property> {
    if w.get(1) == Some(&"list") {
        let ct = w.get(2).and_then(|s| Scalar::parse(s));
        let ty = w.get(3).and_then(|s| Scalar::parse(s));
        match (ct, ty, w.get(4)) {
            (Some(ct), Some(ty), Some(n)) => Ok(Property {
                name: n.to_string(),
                list: Some(ct),
                ty,
            }),
            _ => Err(bad(
                name,
                format!("header line {}: bad list property", ln + 1),
            )),
        }
    } else {
        match (w.get(1).and_then(|s| Scalar::parse(s)), w.get(2)) {
            (Some(ty), Some(n)) => Ok(Property {
                name: n.to_string(),
                list: None,
                ty,
            }),
            _ => Err(bad(name, format!("header line {}: bad property", ln + 1))),
        }
    }
}

/// Reads every row of `el` from `reader`: a `vertex` row's x, y, z become a vertex, a `face` row's
/// vertex indices a fan of triangles; other elements and properties are read and dropped.
fn read_element(
    el: &Element,
    reader: &mut dyn ValueReader,
    mesh: &mut Mesh,
    name: &str,
) -> Result<()> {
    // every row must consume data, so a huge count in a short file ends with "data ends early"
    // instead of looping (and allocating) once per claimed row
    if el.props.is_empty() && el.count > 0 {
        return Err(bad(
            name,
            format!(
                "element {} has {} rows but no properties",
                el.name, el.count
            ),
        ));
    }
    let xi = el.props.iter().position(|p| p.name == "x");
    let yi = el.props.iter().position(|p| p.name == "y");
    let zi = el.props.iter().position(|p| p.name == "z");
    let fi = el
        .props
        .iter()
        .position(|p| p.name == "vertex_indices" || p.name == "vertex_index");
    let mut poly = Vec::new();
    for r in 0..el.count {
        let ends = || bad(name, format!("{} {r}: data ends early", el.name));
        let mut xyz = [0.0; 3];
        for (pi, p) in el.props.iter().enumerate() {
            match p.list {
                None => {
                    let v = reader.next(p.ty).ok_or_else(ends)?;
                    if el.name == "vertex" {
                        if Some(pi) == xi {
                            xyz[0] = v;
                        } else if Some(pi) == yi {
                            xyz[1] = v;
                        } else if Some(pi) == zi {
                            xyz[2] = v;
                        }
                    }
                }
                Some(ct) => {
                    let n = reader.next(ct).ok_or_else(ends)?;
                    if !(0.0..=1.0e6).contains(&n) {
                        return Err(bad(name, format!("{} {r}: bad list length {n}", el.name)));
                    }
                    poly.clear();
                    for _ in 0..n as usize {
                        poly.push(reader.next(p.ty).ok_or_else(ends)?);
                    }
                    if el.name == "face" && Some(pi) == fi {
                        push_polygon(mesh, &poly, name, r)?;
                    }
                }
            }
        }
        if el.name == "vertex" {
            mesh.vertices.push(Vec3::new(xyz[0], xyz[1], xyz[2]));
        }
    }
    Ok(())
}

fn push_polygon(mesh: &mut Mesh, poly: &[f64], name: &str, face: usize) -> Result<()> {
    if poly.len() < 3 {
        return Ok(());
    }
    let idx: Vec<usize> = poly
        .iter()
        .map(|&v| {
            if v >= 0.0 && v.fract() == 0.0 {
                Ok(v as usize)
            } else {
                Err(bad(name, format!("face {face}: bad vertex index {v}")))
            }
        })
        .collect::<Result<_>>()?;
    for k in 1..idx.len() - 1 {
        mesh.triangles.push([idx[0], idx[k], idx[k + 1]]);
    }
    Ok(())
}

fn check_indices(mesh: &Mesh, name: &str) -> Result<()> {
    let n = mesh.vertices.len();
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i >= n))
    {
        return Err(bad(
            name,
            format!("triangle {t} refers to a vertex beyond the {n} vertices"),
        ));
    }
    Ok(())
}

trait ValueReader {
    fn next(&mut self, ty: Scalar) -> Option<f64>;
}

struct BinaryValues<'a> {
    b: &'a [u8],
    pos: usize,
}

impl ValueReader for BinaryValues<'_> {
    fn next(&mut self, ty: Scalar) -> Option<f64> {
        let s = ty.size();
        let chunk = self.b.get(self.pos..self.pos + s)?;
        self.pos += s;
        Some(ty.read(chunk))
    }
}

struct AsciiValues<'a> {
    it: std::str::SplitAsciiWhitespace<'a>,
}

impl<'a> AsciiValues<'a> {
    fn new(b: &'a [u8]) -> Self {
        let s = std::str::from_utf8(b).unwrap_or("");
        AsciiValues {
            it: s.split_ascii_whitespace(),
        }
    }
}

impl ValueReader for AsciiValues<'_> {
    fn next(&mut self, _ty: Scalar) -> Option<f64> {
        self.it.next()?.parse().ok()
    }
}

fn find_subslice(h: &[u8], n: &[u8]) -> Option<usize> {
    h.windows(n.len()).position(|w| w == n)
}

/// Welds identical corner positions into shared vertices.
struct Welder {
    map: HashMap<[u64; 3], usize>,
    mesh: Mesh,
}

impl Welder {
    fn new() -> Self {
        Welder {
            map: HashMap::new(),
            mesh: Mesh::default(),
        }
    }
    fn vertex(&mut self, p: Vec3) -> usize {
        let key = [p.x().to_bits(), p.y().to_bits(), p.z().to_bits()];
        let n = self.mesh.vertices.len();
        *self.map.entry(key).or_insert_with(|| {
            self.mesh.vertices.push(p);
            n
        })
    }
    fn triangle(&mut self, t: [Vec3; 3]) {
        let i = [self.vertex(t[0]), self.vertex(t[1]), self.vertex(t[2])];
        if i[0] != i[1] && i[1] != i[2] && i[0] != i[2] {
            self.mesh.triangles.push(i);
        }
    }
}

fn parse_stl(bytes: &[u8], name: &str) -> Result<Mesh> {
    let binary_len = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    let is_binary = binary_len.is_some_and(|n| bytes.len() == 84 + 50 * n);
    let mut w = Welder::new();
    if is_binary {
        let n = binary_len.unwrap_or(0);
        for t in 0..n {
            let base = 84 + 50 * t + 12;
            let mut c = [Vec3::ZERO; 3];
            for (k, ck) in c.iter_mut().enumerate() {
                let mut xyz = [0.0; 3];
                for (a, v) in xyz.iter_mut().enumerate() {
                    let o = base + 12 * k + 4 * a;
                    *v = Scalar::F32.read(&bytes[o..o + 4]);
                }
                *ck = Vec3(xyz);
            }
            w.triangle(c);
        }
        return Ok(w.mesh);
    }
    let text = String::from_utf8_lossy(bytes);
    if !text.trim_start().starts_with("solid") {
        return Err(bad(
            name,
            "neither binary STL (size does not match the triangle count) nor ascii STL",
        ));
    }
    let mut corners = Vec::with_capacity(3);
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("vertex") => {
                let v: Vec<f64> = it.filter_map(|s| s.parse().ok()).collect();
                if v.len() != 3 {
                    return Err(bad(
                        name,
                        format!("line {}: vertex needs 3 numbers", ln + 1),
                    ));
                }
                corners.push(Vec3::new(v[0], v[1], v[2]));
            }
            Some("endloop") => {
                if corners.len() >= 3 {
                    for k in 1..corners.len() - 1 {
                        w.triangle([corners[0], corners[k], corners[k + 1]]);
                    }
                }
                corners.clear();
            }
            _ => {}
        }
    }
    Ok(w.mesh)
}

fn parse_obj(text: &str, name: &str) -> Result<Mesh> {
    let mut mesh = Mesh::default();
    let mut poly = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let v: Vec<f64> = it.take(3).map(|s| s.parse().unwrap_or(f64::NAN)).collect();
                if v.len() != 3 {
                    return Err(bad(name, format!("line {}: `v` needs 3 numbers", ln + 1)));
                }
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(bad(
                        name,
                        format!(
                            "line {}: `v` needs 3 finite numbers, got `{}`",
                            ln + 1,
                            line.trim()
                        ),
                    ));
                }
                mesh.vertices.push(Vec3::new(v[0], v[1], v[2]));
            }
            Some("f") => {
                poly.clear();
                for tok in it {
                    let first = tok.split('/').next().unwrap_or("");
                    let i: i64 = first.parse().map_err(|_| {
                        bad(name, format!("line {}: bad face index `{tok}`", ln + 1))
                    })?;
                    let n = mesh.vertices.len() as i64;
                    let idx = if i < 0 { n + i } else { i - 1 };
                    if idx < 0 {
                        return Err(bad(
                            name,
                            format!("line {}: face index {i} out of range", ln + 1),
                        ));
                    }
                    poly.push(idx as f64);
                }
                push_polygon(&mut mesh, &poly, name, ln + 1)?;
            }
            _ => {}
        }
    }
    check_indices(&mesh, name)?;
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> (Vec<Vec3>, Vec<[usize; 3]>) {
        let v = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let t = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        (v, t)
    }

    #[test]
    fn obj_vertices_name_what_is_wrong() {
        let e = parse_obj("v 0 0\n", "m.obj").unwrap_err().to_string();
        assert!(e.contains("line 1") && e.contains("needs 3 numbers"), "{e}");
        let e = parse_obj("v 0 0 0\nv nan 0 0\n", "m.obj")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 2") && e.contains("finite") && e.contains("v nan 0 0"),
            "{e}"
        );
    }

    #[test]
    fn all_formats_give_the_same_tetrahedron() {
        let (v, t) = tetra();
        let dir = std::env::temp_dir().join(format!("fairfit_mesh_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // ascii PLY with an extra element
        let mut s = String::from("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int a\nproperty int b\nend_header\n");
        for p in &v {
            s += &format!("{} {} {}\n", p.x(), p.y(), p.z());
        }
        for f in &t {
            s += &format!("3 {} {} {}\n", f[0], f[1], f[2]);
        }
        s += "0 1\n";
        std::fs::write(dir.join("a.ply"), &s).unwrap();
        // binary PLY with a double property in between
        let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty double q\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
        for p in &v {
            b.extend((p.x() as f32).to_le_bytes());
            b.extend(7.5f64.to_le_bytes());
            b.extend((p.y() as f32).to_le_bytes());
            b.extend((p.z() as f32).to_le_bytes());
        }
        for f in &t {
            b.push(3);
            for i in f {
                b.extend((*i as i32).to_le_bytes());
            }
        }
        std::fs::write(dir.join("b.ply"), &b).unwrap();
        // binary STL
        let mut stl = vec![0u8; 80];
        stl.extend((t.len() as u32).to_le_bytes());
        for f in &t {
            stl.extend([0u8; 12]);
            for &i in f {
                for c in v[i].0 {
                    stl.extend((c as f32).to_le_bytes());
                }
            }
            stl.extend([0u8; 2]);
        }
        std::fs::write(dir.join("c.stl"), &stl).unwrap();
        // ascii STL
        let mut a = String::from("solid t\n");
        for f in &t {
            a += "facet normal 0 0 0\nouter loop\n";
            for &i in f {
                a += &format!("vertex {} {} {}\n", v[i].x(), v[i].y(), v[i].z());
            }
            a += "endloop\nendfacet\n";
        }
        a += "endsolid t\n";
        std::fs::write(dir.join("d.stl"), &a).unwrap();
        // OBJ, 1-based and negative indices
        let mut o = String::new();
        for p in &v {
            o += &format!("v {} {} {}\n", p.x(), p.y(), p.z());
        }
        for f in &t[..3] {
            o += &format!("f {}/1 {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
        }
        o += "f -4 -1 -2\n";
        std::fs::write(dir.join("e.obj"), &o).unwrap();
        for f in ["a.ply", "b.ply", "c.stl", "d.stl", "e.obj"] {
            let m = read_mesh(dir.join(f)).unwrap();
            assert_eq!(m.vertices.len(), 4, "{f}");
            assert_eq!(m.triangles.len(), 4, "{f}");
            // same geometry: triangle corner sets match
            let mut got: Vec<[[u64; 3]; 3]> = m
                .triangles
                .iter()
                .map(|tr| tr.map(|i| m.vertices[i].0.map(|c| c.to_bits())))
                .collect();
            let mut want: Vec<[[u64; 3]; 3]> = t
                .iter()
                .map(|tr| tr.map(|i| v[i].0.map(|c| c.to_bits())))
                .collect();
            got.sort();
            want.sort();
            assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                let mut g = *g;
                let mut w = *w;
                g.sort();
                w.sort();
                assert_eq!(g, w, "{f}");
            }
        }
        // truncated binary PLY: an error, no panic
        std::fs::write(dir.join("t.ply"), &b[..b.len() - 5]).unwrap();
        let e = read_mesh(dir.join("t.ply")).unwrap_err().to_string();
        assert!(e.contains("ends early"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn reads_the_bunny_scan() {
        // the shared data folder sits beside the project (main checkout) or two levels up (worktrees)
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let Some(p) = ["../../../shared", "../../../../shared"]
            .iter()
            .map(|r| root.join(r).join("data/scans/StanfordBunny.ply"))
            .find(|p| p.exists())
        else {
            return;
        };
        let m = read_mesh(&p).unwrap();
        assert_eq!(m.vertices.len(), 50_000);
        assert_eq!(m.triangles.len(), 99_785);
    }
}
