//! Closest point on a convex polygon of four or more vertices: projection onto
//! the plane when the query lies inside every edge, else the nearest of the
//! edges it lies outside of (see the module documentation of `polygon.rs` for
//! what this means for faces that are planar only within tolerance).

use super::closest_triangle::closest_on_segment_f64;
use super::segment::closest_on_segment;
use crate::aabb::Aabb;
use crate::math::{Vec3, Vec3A};
use std::cmp::Ordering;

/// The point of the convex polygon `vertices` (unit normal `normal`, bounding
/// box `bounds`) closest to `p`.
///
/// One pass computes the sign of `((b − a) × (p − a)) · n` for every edge
/// `a → b`. The signs decide only which of two answers is given, and both
/// answers are near `p`'s projection when a sign is wrong by rounding: a
/// wrong *inside* projects onto a point within rounding of the edge, a wrong
/// *outside* returns an edge point within rounding of the projection (a point
/// inside a convex polygon is at most its distance to an edge's line from the
/// boundary). So no sliver special case is needed, unlike the triangle's
/// region walk. A sign that is exactly zero or not finite sends the query to
/// [`closest_on_polygon_f64`].
#[inline]
pub(crate) fn closest_on_polygon(vertices: &[Vec3], normal: Vec3A, bounds: Aabb, p: Vec3A) -> Vec3A {
    // Edge k runs from vertex k − 1 (cyclically) to vertex k; bit k of
    // `outside` says that `p` lies strictly outside it.
    let mut outside = 0u32;
    let mut prev = Vec3A::from(vertices[vertices.len() - 1]);
    for (k, &cur) in vertices.iter().enumerate() {
        let cur = Vec3A::from(cur);
        let side = (cur - prev).cross(p - prev).dot(normal);
        match side.partial_cmp(&0.0) {
            Some(Ordering::Less) => outside |= 1 << k,
            Some(Ordering::Greater) => {}
            _ => return closest_on_polygon_f64(vertices, normal, bounds, p),
        }
        prev = cur;
    }
    if outside == 0 {
        let q = p - normal * normal.dot(p - Vec3A::from(vertices[0]));
        return q.clamp(bounds.min.into(), bounds.max.into());
    }
    let mut best = p;
    let mut best_d2 = f32::INFINITY;
    let mut prev = Vec3A::from(vertices[vertices.len() - 1]);
    for (k, &cur) in vertices.iter().enumerate() {
        let cur = Vec3A::from(cur);
        if outside & (1 << k) != 0 {
            let q = closest_on_segment(prev, cur, p);
            let d2 = (q - p).length_squared();
            if d2 < best_d2 {
                (best, best_d2) = (q, d2);
            }
        }
        prev = cur;
    }
    if !best_d2.is_finite() {
        return closest_on_polygon_f64(vertices, normal, bounds, p);
    }
    best
}

/// The same answer computed in `f64`, for queries on an edge's line and for
/// coordinates whose `f32` products underflow or overflow: projection when
/// inside or on every edge, else the nearest of all edges.
#[cold]
#[inline(never)]
pub(crate) fn closest_on_polygon_f64(vertices: &[Vec3], normal: Vec3A, bounds: Aabb, p: Vec3A) -> Vec3A {
    let (n, p) = (normal.as_dvec3(), p.as_dvec3());
    let v = |k: usize| vertices[k % vertices.len()].as_dvec3();
    let inside = (0..vertices.len()).all(|k| (v(k + 1) - v(k)).cross(p - v(k)).dot(n) >= 0.0);
    if inside {
        let q = p - n * n.dot(p - v(0));
        return q.clamp(bounds.min.as_dvec3(), bounds.max.as_dvec3()).as_vec3a();
    }
    let mut best = closest_on_segment_f64(v(0), v(1), p);
    for k in 1..vertices.len() {
        let q = closest_on_segment_f64(v(k), v(k + 1), p);
        if (q - p).length_squared() < (best - p).length_squared() {
            best = q;
        }
    }
    best.as_vec3a()
}
