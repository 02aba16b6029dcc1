//! Frustum queries of the sphere tree: the AABB tree's walk, with each node's
//! sphere classified against the planes instead of its box.

use super::SphereTree;
use super::node::SphereNode;
use crate::bvh::{Counter, QueryStats, frustum_walk};
use crate::frustum::{Frustum, FrustumOverlap};

impl<T: FrustumOverlap> SphereTree<T> {
    /// The build-input indices of the primitives overlapping `frustum`
    /// (closed sets: touching counts), sorted ascending: the same set as
    /// [`AabbTree::frustum`](crate::AabbTree::frustum) and
    /// [`LinearSearch::frustum`](crate::LinearSearch::frustum).
    ///
    /// ```
    /// use proxima::frustum::Frustum;
    /// use proxima::{Point, SphereTree, Vec3};
    /// let points: Vec<Point> = (0..10).map(|i| Point(Vec3::new(0.0, 0.0, -(i as f32)))).collect();
    /// let tree = SphereTree::build(points, &Default::default()).unwrap();
    /// let camera = Frustum::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 1.0, 1.5, 5.5).unwrap();
    /// assert_eq!(tree.frustum(&camera), [2, 3, 4, 5]);
    /// ```
    pub fn frustum(&self, frustum: &Frustum) -> Vec<u32> {
        let mut out = Vec::new();
        self.frustum_counted(frustum, &mut out, &mut ());
        out
    }

    /// [`frustum`](Self::frustum) into a caller-owned vector (cleared first).
    pub fn frustum_into(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        self.frustum_counted(frustum, out, &mut ());
    }

    /// [`frustum`](Self::frustum), also counting the nodes classified and the
    /// primitives tested exactly.
    pub fn frustum_with_stats(&self, frustum: &Frustum) -> (Vec<u32>, QueryStats) {
        let mut out = Vec::new();
        let mut stats = QueryStats::default();
        self.frustum_counted(frustum, &mut out, &mut stats);
        (out, stats)
    }

    fn frustum_counted<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        frustum_walk::<SphereNode, T, C>(&self.nodes, &self.primitives, &self.indices, frustum, out, counter);
    }
}
