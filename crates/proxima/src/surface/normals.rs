//! Vertex normals for meshes whose files carry none.

use crate::math::{DVec3, Vec3};
use crate::mesh::Mesh;
use rayon::prelude::*;

/// Every vertex's unit normal: the sum of its faces' unit normals, each
/// weighted by the face's angle at the vertex (Thürmer and Wüthrich), the
/// weighting that does not change when a face is split. Polygons count by
/// their fan triangles, whose angles at a vertex add up to the polygon's.
/// Summed in `f64`; vertices are the mesh's own (a position stored twice
/// keeps two normals, as a seam or a hard edge in the file asks), and a
/// vertex no face uses, or whose faces cancel, gets zero.
///
/// ```
/// use proxima::prelude::*;
/// use proxima::surface::vertex_normals;
/// // Two faces folded 90° along the edge 0–1: that edge's vertices point halfway.
/// let mesh = Mesh::from_triangles(
///     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
///     &[[0, 1, 2], [1, 0, 3]],
/// )
/// .unwrap();
/// let n = vertex_normals(&mesh);
/// assert!((n[0] - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
/// assert_eq!((n[2], n[3]), (Vec3::Z, Vec3::Y));
/// ```
pub fn vertex_normals(mesh: &Mesh) -> Vec<Vec3> {
    let positions: Vec<DVec3> = mesh.positions().iter().map(|p| p.as_dvec3()).collect();
    let (_, sums) = angle_weighted_sums(&positions, &mesh.triangle_vertex_indices());
    sums.iter().map(|s| s.normalize_or_zero().as_vec3()).collect()
}

/// The unit normal of every triangle (zero without area), and for every
/// vertex the sum of its triangles' unit normals weighted by their angles
/// at it, unnormalized (the vertex pseudonormals of [`crate::sdf`] too).
pub(crate) fn angle_weighted_sums(positions: &[DVec3], triangles: &[[u32; 3]]) -> (Vec<DVec3>, Vec<DVec3>) {
    let normals: Vec<DVec3> = triangles
        .par_iter()
        .map(|c| {
            let [a, b, c] = c.map(|v| positions[v as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect();
    let mut sums = vec![DVec3::ZERO; positions.len()];
    for (corners, n) in triangles.iter().zip(&normals) {
        let p = corners.map(|v| positions[v as usize]);
        for k in 0..3 {
            let angle = (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]);
            if angle.is_finite() {
                sums[corners[k] as usize] += angle * *n;
            }
        }
    }
    (normals, sums)
}
