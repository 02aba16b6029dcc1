//! k-nearest primitive queries on the wide tree.

use super::WideTree;
use super::traverse::LaneVisitor;
use crate::bvh::ClosestHit;
use crate::bvh::knn::{Candidate, KBest, drain_sorted};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;
use std::collections::BinaryHeap;

/// Reusable memory for the wide tree's k-nearest queries, so a loop of
/// queries allocates once.
#[derive(Clone, Debug, Default)]
pub struct WideKnnScratch {
    heap: BinaryHeap<Candidate>,
}

impl WideKnnScratch {
    /// Empty scratch space.
    pub fn new() -> Self {
        Self::default()
    }
}

impl<T: ClosestPoint> LaneVisitor<T> for KBest<'_> {
    /// As `KBest`'s `visit` does with the point it computes.
    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        if d2 <= self.bound {
            KBest::offer(
                self,
                Candidate {
                    distance_squared: d2,
                    index,
                    slot: slot as u32,
                    point: q,
                },
            );
        }
    }
}

impl<T: ClosestPoint> WideTree<T> {
    /// The `k` primitives closest to `p`, nearest first (ties by input index):
    /// the same answer as [`AabbTree::k_nearest`](crate::AabbTree::k_nearest).
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<ClosestHit> {
        let mut out = Vec::new();
        self.k_nearest_into(p, k, &mut WideKnnScratch::new(), &mut out);
        out
    }

    /// [`k_nearest`](Self::k_nearest) writing into `out` (cleared first) and
    /// reusing `scratch`, so repeated queries do not allocate.
    pub fn k_nearest_into(&self, p: Vec3, k: usize, scratch: &mut WideKnnScratch, out: &mut Vec<ClosestHit>) {
        let k = k.min(self.len());
        scratch.heap.clear();
        if k > 0 && crate::bvh::answerable(p) {
            let mut best = KBest {
                heap: &mut scratch.heap,
                k,
                indices: &self.tree.indices,
                bound: f32::INFINITY,
            };
            self.nearest_first(Vec3A::from(p), &mut best, &mut ());
        }
        drain_sorted(&mut scratch.heap, out, |slot| self.tree.sources[slot]);
    }
}
