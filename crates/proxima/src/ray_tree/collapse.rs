//! Collapsing a binary [`AabbTree`] of triangles into a [`RayTree`].

use super::{LEAF, PACKET_INDEX, PAIR, RayNode, RayTree, WIDTH};
use crate::aabb::Aabb;
use crate::aabb_tree::AabbTree;
// Boxes widened as the binary build widens its node boxes (the per-ray
// widening of the slab test assumes boxes at least that wide).
use crate::build::widen;
use crate::memory::HugePageVec;
use crate::primitive::{Bounded, Triangle};
use crate::query::SpatialIndex;
use crate::simd::{Avx2, TrianglePacket};
use crate::wide_tree::{open_largest, subtree_ranges};
use std::ops::Range;

/// Triangles in one packet.
const PACKET: usize = 4;

/// Triangles in one leaf at most: two packets.
const LEAF_TRIANGLES: usize = 2 * PACKET;

/// The slots of binary node `index` when it becomes a leaf: a binary leaf,
/// or an inner node of at most eight triangles, which one AVX2 test takes
/// at once: a level less on each ray's path, for about the cost of testing
/// four.
fn leaf_slots(tree: &AabbTree<Triangle>, ranges: &[Range<u32>], index: usize) -> Option<Range<usize>> {
    let range = ranges[index].start as usize..ranges[index].end as usize;
    (tree.node(index).is_leaf() || range.len() <= LEAF_TRIANGLES).then_some(range)
}

/// Up to eight binary nodes that become the children of one node: the two
/// children of binary node `index`, then, while there are fewer than eight,
/// the inner candidate of largest surface area (the one a ray most likely
/// enters) is replaced by its two children.
fn open(tree: &AabbTree<Triangle>, ranges: &[Range<u32>], index: usize) -> ([usize; WIDTH], usize) {
    open_largest(tree, index, |c| {
        leaf_slots(tree, ranges, c)
            .is_none()
            .then(|| tree.node(c).bounds().surface_area())
    })
}

/// Nodes and packets as they are made.
struct Builder<'a> {
    triangles: &'a [Triangle],
    indices: &'a [u32],
    nodes: HugePageVec<RayNode>,
    packets: HugePageVec<TrianglePacket>,
    depth: u32,
}

impl Builder<'_> {
    fn push_node(&mut self) -> u32 {
        self.nodes.push(RayNode::EMPTY);
        (self.nodes.len() - 1) as u32
    }

    /// A lane's reference to the triangles of `slots`: one packet or two
    /// when they fit, else a node (or tree of nodes) of leaves, `depth`
    /// being the depth of the node that refers to them.
    fn leaf(&mut self, slots: Range<usize>, depth: u32) -> u32 {
        if slots.len() <= LEAF_TRIANGLES {
            let index = self.packets.len() as u32;
            assert!(index < PACKET_INDEX, "more than 2^30 packets");
            for first in slots.clone().step_by(PACKET) {
                let part = first..(first + PACKET).min(slots.end);
                self.packets.push(TrianglePacket::new(
                    &self.triangles[part.clone()],
                    &self.indices[part],
                    first as u32,
                ));
            }
            return LEAF | if slots.len() > PACKET { PAIR } else { 0 } | index;
        }
        // Eight parts of whole leaves (the last may be short).
        let node = self.push_node();
        self.depth = self.depth.max(depth + 1);
        let leaves = slots.len().div_ceil(LEAF_TRIANGLES);
        let per_lane = leaves.div_ceil(WIDTH) * LEAF_TRIANGLES;
        for (lane, start) in (slots.start..slots.end).step_by(per_lane).enumerate() {
            let part = start..(start + per_lane).min(slots.end);
            let bounds = widen(
                self.triangles[part.clone()]
                    .iter()
                    .fold(Aabb::EMPTY, |b, t| b.merge(&t.bounds())),
            );
            let child = self.leaf(part, depth + 1);
            self.nodes.as_mut_slice()[node as usize].set_child(lane, bounds, child);
        }
        node
    }
}

/// The collapse of [`RayTree::from_tree`]: nodes in depth-first order,
/// each leaf's packet made when the leaf is met, so that a subtree's nodes
/// and packets lie close together.
pub(super) fn collapse(tree: AabbTree<Triangle>, avx2: Option<Avx2>) -> RayTree {
    let bounds = tree.bounds();
    let mut builder = Builder {
        triangles: tree.primitives(),
        indices: tree.leaves().indices(),
        // At most one node per inner binary node (leaves of more than eight
        // triangles, made only at the depth limit, add a few: past the
        // capacity a `HugePageVec` moves to the heap). A leaf of `k`
        // triangles takes `ceil(k / 4) <= 1 + k / 4` packets, and there are
        // no more leaves than binary leaves.
        nodes: HugePageVec::with_capacity(tree.node_count().div_ceil(2).max(1)),
        packets: HugePageVec::with_capacity(tree.node_count().div_ceil(2).max(1) + tree.len() / PACKET),
        depth: 0,
    };
    if let Some(root) = tree.root() {
        let root_node = builder.push_node();
        if root.is_leaf() {
            let child = builder.leaf(root.primitive_range(), 0);
            builder.nodes.as_mut_slice()[0].set_child(0, root.bounds(), child);
        } else {
            // (node to fill, binary node it stands for, its depth)
            let ranges = subtree_ranges(&tree);
            let mut work = vec![(root_node, 0usize, 0u32)];
            while let Some((node, binary, depth)) = work.pop() {
                builder.depth = builder.depth.max(depth);
                let (lanes, n) = open(&tree, &ranges, binary);
                // Pushed in reverse, so the first lane's subtree is made next.
                let mut inner = Vec::with_capacity(WIDTH);
                for (lane, &child) in lanes[..n].iter().enumerate() {
                    let binary_child = tree.node(child);
                    let reference = if let Some(slots) = leaf_slots(&tree, &ranges, child) {
                        builder.leaf(slots, depth)
                    } else {
                        let index = builder.push_node();
                        inner.push((index, child, depth + 1));
                        index
                    };
                    builder.nodes.as_mut_slice()[node as usize].set_child(lane, binary_child.bounds(), reference);
                }
                work.extend(inner.into_iter().rev());
            }
        }
    }
    let Builder {
        nodes, packets, depth, ..
    } = builder;
    assert!(depth <= super::walk::MAX_RAY_DEPTH, "ray tree of depth {depth}");
    RayTree {
        leaves: tree.into_leaves(),
        nodes: nodes.finish(),
        packets: packets.finish(),
        bounds,
        depth,
        avx2,
    }
}
