//! Triangles (mesh faces, or pieces of fan-triangulated polygons).

use super::closest_triangle::closest_on_triangle;
use super::{Bounded, BoundingPoints, ClosestPoint};
use crate::aabb::Aabb;
use crate::math::{Vec3, Vec3A};

/// The triangle `a`, `b`, `c`. Degenerate triangles (repeated vertices,
/// collinear vertices, zero area) are valid and behave as the union of their
/// edges.
///
/// ```
/// use proxima::{ClosestPoint, Triangle, Vec3, Vec3A};
/// let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
/// // Above the face: the projection onto its plane.
/// assert_eq!(t.closest_point(Vec3A::new(0.25, 0.25, 2.0)), Vec3A::new(0.25, 0.25, 0.0));
/// // Beyond vertex b: vertex b.
/// assert_eq!(t.closest_point(Vec3A::new(3.0, -1.0, 0.0)), Vec3A::X);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Triangle {
    /// First vertex.
    pub a: Vec3,
    /// Second vertex.
    pub b: Vec3,
    /// Third vertex.
    pub c: Vec3,
}

impl Triangle {
    /// The triangle `a`, `b`, `c`.
    #[inline]
    pub const fn new(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self { a, b, c }
    }

    /// The three vertices in order.
    #[inline]
    pub fn vertices(&self) -> [Vec3; 3] {
        [self.a, self.b, self.c]
    }

    /// `(b - a) × (c - a)`: normal scaled by twice the area (zero when degenerate).
    #[inline]
    pub fn scaled_normal(&self) -> Vec3 {
        (self.b - self.a).cross(self.c - self.a)
    }

    /// Area of the triangle.
    #[inline]
    pub fn area(&self) -> f32 {
        0.5 * self.scaled_normal().length()
    }

    /// Mean of the three vertices.
    #[inline]
    pub fn center(&self) -> Vec3 {
        (self.a + self.b + self.c) / 3.0
    }
}

impl Bounded for Triangle {
    #[inline]
    fn bounds(&self) -> Aabb {
        Aabb::new(self.a.min(self.b).min(self.c), self.a.max(self.b).max(self.c))
    }
}

impl ClosestPoint for Triangle {
    #[inline(always)]
    fn closest_point(&self, p: Vec3A) -> Vec3A {
        closest_on_triangle(self.a.into(), self.b.into(), self.c.into(), p)
    }
}

impl BoundingPoints for Triangle {
    #[inline]
    fn push_bounding_points(&self, out: &mut Vec<Vec3>) {
        out.extend([self.a, self.b, self.c]);
    }
}
