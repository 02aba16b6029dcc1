//! Convex polygons: mesh faces of up to [`MAX_POLYGON_VERTICES`] vertices used
//! as primitives as they are, so quad and n-gon meshes need no triangulation.
//!
//! # What a `ConvexPolygon` is
//!
//! A [`ConvexPolygon`] holds its vertices inline (a fixed array and a count, no
//! heap allocation) and a unit normal `n` (`f32`). There are two kinds:
//!
//! - **Three vertices**: exactly the [`Triangle`], degenerate ones included.
//!   Every method delegates to the triangle's routine, so answers are bit for
//!   bit those of [`Triangle`] ([`ClosestPoint`], [`BoxOverlap`](super::BoxOverlap),
//!   [`WatertightRay::intersect`], grid cells).
//! - **Four or more vertices**: accepted by [`ConvexPolygon::new`] only when,
//!   checked in `f64` against the stored `f32` normal `n` (Newell's normal of
//!   the vertices, normalized):
//!   1. *strictly convex*: at every vertex the boundary turns left seen along
//!      `n`, by an angle whose sine is at least [`CONVEX_SINE`] (no straight,
//!      reflex or hairpin corners, no repeated vertices), and it winds around
//!      once (every vertex lies strictly inside the angle at `v0`);
//!   2. *planar within tolerance*: the **thickness** `t = max nᵀvᵢ − min nᵀvᵢ`
//!      is at most `tolerance × D`, with `D` the diagonal of the vertices'
//!      bounding box and `tolerance` [`DEFAULT_PLANARITY_TOLERANCE`] (10⁻⁵)
//!      unless given.
//!
//!   [`Mesh::polygons`](crate::Mesh::polygons) fan-triangulates every face
//!   that fails (its pieces are 3-vertex polygons with the same source face)
//!   and reports how many did.
//!
//! `f32` vertices of a face are rarely exactly coplanar, so for `t > 0` the
//! answers are defined as follows, and differ from those of the fan
//! triangulation `(v0, vᵢ, vᵢ₊₁)` by at most `2t` (`≤ 2·10⁻⁵ D` by default)
//! plus `f32` rounding. When `t = 0` (exactly planar vertices) they are the
//! fan triangulation's, up to `f32` rounding for distances and exactly for
//! boxes (as exactly as the triangle's test: for coordinates of moderate
//! dynamic range, see `polygon_aabb.rs`).
//!
//! - [`ClosestPoint`]: when the query projects along `n` inside every edge
//!   (the sign of `((vᵢ₊₁ − vᵢ) × (p − vᵢ)) · n`), the projection onto the
//!   plane through `v0` with normal `n`, clamped to the vertices' bounding box
//!   (so the point is never outside the primitive's box, which the trees rely
//!   on); otherwise the closest point on the boundary edges (only the edges the
//!   query lies outside of are tried; for a convex polygon one of them holds
//!   the answer). The distance differs from the fan triangulation's by at most
//!   `2t`: the fan lies within `t` of that plane and covers the same region
//!   seen along `n`, and the boundary edges are edges of the fan. Edge signs
//!   that come out exactly zero or not finite (a query on an edge's line, or
//!   coordinates whose products underflow or overflow) redo the whole
//!   computation in `f64`.
//! - [`BoxOverlap`](super::BoxOverlap): the separating axis test with the box normals, the
//!   polygon normal (Newell's, in `f64`) and every boundary edge × box axis,
//!   in `f64` (see `polygon_aabb.rs`). For coplanar vertices this is exact
//!   (the complete axis set of a planar convex polygon). For `t > 0` it is
//!   conservative: it never misses a box that meets the convex hull of the
//!   vertices (which holds every fan triangle), and may accept a box that
//!   only comes very close to it.
//! - Rays ([`ConvexPolygon::intersect_ray`]): the fan triangles, each with
//!   [`WatertightRay::intersect`], nearest hit first. A boundary edge is an edge
//!   of exactly one fan triangle, with the same two vertices as in the
//!   neighbouring face, so rays cannot slip between a polygon and its
//!   neighbours (nor between two fan triangles of the same polygon).
//!
//! Faces of more than [`MAX_POLYGON_VERTICES`] vertices that pass the checks
//! are cut into pieces of at most that many vertices, all sharing `v0` (a fan
//! of convex polygons); the pieces' fan triangles are the face's.

