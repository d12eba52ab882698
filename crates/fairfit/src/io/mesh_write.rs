//! Mesh files from a [`Mesh`]: Wavefront OBJ (`v`/`vn`/`f`, polylines as `l`), binary STL (triangles
//! only) and ASCII PLY (vertices with normals, faces, polyline segments as `edge` elements).
//!
//! Written by hand: each format is a few lines, and no dependency is needed. Coordinates in OBJ and
//! PLY are written in shortest round-trip form; STL stores `f32` by definition.

use super::numbers::unsigned_zeros;
use super::tessellate::{tessellate_curve, tessellate_surface, Mesh, TessellationOptions};
use crate::errors::{Error, Result};
use crate::nurbs::{NurbsCurve, NurbsSurface, Vec3};
use std::fmt::Write as _;
use std::path::Path;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ (text).
    Obj,
    /// Binary STL (triangles only).
    Stl,
    /// PLY (ASCII).
    Ply,
}

impl MeshFormat {
    /// The format named by a path's extension (`.obj`, `.stl`, `.ply`, any case).
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("obj") => Ok(MeshFormat::Obj),
            Some("stl") => Ok(MeshFormat::Stl),
            Some("ply") => Ok(MeshFormat::Ply),
            _ => Err(Error::InvalidOption(format!(
                "{}: unknown mesh format, expected a .obj, .stl or .ply file name",
                path.display()
            ))),
        }
    }
}

fn v3(p: Vec3) -> String {
    let [x, y, z] = unsigned_zeros(p.0);
    format!("{x:?} {y:?} {z:?}")
}

/// OBJ text of a mesh (1-based indices, `f a//a b//b c//c` when normals are present).
pub fn to_obj(mesh: &Mesh) -> String {
    let mut out = String::from("# fairfit mesh\n");
    for &p in &mesh.vertices {
        let _ = writeln!(out, "v {}", v3(p));
    }
    for &n in &mesh.normals {
        let _ = writeln!(out, "vn {}", v3(n));
    }
    let with_normals = mesh.normals.len() == mesh.vertices.len();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if with_normals {
            let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
        } else {
            let _ = writeln!(out, "f {a} {b} {c}");
        }
    }
    for line in &mesh.polylines {
        let ids: Vec<String> = line.iter().map(|i| (i + 1).to_string()).collect();
        let _ = writeln!(out, "l {}", ids.join(" "));
    }
    out
}

/// Binary STL bytes (facet normals from the triangle corners). A mesh without triangles is an error.
pub fn to_stl(mesh: &Mesh) -> Result<Vec<u8>> {
    if mesh.triangles.is_empty() {
        return Err(Error::InvalidOption(
            "STL holds triangles only: write a curve as .obj or .ply".into(),
        ));
    }
    let count = u32::try_from(mesh.triangles.len())
        .map_err(|_| Error::InvalidOption("too many triangles for STL".into()))?;
    let mut out = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    let mut header = [b' '; 80];
    let title = b"fairfit binary STL";
    header[..title.len()].copy_from_slice(title);
    out.extend_from_slice(&header);
    out.extend_from_slice(&count.to_le_bytes());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let n = (b - a).cross(c - a);
        let n = if n.norm() > 0.0 { n / n.norm() } else { n };
        for p in [n, a, b, c] {
            for x in unsigned_zeros(p.0) {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    Ok(out)
}

/// ASCII PLY text: `vertex` (x y z [nx ny nz] as double), `face`, and `edge` for polyline segments.
pub fn to_ply(mesh: &Mesh) -> String {
    let with_normals = mesh.normals.len() == mesh.vertices.len() && !mesh.normals.is_empty();
    let edges: Vec<[u32; 2]> = mesh
        .polylines
        .iter()
        .flat_map(|l| l.windows(2).map(|w| [w[0], w[1]]))
        .collect();
    let mut out = String::from("ply\nformat ascii 1.0\ncomment fairfit mesh\n");
    let _ = writeln!(out, "element vertex {}", mesh.vertices.len());
    out.push_str("property double x\nproperty double y\nproperty double z\n");
    if with_normals {
        out.push_str("property double nx\nproperty double ny\nproperty double nz\n");
    }
    let _ = writeln!(out, "element face {}", mesh.triangles.len());
    out.push_str("property list uchar int vertex_indices\n");
    let _ = writeln!(out, "element edge {}", edges.len());
    out.push_str("property int vertex1\nproperty int vertex2\nend_header\n");
    for (k, &p) in mesh.vertices.iter().enumerate() {
        if with_normals {
            let _ = writeln!(out, "{} {}", v3(p), v3(mesh.normals[k]));
        } else {
            let _ = writeln!(out, "{}", v3(p));
        }
    }
    for [a, b, c] in &mesh.triangles {
        let _ = writeln!(out, "3 {a} {b} {c}");
    }
    for [a, b] in &edges {
        let _ = writeln!(out, "{a} {b}");
    }
    out
}

/// The bytes of `mesh` in `format`.
pub fn mesh_bytes(mesh: &Mesh, format: MeshFormat) -> Result<Vec<u8>> {
    match format {
        MeshFormat::Obj => Ok(to_obj(mesh).into_bytes()),
        MeshFormat::Stl => to_stl(mesh),
        MeshFormat::Ply => Ok(to_ply(mesh).into_bytes()),
    }
}

/// Tessellates a surface and writes it atomically in the format named by the extension.
pub fn write_surface_mesh(
    path: impl AsRef<Path>,
    s: &NurbsSurface,
    opts: &TessellationOptions,
) -> Result<()> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    super::cad_common::validate_surface(s)?;
    let bytes = mesh_bytes(&tessellate_surface(s, opts)?, format)?;
    super::write_atomic(path, &bytes)
}

/// Tessellates a curve into a polyline and writes it atomically (`.obj` or `.ply`; STL is an error).
pub fn write_curve_mesh(
    path: impl AsRef<Path>,
    c: &NurbsCurve,
    opts: &TessellationOptions,
) -> Result<()> {
    let path = path.as_ref();
    let format = MeshFormat::from_path(path)?;
    super::cad_common::validate_curve(c)?;
    let bytes = mesh_bytes(&tessellate_curve(c, opts)?, format)?;
    super::write_atomic(path, &bytes)
}
