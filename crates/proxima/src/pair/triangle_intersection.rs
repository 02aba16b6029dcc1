//! Exact intersection of closed triangles, and of faces of one mesh that share
//! vertices.
//!
//! Every decision is a sign of Shewchuk's adaptive `orient3d` / `orient2d`
//! (the `robust` crate) or a comparison of two `f64`s, so the answers are exact
//! for the given coordinates, as long as the determinants neither overflow nor
//! underflow (coordinates between about 1e-90 and 1e90 in magnitude, or 0;
//! mesh coordinates are `f32` moved by a pose, far inside). Triangles are
//! closed: touching counts. A triangle whose vertices are collinear is the
//! segment they span, one whose vertices coincide is a point; both are handled.
//! Non-finite coordinates make every test `false`.
//!
//! # Why an edge test suffices
//!
//! **Two closed triangles `A` and `B` intersect iff an edge of one meets the
//! other triangle.** If an edge meets the other triangle they intersect.
//! Conversely let `C = A ∩ B`, a non-empty compact convex set. If `A` is
//! degenerate it is the union of its edges, so any point of `C` lies on an edge
//! of `A` and in `B`; likewise for `B`. Otherwise both span planes. If the
//! planes differ, `C` lies on their common line `L`, and
//! `C = (A ∩ L) ∩ (B ∩ L)` is the overlap of two segments of `L`; it contains an
//! endpoint of one of them, say of `A ∩ L`, and the endpoints of a chord of a
//! triangle along a line of its plane lie on its boundary, the union of its
//! edges. If the planes agree, take an extreme point `x` of the convex polygon
//! `C`: a point interior (in the plane) to both `A` and `B` is interior to `C`,
//! so `x` is on the boundary of `A` or of `B`, that is on an edge of one, and
//! in the other.
//!
//! **Segment against triangle.** For a non-degenerate triangle `t` the signs of
//! `orient3d(t, p)` and `orient3d(t, q)` tell whether `pq` crosses, touches or
//! lies in the plane. Off-plane: when the signs are strict and equal the
//! segment misses; otherwise the line `pq` meets the plane at exactly one point
//! `X` of the segment, and the volumes `[p, q, t_i, t_{i+1}]` are proportional
//! (with one common non-zero factor) to the barycentric coordinates of `X`, so
//! `X` lies in the closed triangle iff no two of them have strictly opposite
//! signs. In-plane: the four points are projected onto the coordinate plane in
//! which the triangle's projection is not degenerate (`orient2d ≠ 0`, exact),
//! an affine bijection of the common plane that keeps every incidence; there
//! the segment meets the closed triangle iff `p` is inside or it meets an
//! edge (from `p` outside to a point inside it crosses the boundary). A degenerate triangle is tested as its three edges.
//!
//! **Segment against segment** (closed, possibly points): non-coplanar
//! (`orient3d ≠ 0`) segments miss. Coplanar ones are projected like above onto
//! a coordinate plane where three of the four points project to a
//! non-degenerate triangle, then decided by the classic 2D test (proper
//! crossing, or an endpoint on the other segment: collinear and inside its
//! bounding box). When all four points are collinear they are compared as
//! intervals on the coordinate axis of largest extent, injective on their line.

use crate::math::DVec3;
use robust::{Coord, Coord3D, orient2d, orient3d};
use std::cmp::Ordering;

/// `true` when the closed triangles share at least one point; exact for the
/// given `f64` coordinates (see the module doc), degenerate triangles
/// (segments, points) included.
///
/// ```
/// use proxima::math::DVec3;
/// use proxima::pair::triangles_intersect;
/// let a = [DVec3::ZERO, DVec3::X, DVec3::Y];
/// // The vertex (0.25, 0.25, 0) of b lies in a: touching counts.
/// let b = [DVec3::new(0.25, 0.25, 0.0), DVec3::new(0.0, 0.0, 1.0), DVec3::new(1.0, 1.0, 1.0)];
/// assert!(triangles_intersect(&a, &b));
/// let lifted = b.map(|p| p + DVec3::new(0.0, 0.0, 1e-300));
/// assert!(!triangles_intersect(&a, &lifted));
/// ```
pub fn triangles_intersect(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    if !(all_finite(a) && all_finite(b)) {
        return false;
    }
    // The common case first: one triangle strictly on one side of the
    // other's plane (a degenerate triangle gives zeros and never exits here).
    let sb = plane_signs(a, b);
    if strictly_one_side(sb) {
        return false;
    }
    let sa = plane_signs(b, a);
    if strictly_one_side(sa) {
        return false;
    }
    // The signs of each edge's ends against the other plane are known: each
    // edge test needs three more orientations at most.
    (0..3).any(|i| segment_meets_signed(a[i], a[(i + 1) % 3], b, sa[i], sa[(i + 1) % 3]))
        || (0..3).any(|i| segment_meets_signed(b[i], b[(i + 1) % 3], a, sb[i], sb[(i + 1) % 3]))
}

