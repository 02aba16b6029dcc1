//! Convex polygon / closed box overlap by the separating axis test.
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
//! As in [`TriangleBoxTest`](super::TriangleBoxTest), each axis is evaluated
//! in `f64` with a bound on its rounding, and decided in integers when the
//! gap lies within it (`exact_sat.rs`): a polygon lying exactly in a cell face
//! touches the cells on both sides, whatever its coordinates. (Before, the
//! `f64` rounding could decide an exact touch either way:
//! spot_quadrangulated.obj has a vertex at x = −4.3e-19 beside one at x = 0 on
//! a cell boundary, and the cell that vertex touches was missed.) Zero axes
//! (an edge parallel to a box axis) project everything to `[0, 0]` and never
//! separate.

use super::exact_sat::{self, box_magnitude, shape_bounds};
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
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolygonBoxTest {
    count: usize,
    /// Bounding box of the polygon.
    lo: [f64; 3],
    hi: [f64; 3],
    /// The normal, its absolute value, and the polygon's shadow on it.
    normal: [f64; 3],
    normal_abs: [f64; 3],
    normal_shadow: [f64; 2],
    /// The axis `edge_i × unit_j` has two non-zero components, `first[j][i]`
    /// at index `(j + 1) % 3` and `second[j][i]` at `(j + 2) % 3`.
    first: [[f64; MAX_POLYGON_VERTICES]; 3],
    second: [[f64; MAX_POLYGON_VERTICES]; 3],
    /// The polygon's shadow on each edge axis.
    shadow_min: [[f64; MAX_POLYGON_VERTICES]; 3],
    shadow_max: [[f64; MAX_POLYGON_VERTICES]; 3],
    /// The vertices, for the exact fallback.
    vertices: [[f64; 3]; MAX_POLYGON_VERTICES],
    /// The largest coordinate magnitude, which scales the rounding bounds
    /// (as in [`TriangleBoxTest`](super::TriangleBoxTest)).
    magnitude: f64,
    /// The bounds for boxes of magnitude at most `box_magnitude`.
    box_magnitude: f64,
    edge_bound: f64,
    normal_bound: f64,
}

