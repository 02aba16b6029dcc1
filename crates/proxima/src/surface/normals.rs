//! Vertex normals for meshes whose files carry none.

use super::angle::normals_and_angles;
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
    let mut weighted = AngleWeighted::default();
    weighted.compute(&positions, &mesh.triangle_vertex_indices());
    weighted.sums.iter().map(|s| s.normalize_or_zero().as_vec3()).collect()
}

/// The unit normal of every triangle (zero without area), and for every
/// vertex the sum of its triangles' unit normals weighted by their angles
/// at it, unnormalized (the vertex pseudonormals of [`crate::sdf`] too).
/// Computed again in the same arrays when the positions move.
#[derive(Clone, Debug, Default)]
pub(crate) struct AngleWeighted {
    /// Per triangle.
    pub normals: Vec<DVec3>,
    /// Per triangle, its angle at each corner.
    angles: Vec<[f64; 3]>,
    /// Per vertex.
    pub sums: Vec<DVec3>,
}

impl AngleWeighted {
    /// The normals and sums of `triangles` (vertex indices into
    /// `positions`), in the arrays of the last call: fresh pages cost about
    /// as much as the arithmetic.
    pub(crate) fn compute(&mut self, positions: &[DVec3], triangles: &[[u32; 3]]) {
        // The normals and the corners' angles on all cores, four triangles
        // at a time (three arc cosines per triangle are most of the work);
        // the sums, which scatter, on one (a gather per vertex read two
        // triangle records per corner at random, and took longer).
        let n = triangles.len();
        self.normals.resize(n, DVec3::ZERO);
        self.angles.resize(n, [0.0; 3]);
        self.normals
            .par_chunks_mut(4)
            .zip(self.angles.par_chunks_mut(4))
            .zip(triangles.par_chunks(4))
            .with_min_len(256)
            .for_each(|((normals, angles), chunk)| {
                // A short last chunk repeats its last triangle.
                let four = std::array::from_fn(|lane| chunk[lane.min(chunk.len() - 1)].map(|v| positions[v as usize]));
                let (n, a) = normals_and_angles(&four);
                normals.copy_from_slice(&n[..chunk.len()]);
                angles.copy_from_slice(&a[..chunk.len()]);
            });
        self.sums.clear();
        self.sums.resize(positions.len(), DVec3::ZERO);
        for ((corners, n), angles) in triangles.iter().zip(&self.normals).zip(&self.angles) {
            for k in 0..3 {
                // A corner without an angle (a side of no length) adds nothing.
                if angles[k].is_finite() {
                    self.sums[corners[k] as usize] += angles[k] * *n;
                }
            }
        }
    }
}