/// `true` when the closed segment `pq` meets the closed triangle `t`; exact,
/// degenerate segments and triangles included.
pub fn segment_meets_triangle(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    all_finite(&[p, q]) && all_finite(t) && segment_meets(p, q, t)
}

/// For two faces of one mesh, with their vertex positions and vertex indices:
/// `true` when they meet anywhere beyond what their shared indices make
/// common (a shared vertex, a shared edge); exact.
///
/// The shared vertices must have the same positions in `a` and `b` (they are
/// one mesh vertex); `a`'s positions are the ones used.
///
/// - No shared index: [`triangles_intersect`].
/// - The same index set (duplicate faces, `[0, 1, 2]` and `[2, 1, 0]`): `true`.
/// - One face's indices all among the other's (a face degenerate by its
///   indices, such as `[0, 0, 1]`, against `[0, 1, 2]`): `false`, it is the
///   shared vertex or edge itself.
/// - One shared vertex `A` (faces `ABC`, `ADE`): they meet beyond `A` iff
///   `BC` meets `ADE` at a point other than `A`, or `DE` meets `ABC` at a point
///   other than `A`. Proof: every point `x ≠ A` of `ABC` is `A + s(y - A)` with
///   `y` on `BC`, `s ∈ (0, 1]`, so `y ≠ A` lies on the ray from `A` through
///   `x`, as does the like point `z` of `DE`; of `y` and `z`, the one nearer
///   to `A` lies on the segment from `A` to the other, inside the other
///   face. When `A` is not on `BC`, "other than `A`" holds by itself; when it
///   is (`ABC` is a segment through `A`), `(A, B]` meets `ADE` iff `B` lies in
///   `ADE` or `[A, B]` meets `DE` at a point other than `A` (same ray
///   argument), and the latter, when `A` is on `DE` too, means `B - A` points
///   the way of `D - A` or `E - A`.
/// - One shared edge `AB` (faces `ABC`, `ABD`): not coplanar
///   (`orient3d(A, B, C, D) ≠ 0`, so both are proper triangles whose planes
///   meet in the line `AB`, which each meets in the edge only): `false`.
///   Coplanar and both proper: `true` iff `C` and `D` lie on the same side of
///   `AB`. A face whose vertices are collinear is a segment on the line `AB`
///   (or on the line through the other vertex when `A` and `B` coincide):
///   against a proper face it never reaches beyond `AB` (a proper face meets
///   that line in `AB` only); two such segments meet beyond `AB` iff both
///   stick out of `AB` on the same side (`A` and `B` at one point: iff `C - A`
///   and `D - A` point the same way).
pub fn neighbours_intersect(a: &[DVec3; 3], ia: [u32; 3], b: &[DVec3; 3], ib: [u32; 3]) -> bool {
    if !(all_finite(a) && all_finite(b)) {
        return false;
    }
    let in_a = |i: u32| ia.contains(&i);
    let in_b = |i: u32| ib.contains(&i);
    let a_within_b = ia.iter().all(|&i| in_b(i));
    let b_within_a = ib.iter().all(|&i| in_a(i));
    if a_within_b && b_within_a {
        return true;
    }
    if a_within_b || b_within_a {
        return false;
    }
    // The common case first: one or two orientations against a plane.
    if neighbours_apart(a, ia, b, ib) {
        return false;
    }
    // Slots of the shared indices (first occurrence) in a, and the other slots.
    let shared = slots(ia, in_b);
    match shared.count {
        0 => triangles_intersect(a, b),
        1 => {
            let sa = shared.slot[0];
            let sb = first_slot(ib, ia[sa]);
            let apex = a[sa];
            let (b1, c1) = (a[(sa + 1) % 3], a[(sa + 2) % 3]);
            let (d1, e1) = (b[(sb + 1) % 3], b[(sb + 2) % 3]);
            let a_face = [apex, b1, c1];
            let b_face = [apex, d1, e1];
            opposite_meets_beyond(apex, b1, c1, &b_face) || opposite_meets_beyond(apex, d1, e1, &a_face)
        }
        _ => {
            // Neither index set holds the other, so each face has exactly one
            // index of its own, and two shared distinct ones.
            let (s0, s1) = (shared.slot[0], shared.slot[1]);
            let apex_a = 3 - s0 - s1;
            let own_b = (0..3).find(|&j| !in_a(ib[j])).unwrap_or(0);
            let (p, q, c, d) = (a[s0], a[s1], a[apex_a], b[own_b]);
            edge_neighbours_meet_beyond(p, q, c, d)
        }
    }
}

