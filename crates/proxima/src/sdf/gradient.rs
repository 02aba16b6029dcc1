//! The gradient of the signed distance.
//!
//! Off the surface the signed distance `s·|p − c|` (`s` = −1 inside, `c`
//! the closest point) has gradient `s·(p − c)/|p − c|` with respect to `p`:
//! unit length, pointing away from the surface outside and towards it
//! inside, so always outward. Across the medial axis (two closest points)
//! it jumps, and any one of the one-sided gradients is returned. On the
//! surface the distance has no gradient; the outward direction there is the
//! closest feature's pseudonormal
//! ([`Pseudonormals::normal`](super::Pseudonormals::normal)).
//!
//! With respect to the closest triangle's corners `v_i`, with the feature
//! held fixed, the gradient is `−w_i` times the one with respect to `p`,
//! `w_i` the closest point's barycentric weights (the envelope theorem:
//! the weights are optimal, so their own change does not count).

use super::{Pseudonormals, SignedDistance};
use crate::math::{DVec3, Vec3};
use crate::mesh::Mesh;
use crate::query::ClosestHit;
use crate::surface::{Attributes, GROUP, Located, SurfacePoint, answer_groups, in_triangle_order_blocks};
use std::borrow::Cow;

/// A signed distance with its gradient with respect to the query point
/// ([`signed_distance_gradients`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdfGradient {
    /// The signed distance and the closest query's answer.
    pub distance: SignedDistance,
    /// The gradient: unit length, outward; the closest feature's unit
    /// pseudonormal on the surface (zero where its faces cancel).
    pub gradient: DVec3,
    /// Where the closest point lies.
    pub at: SurfacePoint,
}

/// The gradients of `answers`, the signed distances at `points` on `mesh`'s
/// faces (a field built on `mesh`), on all cores: each answer's closest
/// point is located again in `f64` (as [`SurfacePoint::closest`] does, a
/// group of answers at a time in the order of their triangles) and
/// [`signed_distance_gradient`] taken from it; points on the surface take
/// the unit pseudonormal of their closest feature, from `pseudonormals`,
/// called once and only when there are such points.
pub fn signed_distance_gradients<'a, E>(
    mesh: &Mesh,
    points: &[Vec3],
    answers: &[Option<SignedDistance>],
    pseudonormals: impl FnOnce() -> Result<Cow<'a, Pseudonormals>, E>,
) -> Result<Vec<Option<SdfGradient>>, E> {
    let hits: Vec<Option<ClosestHit>> = answers.iter().map(|a| a.map(|a| a.closest)).collect();
    let located = Located::Closest { points, hits: &hits };
    let triangles = located.triangles();
    let work = |block: &[u32], out: &mut [Option<(SdfGradient, bool)>]| {
        // A group's surface points, then their gradients while the
        // triangles' corners are still in cache.
        let mut at = [None; GROUP];
        for (group, out) in block.chunks(GROUP).zip(out.chunks_mut(GROUP)) {
            at[..group.len()].fill(None);
            answer_groups(mesh, &[], Attributes::NONE, located, group, &mut at[..group.len()]);
            for ((out, answer), &i) in out.iter_mut().zip(&at).zip(group) {
                let (Some(answer), Some(distance)) = (answer, answers[i as usize]) else {
                    continue;
                };
                let gradient =
                    signed_distance_gradient(points[i as usize], answer.at.point(mesh), distance.is_inside());
                let found = SdfGradient {
                    distance,
                    gradient: gradient.unwrap_or(DVec3::ZERO),
                    at: answer.at,
                };
                *out = Some((found, gradient.is_none()));
            }
        }
    };
    let located = in_triangle_order_blocks(&triangles, None, work);
    let normals = match located.iter().flatten().any(|&(_, on_surface)| on_surface) {
        true => Some(pseudonormals()?),
        false => None,
    };
    Ok(located
        .iter()
        .zip(points)
        .map(|(found, &p)| {
            let (mut answer, on_surface) = (*found)?;
            if let (true, Some(normals)) = (on_surface, &normals) {
                answer.gradient = normals.normal(answer.at.triangle, p);
            }
            Some(answer)
        })
        .collect())
}

/// How close to the surface, in units of the query's largest coordinate,
/// a query counts as on it: 16 `f32` ulps. Closer than that, the `f32`
/// query cannot tell which triangle is closest (two meeting at an edge both
/// answer distance 0) and `p − c` is rounding noise, often along the
/// surface.
pub const ON_SURFACE: f64 = 1.0 / (1u32 << 20) as f64;

/// The gradient with respect to `p` of the signed distance at `p`, from
/// its closest point `closest` (in `f64`, such as
/// [`SurfacePoint::point`](crate::surface::SurfacePoint::point)) and its
/// side; `None` when `p` is on the surface: within [`ON_SURFACE`] times its
/// largest coordinate (and the smallest normal `f32`) of `closest`.
///
/// ```
/// use proxima::prelude::*;
/// use proxima::sdf::signed_distance_gradient;
/// use proxima::DVec3;
/// let g = signed_distance_gradient(Vec3::new(0.0, 0.0, 2.0), DVec3::ZERO, false).unwrap();
/// assert_eq!(g, DVec3::Z);
/// // Inside, the distance grows negative towards p's side: the gradient still points out.
/// assert_eq!(signed_distance_gradient(Vec3::new(0.0, 0.0, -2.0), DVec3::ZERO, true).unwrap(), DVec3::Z);
/// assert_eq!(signed_distance_gradient(Vec3::ZERO, DVec3::ZERO, false), None);
/// ```
pub fn signed_distance_gradient(p: Vec3, closest: DVec3, inside: bool) -> Option<DVec3> {
    let away = p.as_dvec3() - closest;
    let distance = away.length();
    let scale = f64::from(p.abs().max_element().max(f32::MIN_POSITIVE));
    (distance > ON_SURFACE * scale).then(|| if inside { -away / distance } else { away / distance })
}
