//! Where on the surface an answer lies: the triangle, its barycentric
//! coordinates, the mesh feature (face, edge or vertex) that holds the
//! point, and the normals there. What differentiable and graphics pipelines
//! read off a closest point or a ray hit.
//!
//! The answers are computed after the query, from its triangle, so a query
//! that does not ask for them pays nothing. Closest points are located again
//! in `f64` against the answer's triangle (Ericson's Voronoi regions,
//! [`point_triangle_closest`]): the barycentrics are non-negative, sum to 1
//! and reproduce the closest point within a few `f64` ulps, and the feature is
//! the smallest one whose closure holds that point (a weight of exactly 0
//! drops its corner). Ray hits keep the ray test's own `u`, `v`.
//!
//! ```
//! use proxima::prelude::*;
//! use proxima::surface::{Feature, SurfacePoint};
//! use proxima::DVec3;
//! let mesh = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]).unwrap();
//! let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
//! let at = |p: Vec3| SurfacePoint::closest(&mesh, &tree.closest(p).unwrap(), p);
//! // Beyond the quad's corner 2: its closest point is that vertex.
//! let corner = at(Vec3::new(2.0, 3.0, 1.0));
//! assert_eq!(corner.feature, Feature::Vertex(2));
//! assert_eq!(corner.barycentric[corner.corners.iter().position(|&v| v == 2).unwrap()], 1.0);
//! // Beside its edge from vertex 1 to 2.
//! assert_eq!(at(Vec3::new(2.0, 0.5, 0.0)).feature, Feature::Edge([1, 2]));
//! // Above the quad's diagonal: inside the face, not on an edge.
//! let middle = at(Vec3::new(0.5, 0.5, 1.0));
//! assert_eq!((middle.face, middle.feature), (0, Feature::Face));
//! assert!((middle.point(&mesh) - DVec3::new(0.5, 0.5, 0.0)).length() < 1e-12);
//! ```

mod angle;
mod answer;
pub(crate) mod normals;
mod order;

pub use answer::{Attributes, SurfaceAnswer};
pub(crate) use answer::{GROUP, Located, answer_groups};
pub use normals::vertex_normals;
pub use order::{TriangleOrdered, in_triangle_order_blocks};

use crate::math::{DVec3, Vec3};
use crate::mesh::Mesh;
use crate::primitive::closest_f64::point_triangle_closest;
use crate::query::{ClosestHit, RayHit};

/// The part of a mesh that holds a point of its surface, named by mesh
/// vertex indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// The interior of a face (for a polygon, the fan's diagonals too).
    Face,
    /// The edge between these two vertices, in the face's order.
    Edge([u32; 2]),
    /// This vertex.
    Vertex(u32),
}

impl Feature {
    /// 0 for a face, 1 for an edge, 2 for a vertex: the codes of the Python
    /// package and the command line.
    pub fn code(self) -> u8 {
        match self {
            Feature::Face => 0,
            Feature::Edge(_) => 1,
            Feature::Vertex(_) => 2,
        }
    }

    /// The vertices that name the feature, `u32::MAX` where there are
    /// fewer than two: `[MAX, MAX]` for a face, the edge's two, `[v, MAX]`
    /// for a vertex.
    pub fn vertices(self) -> [u32; 2] {
        match self {
            Feature::Face => [u32::MAX; 2],
            Feature::Edge(e) => e,
            Feature::Vertex(v) => [v, u32::MAX],
        }
    }
}

/// A point of a mesh's surface: the fan triangle that holds it, its
/// barycentric coordinates there and its feature.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The face.
    pub face: u32,
    /// The triangle of the face's fan (its index in [`Mesh::triangles`]).
    pub triangle: u32,
    /// The triangle's vertices: the face's `v0`, `vi`, `vi+1`.
    pub corners: [u32; 3],
    /// The weights of `corners`: non-negative, summing to 1.
    pub barycentric: [f64; 3],
    /// The smallest feature of the mesh that holds the point.
    pub feature: Feature,
}