use super::closest_polygon::closest_on_polygon;
use super::closest_triangle::closest_on_triangle;
use super::ray_triangle::{TriangleHit, WatertightRay};
use super::{Bounded, BoundingPoints, ClosestPoint, Triangle};
use crate::aabb::Aabb;
use crate::error::PolygonError;
use crate::math::{Vec3, Vec3A};
use glam::DVec3;

/// Capacity of a [`ConvexPolygon`]: faces with more vertices are cut into pieces.
pub const MAX_POLYGON_VERTICES: usize = 8;

/// Default relative planarity tolerance: the vertices' extent along the
/// normal may be at most this fraction of their bounding box diagonal.
pub const DEFAULT_PLANARITY_TOLERANCE: f32 = 1e-5;

/// Smallest accepted sine of the turn at a vertex, relative to the two edge
/// lengths: corners closer to straight (or to a hairpin) than this are not
/// accepted as convex.
pub const CONVEX_SINE: f64 = 1e-6;

/// A convex polygon of 3 to [`MAX_POLYGON_VERTICES`] vertices, stored inline.
/// See the [module documentation](self) for what it means and what its
/// methods compute.
///
/// ```
/// use proxima::primitive::ConvexPolygon;
/// use proxima::{ClosestPoint, Vec3, Vec3A};
/// let square = ConvexPolygon::new(&[Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]).unwrap();
/// assert_eq!(square.normal(), Vec3::Z);
/// assert_eq!(square.closest_point(Vec3A::new(0.25, 0.5, 2.0)), Vec3A::new(0.25, 0.5, 0.0));
/// assert_eq!(square.closest_point(Vec3A::new(3.0, 0.5, 0.0)), Vec3A::new(1.0, 0.5, 0.0));
/// // A bent quad is not planar; a dart is not convex.
/// assert!(ConvexPolygon::new(&[Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y]).is_err());
/// assert!(ConvexPolygon::new(&[Vec3::ZERO, Vec3::X, Vec3::new(0.2, 0.2, 0.0), Vec3::Y]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexPolygon {
    /// The vertices in order; slots past `count` repeat `vertices[0]`, so
    /// that loops over all slots (bounds, shadows) need no count.
    vertices: [Vec3; MAX_POLYGON_VERTICES],
    /// Unit normal (zero for a degenerate triangle).
    normal: Vec3,
    count: u32,
}

/// Where a ray meets a polygon: the hit of its fan triangle
/// `(v0, v(triangle + 1), v(triangle + 2))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolygonHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Which fan triangle was hit (0-based).
    pub triangle: u32,
    /// Barycentric weights within that triangle (see [`TriangleHit`]).
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
}

impl Default for ConvexPolygon {
    /// The degenerate triangle at the origin (as `Triangle::default()`).
    fn default() -> Self {
        Self::from_triangle(&Triangle::default())
    }
}

impl ConvexPolygon {
    /// The triangle as a 3-vertex polygon (always accepted, degenerate or not).
    pub fn from_triangle(tri: &Triangle) -> Self {
        let normal = tri.scaled_normal().normalize_or_zero();
        Self::from_parts(&tri.vertices(), normal)
    }

    /// The polygon `vertices` with the default planarity tolerance; see
    /// [`ConvexPolygon::with_tolerance`].
    pub fn new(vertices: &[Vec3]) -> Result<Self, PolygonError> {
        Self::with_tolerance(vertices, DEFAULT_PLANARITY_TOLERANCE)
    }

