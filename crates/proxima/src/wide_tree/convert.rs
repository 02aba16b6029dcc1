//! Collapsing a binary [`AabbTree`] into a [`WideTree`].

use super::{WideNode, WidePrimitive, WideTree};
use crate::aabb::Aabb;
use crate::aabb_tree::AabbTree;
use crate::build::BuildConfig;
use crate::error::BuildError;
use crate::math::Vec3;
use crate::memory::{HugePageArray, HugePageVec, prefetch};
use crate::primitive::{Bounded, PrimitiveSet, Triangle};
use crate::query::SpatialIndex;
use crate::simd::{Avx2, TrianglePacket, detect_avx2};
use std::ops::Range;

/// The range of leaf-order slots below each binary node (a subtree covers
/// a contiguous range: its leftmost leaf's start to its rightmost leaf's
/// end), by node index, in one backward pass: children follow their parent
/// in the node array: cheaper than walking down a subtree's two edges each
/// time a node is considered (docs/perf-log.md).
pub(crate) fn subtree_ranges<T>(tree: &AabbTree<T>) -> Vec<Range<u32>> {
    // Index 1 is unused (the root has no sibling), so indices reach `node_count`.
    let mut ranges = vec![0..0; tree.node_count() + 1];
    for index in (0..ranges.len()).rev() {
        if index == 1 {
            continue;
        }
        let node = tree.node(index);
        ranges[index] = if node.is_leaf() {
            let range = node.primitive_range();
            range.start as u32..range.end as u32
        } else {
            let [left, right] = node.children();
            ranges[left as usize].start..ranges[right as usize].end
        };
    }
    ranges
}

/// The primitives a binary node stands for when it becomes a leaf of the
/// wide tree: a binary leaf's, or all those below an inner node that has at
/// most `max_leaf` of them. `None` for an inner node with more.
fn wide_leaf<T>(tree: &AabbTree<T>, ranges: &[Range<u32>], index: usize, max_leaf: usize) -> Option<Range<usize>> {
    let range = ranges[index].start as usize..ranges[index].end as usize;
    (tree.node(index).is_leaf() || range.len() <= max_leaf).then_some(range)
}

/// How likely a point query is to enter box `b`: the volume of `b` grown by
/// `grow` on every side. A point lies within distance `r` of a box when it
/// lies in the box grown by `r` (rounded corners aside), so for queries
/// spread through space that volume is the chance of entering it; `grow`
/// keeps flat boxes, whose own volume is zero, ordered by their area.
fn reach_volume(b: &Aabb, grow: f32) -> f32 {
    let size = b.size() + Vec3::splat(2.0 * grow);
    size.x * size.y * size.z
}

/// Up to four binary nodes that become the children of one wide node: the two
/// children of binary node `index`, then, while there are fewer than four,
/// the inner candidate a query most likely enters ([`reach_volume`]) is
/// replaced by its two children: opening those first saves the most node
/// visits. Nodes that become wide leaves ([`wide_leaf`]) are not opened.
///
/// The volume grown by `grow` (a thousandth of the root box's diagonal) is
/// preferred to the surface area, the measure for rays: it gave fewer wide
/// nodes and fewer node visits, for point queries and for rays alike
/// (counts in docs/perf-log.md).
fn collapse<T>(
    tree: &AabbTree<T>,
    ranges: &[Range<u32>],
    index: usize,
    max_leaf: usize,
    grow: f32,
) -> ([usize; 4], usize) {
    open_largest(tree, index, |c| {
        wide_leaf(tree, ranges, c, max_leaf)
            .is_none()
            .then(|| reach_volume(&tree.node(c).bounds(), grow))
    })
}