impl SurfacePoint {
    /// The point closest to `p` of the triangle of `hit`, a closest-point
    /// answer on the mesh's faces (a tree built on [`Mesh::triangles`], as
    /// [`MeshIndex::closest`](crate::MeshIndex::closest) answers for
    /// [`PrimitiveKind::Faces`](crate::PrimitiveKind)), located in `f64`.
    ///
    /// # Panics
    /// When `hit` names a face or triangle the mesh does not have.
    pub fn closest(mesh: &Mesh, hit: &ClosestHit, p: Vec3) -> Self {
        let fan = FanTriangle::of(mesh, hit.source, hit.primitive);
        let corners = fan.corners.map(|v| mesh.positions()[v as usize].as_dvec3());
        let (_, barycentric) = point_triangle_closest(p.as_dvec3(), &corners);
        fan.at(barycentric)
    }

    /// Where a ray hit (of a tree built on [`Mesh::triangles`], as
    /// [`MeshIndex::ray_tree`](crate::MeshIndex::ray_tree) is) lies: the
    /// ray test's `u`, `v` as weights of the triangle's second and third
    /// corners.
    ///
    /// # Panics
    /// When `hit` names a face or triangle the mesh does not have.
    pub fn of_ray_hit(mesh: &Mesh, hit: &RayHit) -> Self {
        FanTriangle::of(mesh, hit.source, hit.primitive).at(ray_weights(hit.u, hit.v))
    }

    /// The point, in `f64`: the barycentric combination of the corners.
    pub fn point(&self, mesh: &Mesh) -> DVec3 {
        let p = self.corners.map(|v| mesh.positions()[v as usize].as_dvec3());
        p[0] * self.barycentric[0] + p[1] * self.barycentric[1] + p[2] * self.barycentric[2]
    }

    /// The triangle's unit normal (right-handed in the face's order), zero
    /// for a triangle without area.
    pub fn face_normal(&self, mesh: &Mesh) -> DVec3 {
        face_normal(self.corners.map(|v| mesh.positions()[v as usize].as_dvec3()))
    }

    /// The shading normal: the file's per-corner normals
    /// ([`Mesh::corner_normals`]) when the mesh has them, else the per-vertex
    /// `normals` (such as [`vertex_normals`]), interpolated by the
    /// barycentric weights, unit length; the face normal where the weighted
    /// sum vanishes.
    ///
    /// # Panics
    /// When the mesh has no corner normals and `normals` has fewer entries
    /// than it has vertices.
    pub fn interpolated_normal(&self, mesh: &Mesh, normals: &[Vec3]) -> DVec3 {
        let at = corner_normals(mesh, normals, self.corners, self.corner_slots(mesh));
        shading_normal(at, self.barycentric, || self.face_normal(mesh))
    }

    /// The texture coordinates interpolated by the barycentric weights,
    /// when the mesh has them ([`Mesh::corner_uvs`]).
    pub fn uv(&self, mesh: &Mesh) -> Option<[f64; 2]> {
        let uvs = mesh.corner_uvs()?;
        Some(interpolated_uv(
            self.corner_slots(mesh).map(|k| uvs[k]),
            self.barycentric,
        ))
    }

    /// The triangle's corners as face corners (the numbering of
    /// [`Mesh::corner_normals`] and [`Mesh::corner_uvs`]): the face's first,
    /// and its `i + 1`-th and `i + 2`-th for fan triangle `i`.
    pub fn corner_slots(&self, mesh: &Mesh) -> [usize; 3] {
        let face = self.face as usize;
        let first = mesh.face_offset(face);
        let i = self.triangle as usize - mesh.first_triangle(face);
        [first, first + i + 1, first + i + 2]
    }
}

/// The weights of a ray hit's point: the ray test's `u`, `v` for the
/// second and third corners.
#[inline]
fn ray_weights(u: f32, v: f32) -> [f64; 3] {
    // Weights of exactly zero (an edge or vertex hit) become +0, never
    // -0, so the feature reads them as zero and prints them as 0.
    let weight = |w: f64| w.max(0.0) + 0.0;
    let (u, v) = (weight(f64::from(u)), weight(f64::from(v)));
    [weight(1.0 - u - v), u, v]
}

