//! A 4-wide layout of the AABB tree for SIMD traversal.
//!
//! [`WideTree`] is made from a built [`AabbTree`] by collapsing its binary
//! nodes: each wide node takes up to four nodes of the binary tree as its
//! children, opening first the inner child a point query most likely enters
//! (the largest volume of its box grown a little), in the manner of a BVH4.
//! The four child boxes are stored as structure of arrays, so one query
//! computes the four box distances with one `f32x4` computation.
//!
//! The boxes are the binary tree's own (widened) node boxes and the leaves are
//! its leaves, over the same leaf-order primitive array; pruning uses the same
//! `PRUNE_SLACK` (1 + 1e-6) and ties go to the lowest input index.
//! The answers are therefore the binary tree's and brute force's, field for
//! field (see ARCHITECTURE.md, "Exactness").
//!
//! For triangles (on x86-64) the leaves' triangles are also copied into
//! packets of four in structure of arrays form and tested four at a time by a
//! branch-free `f32x4` closest-point routine that repeats the scalar one
//! operation for operation, so each lane's point and distance are bit for bit
//! [`Triangle::closest_point`](crate::Triangle)'s; slivers, which the scalar
//! routine answers in `f64`, are marked when packing and left to it. On CPUs
//! with AVX2 (detected at run time, `avx2.rs`) the leaves hold up to eight
//! triangles and their two packets are tested at once on 256-bit lanes, with
//! the same bits.
//!
//! One walk serves every query (`walk.rs`): distance queries (`nearest.rs`)
//! and rays (`ray.rs`) differ only in the keys they give a node's four
//! children and in what they do at a leaf. The collapse from the binary tree
//! is in `convert.rs`, the triangle packets in `packet.rs`, their AVX2 test
//! in `avx2.rs` (the crate's only `unsafe` code).

pub(crate) use convert::{open_largest, subtree_ranges};
pub(crate) use refit::repack;
mod convert;
mod nearest;
mod oriented;
mod primitive;
mod ray;
pub(crate) use ray::{WideSlabs, entry_order_bits};
mod refit;
pub(crate) mod walk;

pub use oriented::{OrientedBounds, OrientedBox};
pub use primitive::WidePrimitive;

use crate::aabb::Aabb;
use crate::aabb_tree::AabbTree;
use crate::frustum::{Frustum, FrustumOverlap};
use crate::math::Vec3;
use crate::memory::HugePageArray;
use crate::query::{Counter, FrustumQuery, Leaves, SpatialIndex};
use crate::simd::TrianglePacket;
use wide::f32x4;

/// Marks a leaf lane in [`WideNode::counts`]; the low bits are the number of primitives.
const LEAF: u32 = 1 << 31;

/// For an inner lane, [`WideNode::counts`] holds 1 + the index of the first
/// triangle packet of that wide node's own leaf lanes (0: none), so that a
/// walk can prefetch the packets together with the node
/// ([`PREFETCHED_PACKETS`](walk::PREFETCHED_PACKETS) of them). This gives
/// the packet's index, or `usize::MAX` (which no slice holds) for none.
#[inline(always)]
fn packet_hint(count: u32) -> usize {
    (count as usize).wrapping_sub(1)
}

/// One node of a [`WideTree`]: the boxes of up to four children in structure
/// of arrays form, and for each child either the index of a wide node or a
/// leaf (a range of primitives, or of triangle packets). Two cache lines.
/// [`WideTree::child`] says what a lane holds.
///
/// A lane without a child has an empty box (`min = +inf`, `max = -inf`) and
/// refers to an empty range of primitives, so it is harmless even where an
/// infinite radius lets it pass.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
pub struct WideNode {
    /// Smallest x of each child's box.
    pub min_x: [f32; 4],
    /// Smallest y of each child's box.
    pub min_y: [f32; 4],
    /// Smallest z of each child's box.
    pub min_z: [f32; 4],
    /// Largest x of each child's box.
    pub max_x: [f32; 4],
    /// Largest y of each child's box.
    pub max_y: [f32; 4],
    /// Largest z of each child's box.
    pub max_z: [f32; 4],
    /// Inner child: index of its wide node. Leaf child: its first primitive
    /// slot, or for a tree of triangles its first triangle packet.
    children: [u32; 4],
    /// `LEAF | count` for a leaf child; for an inner child, 1 + the index of
    /// the first triangle packet of that node's leaf lanes, or 0.
    counts: [u32; 4],
}

