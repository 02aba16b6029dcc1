//! The 32-byte node of the binary trees, generic over its bounding volume.

use super::walk::PairedNode;
use crate::aabb::Aabb;
use crate::frustum::{Cull, Frustum, PlaneMask};
use crate::math::{Vec3, Vec3A};
use std::fmt;
use std::marker::PhantomData;

/// A bounding volume a binary tree's node can hold ([`Aabb`] or
/// [`Sphere`](crate::Sphere)), kept in the node's two `Vec3` slots, with
/// the two tests the walks make on it.
pub trait NodeVolume: bytemuck::Pod + fmt::Debug + PartialEq {
    /// The slots of a node that holds nothing (padding, placeholders).
    const EMPTY_SLOTS: [Vec3; 2];
    /// The volume kept in `slots`.
    fn from_slots(slots: [Vec3; 2]) -> Self;
    /// The slots that keep `self`.
    fn to_slots(self) -> [Vec3; 2];
    /// A lower bound of the squared distance from `p` to anything the
    /// volume kept in `slots` holds (0 inside), never above the computed
    /// distance to any point within it.
    fn distance_squared(slots: [Vec3; 2], p: Vec3A) -> f32;
    /// Where the volume kept in `slots` lies against the planes of
    /// `frustum` still in `mask`.
    fn classify(slots: [Vec3; 2], frustum: &Frustum, mask: PlaneMask) -> Cull;
}

/// The box's two corners, `min` then `max`.
impl NodeVolume for Aabb {
    const EMPTY_SLOTS: [Vec3; 2] = [Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)];
    #[inline(always)]
    fn from_slots([min, max]: [Vec3; 2]) -> Self {
        Aabb::new(min, max)
    }
    #[inline(always)]
    fn to_slots(self) -> [Vec3; 2] {
        [self.min, self.max]
    }
    /// Squared distance from `p` to the box (0 inside).
    #[inline(always)]
    fn distance_squared([min, max]: [Vec3; 2], p: Vec3A) -> f32 {
        let d = (Vec3A::from(min) - p).max(p - Vec3A::from(max)).max(Vec3A::ZERO);
        d.length_squared()
    }
    #[inline(always)]
    fn classify(slots: [Vec3; 2], frustum: &Frustum, mask: PlaneMask) -> Cull {
        frustum.classify_box(&Self::from_slots(slots), mask)
    }
}

/// What a node holds in its slots, as the walks read them: the two
/// 16-byte halves of the node, a slot and a count each.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(32))]
struct Slots {
    low: Vec3,
    first: u32,
    high: Vec3,
    count: u32,
}

/// A node of the flat node array: its bounding volume `B`, and either two
/// children or a range of primitives.
///
/// An inner node's children sit side by side at `first` and `first + 1` (an
/// even index), in one 64-byte cache line, and the traversal reads them
/// together. A leaf owns the primitives
/// `first..first + count` of the tree's primitive array (kept in leaf order).
/// The AABB tree's nodes are `Node<Aabb>`, the sphere tree's `Node<Sphere>`.
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(transparent)]
pub struct Node<B>(Slots, PhantomData<B>);

// PERF: two nodes per cache line; a change of layout must be measured.
const _: () = assert!(std::mem::size_of::<Node<Aabb>>() == 32 && std::mem::align_of::<Node<Aabb>>() == 32);

impl<B: NodeVolume> fmt::Debug for Node<B> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Node")
            .field("volume", &self.volume())
            .field("first", &self.0.first)
            .field("count", &self.0.count)
            .finish()
    }
}

impl<B: NodeVolume> Node<B> {
    const fn with(slots: [Vec3; 2], first: u32, count: u32) -> Self {
        Self(
            Slots {
                low: slots[0],
                first,
                high: slots[1],
                count,
            },
            PhantomData,
        )
    }

    /// A leaf over the primitive slots `first..first + count`.
    pub(crate) fn leaf(volume: B, first: u32, count: u32) -> Self {
        debug_assert!(count > 0);
        Self::with(volume.to_slots(), first, count)
    }

    /// An inner node whose children are `first_child` and `first_child + 1`.
    pub(crate) fn inner(volume: B, first_child: u32) -> Self {
        Self::with(volume.to_slots(), first_child, 0)
    }

