//! Closest-primitive queries: the AABB tree's traversal loop and `Best`
//! visitor over sphere nodes.

use super::SphereTree;
use super::node::SphereNode;
use crate::bvh::{Best, ClosestHit, Counter, QueryStats, nearest_first};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;

impl<T: ClosestPoint> SphereTree<T> {
    /// The primitive closest to `p`, or `None` for an empty tree, a
    /// non-finite `p`, or distances beyond `f32` range. Ties go to the lowest
    /// input index: the same answer as [`AabbTree::closest`](crate::AabbTree::closest).
    #[inline]
    pub fn closest(&self, p: Vec3) -> Option<ClosestHit> {
        self.closest_within(p, f32::INFINITY)
    }

    /// The closest primitive at distance at most `max_distance` from `p`, or
    /// `None` if there is none.
    #[inline]
    pub fn closest_within(&self, p: Vec3, max_distance: f32) -> Option<ClosestHit> {
        self.closest_counted(p, max_distance, &mut ())
    }

    /// [`closest`](Self::closest), also counting the nodes and primitives visited.
    pub fn closest_with_stats(&self, p: Vec3) -> (Option<ClosestHit>, QueryStats) {
        let mut stats = QueryStats::default();
        let hit = self.closest_counted(p, f32::INFINITY, &mut stats);
        (hit, stats)
    }

    #[inline]
    fn closest_counted<C: Counter>(&self, p: Vec3, max_distance: f32, counter: &mut C) -> Option<ClosestHit> {
        if !crate::bvh::answerable(p) {
            return None;
        }
        let p = Vec3A::from(p);
        let mut best = Best::new(&self.indices, max_distance * max_distance);
        nearest_first::<SphereNode, T, _, _>(&self.nodes, &self.primitives, self.depth, p, &mut best, counter);
        best.found
            .then(|| self.hit(best.slot, best.point, best.distance_squared))
    }
}
