//! The one walk of the wide tree, behind its distance and ray queries.
//!
//! Depth-first, the child of smallest key first, with a fixed stack. At each
//! wide node the query computes its four child keys at once (squared box
//! distances, or ray entry parameters) and which lanes are within its bound;
//! the nearest is entered at once and the others are pushed farthest first
//! with their keys, to be dropped when popped if the bound has shrunk
//! meanwhile. Every child within reach is prefetched as soon as its node is
//! read, so that the cache misses of a step overlap; an inner child's leaf
//! packets are prefetched with it, a level ahead. On CPUs with AVX2 the
//! whole walk runs compiled for AVX2 ([`WideTree::walk`]).

use super::{LEAF, WideNode, WideTree};
use crate::build::MAX_DEPTH;
use crate::memory::prefetch;
use crate::query::Counter;
use std::ops::ControlFlow;
use wide::f32x4;

#[cfg(target_arch = "x86_64")]
use crate::simd::Avx2Task;
use crate::simd::{Avx2, TrianglePacket, prefetch_packet};

/// What the walk of the wide tree asks of the query it serves.
pub(crate) trait WideQuery<T> {
    /// The keys of the four child lanes of `node`, and the mask of the lanes
    /// within the query's [`bound`](Self::bound) (an empty lane never is).
    fn keys(&self, node: &WideNode) -> (f32x4, u32);
    /// Subtrees of larger key are skipped.
    fn bound(&self) -> f32;
    /// Bits of `key` that order keys as the keys do (for the branch-free
    /// sort of a node's lanes). Distances are never negative, so their bits
    /// already do.
    #[inline(always)]
    fn order_bits(key: f32) -> u32 {
        key.to_bits()
    }
    /// Tests the primitives of the leaf `leaf`; `Break` ends the walk.
    fn leaf<C: Counter>(&mut self, tree: &Slices<'_, T>, leaf: Pending, counter: &mut C) -> ControlFlow<()>;
}

/// A subtree waiting on the stack: a wide node (`count & LEAF == 0`) or a
/// leaf (`count == LEAF | n`), with its key.
#[derive(Clone, Copy)]
pub(crate) struct Pending {
    pub(crate) child: u32,
    pub(crate) count: u32,
    pub(crate) key: f32,
}

impl Pending {
    /// The root, entered unconditionally: its lanes are tested when entered.
    const ROOT: Self = Self {
        child: 0,
        count: 0,
        key: 0.0,
    };

    /// The leaf's number of primitives.
    #[inline(always)]
    pub(crate) fn leaf_len(&self) -> usize {
        (self.count & !LEAF) as usize
    }
}

/// Each wide node on the current path pushes at most three entries, and the
/// wide tree is no deeper than the binary one; [`SLACK`] more.
const STACK: usize = 3 * (MAX_DEPTH as usize + 1) + SLACK;

/// Wide trees less deep than this walk with a stack of [`SMALL_STACK`] entries.
const SHALLOW: u32 = 16;

/// Stack entries past the top that [`Slices::enter_node`] may scribble on:
/// it writes all three pushable lanes, whether or not it pushes them.
const SLACK: usize = 3;

/// The stack of trees less deep than [`SHALLOW`].
const SMALL_STACK: usize = 3 * SHALLOW as usize + SLACK;

/// Packets prefetched with a wide node, from the first of its leaf lanes'
/// (see docs/perf-log.md for the counts tried).
pub(crate) const PREFETCHED_PACKETS: usize = 4;

/// The arrays a walk reads, taken once per query: the node and packet
/// arrays may sit behind a [`HugePageArray`](crate::memory::HugePageArray),
/// whose dereference is cheap but not free.
pub(crate) struct Slices<'a, T> {
    pub(crate) nodes: &'a [WideNode],
    pub(crate) packets: &'a [TrianglePacket],
    pub(crate) primitives: &'a [T],
    /// [`WideTree::cull_slack`].
    pub(crate) cull_slack: f32,
}

