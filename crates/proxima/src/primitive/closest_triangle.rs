//! Closest point on a triangle by Voronoi regions (Ericson, *Real-Time
//! Collision Detection*, 5.1.5), made safe for degenerate and sliver triangles.

use crate::math::Vec3A;
use glam::DVec3;
use wide::f32x4;

/// Below this value of sin²(angle at `a`), a triangle counts as a sliver. The
/// region tests of the fast path subtract products of nearly equal size, so
/// for slivers their signs are noise in `f32`; such triangles are rare in real
/// meshes and take the `f64` path instead.
const SLIVER_SIN2: f32 = 1e-4;

/// Squared edge length above which the fast path's products could overflow
/// `f32` (edges longer than 2^30): such triangles take the `f64` path.
pub(crate) const FAST_EDGE2: f32 = (1u64 << 60) as f32;
/// Squared distance from `a` above which the query takes the `f64` path
/// (farther than 2^32). With edges of at most 2^30 every dot product is then
/// below 2^63 and every product of two below 2^126, so no region test
/// overflows; a fuzzed triangle with 1e16-long edges had `|n|²` overflow to
/// infinity and returned the query itself as its closest point.
pub(crate) const FAST_REACH2: f32 = (1u128 << 64) as f32;

/// Whether [`closest_on_triangle`] sends the triangle with edges `ab` and
/// `ac` from its first vertex, and normal `n = ab × ac`, to its `f64` path
/// whatever the query: slivers, and sizes where `f32` products could
/// overflow or lose their precision to underflow (edges shorter than about
/// 1e-10). The triangle packets decide by this same test in four lanes
/// ([`takes_f64_path_x4`]), so the lanes they answer are exactly the
/// triangles the fast path answers.
#[inline(always)]
pub(crate) fn takes_f64_path(ab: Vec3A, ac: Vec3A, n: Vec3A) -> bool {
    let (ab2, ac2) = (ab.length_squared(), ac.length_squared());
    let scale = ab2 * ac2;
    n.length_squared() <= SLIVER_SIN2 * scale
        || scale.is_nan()
        || scale < f32::MIN_POSITIVE
        || ab2.max(ac2) > FAST_EDGE2
}

/// [`takes_f64_path`] in four lanes, from each lane's `|ab|²`, `|ac|²` and
/// `|n|²` computed as the scalar routine computes them: all lanes set where
/// the scalar test holds. The two must agree lane for lane (tested), since
/// the triangle packets answer the lanes this leaves clear.
#[inline(always)]
pub(crate) fn takes_f64_path_x4(ab2: f32x4, ac2: f32x4, n2: f32x4) -> f32x4 {
    let scale = ab2 * ac2;
    // `max(|ab|², |ac|²) > FAST_EDGE2` as two tests: where either is NaN,
    // so is `scale`, and the lane is set by that test already.
    let edge = f32x4::splat(FAST_EDGE2);
    n2.simd_le(f32x4::splat(SLIVER_SIN2) * scale)
        | scale.is_nan()
        | scale.simd_lt(f32x4::splat(f32::MIN_POSITIVE))
        | ab2.simd_gt(edge)
        | ac2.simd_gt(edge)
}

/// The point of triangle `a`, `b`, `c` closest to `p`.
///
/// The query is classified against the triangle's vertex, edge and face
/// regions using dot products only, so a point in a vertex or edge region
/// costs no division. Slivers and degenerate triangles (repeated or collinear
/// vertices), edges beyond 2^30 or below about 1e-10, and queries farther than
/// 2^32 from the triangle go to [`closest_on_sliver`].
#[inline(always)]
pub(crate) fn closest_on_triangle(a: Vec3A, b: Vec3A, c: Vec3A, p: Vec3A) -> Vec3A {
    let ab = b - a;
    let ac = c - a;
    let n = ab.cross(ac);
    let ap = p - a;
    if takes_f64_path(ab, ac, n) || ap.length_squared() > FAST_REACH2 {
        return closest_on_sliver(a, b, c, p);
    }
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    // Inside the face: drop the normal component of `ap`. Unlike summing the
    // barycentric combination, this keeps the query's in-plane coordinates as
    // they are (exactly, for axis-aligned faces).
    p - n * (n.dot(ap) / n.length_squared())
}

/// The closest point for slivers and degenerate triangles, in `f64`: the
/// projection onto the plane when it falls inside (signed areas against the
/// normal), else the nearest of the three edges. A triangle whose normal
/// vanishes even in `f64` is the union of its edges.
#[cold]
#[inline(never)]
pub(crate) fn closest_on_sliver(a: Vec3A, b: Vec3A, c: Vec3A, p: Vec3A) -> Vec3A {
    let (a64, b64, c64, p64) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3(), p.as_dvec3());
    let n = (b64 - a64).cross(c64 - a64);
    let nn = n.length_squared();
    let scale = (b64 - a64).length_squared() * (c64 - a64).length_squared();
    if nn > 1e-24 * scale && nn.is_normal() {
        let q = p64 - n * ((p64 - a64).dot(n) / nn);
        let inside = |u: DVec3, v: DVec3| (v - u).cross(q - u).dot(n) >= 0.0;
        if inside(a64, b64) && inside(b64, c64) && inside(c64, a64) {
            return q.as_vec3a();
        }
    }
    let mut best = closest_on_segment_f64(a64, b64, p64);
    for q in [
        closest_on_segment_f64(b64, c64, p64),
        closest_on_segment_f64(c64, a64, p64),
    ] {
        if (q - p64).length_squared() < (best - p64).length_squared() {
            best = q;
        }
    }
    best.as_vec3a()
}

pub(crate) fn closest_on_segment_f64(a: DVec3, b: DVec3, p: DVec3) -> DVec3 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 <= 0.0 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
}
