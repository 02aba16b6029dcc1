//! The 32-byte tree node.

use crate::aabb::Aabb;
use crate::math::{Vec3, Vec3A};

/// A node of the flat node array: its box, and either two children or a
/// range of primitives.
///
/// An inner node's children sit side by side at `first` and `first + 1` (an
/// even index), in one 64-byte cache line, and the traversal reads them
/// together. A leaf owns the primitives
/// `first..first + count` of the tree's primitive array (kept in leaf order).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(32))]
pub struct Node {
    /// Smallest corner of the node's box.
    pub min: Vec3,
    first: u32,
    /// Largest corner of the node's box.
    pub max: Vec3,
    /// Number of primitives; 0 marks an inner node.
    count: u32,
}

// PERF: two nodes per cache line; a change of layout must be measured.
const _: () = assert!(std::mem::size_of::<Node>() == 32);

/// Two sibling nodes in one 64-byte cache line. The tree stores its nodes as
/// pairs so that the traversal, which always reads both children of a node,
/// touches exactly one line per step. Flat node index `i` lives at
/// `pairs[i / 2][i % 2]`; the root is node 0 and node 1 is padding.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
pub(crate) struct NodePair(pub(crate) [Node; 2]);

const _: () = assert!(std::mem::size_of::<NodePair>() == 64 && std::mem::align_of::<NodePair>() == 64);

impl AsRef<[Node; 2]> for NodePair {
    #[inline(always)]
    fn as_ref(&self) -> &[Node; 2] {
        &self.0
    }
}

impl super::walk::PairedNode for Node {
    type Pair = NodePair;
    #[inline(always)]
    fn is_leaf(&self) -> bool {
        self.count > 0
    }
    #[inline(always)]
    fn primitive_range(&self) -> std::ops::Range<usize> {
        Node::primitive_range(self)
    }
    #[inline(always)]
    fn first_child(&self) -> u32 {
        self.first
    }
    #[inline(always)]
    fn distance_squared(&self, p: Vec3A) -> f32 {
        Node::distance_squared(self, p)
    }
    #[inline(always)]
    fn classify(&self, frustum: &crate::frustum::Frustum, mask: crate::frustum::PlaneMask) -> crate::frustum::Cull {
        frustum.classify_box(&self.bounds(), mask)
    }
}

impl Node {
    pub(crate) fn leaf(bounds: Aabb, first: u32, count: u32) -> Self {
        debug_assert!(count > 0);
        Self {
            min: bounds.min,
            first,
            max: bounds.max,
            count,
        }
    }

    pub(crate) const fn empty_leaf() -> Self {
        Self {
            min: Vec3::splat(f32::INFINITY),
            first: 0,
            max: Vec3::splat(f32::NEG_INFINITY),
            count: 0,
        }
    }

    /// This node with its child index moved up by `by` (leaves unchanged).
    #[inline]
    pub(crate) fn shifted(self, by: u32) -> Self {
        if self.count == 0 {
            Self {
                first: self.first + by,
                ..self
            }
        } else {
            self
        }
    }

    pub(crate) fn inner(bounds: Aabb, first_child: u32) -> Self {
        Self {
            min: bounds.min,
            first: first_child,
            max: bounds.max,
            count: 0,
        }
    }

    /// The node's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    /// `true` for a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// For a leaf, the range of its primitives in the tree's primitive array.
    #[inline]
    pub fn primitive_range(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }

    /// For an inner node, the indices of its two children.
    #[inline]
    pub fn children(&self) -> [u32; 2] {
        [self.first, self.first + 1]
    }

    /// Squared distance from `p` to the node's box (0 inside).
    #[inline(always)]
    pub fn distance_squared(&self, p: Vec3A) -> f32 {
        let d = (Vec3A::from(self.min) - p)
            .max(p - Vec3A::from(self.max))
            .max(Vec3A::ZERO);
        d.length_squared()
    }
}