    /// The polygon `vertices` (3 to [`MAX_POLYGON_VERTICES`], in boundary
    /// order, either orientation). Three vertices are always accepted; more
    /// must be strictly convex and planar within `tolerance` (relative to the
    /// bounding box diagonal), as the [module documentation](self) states.
    pub fn with_tolerance(vertices: &[Vec3], tolerance: f32) -> Result<Self, PolygonError> {
        if !(3..=MAX_POLYGON_VERTICES).contains(&vertices.len()) {
            return Err(PolygonError::VertexCount {
                count: vertices.len(),
                max: MAX_POLYGON_VERTICES,
            });
        }
        if let Some(index) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(PolygonError::NonFinite { index });
        }
        if vertices.len() == 3 {
            return Ok(Self::from_triangle(&Triangle::new(
                vertices[0],
                vertices[1],
                vertices[2],
            )));
        }
        let normal = check_convex_planar(vertices, tolerance)?;
        Ok(Self::from_parts(vertices, normal))
    }

    /// Stores the vertices (at most the capacity) and the normal as given.
    pub(crate) fn from_parts(vertices: &[Vec3], normal: Vec3) -> Self {
        let mut slots = [vertices[0]; MAX_POLYGON_VERTICES];
        slots[..vertices.len()].copy_from_slice(vertices);
        Self {
            vertices: slots,
            normal,
            count: vertices.len() as u32,
        }
    }

    /// The vertices in boundary order.
    #[inline]
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices[..self.count as usize]
    }

    /// Number of vertices (3 to [`MAX_POLYGON_VERTICES`]).
    #[inline]
    #[allow(clippy::len_without_is_empty)] // never empty
    pub fn len(&self) -> usize {
        self.count as usize
    }

    /// The unit normal (right-handed with the vertex order); zero for a
    /// degenerate triangle.
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The polygon as a triangle, when it has three vertices.
    #[inline]
    pub fn as_triangle(&self) -> Option<Triangle> {
        (self.count == 3).then(|| Triangle::new(self.vertices[0], self.vertices[1], self.vertices[2]))
    }

    /// The fan triangles `(v0, vᵢ, vᵢ₊₁)`, i = 1 … n − 2.
    pub fn fan_triangles(&self) -> impl ExactSizeIterator<Item = Triangle> + '_ {
        let v = self.vertices();
        v[1..].windows(2).map(move |w| Triangle::new(v[0], w[0], w[1]))
    }

    /// The vertices' extent along the unit normal (in `f64`): 0 for coplanar
    /// vertices, and for an accepted polygon at most the tolerance times the
    /// bounding box diagonal.
    pub fn thickness(&self) -> f64 {
        let n = self.normal.as_dvec3();
        let heights = self.vertices().iter().map(|v| v.as_dvec3().dot(n));
        let (lo, hi) = heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| (lo.min(h), hi.max(h)));
        hi - lo
    }

    /// The nearest hit of `ray` with a fan triangle at a parameter in
    /// `[t_min, t_max]` (ties to the first triangle), if any. Watertight: see
    /// the [module documentation](self).
    #[inline]
    pub fn intersect_ray(&self, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<PolygonHit> {
        let mut best: Option<PolygonHit> = None;
        for (i, tri) in self.fan_triangles().enumerate() {
            let limit = best.map_or(t_max, |b| b.t);
            if let Some(TriangleHit { t, u, v, .. }) = ray.intersect(&tri, t_min, limit)
                && best.is_none_or(|b| t < b.t)
            {
                best = Some(PolygonHit {
                    t,
                    triangle: i as u32,
                    u,
                    v,
                });
            }
        }
        best
    }
}

