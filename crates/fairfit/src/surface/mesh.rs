//! The triangle mesh (or point cloud) that [`super::slicing`] cuts into sections: vertices and
//! triangles as indices into them. `crate::io::mesh_read` reads it from PLY, STL, OBJ and point files.

use crate::nurbs::Vec3;

/// Vertices and triangles (indices into `vertices`); a point cloud has no triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The vertex positions.
    pub vertices: Vec<Vec3>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[usize; 3]>,
}
