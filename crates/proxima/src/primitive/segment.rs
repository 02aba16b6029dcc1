//! Line segments (mesh edges).

use super::{Bounded, BoundingPoints, ClosestPoint};
use crate::aabb::Aabb;
use crate::math::{Vec3, Vec3A};

/// The segment from `a` to `b`; a zero-length segment is a point.
///
/// ```
/// use proxima::{ClosestPoint, LineSegment, Vec3, Vec3A};
/// let s = LineSegment::new(Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0));
/// assert_eq!(s.length(), 2.0);
/// assert_eq!(s.closest_point(Vec3A::new(0.5, 1.0, 0.0)), Vec3A::new(0.5, 0.0, 0.0));
/// assert_eq!(s.distance_squared(Vec3A::new(3.0, 0.0, 0.0)), 1.0); // past the end b
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LineSegment {
    /// First end.
    pub a: Vec3,
    /// Second end.
    pub b: Vec3,
}

impl LineSegment {
    /// The segment from `a` to `b`.
    #[inline]
    pub const fn new(a: Vec3, b: Vec3) -> Self {
        Self { a, b }
    }

    /// Length of the segment.
    #[inline]
    pub fn length(&self) -> f32 {
        (self.b - self.a).length()
    }
}

/// The point of segment `a`–`b` closest to `p`; `a` when the segment has zero length.
#[inline]
pub(crate) fn closest_on_segment(a: Vec3A, b: Vec3A, p: Vec3A) -> Vec3A {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 <= 0.0 {
        return a;
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    a + ab * t
}

impl Bounded for LineSegment {
    #[inline]
    fn bounds(&self) -> Aabb {
        Aabb::new(self.a.min(self.b), self.a.max(self.b))
    }
    #[inline]
    fn centroid(&self) -> Vec3 {
        (self.a + self.b) * 0.5
    }
}

impl ClosestPoint for LineSegment {
    #[inline]
    fn closest_point(&self, p: Vec3A) -> Vec3A {
        closest_on_segment(self.a.into(), self.b.into(), p)
    }
}

impl BoundingPoints for LineSegment {
    #[inline]
    fn push_bounding_points(&self, out: &mut Vec<Vec3>) {
        out.extend([self.a, self.b]);
    }
}
