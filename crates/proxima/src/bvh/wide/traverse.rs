//! The nearest-first traversal of the wide tree, behind closest and k-nearest.

use super::packet::V3;
use super::{LEAF, WideTree};
use crate::bvh::config::MAX_DEPTH;
use crate::bvh::traverse::{Counter, DistanceVisitor};
use crate::math::Vec3A;
use wide::f32x4;

/// A [`DistanceVisitor`] that also takes candidates computed elsewhere (four
/// triangles at a time).
pub(crate) trait LaneVisitor<T>: DistanceVisitor<T> {
    /// Considers the point `q` at squared distance `d2` of the primitive at
    /// leaf-order slot `slot`, exactly as `visit` would have computed them.
    fn offer(&mut self, slot: usize, q: Vec3A, d2: f32);
}

/// A subtree waiting on the stack: a wide node (`count == 0`) or a leaf
/// (`count == LEAF | n`), with its box distance.
#[derive(Clone, Copy)]
struct Pending {
    child: u32,
    count: u32,
    distance_squared: f32,
}

/// Each wide node on the current path pushes at most three entries, and the
/// wide tree is no deeper than the binary one.
const STACK: usize = 3 * (MAX_DEPTH as usize + 1);

/// Wide trees less deep than this walk with a stack of `3 * SHALLOW` entries.
const SHALLOW: u32 = 16;

/// Asks for the cache line holding `x` without waiting for it.
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = x;
}

/// The arrays a walk reads, taken once per query: the node and packet
/// arrays may sit behind a [`HugePageArray`](crate::memory::HugePageArray),
/// whose dereference is cheap but not free.
pub(crate) struct Slices<'a, T> {
    pub(crate) nodes: &'a [super::WideNode],
    pub(crate) packets: &'a [super::packet::TrianglePacket],
    pub(crate) primitives: &'a [T],
}

impl<T> WideTree<T> {
    /// The arrays a walk reads.
    #[inline(always)]
    pub(crate) fn slices(&self) -> Slices<'_, T> {
        Slices {
            nodes: &self.nodes,
            packets: &self.packets,
            primitives: self.tree.primitives(),
        }
    }
}

impl<T> Slices<'_, T> {
    /// The child lanes set in `mask`, ordered by `keys` ascending (insertion
    /// sort of at most 4), and their count. Every child selected starts
    /// loading at once (node, triangle packet, or first and last primitive of
    /// a leaf), so that the cache misses overlap instead of following one
    /// another. Shared by the distance and the ray walks.
    #[inline(always)]
    pub(crate) fn lanes_nearest_first(
        &self,
        node: &super::WideNode,
        mask: u32,
        keys: &[f32; 4],
    ) -> ([usize; 4], usize) {
        let primitives = self.primitives;
        let mut order = [0usize; 4];
        let mut n = 0;
        let mut bits = mask;
        while bits != 0 {
            let lane = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let mut j = n;
            while j > 0 && keys[order[j - 1]] > keys[lane] {
                order[j] = order[j - 1];
                j -= 1;
            }
            order[j] = lane;
            n += 1;
            let (c, k) = (node.children[lane] as usize, node.counts[lane]);
            if k == 0 {
                let next = &self.nodes[c];
                prefetch(&next.min_x);
                prefetch(&next.max_y);
            } else if !self.packets.is_empty() {
                if let Some(packet) = self.packets.get(c) {
                    prefetch(packet);
                    prefetch(&packet.b);
                    prefetch(&packet.c);
                }
            } else if k != LEAF {
                prefetch(&primitives[c]);
                prefetch(&primitives[c + (k & !LEAF) as usize - 1]);
            }
        }
        (order, n)
    }
}

/// The query point, as a scalar vector and splatted per axis for the node
/// and packet arithmetic.
#[derive(Clone, Copy)]
pub(crate) struct Query {
    p: Vec3A,
    px: f32x4,
    py: f32x4,
    pz: f32x4,
    pv: V3,
}

impl Query {
    #[inline(always)]
    pub(crate) fn new(p: Vec3A) -> Self {
        Self {
            p,
            px: f32x4::splat(p.x),
            py: f32x4::splat(p.y),
            pz: f32x4::splat(p.z),
            pv: V3::splat(p),
        }
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
        entries: [Pending {
            child: 0,
            count: 0,
            distance_squared: 0.0,
        }; N],
        top: 0,
    };