impl<T> WideTree<T> {
    /// The arrays a walk reads.
    #[inline(always)]
    pub(crate) fn slices(&self) -> Slices<'_, T> {
        Slices {
            nodes: &self.nodes,
            packets: &self.packets,
            primitives: self.tree.primitives(),
            cull_slack: self.cull_slack,
        }
    }

    /// Walks the tree for `query` (see the module notes), compiled for AVX2
    /// where the tree tests its leaves with it. `make` builds the query,
    /// given the AVX2 token it may use.
    #[inline(always)]
    pub(crate) fn walk<Q: WideQuery<T>, C: Counter>(&self, make: impl FnOnce(Option<Avx2>) -> Q, counter: &mut C) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(WalkTask {
                slices: self.slices(),
                depth: self.depth,
                make,
                counter,
            });
        }
        let mut query = make(None);
        self.slices().walk(self.depth, &mut query, counter);
    }
}

/// [`Slices::walk`] as a task compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct WalkTask<'a, 'b, T, M, C> {
    slices: Slices<'a, T>,
    depth: u32,
    make: M,
    counter: &'b mut C,
}

#[cfg(target_arch = "x86_64")]
impl<T, Q: WideQuery<T>, M: FnOnce(Option<Avx2>) -> Q, C: Counter> Avx2Task for WalkTask<'_, '_, T, M, C> {
    type Output = ();
    #[inline(always)]
    fn call(self, avx2: Avx2) {
        let mut query = (self.make)(Some(avx2));
        self.slices.walk(self.depth, &mut query, self.counter);
    }
}

/// The pending subtrees of one walk: a fixed stack, no allocation.
#[derive(Clone, Copy)]
pub(crate) struct Stack<const N: usize = STACK> {
    entries: [Pending; N],
    top: usize,
}

impl<const N: usize> Stack<N> {
    pub(crate) const EMPTY: Self = Self {
        entries: [Pending::ROOT; N],
        top: 0,
    };

    /// The next pending subtree within `bound`, dropping those beyond it.
    #[inline(always)]
    fn pop_within(&mut self, bound: f32) -> Option<Pending> {
        while self.top > 0 {
            self.top -= 1;
            let next = self.entries[self.top];
            if next.key <= bound {
                return Some(next);
            }
        }
        None
    }
}