/// Up to `W` binary nodes that become the children of one node of a wide
/// tree: the two children of binary node `index`, then, while there are
/// fewer than `W`, the candidate of largest `measure` is replaced by its two
/// children (`measure` is `None` for a node not to be opened: one that
/// becomes a leaf). Ties go to the first lane.
pub(crate) fn open_largest<T, const W: usize>(
    tree: &AabbTree<T>,
    index: usize,
    measure: impl Fn(usize) -> Option<f32>,
) -> ([usize; W], usize) {
    let mut lanes = [0usize; W];
    let [a, b] = tree.node(index).children();
    lanes[0] = a as usize;
    lanes[1] = b as usize;
    let mut n = 2;
    while n < W {
        let largest = lanes[..n]
            .iter()
            .enumerate()
            .filter_map(|(lane, &c)| measure(c).map(|m| (lane, m)))
            .fold(None, |best: Option<(usize, f32)>, (lane, m)| match best {
                Some((_, v)) if v >= m => best,
                _ => Some((lane, m)),
            });
        let Some((lane, _)) = largest else { break };
        let [left, right] = tree.node(lanes[lane]).children();
        lanes[lane] = left as usize;
        lanes[n] = right as usize;
        n += 1;
    }
    (lanes, n)
}

/// Binary subtrees of at most this many triangles become one leaf of the
/// wide tree when leaves are tested with AVX2: two packets tested at once
/// cost about what one did (without AVX2, larger leaves are slower; see
/// docs/perf-log.md).
const WIDE_LEAF_AVX2: usize = 8;

/// The most primitives of a binary subtree that the collapse merges into
/// one wide leaf: eight triangles (two packets) where AVX2 tests them at
/// once (one level less, and the leaf test costs about what four did);
/// otherwise 1, which keeps the binary leaves as they are.
fn merged_leaf<T: WidePrimitive>(avx2: Option<Avx2>) -> usize {
    if T::PACKED && avx2.is_some() { WIDE_LEAF_AVX2 } else { 1 }
}

/// The leaves' triangles as packets of four, when the primitives are
/// packed ([`WidePrimitive`]).
struct Packer<'a> {
    triangles: Option<&'a [Triangle]>,
    indices: &'a [u32],
    /// Each leaf's slots, in the order of its packets, packed by
    /// [`finish`](Self::finish).
    leaves: Vec<Range<u32>>,
    /// Packets of the leaves so far.
    count: usize,
    packets: HugePageVec<TrianglePacket>,
}

/// How many leaves past the one being packed ([`Packer::finish`]) the
/// triangles are prefetched, so that their misses overlap with the packing
/// (docs/perf-log.md).
const PACK_AHEAD: usize = 8;

impl<'a> Packer<'a> {
    fn new<T: WidePrimitive>(tree: &'a AabbTree<T>) -> Self {
        let triangles = T::as_triangles(tree.primitives());
        // Reserved in place, in the mapping advised for huge pages once
        // written: growing by doubling, or copying into the mapping
        // afterwards, would copy tens of megabytes. A leaf
        // of `k` triangles takes `ceil(k / 4)` packets, at most `1 + k / 4`,
        // and a wide leaf merged from several binary leaves no more than
        // they would: so one packet per binary leaf (half the nodes, the tree
        // being full) and one per four triangles. Pages reserved beyond those
        // written are never touched, so the bound costs nothing, while
        // counting the packets exactly would take a pass over the nodes
        // (measured slower: docs/perf-log.md).
        let packets = triangles.map_or(0, |t| tree.node_count().div_ceil(2) + t.len() / 4);
        let packets = HugePageVec::with_capacity(packets);
        Self {
            triangles,
            indices: tree.leaves().indices(),
            // At most one leaf per binary leaf.
            leaves: Vec::with_capacity(triangles.map_or(0, |_| tree.node_count().div_ceil(2))),
            count: 0,
            packets,
        }
    }

    /// What a leaf lane refers to: its first packet (the leaf is packed
    /// later, by [`finish`](Self::finish)), or its first slot.
    fn leaf(&mut self, range: Range<usize>) -> u32 {
        if self.triangles.is_none() {
            return range.start as u32;
        }
        let index = self.count as u32;
        self.count += range.len().div_ceil(4);
        self.leaves.push(range.start as u32..range.end as u32);
        index
    }

