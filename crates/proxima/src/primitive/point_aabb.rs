//! Point / closed box overlap: containment, with points on the boundary inside.

use super::{BoxOverlap, Point};
use crate::aabb::Aabb;
use crate::math::DVec3;

impl BoxOverlap for Point {
    /// Containment in the closed box (a point on a face, edge or corner counts).
    ///
    /// ```
    /// use proxima::{Aabb, BoxOverlap, Point, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// assert!(Point(Vec3::new(1.0, 1.0, 1.0)).overlaps_box(&b));
    /// assert!(!Point(Vec3::new(1.0, 1.0, 1.5)).overlaps_box(&b));
    /// ```
    #[inline]
    fn overlaps_box(&self, b: &Aabb) -> bool {
        b.contains_point(self.0)
    }

    #[inline]
    fn overlaps_bounds(&self, min: DVec3, max: DVec3) -> bool {
        let p = self.0.as_dvec3();
        min.cmple(p).all() && p.cmple(max).all()
    }
}
