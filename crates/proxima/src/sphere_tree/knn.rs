//! k-nearest primitive queries: the AABB tree's `KBest` visitor and scratch.

use super::SphereTree;
use super::node::SphereNode;
use crate::bvh::{ClosestHit, KnnScratch, k_nearest_with, nearest_first};
use crate::math::Vec3;
use crate::primitive::ClosestPoint;

impl<T: ClosestPoint> SphereTree<T> {
    /// The `k` primitives closest to `p`, nearest first (ties by input index).
    /// Gives all primitives when `k` exceeds their number, none when `k == 0`
    /// or `p` is not finite or beyond [`MAX_QUERY_COORDINATE`](crate::bvh::MAX_QUERY_COORDINATE).
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<ClosestHit> {
        let mut out = Vec::new();
        self.k_nearest_into(p, k, &mut KnnScratch::new(), &mut out);
        out
    }

    /// [`k_nearest`](Self::k_nearest) writing into `out` (cleared first) and
    /// reusing `scratch`, so repeated queries do not allocate.
    pub fn k_nearest_into(&self, p: Vec3, k: usize, scratch: &mut KnnScratch, out: &mut Vec<ClosestHit>) {
        k_nearest_with(p, k, &self.indices, &self.sources, scratch, out, |p, best| {
            nearest_first::<SphereNode, T, _, _>(&self.nodes, &self.primitives, self.depth, p, best, &mut ())
        });
    }
}
