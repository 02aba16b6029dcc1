//! A surface point with the attributes read there, for a batch of answers:
//! everything a query's caller may ask about where its answer lies,
//! computed in one visit of the answer's triangle.

use super::{FanTriangle, SurfacePoint, corner_normals, face_normal, interpolated_uv, ray_weights, shading_normal};
use crate::math::{DVec3, Vec3};
use crate::mesh::Mesh;
use crate::primitive::closest_f64::point_triangle_closest;
use crate::query::{ClosestHit, RayHit};

/// The attributes a [`SurfaceAnswer`] carries besides its location.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Attributes {
    /// The interpolated shading normal and the triangle's normal.
    pub normals: bool,
    /// The interpolated texture coordinates (on a mesh that has them).
    pub uv: bool,
}

impl Attributes {
    /// The location only.
    pub const NONE: Self = Self {
        normals: false,
        uv: false,
    };
}

/// Where an answer lies ([`SurfacePoint`]) and the attributes asked for
/// there, each computed as [`SurfacePoint`]'s own method computes it.
///
/// ```
/// use proxima::index::MeshIndex;
/// use proxima::surface::{Attributes, Feature};
/// use proxima::{DVec3, Mesh, PrimitiveKind, Vec3};
/// let mesh = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[vec![0, 1, 2]]).unwrap();
/// let index = MeshIndex::new(mesh);
/// let points = [Vec3::new(0.25, 0.25, 1.0)];
/// let hits = index.closest(PrimitiveKind::Faces, &points).unwrap();
/// let asked = Attributes { normals: true, uv: false };
/// let answer = index.closest_surface(&points, &hits, asked).get(0).unwrap();
/// assert_eq!(answer.at.feature, Feature::Face);
/// assert_eq!(answer.at.barycentric, [0.5, 0.25, 0.25]);
/// assert_eq!((answer.normal, answer.face_normal), (DVec3::Z, DVec3::Z));
/// assert_eq!(answer.uv, None); // not asked, and the mesh has none
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceAnswer {
    /// The location: triangle, barycentrics and feature.
    pub at: SurfacePoint,
    /// [`SurfacePoint::interpolated_normal`]; zero unless
    /// [`Attributes::normals`] was asked.
    pub normal: DVec3,
    /// [`SurfacePoint::face_normal`]; zero unless [`Attributes::normals`]
    /// was asked.
    pub face_normal: DVec3,
    /// [`SurfacePoint::uv`]; `None` unless [`Attributes::uv`] was asked
    /// and the mesh has texture coordinates.
    pub uv: Option<[f64; 2]>,
}

impl SurfaceAnswer {
    /// The attributes `asked` of `at` on `mesh`, whose per-vertex normals
    /// are `normals` (read only when the mesh has no corner normals).
    ///
    /// # Panics
    /// When normals are asked, the mesh has no corner normals and `normals`
    /// has fewer entries than it has vertices.
    #[inline]
    pub fn new(at: SurfacePoint, mesh: &Mesh, normals: &[Vec3], asked: Attributes) -> Self {
        let (normal, face_normal) = match asked.normals {
            true => (at.interpolated_normal(mesh, normals), at.face_normal(mesh)),
            false => (DVec3::ZERO, DVec3::ZERO),
        };
        Self {
            at,
            normal,
            face_normal,
            uv: if asked.uv { at.uv(mesh) } else { None },
        }
    }
}

/// The answers of a batch, by input index, to be located on their fan
/// triangles.
#[derive(Clone, Copy)]
pub(crate) enum Located<'a> {
    /// Closest-point answers to these query points
    /// ([`SurfacePoint::closest`]).
    Closest {
        /// The query points.
        points: &'a [Vec3],
        /// Their answers on the mesh's faces.
        hits: &'a [Option<ClosestHit>],
    },
    /// First hits of rays ([`SurfacePoint::of_ray_hit`]).
    Rays(&'a [Option<RayHit>]),
}

