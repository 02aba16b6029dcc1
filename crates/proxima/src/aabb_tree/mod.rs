//! The AABB tree (bounding volume hierarchy of axis-aligned boxes).
//!
//! The tree is the binary hierarchy of [`build`](crate::build) as built:
//! its build, node, walks and structure checks live there, shared with the
//! other trees. Here: the tree itself and its distance and frustum queries
//! (this file), first hit and any hit along a ray (`ray.rs`), statistics
//! and invariants (`validate.rs`).

mod ray;
mod refit;
mod validate;

pub(crate) use ray::RaySlabs;
// The build layer's names the tree's users need with it.
pub use crate::build::{BuildConfig, SplitMethod, TreeStats};
// The query layer's names, where the tree's users have always found them.
pub use crate::query::{BatchOptions, ClosestHit, KnnScratch, QueryStats, RayHit};

use crate::aabb::Aabb;
use crate::build::{Node, NodePair, build_hierarchy, frustum_walk, nearest_walk};
use crate::error::BuildError;
use crate::frustum::{Frustum, FrustumOverlap};
use crate::math::Vec3A;
use crate::memory::HugePageArray;
use crate::primitive::{Bounded, ClosestPoint, PrimitiveSet};
use crate::query::{Counter, FrustumQuery, Leaves, NearestQuery, NearestVisitor, SpatialIndex};

/// A node of the AABB tree: the binary trees' node holding a box.
pub type AabbNode = Node<Aabb>;

/// A bounding volume hierarchy of axis-aligned boxes over primitives of type `T`.
///
/// Nodes live in one flat array (index 0 is the root); primitives are stored in
/// leaf order so each leaf is a contiguous range. Build it with
/// [`AabbTree::build`] or [`AabbTree::build_set`], then ask
/// [`closest`](AabbTree::closest) or [`k_nearest`](AabbTree::k_nearest).
#[derive(Clone, Debug)]
pub struct AabbTree<T> {
    /// Node pairs; see [`Node`] for the indexing.
    nodes: HugePageArray<NodePair<Aabb>>,
    /// Primitives in leaf order, with their input indices and sources.
    leaves: Leaves<T>,
    depth: u32,
}

impl<T> AabbTree<T> {
    /// The root node, `None` for an empty tree.
    pub fn root(&self) -> Option<&AabbNode> {
        self.nodes.first().map(|pair| &pair.nodes()[0])
    }

    /// Node `index` (0 is the root; children indices come from
    /// [`Node::children`]).
    #[inline(always)]
    pub fn node(&self, index: usize) -> &AabbNode {
        &self.nodes[index >> 1].nodes()[index & 1]
    }

    /// Number of nodes (inner and leaves).
    pub fn node_count(&self) -> usize {
        (2 * self.nodes.len()).saturating_sub(1)
    }

    /// Every node with its index, root first (the padding node is skipped).
    pub fn nodes(&self) -> impl Iterator<Item = (usize, &AabbNode)> + '_ {
        self.nodes
            .iter()
            .flat_map(|pair| pair.nodes())
            .enumerate()
            .filter(|&(i, _)| i != 1)
    }

    /// The node pairs, as the walks read them.
    #[inline(always)]
    pub(crate) fn pairs(&self) -> &[NodePair<Aabb>] {
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

impl<T: Bounded + Copy + Send + Sync> AabbTree<T> {
    /// Builds a tree over `primitives`; the source of each is its input index.
    ///
    /// Fails when the configuration is invalid, a primitive has a non-finite
    /// coordinate or one beyond [`MAX_COORDINATE`](crate::build::MAX_COORDINATE), or there are 2^32 or more primitives. Large builds use all
    /// threads of rayon's current pool; run it inside a one-thread pool for a
    /// single-thread build (the tree is the same either way).
    pub fn build(primitives: Vec<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        let sources = (0..primitives.len() as u32).collect();
        Self::build_with_sources(primitives, sources, config)
    }

    /// Builds a tree over primitives extracted from a mesh, keeping their sources.
    pub fn build_set(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        Self::build_with_sources(set.primitives, set.sources, config)
    }

    /// Builds a tree over `primitives`, where `sources[i]` is the mesh element
    /// that `primitives[i]` came from.
    pub fn build_with_sources(primitives: Vec<T>, sources: Vec<u32>, config: &BuildConfig) -> Result<Self, BuildError> {
        let built = build_hierarchy(primitives, sources, config)?;
        Ok(Self {
            nodes: built.nodes,
            leaves: built.leaves,
            depth: built.depth,
        })
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
        nearest_walk::<AabbNode, T, V, C>(&self.nodes, self.depth, self.leaves.primitives(), p, visitor, counter);
    }
}

impl<T: FrustumOverlap> FrustumQuery<T> for AabbTree<T> {
    fn frustum_walk<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        frustum_walk::<AabbNode, T, C>(
            &self.nodes,
            self.leaves.primitives(),
            self.leaves.indices(),
            frustum,
            out,
            counter,
        );
    }
}
