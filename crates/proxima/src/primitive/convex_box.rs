//! The separating axis test of a closed box and a convex planar polygon of at
//! most `N` vertices: the one routine behind [`TriangleBoxTest`] (`N = 3`) and
//! [`PolygonBoxTest`].
//!
//! Candidate axes: the three box normals, the polygon's normal, and the `3n`
//! cross products `edge × box axis` of its `n` boundary edges — for a planar
//! convex polygon all the axes two convex polytopes can be separated along.
//! The shapes are disjoint exactly when the shadows on one of these axes are
//! disjoint; shadows that share an end point overlap (touching counts).
//!
//! Each axis is evaluated in `f64` from the `f32` inputs together with a bound
//! on its rounding error (see `exact_sat.rs`); only when the gap between the
//! shadows lies within that bound of zero — touching or nearly touching, as
//! when vertices lie exactly on cell planes — is the axis decided again in
//! integer arithmetic, where every `f32` is exact.
//!
//! An edge parallel to a coordinate axis (a zero component of `edge × unit_j`,
//! exact: a difference of floats is zero only for equal ones) gives a box
//! normal or a zero axis, which the box's overlap with the bounding box (or the
//! cell range) has decided: its shadow is unbounded, never separates and needs
//! no fallback.
//!
//! [`TriangleBoxTest`]: super::TriangleBoxTest
//! [`PolygonBoxTest`]: super::PolygonBoxTest

use super::exact_sat::{self, box_magnitude, shape_bounds};
use super::sat::to64;
use crate::aabb::Aabb;

/// The separating axis test of one convex planar polygon of `count <= N`
/// vertices, prepared once and then run against many boxes (a grid's cells):
/// the normal, the `3 count` edge axes and the polygon's shadow on each are
/// computed once. Used as [`TriangleBoxTest`](super::TriangleBoxTest)
/// (`N = 3`, built by `TriangleBoxTest::new`) and
/// [`PolygonBoxTest`](super::PolygonBoxTest) (built by `PolygonBoxTest::new`),
/// whose documentation has examples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvexBoxTest<const N: usize> {
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
    first: [[f64; N]; 3],
    second: [[f64; N]; 3],
    /// The polygon's shadow on each edge axis.
    shadow_min: [[f64; N]; 3],
    shadow_max: [[f64; N]; 3],
    /// The vertices, for the exact fallback.
    vertices: [[f64; 3]; N],
    /// The largest coordinate magnitude, which scales the rounding bounds.
    magnitude: f64,
    /// The rounding bounds for boxes of magnitude at most `box_magnitude`
    /// ([`ConvexBoxTest::for_boxes_within`]).
    box_magnitude: f64,
    edge_bound: f64,
    normal_bound: f64,
}