/// Checks a face of four or more vertices (any number) and gives its unit
/// normal, rounded to `f32`; the criteria are in the module documentation.
pub(crate) fn check_convex_planar(vertices: &[Vec3], tolerance: f32) -> Result<Vec3, PolygonError> {
    let v0 = vertices[0].as_dvec3();
    let mut newell = DVec3::ZERO;
    for w in vertices[1..].windows(2) {
        newell += (w[0].as_dvec3() - v0).cross(w[1].as_dvec3() - v0);
    }
    let unit = newell.normalize_or_zero();
    if unit == DVec3::ZERO || !unit.is_finite() {
        return Err(PolygonError::Degenerate);
    }
    let normal = unit.as_vec3();
    check_with_normal(vertices, normal, tolerance)?;
    Ok(normal)
}

/// The convexity and planarity checks against a given `f32` unit normal.
pub(crate) fn check_with_normal(vertices: &[Vec3], normal: Vec3, tolerance: f32) -> Result<(), PolygonError> {
    let n = normal.as_dvec3();
    let v = |i: usize| vertices[i].as_dvec3();
    let count = vertices.len();
    // Convex: strict left turns with a margin ...
    for i in 0..count {
        let before = v(i) - v((i + count - 1) % count);
        let after = v((i + 1) % count) - v(i);
        let turn = before.cross(after).dot(n);
        let turns_left = turn > CONVEX_SINE * before.length() * after.length();
        if !turns_left {
            return Err(PolygonError::NotConvex { index: i });
        }
    }
    // ... and winding once: every other vertex strictly inside the angle at v0.
    let (first, last) = (v(1) - v(0), v(count - 1) - v(0));
    for i in 2..count - 1 {
        let d = v(i) - v(0);
        if !(first.cross(d).dot(n) > 0.0 && d.cross(last).dot(n) > 0.0) {
            return Err(PolygonError::NotConvex { index: i });
        }
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut box_lo, mut box_hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for p in vertices.iter().map(|p| p.as_dvec3()) {
        let h = p.dot(n);
        (lo, hi) = (lo.min(h), hi.max(h));
        (box_lo, box_hi) = (box_lo.min(p), box_hi.max(p));
    }
    let allowed = tolerance as f64 * (box_hi - box_lo).length();
    let planar = hi - lo <= allowed; // false for NaN
    if !planar {
        return Err(PolygonError::NotPlanar {
            thickness: hi - lo,
            allowed,
        });
    }
    Ok(())
}

impl Bounded for ConvexPolygon {
    #[inline]
    fn bounds(&self) -> Aabb {
        // Unused slots repeat v0: no count needed.
        let mut lo = self.vertices[0];
        let mut hi = lo;
        for &p in &self.vertices[1..] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        Aabb::new(lo, hi)
    }
}

impl ClosestPoint for ConvexPolygon {
    #[inline]
    fn closest_point(&self, p: Vec3A) -> Vec3A {
        if self.count == 3 {
            let v = &self.vertices;
            return closest_on_triangle(v[0].into(), v[1].into(), v[2].into(), p);
        }
        closest_on_polygon(self.vertices(), self.normal.into(), self.bounds(), p)
    }
}

/// The points a bounding sphere must hold. A triangle or an exactly planar
/// polygon has its closest points in the hull of its vertices, so the
/// vertices are enough. A polygon planar only within its tolerance projects
/// queries onto its plane, clamped to its bounding box, which can leave the
/// vertices' hull by up to its thickness: it gives the box's eight corners.
impl BoundingPoints for ConvexPolygon {
    fn push_bounding_points(&self, out: &mut Vec<Vec3>) {
        if self.count == 3 || self.thickness() == 0.0 {
            out.extend_from_slice(self.vertices());
        } else {
            let b = self.bounds();
            out.extend((0..8).map(|corner| {
                Vec3::new(
                    if corner & 1 == 0 { b.min.x } else { b.max.x },
                    if corner & 2 == 0 { b.min.y } else { b.max.y },
                    if corner & 4 == 0 { b.min.z } else { b.max.z },
                )
            }));
        }
    }
}
