//! What a refit needs of the build layer: the check of moved primitives,
//! and the surface-area cost that says how much a refit has worn a tree.

use crate::aabb::Aabb;
use crate::error::BuildError;
use crate::math::Vec3;
use crate::primitive::BoundingPoints;
use rayon::prelude::*;

/// Fails on the first of `primitives` with a coordinate that is not finite
/// ([`BuildError::NonFinite`]) or beyond [`MAX_COORDINATE`](super::MAX_COORDINATE)
/// ([`BuildError::CoordinateTooLarge`]), as a build refuses them. Every point of each primitive
/// is looked at: a box's `min` and `max` drop a NaN coordinate.
pub(crate) fn check_primitives<T: BoundingPoints + Sync>(primitives: &[T]) -> Result<(), BuildError> {
    let limit = super::MAX_COORDINATE;
    // `!(m <= limit)` also catches NaN and infinities.
    let beyond = |q: &Vec3| !q.abs().cmple(Vec3::splat(limit)).all();
    let bad = |points: &mut Vec<Vec3>, p: &T| {
        points.clear();
        p.push_bounding_points(points);
        points.iter().any(beyond)
    };
    let first = primitives
        .par_iter()
        .with_min_len(4096)
        .map_init(Vec::new, bad)
        .position_first(|b| b);
    match first {
        None => Ok(()),
        Some(index) => {
            let mut points = Vec::new();
            primitives[index].push_bounding_points(&mut points);
            Err(if points.iter().all(|q| q.is_finite()) {
                BuildError::CoordinateTooLarge { index, bound: limit }
            } else {
                BuildError::NonFinite { index }
            })
        }
    }
}

/// The surface-area cost of a tree whose children are `lanes` (each box,
/// with the number of primitives of a leaf, `None` for an inner child),
/// relative to the box `root`: the expected number of boxes and primitives
/// a ray through `root` tests, counting a box as one primitive. A refit
/// keeps a tree's shape while its primitives move, so this grows as the
/// boxes come to overlap; its ratio to the cost at build says when a
/// rebuild pays (`RefitPolicy`). A flat or empty root counts as area 1.
pub(crate) fn surface_area_cost(root: Aabb, lanes: impl Iterator<Item = (Aabb, Option<usize>)>) -> f64 {
    let area = |b: &Aabb| if b.is_empty() { 0.0 } else { f64::from(b.surface_area()) };
    let total: f64 = lanes.map(|(b, leaf)| area(&b) * leaf.map_or(1.0, |n| n as f64)).sum();
    let root = area(&root);
    if root > 0.0 { total / root } else { total }
}
