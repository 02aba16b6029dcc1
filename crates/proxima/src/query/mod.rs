//! The queries every structure answers, each written once.
//!
//! A structure says where its primitives are ([`SpatialIndex`]) and how it
//! walks its nodes for one kind of query: [`NearestQuery::nearest_walk`]
//! (nearest subtrees first, pruned by a shrinking radius),
//! [`RayQuery::ray_walk`] (nearest entry first, pruned by the best hit) and
//! [`FrustumQuery::frustum_walk`]. Every query of a family (`closest`,
//! `closest_within`, `k_nearest`, batches on all cores, statistics, `first_hit`,
//! `any_hit`, ...) is a default method built on that one walk, so each
//! structure answers all of them, and the answers are the same, field for
//! field, from every structure: the leaf visitors ([`NearestVisitor`],
//! [`RayVisitor`]) that decide ties live here, once.
//!
//! ```
//! use proxima::prelude::*;
//! let points: Vec<Point> = (0..10).map(|i| Point(Vec3::new(i as f32, 0.0, 0.0))).collect();
//! let tree = AabbTree::build(points.clone(), &Default::default()).unwrap();
//! let linear = LinearSearch::new(PrimitiveSet::from_primitives(points));
//! /// Written once for any structure.
//! fn nearest_two<S: NearestQuery<Point>>(s: &S) -> Vec<u32> {
//!     s.k_nearest(Vec3::new(3.2, 1.0, 0.0), 2).iter().map(|h| h.primitive).collect()
//! }
//! assert_eq!(nearest_two(&tree), [3, 4]);
//! assert_eq!(nearest_two(&linear), [3, 4]);
//! ```

mod batch;
mod closest;
mod frustum;
pub(crate) mod knn;
mod leaves;
mod nearest;
mod point;
mod ray;
mod visitor;

pub use batch::BatchOptions;
pub use frustum::FrustumQuery;
pub use knn::{KnnScratch, NearestAnswers, distinct_sources};
pub use leaves::Leaves;
pub use nearest::NearestQuery;
pub use point::{QueryError, check_query_point};
pub use ray::{RayHit, RayQuery};
pub use visitor::{Counter, NearestVisitor, QueryStats, RayVisitor};

pub(crate) use batch::answer_batch_indexed;
pub(crate) use batch::{CHUNK, already_coherent, in_chunks, in_chunks_ordered, morton_order, sort_by_code};
pub(crate) use closest::{Announcing, Best};
pub(crate) use nearest::{closest_announcing, closest_chunk};
pub(crate) use point::answerable;
pub(crate) use ray::{
    AnyHit, FarRay, FirstHit, first_hit_by, hit_answer, nearest_to, prepare_structure_ray, sort_points,
};

use crate::aabb::Aabb;
use crate::math::Vec3;

/// A structure over primitives of type `T`: what every query family needs
/// to make its answers.
pub trait SpatialIndex<T> {
    /// The primitives in leaf order, with their input indices and sources.
    fn leaves(&self) -> &Leaves<T>;
    /// A box holding every primitive ([`Aabb::EMPTY`] when there is none).
    fn bounds(&self) -> Aabb;
}

/// The answer to a closest-primitive query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestHit {
    /// Index of the primitive in the build input.
    pub primitive: u32,
    /// The mesh element the primitive came from (vertex, edge or face index).
    pub source: u32,
    /// The closest point on that primitive.
    pub point: Vec3,
    /// Euclidean distance from the query to `point`.
    pub distance: f32,
}

/// Relative slack on pruning comparisons. Node volumes are also widened by
/// a few ulps at build time, so a node is pruned only when it certainly
/// holds nothing closer than the best so far, even after the rounding of the
/// two distance computations: a structure's answer then equals brute force
/// exactly.
pub(crate) const PRUNE_SLACK: f32 = 1.0 + 1e-6;
