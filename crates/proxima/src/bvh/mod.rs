//! The AABB tree (bounding volume hierarchy of axis-aligned boxes).
//!
//! One file per operation: [`build`](AabbTree::build) in `build.rs` (its median
//! split in `median.rs`), the closest-primitive search in `closest.rs`,
//! k-nearest in `knn.rs`, view frustum queries in `frustum.rs`, batches over
//! many points in `batch.rs`, first hit and any hit along a ray in `ray.rs`,
//! statistics and invariants in `validate.rs`.

mod batch;
mod build;
mod closest;
mod config;
mod frustum;
mod knn;
mod median;
mod node;
mod ray;
mod traverse;
mod validate;
pub mod wide;

pub use self::wide::{WideChild, WideKnnScratch, WideNode, WideTree};
pub use batch::BatchOptions;
pub(crate) use config::answerable;
pub use config::{BuildConfig, MAX_COORDINATE, MAX_DEPTH, MAX_QUERY_COORDINATE, SplitMethod, check_query_point};
pub use knn::KnnScratch;
pub use node::Node;
use node::NodePair;
pub(crate) use ray::FarRay;
pub use ray::RayHit;
pub use traverse::QueryStats;
pub use validate::TreeStats;
// Shared with the sphere tree, which answers the same queries the same way.
pub(crate) use closest::Best;
pub(crate) use frustum::frustum_walk;
pub(crate) use knn::k_nearest_with;
pub(crate) use traverse::{Counter, PairedNode, nearest_first};
pub(crate) use validate::check_structure;

use crate::math::Vec3;
use crate::memory::HugePageArray;

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
    /// Primitives in leaf order.
    primitives: Vec<T>,
    /// `indices[i]`: position in the build input of `primitives[i]`.
    indices: Vec<u32>,
    /// `sources[i]`: mesh element `primitives[i]` came from.
    sources: Vec<u32>,
    depth: u32,
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

    /// The two children of an inner node, which share a cache line.
    #[inline(always)]
    fn children_of(&self, node: &Node) -> &[Node; 2] {
        &self.nodes[(node.children()[0] >> 1) as usize].0
    }

    /// The primitives in leaf order.
    pub fn primitives(&self) -> &[T] {
        &self.primitives
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.primitives.len()
    }

    /// `true` when the tree holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }

    /// Depth of the deepest leaf (0 when the root is a leaf).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// The build-input index of the primitive at leaf-order slot `slot`.
    #[inline]
    pub fn input_index(&self, slot: usize) -> u32 {
        self.indices[slot]
    }

    /// The source of the primitive at leaf-order slot `slot`.
    #[inline]
    pub fn source(&self, slot: usize) -> u32 {
        self.sources[slot]
    }

    /// The primitives in leaf order, their input indices and their sources,
    /// for structures converted from this tree.
    pub(crate) fn into_leaf_order(self) -> (Vec<T>, Vec<u32>, Vec<u32>) {
        (self.primitives, self.indices, self.sources)
    }

    /// Replaces the slot that each answer of `hits` holds in `source`
    /// (`WideTree::closest_within_deferred`) by the slot's source. Looked up
    /// at the end of each query, the source was a cache miss that the query
    /// waited on (3% of a batch's samples); here, prefetched a few answers
    /// ahead, the misses of many queries overlap.
    pub(crate) fn resolve_sources(&self, hits: &mut [Option<ClosestHit>]) {
        const AHEAD: usize = 8;
        for k in 0..hits.len() {
            if let Some(Some(ahead)) = hits.get(k + AHEAD) {
                wide::prefetch(&self.sources[ahead.source as usize]);
            }
            if let Some(hit) = &mut hits[k] {
                hit.source = self.sources[hit.source as usize];
            }
        }
    }

    #[inline]
    fn hit(&self, slot: usize, point: crate::math::Vec3A, distance_squared: f32) -> ClosestHit {
        ClosestHit {
            primitive: self.indices[slot],
            source: self.sources[slot],
            point: point.into(),
            distance: distance_squared.sqrt(),
        }
    }
}

/// Relative slack on pruning comparisons. Node boxes are also widened by a few
/// ulps at build time, so a node is pruned only when it certainly holds nothing
/// closer than the best so far, even after the rounding of the two distance
/// computations: the tree's answer then equals brute force exactly.
pub(crate) const PRUNE_SLACK: f32 = 1.0 + 1e-6;
