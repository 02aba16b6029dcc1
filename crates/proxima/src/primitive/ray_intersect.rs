//! The ray test a primitive offers to the ray queries of the trees.

use super::{Bounded, ConvexPolygon, Triangle, TriangleHit, WatertightRay};
use crate::math::Vec3;

/// A primitive that a ray can hit.
///
/// The trees answer "first hit" and "any hit" over any such primitive, and
/// their answers equal a scan calling [`intersect_ray`](Self::intersect_ray)
/// on every primitive (smallest `t`, ties to the lowest index). The test must
/// be *watertight* for a closed surface: a ray through an edge or a vertex
/// shared by several primitives hits at least one of them.
///
/// ```
/// use proxima::primitive::{RayIntersect, WatertightRay};
/// use proxima::{Triangle, Vec3};
/// let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
/// let ray = WatertightRay::new(Vec3::new(0.5, 0.25, 2.0), -Vec3::Z).unwrap();
/// let hit = tri.intersect_ray(&ray, 0.0, f32::INFINITY).unwrap();
/// assert_eq!(hit.t, 2.0);
/// assert_eq!(tri.hit_point(&hit), Vec3::new(0.5, 0.25, 0.0));
/// ```
pub trait RayIntersect: Bounded {
    /// The hit of `ray` with the primitive at a parameter in `[t_min, t_max]`,
    /// if any. A hit's `u`, `v` are surface coordinates that
    /// [`hit_point`](Self::hit_point) turns into a point.
    fn intersect_ray(&self, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<TriangleHit>;

    /// The point of the primitive that `hit` describes.
    fn hit_point(&self, hit: &TriangleHit) -> Vec3;
}

impl RayIntersect for Triangle {
    #[inline(always)]
    fn intersect_ray(&self, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        ray.intersect(self, t_min, t_max)
    }

    /// `a + u (b − a) + v (c − a)`.
    #[inline]
    fn hit_point(&self, hit: &TriangleHit) -> Vec3 {
        self.a + (self.b - self.a) * hit.u + (self.c - self.a) * hit.v
    }
}

/// A polygon is hit where its first hit fan triangle is (the fan shares its
/// edges with the neighbouring faces' fans, so the test stays watertight); the
/// hit's `piece` says which fan triangle.
impl RayIntersect for ConvexPolygon {
    #[inline]
    fn intersect_ray(&self, ray: &WatertightRay, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        ConvexPolygon::intersect_ray(self, ray, t_min, t_max).map(|hit| TriangleHit {
            t: hit.t,
            u: hit.u,
            v: hit.v,
            piece: hit.triangle,
        })
    }

    /// `v0 + u (v[piece + 1] − v0) + v (v[piece + 2] − v0)`: the fan
    /// triangle's formula, so a 3-vertex polygon gives the triangle's point.
    #[inline]
    fn hit_point(&self, hit: &TriangleHit) -> Vec3 {
        let v = self.vertices();
        let i = hit.piece as usize;
        Triangle::new(v[0], v[i + 1], v[i + 2]).hit_point(hit)
    }
}
