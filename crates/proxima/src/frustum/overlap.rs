//! Exact primitive–frustum overlap tests (closed sets: touching counts).

use super::{Frustum, side, to64};
use crate::primitive::{Bounded, ConvexPolygon, LineSegment, Point, Triangle};

/// A primitive that can say exactly whether it shares a point with a
/// frustum (both closed: touching counts).
pub trait FrustumOverlap: Bounded {
    /// `true` when the primitive and the closed frustum share a point.
    fn overlaps_frustum(&self, frustum: &Frustum) -> bool;
}

impl FrustumOverlap for Point {
    #[inline]
    fn overlaps_frustum(&self, frustum: &Frustum) -> bool {
        frustum.contains_point(self.0)
    }
}

impl FrustumOverlap for LineSegment {
    #[inline]
    fn overlaps_frustum(&self, frustum: &Frustum) -> bool {
        frustum.overlaps_hull(&[to64(self.a), to64(self.b)])
    }
}

impl FrustumOverlap for Triangle {
    #[inline]
    fn overlaps_frustum(&self, frustum: &Frustum) -> bool {
        frustum.overlaps_hull(&[to64(self.a), to64(self.b), to64(self.c)])
    }
}

/// A polygon overlaps the frustum when one of its fan triangles does. For a
/// planar convex polygon the fan covers it exactly, so the test is exact; a
/// polygon accepted as planar only within its tolerance is taken as its fan,
/// as its ray test does. A 3-vertex polygon is its triangle, bit for bit.
impl FrustumOverlap for ConvexPolygon {
    #[inline]
    fn overlaps_frustum(&self, frustum: &Frustum) -> bool {
        self.fan_triangles().any(|t| t.overlaps_frustum(frustum))
    }
}

impl Frustum {
    /// `true` when the convex hull of `vertices` (one to three points: a
    /// point, a segment or a triangle, possibly degenerate) shares a point
    /// with the frustum.
    ///
    /// The six plane tests come first and decide most primitives with the
    /// same evaluation as [`Frustum::classify_box`]: all vertices outside one
    /// plane is a miss, a vertex inside every plane a hit. Only primitives
    /// with every vertex outside some plane take the full separating axis test between the two
    /// convex polytopes: the plane normals (whose inner side the plane tests
    /// already settled exactly), the primitive's normal, and the cross
    /// products of the frustum's twelve edges with the primitive's edges. A
    /// zero axis (parallel edges, degenerate triangle) projects everything to
    /// 0 and separates nothing, so degenerate primitives need no special case:
    /// their edges span the segment they collapse to.
    #[inline]
    pub(crate) fn overlaps_hull<const N: usize>(&self, vertices: &[[f64; 3]; N]) -> bool {
        // Per vertex: is it outside some plane?
        let mut outside_somewhere = [false; N];
        for plane in self.raw_planes() {
            let mut inside = 0;
            for (k, &v) in vertices.iter().enumerate() {
                if side(plane, v) >= 0.0 {
                    inside += 1;
                } else {
                    outside_somewhere[k] = true;
                }
            }
            if inside == 0 {
                return false;
            }
        }
        // A vertex inside every plane is a common point (this includes every
        // primitive inside the frustum); it spares most straddling primitives
        // the separating axis test.
        if outside_somewhere.iter().any(|&outside| !outside) {
            return true;
        }
        if N == 1 {
            return false;
        }
        !self.separated(vertices)
    }

    /// The separating axis test, for primitives straddling some plane.
    #[cold]
    fn separated<const N: usize>(&self, vertices: &[[f64; 3]; N]) -> bool {
        let shadow = |axis: [f64; 3], points: &[[f64; 3]]| {
            points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let d = dot(axis, *p);
                (lo.min(d), hi.max(d))
            })
        };
        let separates = |axis: [f64; 3]| {
            let (lo, hi) = shadow(axis, self.corners());
            let (primitive_lo, primitive_hi) = shadow(axis, vertices);
            primitive_hi < lo || primitive_lo > hi
        };
        // Along a plane's inward normal the frustum's low end is the plane
        // itself, already tested exactly; only the far end (at the corners)
        // is left. Using the rounded corners for the low end too could
        // separate a primitive touching the plane.
        if self.raw_planes().iter().any(|p| {
            let axis = [p[0], p[1], p[2]];
            shadow(axis, vertices).0 > shadow(axis, self.corners()).1
        }) {
            return true;
        }
        let mut primitive_edges = [[0.0; 3]; 3];
        let edge_count = if N == 2 { 1 } else { 3 };
        for (i, edge) in primitive_edges.iter_mut().enumerate().take(edge_count) {
            *edge = sub(vertices[(i + 1) % N], vertices[i]);
        }
        if N == 3 && separates(cross(primitive_edges[0], sub(vertices[2], vertices[0]))) {
            return true;
        }
        self.edges()
            .iter()
            .any(|f| primitive_edges[..edge_count].iter().any(|e| separates(cross(*f, *e))))
    }
}

#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