    /// The next pending subtree still within `bound`, dropping those beyond it.
    #[inline(always)]
    fn pop_within(&mut self, bound: f32) -> Option<(u32, u32)> {
        while self.top > 0 {
            self.top -= 1;
            let next = self.entries[self.top];
            if next.distance_squared <= bound {
                return Some((next.child, next.count));
            }
        }
        None
    }
}

impl<T> Slices<'_, T> {
    /// Visits wide node `index`: its children within the visitor's bound are
    /// ordered by box distance, all but the nearest are pushed (farthest
    /// first) and the nearest is returned to be entered next.
    #[inline(always)]
    fn enter_node<V: LaneVisitor<T>, C: Counter, const N: usize>(
        &self,
        index: u32,
        q: &Query,
        visitor: &V,
        stack: &mut Stack<N>,
        counter: &mut C,
    ) -> Option<(u32, u32)> {
        let node = &self.nodes[index as usize];
        counter.nodes(1);
        let d2 = node.distances_squared(q.px, q.py, q.pz);
        let mask = d2.simd_le(f32x4::splat(visitor.bound())).to_bitmask();
        if mask == 0 {
            return None;
        }
        let d = d2.to_array();
        let (order, n) = self.lanes_nearest_first(node, mask, &d);
        for &lane in order[1..n].iter().rev() {
            stack.entries[stack.top] = Pending {
                child: node.children[lane],
                count: node.counts[lane],
                distance_squared: d[lane],
            };
            stack.top += 1;
        }
        Some((node.children[order[0]], node.counts[order[0]]))
    }

    /// Tests the primitives of a leaf lane (`count == LEAF | n`), four
    /// triangles at a time where the tree has packets.
    #[inline(always)]
    fn visit_leaf<V: LaneVisitor<T>, C: Counter>(
        &self,
        child: u32,
        count: u32,
        q: &Query,
        visitor: &mut V,
        counter: &mut C,
    ) {
        let (primitives, packets) = (self.primitives, self.packets);
        let n = (count & !LEAF) as usize;
        counter.primitives(n as u64);
        if packets.is_empty() {
            let first = child as usize;
            for (slot, primitive) in (first..).zip(&primitives[first..first + n]) {
                visitor.visit(slot, primitive, q.p);
            }
            return;
        }
        for packet in &packets[child as usize..child as usize + n.div_ceil(4)] {
            let (point, d2, far) = packet.closest(&q.pv);
            // Only lanes that can change the answer are offered.
            let mut bits = d2.simd_le(f32x4::splat(visitor.bound())).to_bitmask() & packet.fast & !far;
            while bits != 0 {
                let lane = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                visitor.offer(packet.first as usize + lane, point.lane(lane), d2.as_array()[lane]);
            }
            let mut slow = packet.slow | (packet.fast & far);
            while slow != 0 {
                let slot = packet.first as usize + slow.trailing_zeros() as usize;
                slow &= slow - 1;
                visitor.visit(slot, &primitives[slot], q.p);
            }
        }
    }
}

impl<T> WideTree<T> {
    /// Depth-first, nearest child first, with a fixed stack. At each wide
    /// node the four child box distances are computed at once; the children
    /// within the radius are ordered by distance, the nearest is entered at
    /// once and the others are pushed farthest first with their distances, to
    /// be dropped when popped if the radius has shrunk meanwhile.
    #[inline]
    pub(crate) fn nearest_first<V: LaneVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C) {
        self.slices().nearest_first(p, self.depth, visitor, counter);
    }
}

impl<T> Slices<'_, T> {
    /// [`WideTree::nearest_first`] on these arrays. Each wide node on the
    /// current path has at most three children waiting, so a tree of depth
    /// `d` needs `3 (d + 1)` stack entries: shallow trees (all but those of
    /// extreme meshes) get a small stack, whose initialization costs far less
    /// than the full one's (it was 13% of a query's instructions).
    #[inline(always)]
    fn nearest_first<V: LaneVisitor<T>, C: Counter>(&self, p: Vec3A, depth: u32, visitor: &mut V, counter: &mut C) {
        if depth < SHALLOW {
            self.nearest_first_with::<V, C, { 3 * SHALLOW as usize }>(p, visitor, counter);
        } else {
            self.nearest_first_with::<V, C, STACK>(p, visitor, counter);
        }
    }

    #[inline(always)]
    fn nearest_first_with<V: LaneVisitor<T>, C: Counter, const N: usize>(
        &self,
        p: Vec3A,
        visitor: &mut V,
        counter: &mut C,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let q = Query::new(p);
        let mut stack = Stack::<N>::EMPTY;
        // The root, entered unconditionally: its lanes are tested below.
        let mut next = Some((0u32, 0u32));
        while let Some((child, count)) = next {
            next = if count == 0 {
                self.enter_node(child, &q, visitor, &mut stack, counter)
            } else {
                self.visit_leaf(child, count, &q, visitor, counter);
                None
            }
            .or_else(|| stack.pop_within(visitor.bound()));
        }
    }
}

