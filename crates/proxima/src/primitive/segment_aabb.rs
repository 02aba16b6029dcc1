//! Segment / closed box overlap by slab clipping.
//!
//! The segment `a + t (b − a)`, `t ∈ [0, 1]`, is clipped against the three
//! slabs `lo_k ≤ x_k ≤ hi_k` in turn; the segment meets the box exactly when
//! the parameter interval left is not empty. The slabs are closed, so a
//! segment that only touches a face, an edge or a corner counts. An axis along
//! which the segment does not move (including every axis of a zero-length
//! segment, which is then a point) is a plain containment test.
//!
//! The entry and exit parameters are computed in `f64` as `(plane − a) / d`.
//! When the final comparison of the latest entry with the earliest exit is
//! within its rounding bound (a segment through a box edge or corner, or a
//! near miss), it is decided again exactly: every entry is compared with every
//! exit as integer fractions (`exact_sat.rs`), so touching counts and a miss
//! by less than a rounding step is a miss.

use super::exact_sat;
use super::sat::to64;
use super::{BoxOverlap, LineSegment};
use crate::aabb::Aabb;
use crate::math::DVec3;

/// `true` when the segment `a`–`b` meets the closed box `[lo, hi]` (all `f64`).
#[inline]
pub(crate) fn segment_overlaps(a: [f64; 3], b: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> bool {
    let mut t0 = 0.0f64;
    let mut t1 = 1.0f64;
    for k in 0..3 {
        let d = b[k] - a[k];
        if d == 0.0 {
            // A zero difference of floats means equal coordinates: a plain containment.
            if !(lo[k] <= a[k] && a[k] <= hi[k]) {
                return false;
            }
            continue;
        }
        let (p, q) = ((lo[k] - a[k]) / d, (hi[k] - a[k]) / d);
        let (near, far) = if p <= q { (p, q) } else { (q, p) };
        t0 = t0.max(near);
        t1 = t1.min(far);
    }
    // Each parameter carries a few rounding steps relative to its size (the
    // differences, the division); 8 u of the larger covers them with room.
    let bound = 8.0 * f64::EPSILON * (t0.abs().max(t1.abs()));
    if t0 < t1 - bound {
        true
    } else if t0 > t1 + bound {
        false
    } else {
        exact_sat::segment_overlaps(a, b, lo, hi)
    }
}

impl BoxOverlap for LineSegment {
    /// Slab clipping of the segment's parameter interval by the closed box.
    ///
    /// ```
    /// use proxima::{Aabb, BoxOverlap, LineSegment, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// // Passes exactly through the box's edge x = 1, y = 1: touching counts.
    /// assert!(LineSegment::new(Vec3::new(0.0, 2.0, 0.5), Vec3::new(2.0, 0.0, 0.5)).overlaps_box(&b));
    /// assert!(!LineSegment::new(Vec3::new(0.0, 2.1, 0.5), Vec3::new(2.1, 0.0, 0.5)).overlaps_box(&b));
    /// ```
    #[inline]
    fn overlaps_box(&self, b: &Aabb) -> bool {
        segment_overlaps(to64(self.a), to64(self.b), to64(b.min), to64(b.max))
    }

    #[inline]
    fn overlaps_bounds(&self, min: DVec3, max: DVec3) -> bool {
        segment_overlaps(to64(self.a), to64(self.b), min.to_array(), max.to_array())
    }
}
