//! Closest-primitive queries on the wide tree.

use super::WideTree;
use super::traverse::LaneVisitor;
use crate::bvh::ClosestHit;
use crate::bvh::closest::Best;
use crate::bvh::traverse::{Counter, QueryStats};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;

impl<T: ClosestPoint> LaneVisitor<T> for Best<'_> {
    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        Best::offer_indexed(self, slot, index, q, d2);
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

    /// [`closest_within`](Self::closest_within), except that the answer's
    /// `source` holds its leaf-order slot, for
    /// [`resolve_sources`](crate::AabbTree::resolve_sources) to replace
    /// later; `primitive` is the input index the walk already knows (from
    /// the packet, in the common case), not read from the index array.
    #[inline]
    pub(crate) fn closest_within_deferred(&self, p: Vec3, max_distance: f32) -> Option<ClosestHit> {
        let best = self.best_within(p, max_distance, &mut ())?;
        Some(ClosestHit {
            primitive: best.index(),
            source: best.slot as u32,
            point: best.point.into(),
            distance: best.distance_squared.sqrt(),
        })
    }

    #[inline]
    fn closest_counted<C: Counter>(&self, p: Vec3, max_distance: f32, counter: &mut C) -> Option<ClosestHit> {
        let best = self.best_within(p, max_distance, counter)?;
        Some(self.tree.hit(best.slot, best.point, best.distance_squared))
    }

    /// The walk's best primitive within `max_distance` of `p`, if any.
    #[inline(always)]
    fn best_within<C: Counter>(&self, p: Vec3, max_distance: f32, counter: &mut C) -> Option<Best<'_>> {
        if !crate::bvh::answerable(p) {
            return None;
        }
        let mut best = Best::new(&self.tree.indices, max_distance * max_distance);
        self.nearest_first(Vec3A::from(p), &mut best, counter);
        best.found.then_some(best)
    }
}
