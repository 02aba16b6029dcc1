//! A single point (a mesh vertex).

use super::{Bounded, BoundingPoints, ClosestPoint};
use crate::aabb::Aabb;
use crate::math::{Vec3, Vec3A};

/// A point primitive: a mesh vertex.
///
/// ```
/// use proxima::{ClosestPoint, Point, Vec3, Vec3A};
/// let p = Point(Vec3::new(1.0, 2.0, 2.0));
/// assert_eq!(p.distance_squared(Vec3A::ZERO), 9.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Point(pub Vec3);

impl Bounded for Point {
    #[inline]
    fn bounds(&self) -> Aabb {
        Aabb::new(self.0, self.0)
    }
    #[inline]
    fn centroid(&self) -> Vec3 {
        self.0
    }
}

impl ClosestPoint for Point {
    #[inline]
    fn closest_point(&self, _p: Vec3A) -> Vec3A {
        self.0.into()
    }
}

impl BoundingPoints for Point {
    #[inline]
    fn push_bounding_points(&self, out: &mut Vec<Vec3>) {
        out.push(self.0);
    }
}