impl Located<'_> {
    /// Each answer's fan triangle, `u32::MAX` where there is no answer: the
    /// key of [`in_triangle_order_blocks`](super::in_triangle_order_blocks).
    pub(crate) fn triangles(&self) -> Vec<u32> {
        let triangle = |primitive: Option<u32>| primitive.unwrap_or(u32::MAX);
        match self {
            Located::Closest { hits, .. } => hits.iter().map(|h| triangle(h.map(|h| h.primitive))).collect(),
            Located::Rays(hits) => hits.iter().map(|h| triangle(h.map(|h| h.primitive))).collect(),
        }
    }

    /// What answer `i` reads of the batch: its face and fan triangle, and
    /// its query point or its ray hit's `u`, `v` (in the first two lanes).
    #[inline]
    fn read(&self, i: usize) -> Option<Read> {
        match self {
            Located::Closest { points, hits } => hits[i].map(|h| Read {
                face: h.source,
                triangle: h.primitive,
                query: points[i],
            }),
            Located::Rays(hits) => hits[i].map(|h| Read {
                face: h.source,
                triangle: h.primitive,
                query: Vec3::new(h.u, h.v, 0.0),
            }),
        }
    }

    /// The weights of an answer read as `read` on its triangle of corners
    /// `at` (used only for closest points).
    #[inline]
    fn weights(&self, read: &Read, at: &[DVec3; 3]) -> [f64; 3] {
        match self {
            Located::Closest { .. } => point_triangle_closest(read.query.as_dvec3(), at).1,
            Located::Rays(_) => ray_weights(read.query.x, read.query.y),
        }
    }
}

/// What an answer reads of its batch ([`Located::read`]).
#[derive(Clone, Copy, Default)]
struct Read {
    face: u32,
    triangle: u32,
    query: Vec3,
}

/// Answers gathered together: enough independent loads in flight to hide
/// most of the mesh arrays' cache misses, little enough stack.
pub(crate) const GROUP: usize = 64;

/// What an answer reads at its triangle's corners.
#[derive(Clone, Copy, Default)]
struct Corners {
    positions: [DVec3; 3],
    normals: [Vec3; 3],
    uvs: [[f32; 2]; 3],
}

/// The answers `block` (input indices) of `located` with the attributes
/// `asked`, written to `out` (as long as `block`); those without an answer
/// are left as they are. Each group of [`GROUP`] answers is taken in four
/// passes: what they read of the batch, their fan triangles, every corner
/// value they read, then the arithmetic, so that the loads of a pass do
/// not wait on one another (about twice as fast as one answer after
/// another: docs/perf-log.md). Each answer equals [`SurfaceAnswer::new`]
/// of the surface point located alone.
pub(crate) fn answer_groups(
    mesh: &Mesh,
    normals: &[Vec3],
    asked: Attributes,
    located: Located<'_>,
    block: &[u32],
    out: &mut [Option<SurfaceAnswer>],
) {
    let positions = matches!(located, Located::Closest { .. }) || asked.normals;
    let uvs = if asked.uv { mesh.corner_uvs() } else { None };
    let mut reads = [None::<Read>; GROUP];
    let mut fans = [None::<FanTriangle>; GROUP];
    let mut corners = [Corners::default(); GROUP];
    for (group, out) in block.chunks(GROUP).zip(out.chunks_mut(GROUP)) {
        for (read, &i) in reads.iter_mut().zip(group) {
            *read = located.read(i as usize);
        }
        for (fan, read) in fans.iter_mut().zip(&reads[..group.len()]) {
            *fan = read.map(|r| FanTriangle::of(mesh, r.face, r.triangle));
        }
        for (at, fan) in corners.iter_mut().zip(&fans[..group.len()]) {
            let Some(fan) = fan else { continue };
            if positions {
                at.positions = fan.corners.map(|v| mesh.positions()[v as usize].as_dvec3());
            }
            if asked.normals {
                at.normals = corner_normals(mesh, normals, fan.corners, fan.slots);
            }
            if let Some(uvs) = uvs {
                at.uvs = fan.slots.map(|k| uvs[k]);
            }
        }
        for (((fan, read), at), out) in fans.iter().zip(&reads).zip(&corners).zip(out) {
            let (Some(fan), Some(read)) = (fan, read) else { continue };
            let point = fan.at(located.weights(read, &at.positions));
            let face_normal = if asked.normals {
                face_normal(at.positions)
            } else {
                DVec3::ZERO
            };
            let answer = SurfaceAnswer {
                at: point,
                normal: match asked.normals {
                    true => shading_normal(at.normals, point.barycentric, || face_normal),
                    false => DVec3::ZERO,
                },
                face_normal,
                uv: uvs.map(|_| interpolated_uv(at.uvs, point.barycentric)),
            };
            *out = Some(answer);
        }
    }
}