impl<const N: usize> ConvexBoxTest<N> {
    /// Prepares the test for the polygon `v` (3 to `N` finite vertices in
    /// boundary order; edge `i` runs from `v[i]` to `v[(i + 1) % n]`).
    pub(crate) fn from_vertices(v: &[[f64; 3]]) -> Self {
        let count = v.len();
        debug_assert!((3..=N).contains(&count), "3 to N vertices");
        let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        // The sum of the fan's cross products; for a triangle the one
        // `(v1 − v0) × (v2 − v0)`.
        let fan = |i: usize| {
            let (a, b) = (sub(v[i], v[0]), sub(v[i + 1], v[0]));
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let mut normal = fan(1);
        for i in 2..count - 1 {
            let n = fan(i);
            normal = [normal[0] + n[0], normal[1] + n[1], normal[2] + n[2]];
        }
        // Plain comparisons (inputs are finite): no NaN handling needed.
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let max = |a: f64, b: f64| if a > b { a } else { b };
        let shadow = |axis: &dyn Fn(&[f64; 3]) -> f64| {
            let first = axis(&v[0]);
            v[1..]
                .iter()
                .map(axis)
                .fold([first, first], |[lo, hi], x| [min(lo, x), max(hi, x)])
        };
        let mut t = Self {
            count,
            lo: std::array::from_fn(|k| v[1..].iter().fold(v[0][k], |m, p| min(m, p[k]))),
            hi: std::array::from_fn(|k| v[1..].iter().fold(v[0][k], |m, p| max(m, p[k]))),
            normal,
            normal_abs: normal.map(f64::abs),
            normal_shadow: shadow(&|x| x[0] * normal[0] + x[1] * normal[1] + x[2] * normal[2]),
            first: [[0.0; N]; 3],
            second: [[0.0; N]; 3],
            shadow_min: [[0.0; N]; 3],
            shadow_max: [[0.0; N]; 3],
            vertices: [[0.0; 3]; N],
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

    /// The number of vertices; a compile-time 3 for triangles, so that their
    /// axis loops are unrolled.
    #[inline(always)]
    fn len(&self) -> usize {
        if N == 3 { 3 } else { self.count }
    }

    /// The vertices, for the exact fallback and for scan-line clipping.
    #[inline(always)]
    pub(crate) fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices[..self.len()]
    }

    /// The test prepared for boxes whose bounds are all at most `magnitude`
    /// in absolute value (a grid's cells near the polygon): the rounding
    /// bounds of every axis are computed once here instead of per box.
    pub(crate) fn for_boxes_within(mut self, magnitude: f64) -> Self {
        self.box_magnitude = magnitude;
        (self.edge_bound, self.normal_bound) = shape_bounds(self.magnitude, magnitude, self.len());
        self
    }

    /// `true` when the vertices are coplanar in `f64` (their shadow on the
    /// normal is a single value): then the test is exact.
    pub fn is_planar(&self) -> bool {
        self.normal_shadow[0] == self.normal_shadow[1]
    }

    /// `true` when the polygon and the closed box share at least one point
    /// (exactly so for a triangle or a planar polygon; see
    /// [`PolygonBoxTest`](super::PolygonBoxTest) for the others).
    #[inline]
    pub fn overlaps(&self, b: &Aabb) -> bool {
        self.overlaps_bounds(to64(b.min), to64(b.max))
    }

    /// [`ConvexBoxTest::overlaps`] for a box with `f64` bounds.
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
    /// along `q`: one test decides them for a whole run of cells along `q`
    /// (`lo[q]`, `hi[q]` are ignored).
    #[inline(always)]
    pub(crate) fn overlaps_run_axes(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        debug_assert!(
            box_magnitude(&lo, &hi) <= self.box_magnitude,
            "the bounds were prepared for smaller boxes"
        );
        let (c, h) = center_half(lo, hi);
        (0..self.len()).all(|i| !self.edge_axis_separates(q, i, &c, &h, &lo, &hi))
    }

    /// The other non-box axes: the normal and `edge_i × unit_j`, j ≠ q.
    ///
    /// On each axis `a` the box's shadow is `c·a ± h·|a|` with `c` the box
    /// center and `h` its half extents (within a rounding); the axis
    /// separates when that interval misses the polygon's shadow.
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
        if gap > bound || (gap >= -bound && exact_sat::normal_separates(self.vertices(), &lo, &hi)) {
            return false;
        }
        for j in (0..3).filter(|&j| j != q) {
            for i in 0..self.len() {
                if self.edge_axis_separates(j, i, &c, &h, &lo, &hi) {
                    return false;
                }
            }
        }
        true
    }

    /// `true` when `edge_i × unit_j` separates the box `c ± h` (bounds `lo`,
    /// `hi`) from the polygon: decided in `f64` when the gap between the
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
        exact_sat::edge_axis_gap_separates(
            j,
            (self.first[j][i], self.second[j][i]),
            (self.shadow_min[j][i], self.shadow_max[j][i]),
            self.edge_bound,
            (c, h),
            (lo, hi),
            self.vertices(),
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
