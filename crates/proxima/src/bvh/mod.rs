//! The AABB tree (bounding volume hierarchy of axis-aligned boxes).
//!
//! One file per operation: [`build`](AabbTree::build) in `build.rs` (its median
//! split in `median.rs`), the closest-primitive search in `closest.rs`,
//! k-nearest in `knn.rs`, view frustum queries in `frustum.rs`, batches over
//! many points in `batch.rs`, first hit and any hit along a ray in `ray.rs`,
//! statistics and invariants in `validate.rs`.

mod build;
mod config;
mod frustum;
mod median;
mod node;
mod ray;
mod validate;
mod walk;

pub(crate) use config::answerable;
pub use config::{BuildConfig, MAX_COORDINATE, MAX_DEPTH, MAX_QUERY_COORDINATE, SplitMethod, check_query_point};
pub use node::Node;
use node::NodePair;
pub(crate) use ray::RaySlabs;
pub use validate::TreeStats;
// Shared with the sphere tree, which answers the same queries the same way.
pub(crate) use frustum::frustum_walk;
pub(crate) use validate::check_structure;
pub(crate) use walk::{PairedNode, nearest_walk};
// The query layer's names, where the tree's users have always found them.
pub use crate::query::{BatchOptions, ClosestHit, KnnScratch, QueryStats, RayHit};

use crate::aabb::Aabb;
use crate::frustum::{Frustum, FrustumOverlap};
use crate::math::Vec3A;
use crate::memory::HugePageArray;
use crate::primitive::ClosestPoint;
use crate::query::{Counter, FrustumQuery, Leaves, NearestQuery, NearestVisitor, SpatialIndex};

/// A bounding volume hierarchy of axis-aligned boxes over primitives of type `T`.
///
/// Nodes live in one flat array (index 0 is the root); primitives are stored in
/// leaf order so each leaf is a contiguous range. Build it with
/// [`AabbTree::build`] or [`AabbTree::build_set`], then ask
/// [`closest`](AabbTree::closest) or [`k_nearest`](AabbTree::k_nearest).
#[derive(Clone, Debug)]
pub struct AabbTree<T> {
    /// Node pairs; see [`Node`] for the indexing.
    nodes: HugePageArray<NodePair>,
    /// Primitives in leaf order, with their input indices and sources.
    leaves: Leaves<T>,
    depth: u32,
}

impl<T> AabbTree<T> {
    /// The root node, `None` for an empty tree.
    pub fn root(&self) -> Option<&Node> {
        self.nodes.first().map(|pair| &pair.0[0])
    }

    /// Node `index` (0 is the root; children indices come from
    /// [`Node::children`]).
    #[inline(always)]
    pub fn node(&self, index: usize) -> &Node {
        &self.nodes[index >> 1].0[index & 1]
    }

    /// Number of nodes (inner and leaves).
    pub fn node_count(&self) -> usize {
        (2 * self.nodes.len()).saturating_sub(1)
    }

    /// Every node with its index, root first (the padding node is skipped).
    pub fn nodes(&self) -> impl Iterator<Item = (usize, &Node)> + '_ {
        self.nodes
            .iter()
            .flat_map(|pair| &pair.0)
            .enumerate()
            .filter(|&(i, _)| i != 1)
    }

    /// The node pairs, as the walks read them.
    #[inline(always)]
    pub(crate) fn pairs(&self) -> &[NodePair] {
        &self.nodes
    }

    /// The primitives in leaf order.
    pub fn primitives(&self) -> &[T] {
        self.leaves.primitives()
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// `true` when the tree holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }

    /// Depth of the deepest leaf (0 when the root is a leaf).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The build-input index of the primitive at leaf-order slot `slot`.
    #[inline]
    pub fn input_index(&self, slot: usize) -> u32 {
        self.leaves.indices()[slot]
    }

    /// The source of the primitive at leaf-order slot `slot`.
    #[inline]
    pub fn source(&self, slot: usize) -> u32 {
        self.leaves.sources()[slot]
    }

    /// The leaves, for structures converted from this tree.
    pub(crate) fn into_leaves(self) -> Leaves<T> {
        self.leaves
    }
}

impl<T> SpatialIndex<T> for AabbTree<T> {
    #[inline(always)]
    fn leaves(&self) -> &Leaves<T> {
        &self.leaves
    }
    fn bounds(&self) -> Aabb {
        self.root().map_or(Aabb::EMPTY, |n| n.bounds())
    }
}

impl<T: ClosestPoint> NearestQuery<T> for AabbTree<T> {
    #[inline(always)]
    fn nearest_walk<V: NearestVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C) {
        nearest_walk::<Node, T, V, C>(&self.nodes, self.depth, self.leaves.primitives(), p, visitor, counter);
    }
}

impl<T: FrustumOverlap> FrustumQuery<T> for AabbTree<T> {
    fn frustum_walk<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        frustum_walk::<Node, T, C>(
            &self.nodes,
            self.leaves.primitives(),
            self.leaves.indices(),
            frustum,
            out,
            counter,
        );
    }
}