    /// The packets of every leaf, in the order the leaves were given. The
    /// collapse meets the leaves in depth-first order, which jumps about
    /// the leaf-order triangle array; here the triangles of the leaf
    /// [`PACK_AHEAD`] places on are asked for while this one is packed.
    fn finish(self) -> HugePageArray<TrianglePacket> {
        let Self {
            triangles,
            indices,
            leaves,
            mut packets,
            ..
        } = self;
        if let Some(triangles) = triangles {
            for (k, leaf) in leaves.iter().enumerate() {
                if let Some(next) = leaves.get(k + PACK_AHEAD) {
                    let next = next.start as usize..next.end as usize;
                    // Every other triangle (72 bytes apart) reaches all but
                    // about one in nine of the leaf's lines; the variant measured.
                    for triangle in triangles[next.clone()].iter().step_by(2) {
                        prefetch(triangle);
                    }
                    prefetch(&indices[next.start]);
                }
                let (start, end) = (leaf.start as usize, leaf.end as usize);
                for first in (start..end).step_by(4) {
                    let last = (first + 4).min(end);
                    packets.push(TrianglePacket::new(
                        &triangles[first..last],
                        &indices[first..last],
                        first as u32,
                    ));
                }
            }
        }
        packets.finish()
    }
}

/// [`WideTree::cull_slack`] for `tree`: 16 ulps of its largest coordinate.
pub(super) fn cull_slack<T>(tree: &AabbTree<T>) -> f32 {
    tree.root().map_or(0.0, |root| {
        let b = root.bounds();
        16.0 * f32::EPSILON * b.min.abs().max(b.max.abs()).max_element()
    })
}

impl<T: WidePrimitive> WideTree<T> {
    /// Collapses the binary tree into wide nodes; the binary tree is kept and
    /// its primitives are shared, not copied. Linear in the number of nodes.
    ///
    /// For [`Triangle`]s (on x86-64) the leaves' triangles are also copied into
    /// packets of four, tested at once with the same results as one by one.
    /// Where the CPU has AVX2, binary subtrees of at most eight triangles
    /// become one wide leaf, whose two packets are tested at once.
    pub fn from_tree(tree: AabbTree<T>) -> Self {
        Self::collapse(tree, detect_avx2())
    }

    /// [`from_tree`](Self::from_tree) as on a CPU without AVX2: the binary
    /// tree's leaves, four triangles tested at a time. The answers are the
    /// same; this is for comparing the two, and for testing both here.
    pub fn from_tree_portable(tree: AabbTree<T>) -> Self {
        Self::collapse(tree, None)
    }

    fn collapse(tree: AabbTree<T>, avx2: Option<Avx2>) -> Self {
        // Each wide node stands for a distinct inner binary node, so there
        // are at most as many as those: (nodes + 1) / 2 of a full binary tree.
        let mut nodes = HugePageVec::with_capacity(tree.node_count().div_ceil(2));
        let mut depth = 0;
        let mut packer = Packer::new(&tree);
        let max_leaf = merged_leaf::<T>(avx2);
        if let Some(root) = tree.root() {
            nodes.push(WideNode::EMPTY);
            if root.is_leaf() {
                let range = root.primitive_range();
                let first = packer.leaf(range.clone());
                nodes.as_mut_slice()[0].set_child(0, root.bounds(), first, Some(range.len() as u32));
            } else {
                // (wide node to fill, binary node it stands for, its depth,
                // the parent's wide node and lane)
                let ranges = subtree_ranges(&tree);
                let grow = 1e-3 * root.bounds().diagonal();
                let mut work = vec![(0usize, 0usize, 0u32, None)];
                while let Some((wide, binary, d, parent)) = work.pop() {
                    depth = depth.max(d);
                    let (lanes, n) = collapse(&tree, &ranges, binary, max_leaf, grow);
                    let first_packet = packer.count as u32;
                    for (lane, &child) in lanes[..n].iter().enumerate() {
                        let node = tree.node(child);
                        if let Some(range) = wide_leaf(&tree, &ranges, child, max_leaf) {
                            let first = packer.leaf(range.clone());
                            nodes.as_mut_slice()[wide].set_child(lane, node.bounds(), first, Some(range.len() as u32));
                        } else {
                            let index = nodes.len();
                            nodes.push(WideNode::EMPTY);
                            nodes.as_mut_slice()[wide].set_child(lane, node.bounds(), index as u32, None);
                            work.push((index, child, d + 1, Some((wide, lane))));
                        }
                    }
                    if let Some((parent, lane)) = parent
                        && packer.count as u32 > first_packet
                    {
                        nodes.as_mut_slice()[parent].set_packet_hint(lane, first_packet);
                    }
                }
            }
        }
        let packets = packer.finish();
        let cull_slack = cull_slack(&tree);
        Self {
            tree,
            nodes: nodes.finish(),
            packets,
            depth,
            avx2,
            cull_slack,
        }
    }
}

