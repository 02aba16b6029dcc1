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
//! The test is exact. Each axis is evaluated in `f64` from the `f32` inputs
//! together with a bound on its rounding error (see `exact_sat.rs`); only when
//! the gap between the shadows lies within that bound of zero — touching or
//! nearly touching, as when vertices lie exactly on cell planes — is the axis
//! decided again in integer arithmetic, where every `f32` is exact. Touching
//! counts, whatever the coordinates' magnitudes.

use super::exact_sat::{self, box_magnitude, shape_bounds};
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleBoxTest {
    /// Bounding box of the triangle.
    lo: [f64; 3],
    hi: [f64; 3],
    /// The normal, its absolute value, and the triangle's shadow on it.
    normal: [f64; 3],
    normal_abs: [f64; 3],
    normal_shadow: [f64; 2],
    /// The axis `edge_i × unit_j` at `3 j + i` has two non-zero components,
    /// `first` at index `(j + 1) % 3` and `second` at `(j + 2) % 3`.
    first: [f64; 9],
    second: [f64; 9],
    /// The triangle's shadow on each edge axis.
    shadow_min: [f64; 9],
    shadow_max: [f64; 9],
    /// The vertices, for the exact fallback.
    vertices: [[f64; 3]; 3],
    /// The largest coordinate magnitude, which scales the rounding bounds.
    magnitude: f64,
    /// The rounding bounds for boxes of magnitude at most `box_magnitude`
    /// ([`TriangleBoxTest::for_boxes_within`]).
    box_magnitude: f64,
    edge_bound: f64,
    normal_bound: f64,
}