/// A quick sufficient test for two faces of one mesh that share one vertex
/// or one edge (by index, three distinct indices each): `true` certifies
/// that [`neighbours_intersect`] is `false`; `false` says nothing. One or
/// two filtered orientations against a face's plane:
///
/// - One shared vertex: the other face's far edge strictly on one side of
///   a face's plane, so that face meets that plane at the apex only (every
///   other point of it is a convex combination with weight on that edge)
///   and the faces share nothing beyond it.
/// - One shared edge: the other face's own vertex off the face's plane (the
///   planes then meet in the edge's line only).
fn neighbours_apart(a: &[DVec3; 3], ia: [u32; 3], b: &[DVec3; 3], ib: [u32; 3]) -> bool {
    let distinct = |i: [u32; 3]| i[0] != i[1] && i[1] != i[2] && i[0] != i[2];
    if !(distinct(ia) && distinct(ib)) {
        return false;
    }
    let shared = ib.map(|i| ia.contains(&i));
    match shared.iter().filter(|&&s| s).count() {
        1 => {
            let k = shared.iter().position(|&s| s).unwrap_or(0);
            let sa = first_slot(ia, ib[k]);
            let one_side = |p: DVec3, q: DVec3, t: &[DVec3; 3]| {
                let plane = Plane::new(t);
                let s = plane.side(p);
                s != Ordering::Equal && s == plane.side(q)
            };
            one_side(b[(k + 1) % 3], b[(k + 2) % 3], a) || one_side(a[(sa + 1) % 3], a[(sa + 2) % 3], b)
        }
        2 => {
            let own = shared.iter().position(|&s| !s).unwrap_or(0);
            Plane::new(a).side(b[own]) != Ordering::Equal
        }
        _ => false,
    }
}

/// Which slots of a face hold indices shared with the other face (first
/// occurrence of each index).
struct SharedSlots {
    slot: [usize; 3],
    count: usize,
}

fn slots(ia: [u32; 3], shared: impl Fn(u32) -> bool) -> SharedSlots {
    let mut out = SharedSlots { slot: [0; 3], count: 0 };
    for (k, &i) in ia.iter().enumerate() {
        if shared(i) && !ia[..k].contains(&i) {
            out.slot[out.count] = k;
            out.count += 1;
        }
    }
    out
}

fn first_slot(ib: [u32; 3], index: u32) -> usize {
    ib.iter().position(|&j| j == index).unwrap_or(0)
}

/// `(BC ∩ T) \ {A}` is not empty, where `A = t[0]` (the shared vertex).
fn opposite_meets_beyond(apex: DVec3, b: DVec3, c: DVec3, t: &[DVec3; 3]) -> bool {
    if !on_segment_3d(apex, b, c) {
        return segment_meets(b, c, t);
    }
    // BC = [A, B] ∪ [A, C].
    half_open_meets(apex, b, t) || half_open_meets(apex, c, t)
}

/// `(A, B] ∩ T` is not empty, where `A = t[0]`: `B ∈ T`, or `[A, B]` meets the
/// opposite edge `DE` of `T` at a point other than `A`.
fn half_open_meets(apex: DVec3, b: DVec3, t: &[DVec3; 3]) -> bool {
    if b == apex {
        return false;
    }
    if segment_meets(b, b, t) {
        return true;
    }
    let (d, e) = (t[1], t[2]);
    if !on_segment_3d(apex, d, e) {
        return segments_meet(apex, b, d, e);
    }
    // [A, B] and [D, E] both hold A: beyond it they overlap iff B - A points
    // the way of D - A or of E - A.
    same_ray(apex, b, d) || same_ray(apex, b, e)
}