// PERF: exactly two cache lines; a change of layout must be measured.
const _: () = assert!(std::mem::size_of::<WideNode>() == 128 && std::mem::align_of::<WideNode>() == 64);

/// What one lane of a [`WideNode`] holds ([`WideTree::child`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WideChild {
    /// No child in this lane.
    Empty,
    /// The wide node of that index.
    Inner(usize),
    /// The primitives of these leaf-order slots.
    Leaf(std::ops::Range<usize>),
}

impl WideNode {
    /// A node whose four lanes are empty.
    pub(crate) const EMPTY: Self = Self {
        min_x: [f32::INFINITY; 4],
        min_y: [f32::INFINITY; 4],
        min_z: [f32::INFINITY; 4],
        max_x: [f32::NEG_INFINITY; 4],
        max_y: [f32::NEG_INFINITY; 4],
        max_z: [f32::NEG_INFINITY; 4],
        children: [0; 4],
        counts: [LEAF; 4],
    };

    /// The box of lane `lane` (empty for an empty lane).
    pub fn child_bounds(&self, lane: usize) -> Aabb {
        Aabb::new(
            Vec3::new(self.min_x[lane], self.min_y[lane], self.min_z[lane]),
            Vec3::new(self.max_x[lane], self.max_y[lane], self.max_z[lane]),
        )
    }

    pub(crate) fn set_child(&mut self, lane: usize, bounds: Aabb, child: u32, leaf_count: Option<u32>) {
        self.min_x[lane] = bounds.min.x;
        self.min_y[lane] = bounds.min.y;
        self.min_z[lane] = bounds.min.z;
        self.max_x[lane] = bounds.max.x;
        self.max_y[lane] = bounds.max.y;
        self.max_z[lane] = bounds.max.z;
        self.children[lane] = child;
        self.counts[lane] = match leaf_count {
            Some(n) => {
                assert!(n > 0 && n < LEAF, "leaf of {n} primitives");
                LEAF | n
            }
            None => 0,
        };
    }

    /// Records in inner lane `lane` the first packet of its node's leaf lanes.
    pub(crate) fn set_packet_hint(&mut self, lane: usize, packet: u32) {
        assert!(self.counts[lane] == 0 && packet < LEAF - 1);
        self.counts[lane] = packet + 1;
    }

    /// Squared distances from the query (splatted per axis) to the four child
    /// boxes, 0 inside; an empty lane gives `+inf`. Same formula as
    /// [`Node::distance_squared`](super::Node::distance_squared), up to the
    /// order of the final sum, which `PRUNE_SLACK` (1 + 1e-6) absorbs.
    #[inline(always)]
    pub(crate) fn distances_squared(&self, px: f32x4, py: f32x4, pz: f32x4) -> f32x4 {
        let zero = f32x4::ZERO;
        let dx = (f32x4::new(self.min_x) - px)
            .fast_max(px - f32x4::new(self.max_x))
            .fast_max(zero);
        let dy = (f32x4::new(self.min_y) - py)
            .fast_max(py - f32x4::new(self.max_y))
            .fast_max(zero);
        let dz = (f32x4::new(self.min_z) - pz)
            .fast_max(pz - f32x4::new(self.max_z))
            .fast_max(zero);
        dx * dx + dy * dy + dz * dz
    }
}

