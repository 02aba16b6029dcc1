//! Closest-primitive queries on the wide tree.

use super::WideTree;
use super::traverse::LaneVisitor;
use crate::bvh::traverse::{Counter, DistanceVisitor, QueryStats};
use crate::bvh::{ClosestHit, PRUNE_SLACK};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;

/// Keeps the best candidate; ties in distance go to the lower input index, so
/// the answer is the same as a linear scan's (the binary tree's `Best`).
pub(super) struct Best<'a> {
    indices: &'a [u32],
    pub(super) slot: usize,
    pub(super) point: Vec3A,
    pub(super) distance_squared: f32,
    bound: f32,
    pub(super) found: bool,
}

impl<'a> Best<'a> {
    pub(super) fn new(indices: &'a [u32], max_distance_squared: f32) -> Self {
        Self {
            indices,
            slot: 0,
            point: Vec3A::ZERO,
            distance_squared: max_distance_squared,
            bound: max_distance_squared * PRUNE_SLACK,
            found: false,
        }
    }

    #[inline(always)]
    pub(super) fn offer(&mut self, slot: usize, q: Vec3A, d2: f32) {
        let better = d2 < self.distance_squared
            || (d2 == self.distance_squared && (!self.found || self.indices[slot] < self.indices[self.slot]));
        if better {
            self.slot = slot;
            self.point = q;
            self.distance_squared = d2;
            self.bound = d2 * PRUNE_SLACK;
            self.found = true;
        }
    }
}

impl<T: ClosestPoint> DistanceVisitor<T> for Best<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }
    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A) {
        let q = primitive.closest_point(p);
        self.offer(slot, q, (q - p).length_squared());
    }
}

impl<T: ClosestPoint> LaneVisitor<T> for Best<'_> {
    #[inline(always)]
    fn offer(&mut self, slot: usize, q: Vec3A, d2: f32) {
        Best::offer(self, slot, q, d2);
    }
}

impl<T: ClosestPoint> WideTree<T> {
    /// The primitive closest to `p`, or `None` for an empty tree, a
    /// non-finite `p`, or distances beyond `f32` range. Ties go to the lowest
    /// input index. The same answer as [`AabbTree::closest`](crate::AabbTree::closest).
    #[inline]
    pub fn closest(&self, p: Vec3) -> Option<ClosestHit> {
        self.closest_within(p, f32::INFINITY)
    }

    /// The closest primitive at distance at most `max_distance` from `p`, or
    /// `None` if there is none (as [`AabbTree::closest_within`](crate::AabbTree::closest_within)).
    #[inline]
    pub fn closest_within(&self, p: Vec3, max_distance: f32) -> Option<ClosestHit> {
        self.closest_counted(p, max_distance, &mut ())
    }

    /// [`closest`](Self::closest), also counting the work: `nodes_visited`
    /// counts wide nodes, each of which tests four child boxes.
    pub fn closest_with_stats(&self, p: Vec3) -> (Option<ClosestHit>, QueryStats) {
        let mut stats = QueryStats::default();
        let hit = self.closest_counted(p, f32::INFINITY, &mut stats);
        (hit, stats)
    }

    #[inline]
    fn closest_counted<C: Counter>(&self, p: Vec3, max_distance: f32, counter: &mut C) -> Option<ClosestHit> {
        if !p.is_finite() {
            return None;
        }
        let p = Vec3A::from(p);
        let mut best = Best::new(&self.tree.indices, max_distance * max_distance);
        self.nearest_first(p, &mut best, counter);
        best.found
            .then(|| self.tree.hit(best.slot, best.point, best.distance_squared))
    }
}