/// Faces `PQC` and `PQD` sharing the edge `PQ` meet beyond it.
fn edge_neighbours_meet_beyond(p: DVec3, q: DVec3, c: DVec3, d: DVec3) -> bool {
    if o3(p, q, c, d) != Ordering::Equal {
        return false;
    }
    let c_proper = !collinear(p, q, c);
    let d_proper = !collinear(p, q, d);
    match (c_proper, d_proper) {
        (true, true) => {
            // Project where PQC is not degenerate; PQD, coplanar and proper,
            // is not degenerate there either.
            let axis = proper_axis(p, q, c);
            let sc = o2(axis, p, q, c);
            let sd = o2(axis, p, q, d);
            sc == sd
        }
        (true, false) | (false, true) => false,
        (false, false) => {
            if p == q {
                return same_ray(p, c, d);
            }
            // All on the line PQ: both stick out beyond Q, or both beyond P.
            let beyond = |end: DVec3, other: DVec3, x: DVec3| x != end && on_segment_3d(end, other, x);
            (beyond(q, p, c) && beyond(q, p, d)) || (beyond(p, q, c) && beyond(p, q, d))
        }
    }
}

fn all_finite(points: &[DVec3]) -> bool {
    points.iter().all(|p| p.is_finite())
}

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D { x: p.x, y: p.y, z: p.z }
}