/// A 4-wide bounding volume hierarchy, made from an [`AabbTree`] (see the
/// module documentation). It keeps the binary tree, whose primitives, input
/// indices and sources its leaves refer to.
///
/// ```
/// use proxima::prelude::*;
/// let points = (0..100).map(|i| Point(Vec3::new(i as f32, 0.0, 0.0))).collect();
/// let tree = AabbTree::build(points, &Default::default()).unwrap();
/// let wide = WideTree::from_tree(tree);
/// let hit = wide.closest(Vec3::new(41.8, 1.0, 0.0)).unwrap();
/// assert_eq!(hit.primitive, 42);
/// assert_eq!(Some(hit), wide.tree().closest(Vec3::new(41.8, 1.0, 0.0)));
/// ```
#[derive(Clone, Debug)]
pub struct WideTree<T> {
    /// The binary tree the wide one was made from; owns the primitives.
    tree: AabbTree<T>,
    /// Wide nodes; node 0 is the root. Empty for an empty tree. On huge
    /// pages when large: a query's node loads are mostly cache misses.
    nodes: HugePageArray<WideNode>,
    /// Triangles of the leaves, four at a time, for trees of [`Triangle`](crate::Triangle)s on
    /// x86-64 (empty otherwise: leaves are then tested one primitive at a time).
    packets: HugePageArray<TrianglePacket>,
    /// Depth of the deepest wide node (the root has depth 0).
    depth: u32,
    /// Present when leaves are tested two packets at a time with AVX2.
    avx2: Option<crate::simd::Avx2>,
    /// How far outside its triangle's box a computed closest point may lie:
    /// 16 ulps of the largest coordinate of the tree (twice the slack of
    /// the node boxes' widening). A pair of triangle packets is skipped only
    /// when every triangle's box lies farther than the search radius plus
    /// this, and than that times `1 + 1e-4` in squared distance, which
    /// covers the rounding that grows with the distance itself.
    cull_slack: f32,
}

impl<T> WideTree<T> {
    /// The binary tree this one was made from.
    pub fn tree(&self) -> &AabbTree<T> {
        &self.tree
    }

    /// Gives the binary tree back.
    pub fn into_tree(self) -> AabbTree<T> {
        self.tree
    }

    /// The wide nodes, root first (empty for an empty tree).
    pub fn nodes(&self) -> &[WideNode] {
        &self.nodes
    }

    /// What lane `lane` of wide node `node` holds.
    pub fn child(&self, node: usize, lane: usize) -> WideChild {
        let n = &self.nodes[node];
        let (child, count) = (n.children[lane] as usize, n.counts[lane]);
        match count {
            _ if count & LEAF == 0 => WideChild::Inner(child),
            LEAF => WideChild::Empty,
            _ => {
                let first = match self.packets.get(child) {
                    Some(packet) => packet.first as usize,
                    None => child,
                };
                WideChild::Leaf(first..first + (count & !LEAF) as usize)
            }
        }
    }

    /// `true` when leaf triangles are tested four at a time (trees of
    /// [`Triangle`](crate::Triangle)s on x86-64).
    pub fn has_triangle_packets(&self) -> bool {
        !self.packets.is_empty()
    }

    /// Whether leaf triangles are tested eight at a time with AVX2 (trees of
    /// triangles, on x86-64 CPUs that have it); otherwise four at a time.
    /// The answers are the same either way.
    pub fn uses_avx2(&self) -> bool {
        self.avx2.is_some() && self.has_triangle_packets()
    }

    /// Turns the AVX2 leaf test off, or back on where the CPU has AVX2 (it
    /// is on by default), to compare the two; answers are identical. The
    /// leaves stay as they were made (see [`from_tree_portable`](Self::from_tree_portable)).
    pub fn set_avx2(&mut self, enabled: bool) {
        self.avx2 = if enabled { crate::simd::detect_avx2() } else { None };
    }

    /// Bytes of the wide nodes and triangle packets, on top of the binary
    /// tree's (see [`AabbTree::stats`]).
    pub fn extra_memory_bytes(&self) -> usize {
        std::mem::size_of_val(&self.nodes[..]) + std::mem::size_of_val(&self.packets[..])
    }

    /// Number of wide nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the deepest wide node (0 when the root is the only one).
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.tree.len()
    }

    /// `true` when the tree holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.tree.is_empty()
    }
}

impl<T: WidePrimitive> From<AabbTree<T>> for WideTree<T> {
    fn from(tree: AabbTree<T>) -> Self {
        Self::from_tree(tree)
    }
}

impl<T> SpatialIndex<T> for WideTree<T> {
    #[inline(always)]
    fn leaves(&self) -> &Leaves<T> {
        self.tree.leaves()
    }
    fn bounds(&self) -> Aabb {
        self.tree.bounds()
    }
}

/// The binary tree's frustum walk: a frustum query visits whole subtrees
/// at once, which four-wide nodes do not speed up.
impl<T: FrustumOverlap> FrustumQuery<T> for WideTree<T> {
    fn frustum_walk<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        self.tree.frustum_walk(frustum, out, counter);
    }
}