impl PolygonBoxTest {
    /// Prepares the test for `polygon`.
    pub fn new(polygon: &ConvexPolygon) -> Self {
        let vertices = polygon.vertices();
        let count = vertices.len();
        let mut v = [[0.0f64; 3]; MAX_POLYGON_VERTICES];
        for (slot, p) in v.iter_mut().zip(vertices) {
            *slot = to64(*p);
        }
        let v = &v[..count];
        let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let mut normal = [0.0; 3];
        for i in 1..count - 1 {
            let (a, b) = (sub(v[i], v[0]), sub(v[i + 1], v[0]));
            normal[0] += a[1] * b[2] - a[2] * b[1];
            normal[1] += a[2] * b[0] - a[0] * b[2];
            normal[2] += a[0] * b[1] - a[1] * b[0];
        }
        // Plain comparisons (inputs are finite): no NaN handling needed.
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let max = |a: f64, b: f64| if a > b { a } else { b };
        let shadow = |axis: &dyn Fn(&[f64; 3]) -> f64| {
            v.iter()
                .map(axis)
                .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], x| {
                    [min(lo, x), max(hi, x)]
                })
        };
        let mut t = Self {
            count,
            lo: std::array::from_fn(|k| v.iter().map(|p| p[k]).fold(f64::INFINITY, min)),
            hi: std::array::from_fn(|k| v.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, max)),
            normal,
            normal_abs: normal.map(f64::abs),
            normal_shadow: shadow(&|x| x[0] * normal[0] + x[1] * normal[1] + x[2] * normal[2]),
            first: [[0.0; MAX_POLYGON_VERTICES]; 3],
            second: [[0.0; MAX_POLYGON_VERTICES]; 3],
            shadow_min: [[0.0; MAX_POLYGON_VERTICES]; 3],
            shadow_max: [[0.0; MAX_POLYGON_VERTICES]; 3],
            vertices: [[0.0; 3]; MAX_POLYGON_VERTICES],
            magnitude: 0.0,
            box_magnitude: f64::NAN,
            edge_bound: 0.0,
            normal_bound: 0.0,
        };
        t.vertices[..count].copy_from_slice(v);
        t.magnitude = box_magnitude(&t.lo, &t.hi);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            for i in 0..count {
                let edge = sub(v[(i + 1) % count], v[i]);
                // edge × unit_j = (…, edge[j2] at j1, −edge[j1] at j2).
                let (a1, a2) = (edge[j2], -edge[j1]);
                // Parallel to a coordinate axis: decided by the bounding box
                // (see TriangleBoxTest); an unbounded shadow never separates.
                let [lo, hi] = if a1 == 0.0 || a2 == 0.0 {
                    [f64::NEG_INFINITY, f64::INFINITY]
                } else {
                    shadow(&|p| p[j1] * a1 + p[j2] * a2)
                };
                (t.first[j][i], t.second[j][i]) = (a1, a2);
                (t.shadow_min[j][i], t.shadow_max[j][i]) = (lo, hi);
            }
        }
        t
    }

    /// The test prepared for boxes whose bounds are all at most `magnitude`
    /// in absolute value: the rounding bounds computed once.
    pub(crate) fn for_boxes_within(mut self, magnitude: f64) -> Self {
        self.box_magnitude = magnitude;
        (self.edge_bound, self.normal_bound) = shape_bounds(self.magnitude, magnitude, self.count);
        self
    }

    /// `true` when the vertices are coplanar in `f64` (their shadow on the
    /// normal is a single value): then the test is exact.
    pub fn is_planar(&self) -> bool {
        self.normal_shadow[0] == self.normal_shadow[1]
    }

    /// `true` when the polygon and the closed box share at least one point
    /// (exactly so for a planar polygon; see the module documentation).
    #[inline]
    pub fn overlaps(&self, b: &Aabb) -> bool {
        self.overlaps_bounds(to64(b.min), to64(b.max))
    }

    /// [`PolygonBoxTest::overlaps`] for a box with `f64` bounds.
    #[inline]
    pub fn overlaps_bounds(&self, lo: [f64; 3], hi: [f64; 3]) -> bool {
        for k in 0..3 {
            if !(self.lo[k] <= hi[k] && lo[k] <= self.hi[k]) {
                return false;
            }
        }
        let test = self.for_boxes_within(box_magnitude(&lo, &hi));
        test.overlaps_run_axes(0, lo, hi) && test.overlaps_cell_axes(0, lo, hi)
    }

    /// The axes `edge_i × unit_q`, which do not involve the box's extent
    /// along `q`: one test decides them for a whole run of cells along `q`.
    #[inline]
    pub(crate) fn overlaps_run_axes(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        debug_assert!(
            box_magnitude(&lo, &hi) <= self.box_magnitude,
            "bounds prepared for smaller boxes"
        );
        let (c, h) = center_half(lo, hi);
        (0..self.count).all(|i| !self.edge_axis_separates(q, i, &c, &h, &lo, &hi))
    }

    /// The other non-box axes: the normal and `edge_i × unit_j`, j ≠ q.
    #[inline]
    pub(crate) fn overlaps_cell_axes(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        debug_assert!(
            box_magnitude(&lo, &hi) <= self.box_magnitude,
            "bounds prepared for smaller boxes"
        );
        let (c, h) = center_half(lo, hi);
        let n = &self.normal;
        let na = &self.normal_abs;
        let p = c[0] * n[0] + c[1] * n[1] + c[2] * n[2];
        let r = h[0] * na[0] + h[1] * na[1] + h[2] * na[2];
        let gap = (p - r - self.normal_shadow[1]).max(self.normal_shadow[0] - p - r);
        let bound = self.normal_bound;
        if gap > bound || (gap >= -bound && exact_sat::normal_separates(&self.vertices[..self.count], &lo, &hi)) {
            return false;
        }
        for j in (0..3).filter(|&j| j != q) {
            for i in 0..self.count {
                if self.edge_axis_separates(j, i, &c, &h, &lo, &hi) {
                    return false;
                }
            }
        }
        true
    }

    /// `true` when `edge_i × unit_j` separates the box `c ± h` from the polygon.
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
        exact_sat::edge_axis_gap_separates(
            j,
            (self.first[j][i], self.second[j][i]),
            (self.shadow_min[j][i], self.shadow_max[j][i]),
            self.edge_bound,
            (c, h),
            (lo, hi),
            &self.vertices[..self.count],
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
