//! Queries over many points at once on the wide tree, on all cores.

use super::{WideKnnScratch, WideTree};
use crate::aabb::Aabb;
use crate::bvh::batch::answer_batch;
use crate::bvh::{BatchOptions, ClosestHit};
use crate::math::Vec3;
use crate::primitive::ClosestPoint;

impl<T: ClosestPoint + Sync> WideTree<T> {
    fn root_bounds(&self) -> Aabb {
        self.tree.root().map_or(Aabb::EMPTY, |n| n.bounds())
    }

    /// [`closest`](Self::closest) for every point, in parallel on rayon's
    /// pool, in Morton order; results in input order. No allocation per query.
    pub fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<ClosestHit>> {
        self.closest_batch_with(points, BatchOptions::default())
    }

    /// [`closest_batch`](Self::closest_batch) with explicit options.
    pub fn closest_batch_with(&self, points: &[Vec3], options: BatchOptions) -> Vec<Option<ClosestHit>> {
        answer_batch(
            points,
            &self.root_bounds(),
            options.reorder,
            || (),
            |_, p| self.closest(p),
        )
    }

    /// [`k_nearest`](Self::k_nearest) for every point, in parallel, in Morton
    /// order; results in input order. Scratch memory is allocated once per
    /// worker, not per query.
    pub fn k_nearest_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>> {
        answer_batch(points, &self.root_bounds(), true, WideKnnScratch::new, |scratch, p| {
            let mut out = Vec::with_capacity(k.min(self.len()));
            self.k_nearest_into(p, k, scratch, &mut out);
            out
        })
    }
}