/// One nearest-first walk that can be advanced a step at a time, so that a
/// thread can interleave the walks of several queries: while one waits for
/// the node or triangles it just asked for, the others compute
/// ([`WideTree::step`]). Each walk makes exactly the visits
/// [`WideTree::nearest_first`] would, in the same order, so its answer is the same.
pub(crate) struct Walk<V> {
    query: Query,
    pub(crate) visitor: V,
    stack: Stack,
    next: Option<(u32, u32)>,
}

impl<V> Walk<V> {
    /// A walk for `p` from the root (none for an empty tree).
    #[inline(always)]
    pub(crate) fn new<T>(tree: &Slices<'_, T>, p: Vec3A, visitor: V) -> Self {
        if let Some(root) = tree.nodes.first() {
            prefetch(&root.min_x);
            prefetch(&root.max_y);
        }
        Self {
            query: Query::new(p),
            visitor,
            stack: Stack::EMPTY,
            next: (!tree.nodes.is_empty()).then_some((0, 0)),
        }
    }

    /// Starts over for `p` with `visitor`, reusing the stack's memory.
    #[inline(always)]
    pub(crate) fn restart<T>(&mut self, tree: &Slices<'_, T>, p: Vec3A, visitor: V) {
        if let Some(root) = tree.nodes.first() {
            prefetch(&root.min_x);
            prefetch(&root.max_y);
        }
        self.query = Query::new(p);
        self.visitor = visitor;
        self.stack.top = 0;
        self.next = (!tree.nodes.is_empty()).then_some((0, 0));
    }
}

impl<T> Slices<'_, T> {
    /// Advances `walk` by one node or leaf; `false` once it is finished. The
    /// next node or leaf it will visit has been prefetched (when its parent
    /// was entered), so a caller that steps other walks in between finds it
    /// in cache.
    #[inline(always)]
    pub(crate) fn step<V: LaneVisitor<T>>(&self, walk: &mut Walk<V>) -> bool {
        let Some((child, count)) = walk.next else {
            return false;
        };
        walk.next = if count == 0 {
            self.enter_node(child, &walk.query, &walk.visitor, &mut walk.stack, &mut ())
        } else {
            self.visit_leaf(child, count, &walk.query, &mut walk.visitor, &mut ());
            None
        }
        .or_else(|| walk.stack.pop_within(walk.visitor.bound()));
        walk.next.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::closest::Best;
    use crate::{AabbTree, BuildConfig, Triangle, Vec3};

    /// The small stack and the full one make the same walk; real trees are
    /// too shallow to reach the full one, so it is tested directly.
    #[test]
    fn small_and_full_stacks_walk_alike() {
        let mut rng = crate::sample::Rng::new(5);
        let mut v = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let triangles: Vec<Triangle> = (0..5000)
            .map(|_| {
                let a = v();
                Triangle::new(a, a + v() * 0.05, a + v() * 0.05)
            })
            .collect();
        let tree = AabbTree::build(triangles, &BuildConfig::default()).unwrap();
        let wide = WideTree::from_tree(tree);
        assert!(wide.depth() < SHALLOW);
        let slices = wide.slices();
        for _ in 0..500 {
            let p = Vec3A::from(v() * 1.5);
            let mut small = Best::new(&wide.tree.indices, f32::INFINITY);
            let mut full = Best::new(&wide.tree.indices, f32::INFINITY);
            let (mut small_stats, mut full_stats) =
                (crate::bvh::QueryStats::default(), crate::bvh::QueryStats::default());
            slices.nearest_first_with::<_, _, { 3 * SHALLOW as usize }>(p, &mut small, &mut small_stats);
            slices.nearest_first_with::<_, _, STACK>(p, &mut full, &mut full_stats);
            assert!(small.found && full.found);
            assert_eq!(
                (small.slot, small.point, small.distance_squared),
                (full.slot, full.point, full.distance_squared)
            );
            assert_eq!(small_stats, full_stats);
            assert_eq!(wide.closest(p.into()).unwrap().distance, small.distance_squared.sqrt());
        }
    }
}
