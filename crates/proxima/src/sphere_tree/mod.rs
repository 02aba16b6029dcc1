//! The bounding-sphere tree: the same hierarchy and queries as the
//! [`AabbTree`](crate::AabbTree), with a sphere instead of a box per node.
//!
//! The build (a conversion of the AABB tree's topology) is in `build.rs`,
//! the node in `node.rs`, invariant checks in `validate.rs`; the queries
//! are the shared ones ([`NearestQuery`], [`FrustumQuery`]) on the AABB
//! tree's walks, classifying spheres instead of boxes.
//!
//! # Exactness
//!
//! The answers equal brute force ([`LinearSearch`](crate::LinearSearch)) on
//! every field, as the AABB tree's do, for the same three reasons:
//!
//! 1. every node's sphere holds every point of its primitives for certain
//!    (radius measured in `f64` and rounded up), and is then widened by
//!    8 ulps of its largest coordinate (`|center| + radius`), which holds
//!    the computed closest points too, a few ulps off their primitive;
//! 2. the node distance `|p - c| (1 - 4 eps) - r` is a lower bound even after
//!    rounding, and pruning uses the same `PRUNE_SLACK` as the AABB tree;
//! 3. the leaves are visited with the AABB tree's `Best` and `KBest`
//!    visitors, so ties go to the lowest input index.

mod build;
mod node;
mod validate;

pub use node::SphereNode;

use crate::aabb::Aabb;
use crate::build::{NodePair, frustum_walk, nearest_walk};
use crate::frustum::{Frustum, FrustumOverlap};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;
use crate::query::{Counter, FrustumQuery, Leaves, NearestQuery, NearestVisitor, SpatialIndex};
use crate::sphere::Sphere;

/// A bounding volume hierarchy of spheres over primitives of type `T`.
///
/// Built from the same median (or SAH) split as the [`AabbTree`](crate::AabbTree)
/// with the same [`BuildConfig`](crate::BuildConfig): same nodes, same leaves,
/// same leaf order; only the bounding volumes differ. Nodes live in one flat
/// array of 64-byte sibling pairs (node 0 is the root, node 1 padding).
///
/// ```
/// use proxima::prelude::*;
/// let points = vec![Point(Vec3::ZERO), Point(Vec3::X), Point(Vec3::Y)];
/// let tree = SphereTree::build(points, &Default::default()).unwrap();
/// assert_eq!(tree.closest(Vec3::new(0.9, 0.2, 0.0)).unwrap().primitive, 1);
/// ```
#[derive(Clone, Debug)]
pub struct SphereTree<T> {
    nodes: Vec<NodePair<Sphere>>,
    /// Primitives in leaf order, with their input indices and sources.
    leaves: Leaves<T>,
    depth: u32,
}

impl<T> SphereTree<T> {
    /// The root node, `None` for an empty tree.
    pub fn root(&self) -> Option<&SphereNode> {
        self.nodes.first().map(|pair| &pair.nodes()[0])
    }

    /// Node `index` (0 is the root; children indices come from
    /// [`SphereNode::children`]).
    #[inline]
    pub fn node(&self, index: usize) -> &SphereNode {
        &self.nodes[index >> 1].nodes()[index & 1]
    }

    /// Number of nodes (inner and leaves).
    pub fn node_count(&self) -> usize {
        (2 * self.nodes.len()).saturating_sub(1)
    }

    /// Every node with its index, root first (the padding node is skipped).
    pub fn nodes(&self) -> impl Iterator<Item = (usize, &SphereNode)> + '_ {
        self.nodes
            .iter()
            .flat_map(|pair| pair.nodes())
            .enumerate()
            .filter(|&(i, _)| i != 1)
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
}

impl<T> SpatialIndex<T> for SphereTree<T> {
    #[inline(always)]
    fn leaves(&self) -> &Leaves<T> {
        &self.leaves
    }
    fn bounds(&self) -> Aabb {
        self.root().map_or(Aabb::EMPTY, |n| {
            let sphere = n.sphere();
            Aabb::new(
                sphere.center - Vec3::splat(sphere.radius),
                sphere.center + Vec3::splat(sphere.radius),
            )
        })
    }
}

/// The AABB tree's walk over sphere nodes.
impl<T: ClosestPoint> NearestQuery<T> for SphereTree<T> {
    #[inline(always)]
    fn nearest_walk<V: NearestVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C) {
        nearest_walk::<SphereNode, T, V, C>(&self.nodes, self.depth, self.leaves.primitives(), p, visitor, counter);
    }
}

/// The AABB tree's frustum walk, with each node's sphere classified against
/// the planes instead of its box.
impl<T: FrustumOverlap> FrustumQuery<T> for SphereTree<T> {
    fn frustum_walk<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        frustum_walk::<SphereNode, T, C>(
            &self.nodes,
            self.leaves.primitives(),
            self.leaves.indices(),
            frustum,
            out,
            counter,
        );
    }
}