impl TriangleBoxTest {
    /// Prepares the test for `tri`.
    pub fn new(tri: &Triangle) -> Self {
        let v = [to64(tri.a), to64(tri.b), to64(tri.c)];
        let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let e = [sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])];
        let (e0, e1) = (e[0], sub(v[2], v[0]));
        let normal = [
            e0[1] * e1[2] - e0[2] * e1[1],
            e0[2] * e1[0] - e0[0] * e1[2],
            e0[0] * e1[1] - e0[1] * e1[0],
        ];
        // Plain comparisons (inputs are finite): no NaN handling needed.
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let max = |a: f64, b: f64| if a > b { a } else { b };
        let shadow = |p: [f64; 3]| [min(min(p[0], p[1]), p[2]), max(max(p[0], p[1]), p[2])];
        let normal_shadow = shadow(v.map(|x| x[0] * normal[0] + x[1] * normal[1] + x[2] * normal[2]));
        let mut t = Self {
            lo: std::array::from_fn(|k| min(min(v[0][k], v[1][k]), v[2][k])),
            hi: std::array::from_fn(|k| max(max(v[0][k], v[1][k]), v[2][k])),
            normal,
            normal_abs: normal.map(f64::abs),
            normal_shadow,
            first: [0.0; 9],
            second: [0.0; 9],
            shadow_min: [0.0; 9],
            shadow_max: [0.0; 9],
            vertices: v,
            magnitude: 0.0,
            box_magnitude: f64::NAN,
            edge_bound: 0.0,
            normal_bound: 0.0,
        };
        t.magnitude = box_magnitude(&t.lo, &t.hi);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            for (i, edge) in e.iter().enumerate() {
                let x = 3 * j + i;
                // edge × unit_j = (…, edge[j2] at j1, −edge[j1] at j2).
                let (a1, a2) = (edge[j2], -edge[j1]);
                let [lo, hi] = if a1 == 0.0 || a2 == 0.0 {
                    // An edge parallel to a coordinate axis (a zero component,
                    // exact: a difference of floats is zero only for equal ones)
                    // gives a box normal or a zero axis, which the box's overlap
                    // with the bounding box (or the cell range) has decided: an
                    // unbounded shadow never separates and needs no fallback.
                    [f64::NEG_INFINITY, f64::INFINITY]
                } else {
                    shadow(v.map(|p| p[j1] * a1 + p[j2] * a2))
                };
                (t.first[x], t.second[x]) = (a1, a2);
                (t.shadow_min[x], t.shadow_max[x]) = (lo, hi);
            }
        }
        t
    }

    /// The test prepared for boxes whose bounds are all at most `magnitude`
    /// in absolute value (a grid's cells near the triangle): the rounding
    /// bounds of every axis are computed once here instead of per box.
    pub(crate) fn for_boxes_within(mut self, magnitude: f64) -> Self {
        self.box_magnitude = magnitude;
        (self.edge_bound, self.normal_bound) = shape_bounds(self.magnitude, magnitude, 3);
        self
    }

    /// `true` when the triangle and the closed box share at least one point.
    #[inline]
    pub fn overlaps(&self, b: &Aabb) -> bool {
        self.overlaps_bounds(to64(b.min), to64(b.max))
    }

    /// [`TriangleBoxTest::overlaps`] for a box with `f64` bounds (exact too).
    #[inline]
    pub fn overlaps_bounds(&self, lo: [f64; 3], hi: [f64; 3]) -> bool {
        for k in 0..3 {
            if !(self.lo[k] <= hi[k] && lo[k] <= self.hi[k]) {
                return false;
            }
        }
        self.for_boxes_within(box_magnitude(&lo, &hi)).overlaps_axes(lo, hi)
    }

    /// The ten non-box axes only, for a box already known to overlap the
    /// triangle's bounding box (a cell of the bounding box's cell range).
    ///
    /// On each axis `a` the box's shadow is `c·a ± h·|a|` with `c` the box
    /// center and `h` its half extents (within a rounding); the axis
    /// separates when that interval misses the triangle's shadow.
    #[inline]
    pub(crate) fn overlaps_axes(&self, lo: [f64; 3], hi: [f64; 3]) -> bool {
        self.overlaps_run_axes(0, lo, hi) && self.overlaps_cell_axes(0, lo, hi)
    }

    /// The three axes `edge_i × unit_q`, which do not involve the box's
    /// extent along `q`: one test decides them for a whole run of cells along
    /// `q` (`lo[q]`, `hi[q]` are ignored).
    #[inline(always)]
    pub(crate) fn overlaps_run_axes(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        debug_assert!(
            box_magnitude(&lo, &hi) <= self.box_magnitude,
            "the bounds were prepared for smaller boxes"
        );
        let (c, h) = center_half(lo, hi);
        (0..3).all(|i| !self.edge_axis_separates(q, i, &c, &h, &lo, &hi))
    }

    /// The other seven non-box axes: the normal and `edge_i × unit_j`, j ≠ q.
    #[inline(always)]
    pub(crate) fn overlaps_cell_axes(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        debug_assert!(
            box_magnitude(&lo, &hi) <= self.box_magnitude,
            "the bounds were prepared for smaller boxes"
        );
        let (c, h) = center_half(lo, hi);
        let n = &self.normal;
        let na = &self.normal_abs;
        let p = c[0] * n[0] + c[1] * n[1] + c[2] * n[2];
        let r = h[0] * na[0] + h[1] * na[1] + h[2] * na[2];
        let gap = (p - r - self.normal_shadow[1]).max(self.normal_shadow[0] - p - r);
        let bound = self.normal_bound;
        if gap > bound || (gap >= -bound && exact_sat::normal_separates(&self.vertices, &lo, &hi)) {
            return false;
        }
        for j in (0..3).filter(|&j| j != q) {
            for i in 0..3 {
                if self.edge_axis_separates(j, i, &c, &h, &lo, &hi) {
                    return false;
                }
            }
        }
        true
    }

    /// `true` when `edge_i × unit_j` separates the box `c ± h` (bounds `lo`,
    /// `hi`) from the triangle: decided in `f64` when the gap between the
    /// shadows exceeds its rounding bound, exactly otherwise.
    #[inline(always)]
    fn edge_axis_separates(
        &self,
        j: usize,
        i: usize,
        c: &[f64; 3],
        h: &[f64; 3],
        lo: &[f64; 3],
        hi: &[f64; 3],
    ) -> bool {
        let x = 3 * j + i;
        exact_sat::edge_axis_gap_separates(
            j,
            (self.first[x], self.second[x]),
            (self.shadow_min[x], self.shadow_max[x]),
            self.edge_bound,
            (c, h),
            (lo, hi),
            &self.vertices,
            i,
        )
    }
}

/// Center and half extents of the box `[lo, hi]` (exact for `f32` bounds;
/// for a grid's exact `f64` planes within one rounding, which the axes'
/// rounding bound covers).
#[inline(always)]
fn center_half(lo: [f64; 3], hi: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    (
        [(lo[0] + hi[0]) * 0.5, (lo[1] + hi[1]) * 0.5, (lo[2] + hi[2]) * 0.5],
        [(hi[0] - lo[0]) * 0.5, (hi[1] - lo[1]) * 0.5, (hi[2] - lo[2]) * 0.5],
    )
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
