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

/// The closest point of triangle `t` to `p` and its barycentric coordinates
/// (weights of `t[0]`, `t[1]`, `t[2]`, non-negative, summing to 1).
///
/// Ericson's Voronoi-region walk. An edge region is entered only when that
/// edge has a length (`|ab|² = d1 - d3 > 0`: a zero-length edge would answer
/// its endpoint for any point); when the face region is reached with a
/// weight that rounding made non-positive (a degenerate or nearly degenerate
/// triangle) the closest of the three edges' points is taken instead, so the
/// answer is finite for finite input.
///
/// Slivers (sin² of the angle at `a` at most 1e-4) do not take the walk: its
/// face weights are differences of products nearly equal in size, and on a
/// triangle with sin² = 2e-15 they were 10% off and put the point 3e-3 away
/// from the triangle. A sliver's point is the projection onto its plane when
/// that falls inside, weighted by triple products with the normal (as
/// accurate as the normal), else the closest of its edges' points.
pub fn point_triangle_closest(p: DVec3, t: &[DVec3; 3]) -> (DVec3, [f64; 3]) {
    let [a, b, c] = *t;
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let n = ab.cross(ac);
    let nn = n.length_squared();
    if nn <= 1e-4 * ab.length_squared() * ac.length_squared() || !nn.is_normal() {
        return closest_on_sliver(p, t, n, nn);
    }
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 > d3 {
        let v = ratio(d1, d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 > d6 {
        let w = ratio(d2, d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0 {
        let w = ratio(d4 - d3, (d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    if va > 0.0 && vb > 0.0 && vc > 0.0 {
        let sum = va + vb + vc;
        let v = vb / sum;
        let w = vc / sum;
        if v.is_finite() && w.is_finite() {
            return (a + ab * v + ac * w, [1.0 - v - w, v, w]);
        }
    }
    closest_on_edges(p, t)
}

/// The closest points of the segments `p0 p1` and `q0 q1`: `(on p, on q, s, t)`
/// with the points `p0 + s (p1 - p0)` and `q0 + t (q1 - q0)`, `s, t ∈ [0, 1]`.
///
/// Ericson's clamped solution; a zero-length segment is its point (parameter
/// 0), parallel segments take `s = 0` first, so the answer is finite for
/// finite input.
pub fn segment_segment_closest(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (DVec3, DVec3, f64, f64) {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.dot(d1);
    let e = d2.dot(d2);
    let f = d2.dot(r);
    let (s, t) = if a == 0.0 && e == 0.0 {
        (0.0, 0.0)
    } else if a == 0.0 {
        (0.0, clamp01(ratio(f, e)))
    } else {
        let c = d1.dot(r);
        if e == 0.0 {
            (clamp01(ratio(-c, a)), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s = if denom > 0.0 {
                clamp01(ratio(b * f - c * e, denom))
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = clamp01(ratio(-c, a));
            } else if t > 1.0 {
                t = 1.0;
                s = clamp01(ratio(b - c, a));
            }
            (s, t)
        }
    };
    (p0 + d1 * s, q0 + d2 * t, s, t)
}

/// `n / d`, or 0 when that is not a finite number (`d` zero or underflowed).
fn ratio(n: f64, d: f64) -> f64 {
    let r = n / d;
    if r.is_finite() { r } else { 0.0 }
}

fn clamp01(x: f64) -> f64 {
    x.clamp(0.0, 1.0)
}

fn unit(i: usize) -> [f64; 3] {
    let mut w = [0.0; 3];
    w[i] = 1.0;
    w
}

/// Weights of the point at parameter `s` on edge `t_i t_{i+1}`.
fn on_edge(i: usize, s: f64) -> [f64; 3] {
    let mut w = [0.0; 3];
    w[i] = 1.0 - s;
    w[(i + 1) % 3] = s;
    w
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
/// [`point_triangle_closest`] for slivers and degenerate triangles, `n`
/// their normal `ab × ac` and `nn` its squared length.
fn closest_on_sliver(p: DVec3, t: &[DVec3; 3], n: DVec3, nn: f64) -> (DVec3, [f64; 3]) {
    if nn.is_normal() {
        let (ab, ac, ap) = (t[1] - t[0], t[2] - t[0], p - t[0]);
        // q − a = v·ab + w·ac for the projection q; the normal part of `ap`
        // drops out of both triple products.
        let v = ap.cross(ac).dot(n) / nn;
        let w = ab.cross(ap).dot(n) / nn;
        if v >= 0.0 && w >= 0.0 && v + w <= 1.0 {
            return (t[0] + ab * v + ac * w, [1.0 - v - w, v, w]);
        }
    }
    closest_on_edges(p, t)
}

fn closest_on_edges(p: DVec3, t: &[DVec3; 3]) -> (DVec3, [f64; 3]) {
    let mut best = (t[0], unit(0));
    let mut best_d2 = f64::INFINITY;
    for i in 0..3 {
        let (x, _, s, _) = segment_segment_closest(t[i], t[(i + 1) % 3], p, p);
        let d2 = (x - p).length_squared();
        if d2 < best_d2 {
            best_d2 = d2;
            best = (x, on_edge(i, s));
        }
    }
    best
}

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
