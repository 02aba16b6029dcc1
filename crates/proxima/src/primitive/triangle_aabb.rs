//! Triangle / closed box overlap by the separating axis test (Akenine-Möller):
//! the box/convex-polygon test of `convex_box.rs` for three vertices.
//!
//! Thirteen candidate axes: the three box normals, the triangle normal, and
//! the nine cross products `edge × box axis`. The shapes are disjoint exactly
//! when the shadows ([`sat::Interval`](super::sat::Interval)) on one of these
//! axes are disjoint; shadows that share an end point overlap (touching counts).
//!
//! Degenerate triangles need no special case: a zero axis (the normal of a
//! zero-area triangle, the cross products of a zero-length edge or of an edge
//! parallel to a box axis) projects everything onto `[0, 0]` and so never
//! separates, and the axes left for a collinear triangle — the box normals and
//! `direction × box axis` — are exactly the separating axes of a segment and a
//! box, so a collinear triangle is tested as the segment it is, and a triangle
//! whose three vertices coincide as the point it is.
//!
//! The test is exact, whether or not the vertices are coplanar in `f64`
//! (three points always are): near-touching axes are decided again in integer
//! arithmetic (see `exact_sat.rs`). Touching counts, whatever the
//! coordinates' magnitudes.

use super::convex_box::ConvexBoxTest;
use super::sat::to64;
use super::{BoxOverlap, Triangle};
use crate::aabb::Aabb;
use crate::math::DVec3;

/// The separating axis test of one triangle, prepared once and then run
/// against many boxes (a grid's cells): the edge vectors, the ten non-box axes
/// and the triangle's shadow on each are computed in [`TriangleBoxTest::new`].
///
/// ```
/// use proxima::primitive::TriangleBoxTest;
/// use proxima::{Aabb, Triangle, Vec3};
/// let tri = Triangle::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0));
/// let test = TriangleBoxTest::new(&tri);
/// // The triangle lies in the top face plane of the unit box: touching counts.
/// assert!(test.overlaps(&Aabb::new(Vec3::ZERO, Vec3::ONE)));
/// // This box only meets the triangle's plane beyond its hypotenuse x + y = 1.
/// assert!(!test.overlaps(&Aabb::new(Vec3::new(0.6, 0.6, 0.0), Vec3::new(2.0, 2.0, 2.0))));
/// ```
pub type TriangleBoxTest = ConvexBoxTest<3>;

impl ConvexBoxTest<3> {
    /// Prepares the test for `tri` (edges `a → b → c → a`).
    pub fn new(tri: &Triangle) -> Self {
        Self::from_vertices(&[to64(tri.a), to64(tri.b), to64(tri.c)])
    }
}

impl BoxOverlap for Triangle {
    /// The 13-axis separating axis test; see [`TriangleBoxTest`] to test one
    /// triangle against many boxes.
    #[inline]
    fn overlaps_box(&self, b: &Aabb) -> bool {
        TriangleBoxTest::new(self).overlaps(b)
    }

    #[inline]
    fn overlaps_bounds(&self, min: DVec3, max: DVec3) -> bool {
        TriangleBoxTest::new(self).overlaps_bounds(min.to_array(), max.to_array())
    }
}