impl<T: Bounded + WidePrimitive + Copy + Send + Sync> WideTree<T> {
    /// Builds the binary tree ([`AabbTree::build_set`]) and collapses it
    /// ([`from_tree`](Self::from_tree)).
    ///
    /// Where the collapse merges binary subtrees of up to eight triangles
    /// into one wide leaf (triangles, with AVX2), the binary tree is built
    /// with leaves of up to eight (`min_size` at least 8): splitting such
    /// nodes further would only make nodes the collapse then merges. The
    /// wide tree is the same as from the binary tree of `config`: the same
    /// wide nodes and leaves, each leaf with the same triangles, whose order
    /// within the leaf the paired test does not see, built faster.
    pub fn build_set(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        config.validate()?;
        let avx2 = detect_avx2();
        let merged = merged_leaf::<T>(avx2) as u32;
        let config = BuildConfig {
            min_size: config.min_size.max(merged),
            ..*config
        };
        AabbTree::build_set(set, &config).map(|tree| Self::collapse(tree, avx2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wide_tree::{LEAF, packet_hint};

    /// Each node's range is the span of the leaves found below it by a
    /// depth-first walk, and holds exactly their primitives.
    #[test]
    fn subtree_ranges_span_the_leaves_below() {
        for (n, min_size) in [(1, 4), (3000, 4), (3000, 1), (777, 3)] {
            let tree = AabbTree::build(
                crate::sample::small_triangles(n, 12),
                &BuildConfig {
                    min_size,
                    ..Default::default()
                },
            )
            .unwrap();
            let ranges = subtree_ranges(&tree);
            for (index, _) in tree.nodes() {
                let (mut start, mut end, mut count) = (usize::MAX, 0, 0);
                let mut stack = vec![index];
                while let Some(i) = stack.pop() {
                    let node = tree.node(i);
                    if node.is_leaf() {
                        let r = node.primitive_range();
                        (start, end, count) = (start.min(r.start), end.max(r.end), count + r.len());
                    } else {
                        stack.extend(node.children().map(|c| c as usize));
                    }
                }
                assert_eq!(ranges[index], start as u32..end as u32, "node {index}");
                assert_eq!(count, end - start);
            }
        }
    }

    /// The wide tree that `build_set` makes from leaves of up to eight
    /// equals the one collapsed from the tree of the configuration as given:
    /// lane for lane the same kind, inner lanes the same node, leaves the
    /// same triangles, and boxes that differ only by the widening of a leaf
    /// box against the union of its binary children's widened boxes.
    #[test]
    fn merged_leaves_make_the_same_wide_tree() {
        use crate::build::SplitMethod;
        use crate::wide_tree::WideChild;
        for (n, seed) in [(1, 1), (9, 2), (3000, 3), (20_000, 4)] {
            let triangles = crate::sample::small_triangles(n, seed);
            for (min_size, split) in [
                (1, SplitMethod::Median),
                (4, SplitMethod::Median),
                (6, SplitMethod::BinnedSah),
            ] {
                let config = BuildConfig {
                    min_size,
                    split,
                    ..Default::default()
                };
                let set = PrimitiveSet {
                    primitives: triangles.clone(),
                    sources: (0..n as u32).collect(),
                };
                let merged = WideTree::build_set(set, &config).unwrap();
                let given = WideTree::from_tree(AabbTree::build(triangles.clone(), &config).unwrap());
                assert_eq!(merged.node_count(), given.node_count(), "{n} {config:?}");
                // Where leaves are merged, the binary tree behind them stops earlier.
                if detect_avx2().is_some() && min_size < 8 && n > 16 {
                    assert!(merged.tree().node_count() < given.tree().node_count());
                }
                let leaf = |tree: &WideTree<Triangle>, range: Range<usize>| {
                    let mut indices = tree.leaves().indices()[range].to_vec();
                    indices.sort_unstable();
                    indices
                };
                for node in 0..merged.node_count() {
                    for lane in 0..4 {
                        match (merged.child(node, lane), given.child(node, lane)) {
                            (WideChild::Leaf(a), WideChild::Leaf(b)) => assert_eq!(leaf(&merged, a), leaf(&given, b)),
                            (a, b) => assert_eq!(a, b, "{n} {config:?} node {node} lane {lane}"),
                        }
                        let (a, b) = (
                            merged.nodes()[node].child_bounds(lane),
                            given.nodes()[node].child_bounds(lane),
                        );
                        // The merged box holds the given one, a few ulps of
                        // the coordinates' size larger at most.
                        let slack = 1e-6 * a.min.abs().max(a.max.abs()).max_element();
                        assert!(a.contains(&b) || b.is_empty(), "{a:?} {b:?}");
                        assert!(
                            (a.min - b.min).abs().max((a.max - b.max).abs()).max_element() <= slack || b.is_empty()
                        );
                    }
                }
            }
        }
    }

    /// Fat boxes are ordered by volume, flat ones by area, and a box that
    /// holds another measures at least as much.
    #[test]
    fn reach_volume_orders_fat_and_flat_boxes() {
        let cube = |size: Vec3| Aabb::new(Vec3::ZERO, size);
        let grow = 1e-3;
        assert!(reach_volume(&cube(Vec3::splat(2.0)), grow) > reach_volume(&cube(Vec3::new(8.0, 8.0, 0.1)), grow));
        assert!(
            reach_volume(&cube(Vec3::new(3.0, 3.0, 0.0)), grow) > reach_volume(&cube(Vec3::new(2.0, 4.0, 0.0)), grow)
        );
        assert!(
            reach_volume(&cube(Vec3::new(1.0, 0.0, 0.0)), grow) > reach_volume(&cube(Vec3::new(0.5, 0.0, 0.0)), grow)
        );
        assert!(reach_volume(&cube(Vec3::ZERO), grow) > 0.0);
        let mut rng = crate::sample::Rng::new(5);
        for _ in 0..1000 {
            let outer = Vec3::new(rng.range(0.0, 2.0), rng.range(0.0, 2.0), rng.range(0.0, 2.0));
            let inner = outer * Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            assert!(reach_volume(&cube(outer), grow) >= reach_volume(&cube(inner), grow));
        }
    }

    /// Every inner lane points to the first packet of its node's own leaf
    /// lanes (the one a walk prefetches with the node), or to none when that
    /// node has no leaf lane; with and without AVX2's merged leaves.
    #[test]
    fn inner_lanes_point_to_their_nodes_first_packet() {
        let triangles = crate::sample::small_triangles(3000, 11);
        for config in [
            BuildConfig::default(),
            BuildConfig {
                min_size: 1,
                ..Default::default()
            },
        ] {
            let tree = AabbTree::build(triangles.clone(), &config).unwrap();
            for wide in [WideTree::from_tree(tree.clone()), WideTree::from_tree_portable(tree)] {
                assert!(wide.has_triangle_packets());
                let mut inner_lanes = 0;
                for node in wide.nodes.iter() {
                    for lane in 0..4 {
                        let (child, count) = (node.children[lane] as usize, node.counts[lane]);
                        if count & LEAF != 0 {
                            continue;
                        }
                        inner_lanes += 1;
                        let target = &wide.nodes[child];
                        let first = (0..4)
                            .filter(|&l| target.counts[l] & LEAF != 0 && target.counts[l] != LEAF)
                            .map(|l| target.children[l] as usize)
                            .min();
                        match first {
                            Some(first) => assert_eq!(packet_hint(count), first),
                            None => assert_eq!(count, 0),
                        }
                    }
                }
                assert!(inner_lanes > 100);
            }
        }
    }
}
