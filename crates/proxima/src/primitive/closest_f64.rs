//! Closest points in `f64` with their barycentric or segment parameters:
//! point to triangle and segment to segment (Ericson, *Real-Time Collision
//! Detection*, 5.1.5 and 5.1.9), every division guarded so that degenerate
//! triangles and zero-length segments give finite answers for finite input.
//! The triangle-pair distances of [`crate::pair`] and the surface points of
//! [`crate::surface`] are built on them.

use crate::math::DVec3;

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
        return sliver_closest(p, t, n, nn);
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

/// [`point_triangle_closest`] for slivers and degenerate triangles, `n`
/// their normal `ab × ac` and `nn` its squared length.
fn sliver_closest(p: DVec3, t: &[DVec3; 3], n: DVec3, nn: f64) -> (DVec3, [f64; 3]) {
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

/// `n / d`, or 0 when that is not a finite number (`d` zero or underflowed).
pub(crate) fn ratio(n: f64, d: f64) -> f64 {
    let r = n / d;
    if r.is_finite() { r } else { 0.0 }
}

pub(crate) fn clamp01(x: f64) -> f64 {
    x.clamp(0.0, 1.0)
}

pub(crate) fn unit(i: usize) -> [f64; 3] {
    let mut w = [0.0; 3];
    w[i] = 1.0;
    w
}

/// Weights of the point at parameter `s` on edge `t_i t_{i+1}`.
pub(crate) fn on_edge(i: usize, s: f64) -> [f64; 3] {
    let mut w = [0.0; 3];
    w[i] = 1.0 - s;
    w[(i + 1) % 3] = s;
    w
}