/// The sign of Shewchuk's `orient3d(a, b, c, d)`, exact.
fn o3(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Ordering {
    sign(orient3d(c3(a), c3(b), c3(c), c3(d)))
}

/// Projection dropping coordinate `axis`.
fn c2(axis: usize, p: DVec3) -> Coord<f64> {
    match axis {
        0 => Coord { x: p.y, y: p.z },
        1 => Coord { x: p.z, y: p.x },
        _ => Coord { x: p.x, y: p.y },
    }
}

/// The sign of `orient2d` of the projections dropping `axis`, exact.
fn o2(axis: usize, a: DVec3, b: DVec3, c: DVec3) -> Ordering {
    sign(orient2d(c2(axis, a), c2(axis, b), c2(axis, c)))
}

fn sign(x: f64) -> Ordering {
    x.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
}

/// A coordinate to drop so that the projection of `abc` is not degenerate;
/// `None` when `a`, `b`, `c` are collinear (the three projected orientations
/// are the components of `(b - a) × (c - a)`).
fn axis_of(a: DVec3, b: DVec3, c: DVec3) -> Option<usize> {
    (0..3).find(|&axis| o2(axis, a, b, c) != Ordering::Equal)
}

fn proper_axis(a: DVec3, b: DVec3, c: DVec3) -> usize {
    axis_of(a, b, c).unwrap_or(2)
}

fn collinear(a: DVec3, b: DVec3, c: DVec3) -> bool {
    axis_of(a, b, c).is_none()
}

/// `x` lies on the closed segment `pq` (exact).
fn on_segment_3d(x: DVec3, p: DVec3, q: DVec3) -> bool {
    collinear(p, q, x) && in_box(x, p, q)
}

/// `x` lies in the bounding box of `p` and `q`.
fn in_box(x: DVec3, p: DVec3, q: DVec3) -> bool {
    x.cmpge(p.min(q)).all() && x.cmple(p.max(q)).all()
}

/// `b ≠ a`, `c ≠ a` and `b - a`, `c - a` point the same way (exact).
fn same_ray(a: DVec3, b: DVec3, c: DVec3) -> bool {
    b != a && c != a && collinear(a, b, c) && (0..3).all(|k| b[k].partial_cmp(&a[k]) == c[k].partial_cmp(&a[k]))
}

/// The orientations of `t`'s vertices against the plane of `plane` (all
/// zero when `plane` is degenerate).
fn plane_signs(plane: &[DVec3; 3], t: &[DVec3; 3]) -> [Ordering; 3] {
    let plane = Plane::new(plane);
    t.map(|p| plane.side(p))
}

/// Shewchuk's bound on the rounding error of an orientation evaluated
/// once in `f64`, over its permanent (`(7 + 56ε)ε`, ε = 2⁻⁵³), doubled for
/// margin.
const ORIENT3D_BOUND: f64 = 2.0 * (7.0 + 56.0 * (f64::EPSILON / 2.0)) * (f64::EPSILON / 2.0);

/// The plane of a triangle, for the orientations of several points against
/// it: `side(p)` is the sign of `orient3d(t0, t1, t2, p)`, exact. The
/// normal is computed once; each point costs one dot product, whose sign is
/// taken when Shewchuk's first-stage error bound certifies it (the common
/// case), and the adaptive predicate decides the rest.
struct Plane {
    origin: DVec3,
    /// `(t1 - t0) × (t2 - t0)`.
    normal: DVec3,
    /// The same products' absolute values, summed per component: the
    /// permanent's factor.
    magnitude: DVec3,
    corners: [DVec3; 3],
}

impl Plane {
    fn new(t: &[DVec3; 3]) -> Self {
        let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
        let magnitude = DVec3::new(
            (e1.y * e2.z).abs() + (e1.z * e2.y).abs(),
            (e1.z * e2.x).abs() + (e1.x * e2.z).abs(),
            (e1.x * e2.y).abs() + (e1.y * e2.x).abs(),
        );
        Self {
            origin: t[0],
            normal: e1.cross(e2),
            magnitude,
            corners: *t,
        }
    }

    /// The sign of `orient3d(t0, t1, t2, p)`, which is that of
    /// `-(normal · (p - t0))`: with `q = t0 - p`, `orient3d` is
    /// `q · ((q + e1) × (q + e2)) = q · (e1 × e2)`.
    #[inline]
    fn side(&self, p: DVec3) -> Ordering {
        let d = p - self.origin;
        let det = -self.normal.dot(d);
        if det.abs() > ORIENT3D_BOUND * self.magnitude.dot(d.abs()) {
            return sign(det);
        }
        let [a, b, c] = self.corners;
        o3(a, b, c, p)
    }
}

/// All three strictly on one side.
fn strictly_one_side(s: [Ordering; 3]) -> bool {
    s[0] != Ordering::Equal && s[0] == s[1] && s[0] == s[2]
}

/// Closed segment `pq` against closed triangle `t`, finite inputs.
fn segment_meets(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    let plane = Plane::new(t);
    let (sp, sq) = (plane.side(p), plane.side(q));
    segment_meets_signed(p, q, t, sp, sq)
}

/// [`segment_meets`] given `sp`, `sq`, the orientations of `p` and `q`
/// against `t`'s plane (both zero when `t` is degenerate).
fn segment_meets_signed(p: DVec3, q: DVec3, t: &[DVec3; 3], sp: Ordering, sq: Ordering) -> bool {
    if sp == Ordering::Equal && sq == Ordering::Equal {
        return match axis_of(t[0], t[1], t[2]) {
            Some(axis) => segment_meets_in_plane(axis, p, q, t),
            // A degenerate triangle is the union of its edges.
            None => (0..3).any(|i| segments_meet(p, q, t[i], t[(i + 1) % 3])),
        };
    }
    if sp == sq {
        return false;
    }
    // One point X of the segment on the plane: its barycentric coordinates
    // have the signs of these volumes (one common factor, not zero).
    let v0 = o3(p, q, t[1], t[2]);
    let v1 = o3(p, q, t[2], t[0]);
    if v0 != Ordering::Equal && v1 != Ordering::Equal && v0 != v1 {
        return false;
    }
    let v2 = o3(p, q, t[0], t[1]);
    let has_less = [v0, v1, v2].contains(&Ordering::Less);
    let has_greater = [v0, v1, v2].contains(&Ordering::Greater);
    !(has_less && has_greater)
}

/// Coplanar segment and non-degenerate triangle, projected dropping `axis`:
/// `p` inside, or the segment meets an edge (a segment from outside to `q`
/// inside crosses the boundary, so `q` needs no test of its own).
fn segment_meets_in_plane(axis: usize, p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    point_in_triangle_2d(axis, p, t) || (0..3).any(|i| segments_meet_2d(axis, p, q, t[i], t[(i + 1) % 3]))
}

/// `x` in the closed projected triangle (not degenerate in that projection).
fn point_in_triangle_2d(axis: usize, x: DVec3, t: &[DVec3; 3]) -> bool {
    let s = [
        o2(axis, t[0], t[1], x),
        o2(axis, t[1], t[2], x),
        o2(axis, t[2], t[0], x),
    ];
    !(s.contains(&Ordering::Less) && s.contains(&Ordering::Greater))
}

/// Closed segments `pq` and `rs` (either may be a point) share a point; exact.
fn segments_meet(p: DVec3, q: DVec3, r: DVec3, s: DVec3) -> bool {
    if o3(p, q, r, s) != Ordering::Equal {
        return false;
    }
    let plane = axis_of(p, q, r)
        .or_else(|| axis_of(p, q, s))
        .or_else(|| axis_of(r, s, p))
        .or_else(|| axis_of(r, s, q));
    if let Some(axis) = plane {
        return segments_meet_2d(axis, p, q, r, s);
    }
    // All four collinear (or points): intervals on the axis of largest extent.
    let lo = p.min(q).min(r.min(s));
    let hi = p.max(q).max(r.max(s));
    let extent = hi - lo;
    let k = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    p[k].min(q[k]) <= r[k].max(s[k]) && r[k].min(s[k]) <= p[k].max(q[k])
}

/// Closed segments in the projection dropping `axis` (exact): a proper
/// crossing, or an endpoint on the other segment.
fn segments_meet_2d(axis: usize, p: DVec3, q: DVec3, r: DVec3, s: DVec3) -> bool {
    let d1 = o2(axis, r, s, p);
    let d2 = o2(axis, r, s, q);
    let d3 = o2(axis, p, q, r);
    let d4 = o2(axis, p, q, s);
    let strictly_opposite = |x: Ordering, y: Ordering| x != Ordering::Equal && y != Ordering::Equal && x != y;
    if strictly_opposite(d1, d2) && strictly_opposite(d3, d4) {
        return true;
    }
    let on = |d: Ordering, x: DVec3, a: DVec3, b: DVec3| d == Ordering::Equal && in_box_2d(axis, x, a, b);
    on(d1, p, r, s) || on(d2, q, r, s) || on(d3, r, p, q) || on(d4, s, p, q)
}

/// The projection of `x` lies in the bounding box of those of `a` and `b`.
fn in_box_2d(axis: usize, x: DVec3, a: DVec3, b: DVec3) -> bool {
    (0..3)
        .filter(|&k| k != axis)
        .all(|k| a[k].min(b[k]) <= x[k] && x[k] <= a[k].max(b[k]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    /// The filtered sign equals the adaptive predicate's, on random points
    /// and on points on the plane and a few ulps off it, at every scale.
    #[test]
    fn the_plane_filter_gives_orient3d_signs() {
        let mut rng = Rng::new(9);
        let mut point = |scale: f64| {
            DVec3::new(
                f64::from(rng.range(-1.0, 1.0)),
                f64::from(rng.range(-1.0, 1.0)),
                f64::from(rng.range(-1.0, 1.0)),
            ) * scale
        };
        let mut undecided = 0;
        for scale in [1e-30, 1e-3, 1.0, 7e4, 1e30] {
            for _ in 0..2000 {
                let t = [point(scale), point(scale), point(scale)];
                let plane = Plane::new(&t);
                // On the plane (an exact dyadic combination where it rounds
                // exactly: corners, edge midpoints), near it, and anywhere.
                let mid = (t[0] + t[1]) * 0.5;
                let mut probes = vec![t[0], t[1], t[2], mid, point(scale)];
                for base in [mid, t[2]] {
                    for k in 0..3 {
                        let mut up = base;
                        up[k] = up[k].next_up();
                        let mut down = base;
                        down[k] = down[k].next_down();
                        probes.extend([up, down]);
                    }
                }
                for p in probes {
                    let exact = o3(t[0], t[1], t[2], p);
                    assert_eq!(plane.side(p), exact, "{t:?} {p:?}");
                    let d = p - plane.origin;
                    undecided +=
                        usize::from((-plane.normal.dot(d)).abs() <= ORIENT3D_BOUND * plane.magnitude.dot(d.abs()));
                }
            }
        }
        // The points on the plane and next to it need the exact predicate.
        assert!(undecided > 1000, "{undecided}");
    }
}