/// A triangle's unit normal (right-handed in the corners' order), zero for
/// a triangle without area.
#[inline]
fn face_normal([a, b, c]: [DVec3; 3]) -> DVec3 {
    (b - a).cross(c - a).normalize_or_zero()
}

/// The normals at a fan triangle's corners (vertex ids `corners`, face
/// corner slots `slots`): the file's corner normals when the mesh has them,
/// else `normals` per vertex.
#[inline]
fn corner_normals(mesh: &Mesh, normals: &[Vec3], corners: [u32; 3], slots: [usize; 3]) -> [Vec3; 3] {
    match mesh.corner_normals() {
        Some(corner_normals) => slots.map(|k| corner_normals[k]),
        None => corners.map(|v| normals[v as usize]),
    }
}

/// The corner normals `at` interpolated by the weights `w`, unit length;
/// `face_normal()` where the weighted sum vanishes.
#[inline]
fn shading_normal(at: [Vec3; 3], w: [f64; 3], face_normal: impl FnOnce() -> DVec3) -> DVec3 {
    let sum: DVec3 = (0..3).map(|k| at[k].as_dvec3() * w[k]).sum();
    let n = sum.normalize_or_zero();
    if n == DVec3::ZERO { face_normal() } else { n }
}

/// The corner texture coordinates `uvs` interpolated by the weights `w`.
#[inline]
fn interpolated_uv(uvs: [[f32; 2]; 3], w: [f64; 3]) -> [f64; 2] {
    let mut uv = [0.0; 2];
    for (w, at) in w.iter().zip(uvs) {
        uv[0] += w * f64::from(at[0]);
        uv[1] += w * f64::from(at[1]);
    }
    uv
}

/// One triangle of a face's fan and which of its sides are the face's edges.
#[derive(Clone, Copy)]
struct FanTriangle {
    face: u32,
    triangle: u32,
    corners: [u32; 3],
    /// The corners' face corner slots ([`SurfacePoint::corner_slots`]).
    slots: [usize; 3],
    /// Side `k` runs from corner `k` to corner `(k + 1) % 3`; a side that is
    /// a diagonal of the polygon lies inside the face.
    side_is_edge: [bool; 3],
}

impl FanTriangle {
    #[inline]
    fn of(mesh: &Mesh, face: u32, triangle: u32) -> Self {
        let vertices = mesh.face(face as usize);
        let first = mesh.face_offset(face as usize);
        let i = triangle as usize - mesh.first_triangle(face as usize);
        let last = vertices.len() - 3;
        assert!(i <= last, "triangle {triangle} is not in face {face}");
        Self {
            face,
            triangle,
            corners: [vertices[0], vertices[i + 1], vertices[i + 2]],
            slots: [first, first + i + 1, first + i + 2],
            side_is_edge: [i == 0, true, i == last],
        }
    }

    /// Side `k` as a feature: the face's edge, or the face where the side is
    /// a diagonal.
    fn side(&self, k: usize) -> Feature {
        if self.side_is_edge[k] {
            Feature::Edge([self.corners[k], self.corners[(k + 1) % 3]])
        } else {
            Feature::Face
        }
    }

    /// The surface point of weights `barycentric`: its feature is the
    /// support of the weights.
    #[inline]
    fn at(&self, barycentric: [f64; 3]) -> SurfacePoint {
        let zero = barycentric.map(|w| w == 0.0);
        let feature = match zero {
            // Two weights zero: the third corner.
            [false, true, true] => Feature::Vertex(self.corners[0]),
            [true, false, true] => Feature::Vertex(self.corners[1]),
            [true, true, false] => Feature::Vertex(self.corners[2]),
            // One zero: the side opposite it (side k runs from corner k to k + 1).
            [false, false, true] => self.side(0),
            [true, false, false] => self.side(1),
            [false, true, false] => self.side(2),
            _ => Feature::Face,
        };
        SurfacePoint {
            face: self.face,
            triangle: self.triangle,
            corners: self.corners,
            barycentric,
            feature,
        }
    }
}