impl<T> Slices<'_, T> {
    /// Starts loading every child lane set in `mask` (node, triangle
    /// packet, or first and last primitive of a leaf), so that the cache
    /// misses overlap instead of following one another.
    #[inline(always)]
    fn prefetch_children(&self, node: &WideNode, mask: u32) {
        let primitives = self.primitives;
        let mut bits = mask;
        while bits != 0 {
            let lane = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let (c, k) = (node.children[lane] as usize, node.counts[lane]);
            if k & LEAF == 0 {
                let next = &self.nodes[c];
                prefetch(&next.min_x);
                prefetch(&next.max_y);
                // The triangles of that node's leaves, a level ahead: the
                // leaf it enters first would otherwise be a second miss
                // after the node itself.
                let packets = self.packets.get(super::packet_hint(k)..).unwrap_or(&[]);
                for packet in &packets[..packets.len().min(PREFETCHED_PACKETS)] {
                    prefetch_packet(packet);
                }
            } else if !self.packets.is_empty() {
                if let Some(packet) = self.packets.get(c) {
                    prefetch_packet(packet);
                }
            } else if k != LEAF {
                prefetch(&primitives[c]);
                prefetch(&primitives[c + (k & !LEAF) as usize - 1]);
            }
        }
    }

    /// Visits wide node `index`: its children within the query's bound are
    /// ordered by key, all but the nearest are pushed (farthest first) and
    /// the nearest is returned to be entered next. Without a branch on the
    /// keys, which a predictor cannot learn (docs/perf-log.md).
    #[inline(always)]
    fn enter_node<Q: WideQuery<T>, C: Counter, const N: usize>(
        &self,
        index: u32,
        query: &Q,
        stack: &mut Stack<N>,
        counter: &mut C,
    ) -> Option<Pending> {
        let node = &self.nodes[index as usize];
        counter.nodes(1);
        let (keys, mask) = query.keys(node);
        if mask == 0 {
            return None;
        }
        let d = keys.to_array();
        self.prefetch_children(node, mask);
        // One child within reach: it is entered at once, with nothing to
        // order or push (a frequent case near the surface: docs/perf-log.md).
        if mask & (mask - 1) == 0 {
            let lane = mask.trailing_zeros() as usize;
            return Some(Pending {
                child: node.children[lane],
                count: node.counts[lane],
                key: d[lane],
            });
        }
        // Nearest first without a branch: each lane's sort key is its key's
        // order bits, the lane below them to break ties as the lane order
        // does; lanes beyond the bound sort last. A sorting network of five
        // compare-exchanges orders them.
        let mut order: [u64; 4] = std::array::from_fn(|lane| {
            let bits = if mask & (1 << lane) != 0 {
                Q::order_bits(d[lane])
            } else {
                u32::MAX
            };
            (u64::from(bits) << 2) | lane as u64
        });
        for (i, j) in [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)] {
            let (a, b) = (order[i], order[j]);
            (order[i], order[j]) = (a.min(b), a.max(b));
        }
        // The `n - 1` farthest are pushed, farthest first; the writes past
        // them land beyond the new top, in the stack's slack.
        let n = mask.count_ones() as usize;
        for (i, entry) in stack.entries[stack.top..stack.top + SLACK].iter_mut().enumerate() {
            let lane = (order[n.wrapping_sub(1 + i) & 3] & 3) as usize;
            *entry = Pending {
                child: node.children[lane],
                count: node.counts[lane],
                key: d[lane],
            };
        }
        stack.top += n - 1;
        let nearest = (order[0] & 3) as usize;
        Some(Pending {
            child: node.children[nearest],
            count: node.counts[nearest],
            key: d[nearest],
        })
    }

    /// [`WideTree::walk`] on these arrays. Each wide node on the current
    /// path has at most three children waiting, so a tree of depth `d`
    /// needs `3 (d + 1)` stack entries: shallow trees (all but those of
    /// extreme meshes) get a small stack, whose initialization costs far
    /// less than the full one's.
    #[inline(always)]
    pub(crate) fn walk<Q: WideQuery<T>, C: Counter>(&self, depth: u32, query: &mut Q, counter: &mut C) {
        if depth < SHALLOW {
            self.walk_with::<Q, C, SMALL_STACK>(query, counter);
        } else {
            self.walk_with::<Q, C, STACK>(query, counter);
        }
    }

    #[inline(always)]
    fn walk_with<Q: WideQuery<T>, C: Counter, const N: usize>(&self, query: &mut Q, counter: &mut C) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = Stack::<N>::EMPTY;
        let mut next = Some(Pending::ROOT);
        while let Some(pending) = next {
            next = if pending.count & LEAF == 0 {
                self.enter_node(pending.child, query, &mut stack, counter)
            } else {
                if query.leaf(self, pending, counter).is_break() {
                    return;
                }
                None
            }
            .or_else(|| stack.pop_within(query.bound()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3A;
    use crate::query::{Best, QueryStats, SpatialIndex};
    use crate::wide_tree::nearest::Nearest;
    use crate::{AabbTree, BuildConfig, Vec3};

    /// The small stack and the full one make the same walk; real trees are
    /// too shallow to reach the full one, so it is tested directly.
    #[test]
    fn small_and_full_stacks_walk_alike() {
        let triangles = crate::sample::small_triangles(5000, 5);
        let mut rng = crate::sample::Rng::new(105);
        let mut v = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let tree = AabbTree::build(triangles, &BuildConfig::default()).unwrap();
        let wide = WideTree::from_tree(tree);
        assert!(wide.depth() < SHALLOW);
        let slices = wide.slices();
        let indices = wide.leaves().indices();
        for _ in 0..500 {
            let p = Vec3A::from(v() * 1.5);
            let mut small = Best::new(indices, f32::INFINITY);
            let mut full = Best::new(indices, f32::INFINITY);
            let (mut small_stats, mut full_stats) = (QueryStats::default(), QueryStats::default());
            slices.walk_with::<_, _, SMALL_STACK>(&mut Nearest::new(p, wide.avx2, &mut small), &mut small_stats);
            slices.walk_with::<_, _, STACK>(&mut Nearest::new(p, wide.avx2, &mut full), &mut full_stats);
            assert!(small.found && full.found);
            assert_eq!(
                (small.slot, small.point, small.distance_squared),
                (full.slot, full.point, full.distance_squared)
            );
            assert_eq!(small_stats, full_stats);
        }
    }
}
