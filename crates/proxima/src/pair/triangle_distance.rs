//! The distance between two triangles, with its closest points.
//!
//! Two triangles that intersect (exactly, [`triangles_intersect`]) are at
//! distance 0. Two that do not are closest either at a vertex of one against
//! the other triangle or at an edge of one against an edge of the other, so
//! the distance is the least of 6 point-triangle and 9 segment-segment
//! distances, each computed in `f64` (Ericson, *Real-Time Collision
//! Detection*, 5.1.5 and 5.1.9) with every division guarded: degenerate
//! triangles (segments, points) and zero-length edges give finite answers,
//! never NaN, for finite input.

use super::triangle_intersection::{segment_meets_triangle, triangles_intersect};
use crate::math::DVec3;
use crate::primitive::closest_f64::{clamp01, on_edge, point_triangle_closest, ratio, segment_segment_closest, unit};

/// The distance between two triangles and where it is reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePairDistance {
    /// `|point_a - point_b|`; 0 when the triangles intersect.
    pub distance: f64,
    /// The closest point on the first triangle.
    pub point_a: DVec3,
    /// The closest point on the second triangle.
    pub point_b: DVec3,
    /// `point_a` as weights of the first triangle's vertices, in their given
    /// order (non-negative, summing to 1 within rounding).
    pub barycentric_a: [f64; 3],
    /// `point_b` as weights of the second triangle's vertices.
    pub barycentric_b: [f64; 3],
}

/// The distance between triangles `a` and `b` with the closest points and
/// their barycentric coordinates.
///
/// When [`triangles_intersect`] says they intersect: distance 0 and
/// `point_a == point_b`, a common point (computed in `f64`: the point where an
/// edge of one meets the other, within rounding of both triangles), the
/// barycentric coordinates those of its closest points on each triangle.
/// Otherwise the least of the 6 point-triangle distances (the vertices of `a`
/// against `b`, then those of `b` against `a`) and the 9 segment-segment
/// distances (edge `a_i a_{i+1}` against edge `b_j b_{j+1}`, `i` then `j`),
/// the first of equal ones in that order; `distance` is
/// `(point_a - point_b).length()`.
///
/// ```
/// use proxima::math::DVec3;
/// use proxima::pair::triangle_distance;
/// let a = [DVec3::ZERO, DVec3::X, DVec3::Y];
/// let b = a.map(|p| p + DVec3::new(0.0, 0.0, 2.0));
/// let d = triangle_distance(&a, &b);
/// assert_eq!(d.distance, 2.0);
/// assert_eq!(d.barycentric_a, [1.0, 0.0, 0.0]); // the first minimum: vertex a_0
/// ```
pub fn triangle_distance(a: &[DVec3; 3], b: &[DVec3; 3]) -> TrianglePairDistance {
    if triangles_intersect(a, b) {
        return common_point(a, b);
    }
    separated_triangle_distance(a, b)
}

/// [`triangle_distance`] for two triangles known not to intersect (their
/// boxes are apart, or an exact test said so): the least of the 15
/// sub-distances, without the intersection test. For triangles that do
/// intersect the answer is meaningless (not 0).
pub fn separated_triangle_distance(a: &[DVec3; 3], b: &[DVec3; 3]) -> TrianglePairDistance {
    let mut best: Option<TrianglePairDistance> = None;
    let mut offer = |candidate: TrianglePairDistance| {
        if best.is_none_or(|b| candidate.distance < b.distance) {
            best = Some(candidate);
        }
    };
    for (i, &p) in a.iter().enumerate() {
        let (q, bary_b) = point_triangle_closest(p, b);
        offer(pair(p, q, unit(i), bary_b));
    }
    for (j, &q) in b.iter().enumerate() {
        let (p, bary_a) = point_triangle_closest(q, a);
        offer(pair(p, q, bary_a, unit(j)));
    }
    for i in 0..3 {
        let (a0, a1) = (a[i], a[(i + 1) % 3]);
        for j in 0..3 {
            let (b0, b1) = (b[j], b[(j + 1) % 3]);
            let (p, q, s, t) = segment_segment_closest(a0, a1, b0, b1);
            offer(pair(p, q, on_edge(i, s), on_edge(j, t)));
        }
    }
    best.unwrap_or_else(|| pair(a[0], b[0], unit(0), unit(0)))
}

fn pair(point_a: DVec3, point_b: DVec3, barycentric_a: [f64; 3], barycentric_b: [f64; 3]) -> TrianglePairDistance {
    TrianglePairDistance {
        distance: (point_a - point_b).length(),
        point_a,
        point_b,
        barycentric_a,
        barycentric_b,
    }
}

/// The closest of the three edges' closest points to `p` (the first on ties).
/// Distance 0 at a common point of intersecting triangles: the point where the
/// first edge (of `a`, then of `b`) that meets the other triangle does so.
fn common_point(a: &[DVec3; 3], b: &[DVec3; 3]) -> TrianglePairDistance {
    let x = (0..3)
        .find_map(|i| edge_hit(a[i], a[(i + 1) % 3], b))
        .or_else(|| (0..3).find_map(|j| edge_hit(b[j], b[(j + 1) % 3], a)))
        .unwrap_or(a[0]);
    let (_, barycentric_a) = point_triangle_closest(x, a);
    let (_, barycentric_b) = point_triangle_closest(x, b);
    TrianglePairDistance {
        distance: 0.0,
        point_a: x,
        point_b: x,
        barycentric_a,
        barycentric_b,
    }
}

/// Where segment `pq` meets triangle `t`, in `f64`, when it does (exactly):
/// of the point where the segment crosses the triangle's plane (when the
/// rounded heights of its ends have opposite signs) and the closest points of
/// the segment to the triangle's boundary and of its ends to the triangle,
/// the one nearest to the triangle. Both are needed: a segment piercing the
/// face meets no edge, and one nearly in the plane crosses it anywhere along
/// its length as far as rounded heights tell.
fn edge_hit(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> Option<DVec3> {
    if !segment_meets_triangle(p, q, t) {
        return None;
    }
    let mut best = p;
    let mut best_d = f64::INFINITY;
    let offer_point = |x: DVec3, best: &mut DVec3, best_d: &mut f64| {
        let (y, _) = point_triangle_closest(x, t);
        let d = (x - y).length_squared();
        if d < *best_d {
            (*best, *best_d) = (x, d);
        }
    };
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let dp = n.dot(p - t[0]);
    let dq = n.dot(q - t[0]);
    if dp != dq && dp * dq <= 0.0 {
        let s = clamp01(ratio(dp, dp - dq));
        offer_point(p + (q - p) * s, &mut best, &mut best_d);
    }
    offer_point(p, &mut best, &mut best_d);
    offer_point(q, &mut best, &mut best_d);
    for i in 0..3 {
        let (x, y, _, _) = segment_segment_closest(p, q, t[i], t[(i + 1) % 3]);
        let d = (x - y).length_squared();
        if d < best_d {
            (best, best_d) = (x, d);
        }
    }
    Some(best)
}
