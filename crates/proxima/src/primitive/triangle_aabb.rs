//! Triangle / closed box overlap by the separating axis test (Akenine-Möller).
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
//! Everything is computed in `f64` from the `f32` inputs: edge vectors are
//! differences of `f32` values and products of two such numbers are exact, so
//! for coordinates of moderate dynamic range (in particular for all small
//! dyadic values, as in a triangle lying exactly in a cell's face, edge or
//! corner plane) the test carries no rounding at all; otherwise its error is a
//! few `f64` ulps of the coordinates' magnitude.

use super::sat::to64;
use super::{BoxOverlap, Triangle};
use crate::aabb::Aabb;

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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleBoxTest {
    /// Bounding box of the triangle.
    lo: [f64; 3],
    hi: [f64; 3],
    /// The normal, then `edge_i × unit_j` for i, j in 0..3.
    axes: [[f64; 3]; 10],
    /// The triangle's shadow on each axis.
    shadows: [[f64; 2]; 10],
}

impl TriangleBoxTest {
    /// Prepares the test for `tri`.
    pub fn new(tri: &Triangle) -> Self {
        let v = [to64(tri.a), to64(tri.b), to64(tri.c)];
        let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let e = [sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])];
        let (e0, e1) = (e[0], sub(v[2], v[0]));
        let mut axes = [[0.0; 3]; 10];
        axes[0] = [
            e0[1] * e1[2] - e0[2] * e1[1],
            e0[2] * e1[0] - e0[0] * e1[2],
            e0[0] * e1[1] - e0[1] * e1[0],
        ];
        for (i, edge) in e.iter().enumerate() {
            for j in 0..3 {
                // edge × unit_j: two non-zero components.
                let axis = &mut axes[1 + 3 * i + j];
                axis[(j + 1) % 3] = edge[(j + 2) % 3];
                axis[(j + 2) % 3] = -edge[(j + 1) % 3];
            }
        }
        let mut shadows = [[0.0; 2]; 10];
        for (shadow, a) in shadows.iter_mut().zip(&axes) {
            let p = v.map(|x| x[0] * a[0] + x[1] * a[1] + x[2] * a[2]);
            *shadow = [p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2])];
        }
        let lo = std::array::from_fn(|k| v[0][k].min(v[1][k]).min(v[2][k]));
        let hi = std::array::from_fn(|k| v[0][k].max(v[1][k]).max(v[2][k]));
        Self { lo, hi, axes, shadows }
    }

    /// `true` when the triangle and the closed box share at least one point.
    #[inline]
    pub fn overlaps(&self, b: &Aabb) -> bool {
        let (lo, hi) = (to64(b.min), to64(b.max));
        for k in 0..3 {
            if !(self.lo[k] <= hi[k] && lo[k] <= self.hi[k]) {
                return false;
            }
        }
        self.overlaps_axes(lo, hi)
    }

    /// The ten non-box axes only, for a box already known to overlap the
    /// triangle's bounding box (a cell of the bounding box's cell range).
    #[inline]
    pub(crate) fn overlaps_axes(&self, lo: [f64; 3], hi: [f64; 3]) -> bool {
        for (a, s) in self.axes.iter().zip(&self.shadows) {
            let mut bmin = 0.0;
            let mut bmax = 0.0;
            for k in 0..3 {
                let (p, q) = (lo[k] * a[k], hi[k] * a[k]);
                bmin += p.min(q);
                bmax += p.max(q);
            }
            // Written so that a NaN anywhere reports no overlap.
            if !(bmin <= s[1] && s[0] <= bmax) {
                return false;
            }
        }
        true
    }
}

impl BoxOverlap for Triangle {
    /// The 13-axis separating axis test; see [`TriangleBoxTest`] to test one
    /// triangle against many boxes.
    #[inline]
    fn overlaps_box(&self, b: &Aabb) -> bool {
        TriangleBoxTest::new(self).overlaps(b)
    }
}