    /// A node that holds nothing (padding, placeholders).
    pub(crate) const fn empty_leaf() -> Self {
        Self::with(B::EMPTY_SLOTS, 0, 0)
    }

    /// This node with its child index moved up by `by` (leaves unchanged).
    #[inline]
    pub(crate) fn shifted(self, by: u32) -> Self {
        if self.0.count == 0 {
            Self::with(self.slots(), self.0.first + by, 0)
        } else {
            self
        }
    }

    /// Replaces the node's volume.
    #[inline]
    pub(crate) fn set_volume(&mut self, volume: B) {
        [self.0.low, self.0.high] = volume.to_slots();
    }

    #[inline(always)]
    fn slots(&self) -> [Vec3; 2] {
        [self.0.low, self.0.high]
    }

    /// The node's bounding volume.
    #[inline]
    pub fn volume(&self) -> B {
        B::from_slots(self.slots())
    }

    /// `true` for a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.0.count > 0
    }

    /// For a leaf, the range of its primitives in the tree's primitive array.
    #[inline]
    pub fn primitive_range(&self) -> std::ops::Range<usize> {
        self.0.first as usize..(self.0.first + self.0.count) as usize
    }

    /// For an inner node, the indices of its two children.
    #[inline]
    pub fn children(&self) -> [u32; 2] {
        [self.0.first, self.0.first + 1]
    }

    /// A lower bound of the squared distance from `p` to anything the node
    /// holds (0 inside its volume).
    #[inline(always)]
    pub fn distance_squared(&self, p: Vec3A) -> f32 {
        B::distance_squared(self.slots(), p)
    }
}

impl Node<Aabb> {
    /// The node's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        self.volume()
    }
}

/// Two sibling nodes in one 64-byte cache line. A tree stores its nodes as
/// pairs so that the traversal, which always reads both children of a node,
/// touches exactly one line per step. Flat node index `i` lives at
/// `pairs[i / 2].nodes()[i % 2]`; the root is node 0 and node 1 is padding.
#[derive(Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(transparent)]
pub(crate) struct NodePair<B>(PairSlots, PhantomData<B>);

#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
struct PairSlots([Slots; 2]);

const _: () = assert!(std::mem::size_of::<NodePair<Aabb>>() == 64 && std::mem::align_of::<NodePair<Aabb>>() == 64);

impl<B: NodeVolume> NodePair<B> {
    /// The pair of `nodes`.
    #[inline]
    pub(crate) fn new(nodes: [Node<B>; 2]) -> Self {
        Self(PairSlots(nodes.map(|n| n.0)), PhantomData)
    }

    /// The two nodes.
    #[inline(always)]
    pub(crate) fn nodes(&self) -> &[Node<B>; 2] {
        bytemuck::cast_ref(&self.0)
    }

    /// The two nodes, to change.
    #[inline(always)]
    pub(crate) fn nodes_mut(&mut self) -> &mut [Node<B>; 2] {
        bytemuck::cast_mut(&mut self.0)
    }
}

impl<B: NodeVolume> fmt::Debug for NodePair<B> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("NodePair").field(self.nodes()).finish()
    }
}

impl<B: NodeVolume> AsRef<[Node<B>; 2]> for NodePair<B> {
    #[inline(always)]
    fn as_ref(&self) -> &[Node<B>; 2] {
        self.nodes()
    }
}

impl<B: NodeVolume> PairedNode for Node<B> {
    type Pair = NodePair<B>;
    #[inline(always)]
    fn is_leaf(&self) -> bool {
        self.0.count > 0
    }
    #[inline(always)]
    fn primitive_range(&self) -> std::ops::Range<usize> {
        Node::primitive_range(self)
    }
    #[inline(always)]
    fn first_child(&self) -> u32 {
        self.0.first
    }
    #[inline(always)]
    fn distance_squared(&self, p: Vec3A) -> f32 {
        Node::distance_squared(self, p)
    }
    #[inline(always)]
    fn classify(&self, frustum: &Frustum, mask: PlaneMask) -> Cull {
        B::classify(self.slots(), frustum, mask)
    }
}
