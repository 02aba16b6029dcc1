//! Convex polygon / closed box overlap by the separating axis test: the
//! box/convex-polygon test of `convex_box.rs` for up to
//! [`MAX_POLYGON_VERTICES`] vertices.
//!
//! Candidate axes: the three box normals, the polygon's normal, and the
//! `3n` cross products `edge × box axis` of its `n` boundary edges. For a
//! planar convex polygon these are all the axes two convex polytopes can be
//! separated along (face normals of each, and cross products of their edge
//! directions), so the test is exact. For vertices that are coplanar only
//! within tolerance (see `polygon.rs`) the shadows are those of the vertices'
//! convex hull, and the test is conservative: no box meeting the hull is
//! missed.
//!
//! Near-touching axes are decided in integers (`exact_sat.rs`): a polygon
//! lying exactly in a cell face touches the cells on both sides, whatever its
//! coordinates (spot_quadrangulated.obj has a vertex at x = −4.3e-19 beside
//! one at x = 0 on a cell boundary, and the cell that vertex touches is
//! found). Zero axes (an edge parallel to a box axis) project everything to
//! `[0, 0]` and never separate.

use super::convex_box::ConvexBoxTest;
use super::polygon::{ConvexPolygon, MAX_POLYGON_VERTICES};
use super::sat::{Interval, Project, project_points, to64};
use super::{BoxOverlap, Triangle};
use crate::aabb::Aabb;
use crate::math::DVec3;

/// The separating axis test of one polygon, prepared once and then run
/// against many boxes (a grid's cells).
///
/// ```
/// use proxima::primitive::{ConvexPolygon, PolygonBoxTest};
/// use proxima::{Aabb, Vec3};
/// // A hexagon in the plane z = 1: touching the unit box's top face counts.
/// let hexagon: Vec<Vec3> = [(2.0, 0.0), (1.0, 2.0), (-1.0, 2.0), (-2.0, 0.0), (-1.0, -2.0), (1.0, -2.0)]
///     .iter()
///     .map(|&(x, y)| Vec3::new(x, y, 1.0))
///     .collect();
/// let test = PolygonBoxTest::new(&ConvexPolygon::new(&hexagon).unwrap());
/// assert!(test.overlaps(&Aabb::new(Vec3::ZERO, Vec3::ONE)));
/// // Beyond the edge from (2, 0) to (1, 2), whose line is 2x + y = 4.
/// assert!(!test.overlaps(&Aabb::new(Vec3::new(1.6, 1.0, 0.0), Vec3::new(3.0, 3.0, 2.0))));
/// ```
pub type PolygonBoxTest = ConvexBoxTest<MAX_POLYGON_VERTICES>;

impl ConvexBoxTest<MAX_POLYGON_VERTICES> {
    /// Prepares the test for `polygon`.
    pub fn new(polygon: &ConvexPolygon) -> Self {
        let mut v = [[0.0f64; 3]; MAX_POLYGON_VERTICES];
        for (slot, p) in v.iter_mut().zip(polygon.vertices()) {
            *slot = to64(*p);
        }
        Self::from_vertices(&v[..polygon.len()])
    }
}

impl BoxOverlap for ConvexPolygon {
    /// A triangle's own test for three vertices, else the polygon's separating
    /// axis test; see [`PolygonBoxTest`] to test one polygon against many boxes.
    #[inline]
    fn overlaps_box(&self, b: &Aabb) -> bool {
        match self.as_triangle() {
            Some(tri) => Triangle::overlaps_box(&tri, b),
            None => PolygonBoxTest::new(self).overlaps(b),
        }
    }

    #[inline]
    fn overlaps_bounds(&self, min: DVec3, max: DVec3) -> bool {
        match self.as_triangle() {
            Some(tri) => Triangle::overlaps_bounds(&tri, min, max),
            None => PolygonBoxTest::new(self).overlaps_bounds(min.to_array(), max.to_array()),
        }
    }
}

impl Project for ConvexPolygon {
    #[inline]
    fn project(&self, axis: crate::math::Vec3) -> Interval {
        project_points(self.vertices(), axis)
    }
}
