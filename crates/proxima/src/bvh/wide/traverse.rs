//! The nearest-first traversal of the wide tree, behind closest and k-nearest.

use super::packet::V3;
use super::{LEAF, WideTree};
use crate::bvh::config::MAX_DEPTH;
use crate::bvh::traverse::{Counter, DistanceVisitor};
use crate::math::Vec3A;
use wide::f32x4;

#[cfg(target_arch = "x86_64")]
pub(crate) use super::avx2::Avx2;
#[cfg(target_arch = "x86_64")]
use super::avx2::{Avx2Task, V8};
/// The AVX2 token when this CPU has AVX2.
pub(crate) fn detect_avx2() -> Option<Avx2> {
    #[cfg(target_arch = "x86_64")]
    return Avx2::detect();
    #[cfg(not(target_arch = "x86_64"))]
    None
}

/// Stands for the AVX2 token where there is no AVX2: never made.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
pub(crate) enum Avx2 {}

/// A [`DistanceVisitor`] that also takes candidates computed elsewhere (four
/// or eight triangles at a time).
pub(crate) trait LaneVisitor<T>: DistanceVisitor<T> {
    /// Considers the point `q` at squared distance `d2` of the primitive at
    /// leaf-order slot `slot`, of input index `index`, exactly as `visit`
    /// would have computed them.
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32);
}

/// A subtree waiting on the stack: a wide node (`count & LEAF == 0`) or a
/// leaf (`count == LEAF | n`), with its box distance.
#[derive(Clone, Copy)]
struct Pending {
    child: u32,
    count: u32,
    distance_squared: f32,
}

impl Pending {
    /// The root, entered unconditionally: its lanes are tested when entered.
    const ROOT: Self = Self {
        child: 0,
        count: 0,
        distance_squared: 0.0,
    };
}

/// Each wide node on the current path pushes at most three entries, and the
/// wide tree is no deeper than the binary one; [`SLACK`] more.
const STACK: usize = 3 * (MAX_DEPTH as usize + 1) + SLACK;

/// Wide trees less deep than this walk with a stack of [`SMALL_STACK`] entries.
const SHALLOW: u32 = 16;

/// Stack entries past the top that [`Slices::enter_node`] may scribble on:
/// it writes all three pushable lanes, whether or not it pushes them.
const SLACK: usize = 3;

/// A leaf's triangle pairs are first checked against the search radius by
/// their triangles' boxes ([`Avx2::box_beyond`]) only when the leaf's own
/// box lies farther than this fraction of the radius (in squared distance):
/// leaves nearer than that mostly hold triangles within reach, and the
/// check would be wasted. Counted over 20,000 queries per set (dragon and
/// ico1m, near and uniform): at 0.9, 32–97% of pairs are checked and
/// 18–52% skipped, against 92–99% and 26–52% when every leaf is checked.
/// The check costs about a quarter of the pair's test. Measured in-cache
/// (the same queries four times, 40 alternating rounds, median ratio):
/// 1.01–1.03x on three rows, 1.07x on ico1m uniform.
const CULL_FROM: f32 = 0.9;

/// The stack of trees less deep than [`SHALLOW`].
const SMALL_STACK: usize = 3 * SHALLOW as usize + SLACK;

/// Packets prefetched with a wide node, from the first of its leaf lanes'.
/// Measured (near and uniform queries on the dragon and ico1m, one A/B
/// run): none 1, 1 packet 1.05–1.07x, 2 1.01–1.19x, 4 1.06–1.29x, 6 and 8
/// less than 4; the node's own packets only (at most 4 when leaves hold
/// up to 4 triangles) did 0.93–1.01x of 4 taken blindly, since the next
/// packets belong to the next node in depth-first order, often visited too.
pub(crate) const PREFETCHED_PACKETS: usize = 4;

/// Asks for the cache line holding `x` without waiting for it.
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = x;
}

/// Asks for every cache line of a triangle packet (176 bytes at a 16-byte
/// boundary: three or four lines).
#[inline(always)]
fn prefetch_packet(packet: &super::packet::TrianglePacket) {
    prefetch(packet);
    prefetch(&packet.a[2]);
    prefetch(&packet.b[2]);
    prefetch(&packet.c[2]);
}

/// The arrays a walk reads, taken once per query: the node and packet
/// arrays may sit behind a [`HugePageArray`](crate::memory::HugePageArray),
/// whose dereference is cheap but not free.
pub(crate) struct Slices<'a, T> {
    pub(crate) nodes: &'a [super::WideNode],
    pub(crate) packets: &'a [super::packet::TrianglePacket],
    pub(crate) primitives: &'a [T],
    /// [`WideTree::cull_slack`].
    cull_slack: f32,
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
}

impl<T> Slices<'_, T> {
    /// The child lanes set in `mask`, ordered by `keys` ascending (insertion
    /// sort of at most 4), and their count. Every child selected starts
    /// loading at once ([`prefetch_children`](Self::prefetch_children)).
    #[inline(always)]
    pub(crate) fn lanes_nearest_first(
        &self,
        node: &super::WideNode,
        mask: u32,
        keys: &[f32; 4],
    ) -> ([usize; 4], usize) {
        self.prefetch_children(node, mask);
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
        }
        (order, n)
    }

    /// Starts loading every child lane set in `mask` (node, triangle
    /// packet, or first and last primitive of a leaf), so that the cache
    /// misses overlap instead of following one another. Shared by the
    /// distance and the ray walks.
    #[inline(always)]
    pub(crate) fn prefetch_children(&self, node: &super::WideNode, mask: u32) {
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
}

/// The query point, as a scalar vector and splatted per axis for the node
/// and packet arithmetic; on eight lanes too when the leaves are tested two
/// packets at a time with AVX2.
#[derive(Clone, Copy)]
pub(crate) struct Query {
    p: Vec3A,
    px: f32x4,
    py: f32x4,
    pz: f32x4,
    pv: V3,
    #[cfg(target_arch = "x86_64")]
    avx2: Option<(Avx2, V8)>,
}

impl Query {
    #[inline(always)]
    pub(crate) fn new(p: Vec3A, avx2: Option<Avx2>) -> Self {
        #[cfg(not(target_arch = "x86_64"))]
        let _ = avx2;
        Self {
            p,
            px: f32x4::splat(p.x),
            py: f32x4::splat(p.y),
            pz: f32x4::splat(p.z),
            pv: V3::splat(p),
            #[cfg(target_arch = "x86_64")]
            avx2: avx2.map(|t| (t, t.splat(p.x, p.y, p.z))),
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
    fn pop_within(&mut self, bound: f32) -> Option<Pending> {
        while self.top > 0 {
            self.top -= 1;
            let next = self.entries[self.top];
            if next.distance_squared <= bound {
                return Some(next);
            }
        }
        None
    }
}

impl<T> Slices<'_, T> {
    /// Visits wide node `index`: its children within the visitor's bound are
    /// ordered by box distance, all but the nearest are pushed (farthest
    /// first) and the nearest is returned to be entered next. Without a
    /// branch on the distances: against the insertion sort of
    /// [`lanes_nearest_first`](Self::lanes_nearest_first), whose branches
    /// a predictor cannot learn and whose order array was copied through a
    /// stalled store, 1.06–1.20x per query and 1.07–1.31x in Morton
    /// batches (two in-process A/B runs, dragon and ico1m, both query sets).
    #[inline(always)]
    fn enter_node<V: LaneVisitor<T>, C: Counter, const N: usize>(
        &self,
        index: u32,
        q: &Query,
        visitor: &V,
        stack: &mut Stack<N>,
        counter: &mut C,
    ) -> Option<Pending> {
        let node = &self.nodes[index as usize];
        counter.nodes(1);
        let d2 = node.distances_squared(q.px, q.py, q.pz);
        let mask = d2.simd_le(f32x4::splat(visitor.bound())).to_bitmask();
        if mask == 0 {
            return None;
        }
        let d = d2.to_array();
        self.prefetch_children(node, mask);
        // One child within reach: it is entered at once, with nothing to
        // order or push. That is 40% of the node visits of a near-surface
        // query in a batch (10.2 of 25.6 on the dragon, 10.4 of 26.3 on
        // ico1m; uniform 28% and 15%). Against the branch-free path alone:
        // 1.01–1.04x per one-thread batch and 1.01–1.02x per query on the
        // dragon and ico1m (15 alternating rounds, median ratio).
        if mask & (mask - 1) == 0 {
            let lane = mask.trailing_zeros() as usize;
            return Some(Pending {
                child: node.children[lane],
                count: node.counts[lane],
                distance_squared: d[lane],
            });
        }
        // Nearest first without a branch: each lane's key is its distance's
        // bits (in the order of the distances, which are not negative), the
        // lane below them to break ties as the lane order does; lanes
        // beyond the bound sort last. A sorting network of five
        // compare-exchanges orders them.
        let mut keys: [u64; 4] = std::array::from_fn(|lane| {
            let bits = if mask & (1 << lane) != 0 {
                d[lane].to_bits()
            } else {
                u32::MAX
            };
            (u64::from(bits) << 2) | lane as u64
        });
        for (i, j) in [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)] {
            let (a, b) = (keys[i], keys[j]);
            (keys[i], keys[j]) = (a.min(b), a.max(b));
        }
        // The `n - 1` farthest are pushed, farthest first; the writes past
        // them land beyond the new top, in the stack's slack.
        let n = mask.count_ones() as usize;
        for (i, entry) in stack.entries[stack.top..stack.top + SLACK].iter_mut().enumerate() {
            let lane = (keys[n.wrapping_sub(1 + i) & 3] & 3) as usize;
            *entry = Pending {
                child: node.children[lane],
                count: node.counts[lane],
                distance_squared: d[lane],
            };
        }
        stack.top += n - 1;
        let nearest = (keys[0] & 3) as usize;
        Some(Pending {
            child: node.children[nearest],
            count: node.counts[nearest],
            distance_squared: d[nearest],
        })
    }

    /// Tests the primitives of a leaf lane (`count == LEAF | n`), four
    /// triangles at a time where the tree has packets; the leaf's box
    /// distance decides whether its pairs are first checked by their
    /// triangles' boxes ([`CULL_FROM`]).
    #[inline(always)]
    fn visit_leaf<V: LaneVisitor<T>, C: Counter>(
        &self,
        Pending {
            child,
            count,
            distance_squared,
        }: Pending,
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
        let packets = &packets[child as usize..child as usize + n.div_ceil(4)];
        #[cfg(target_arch = "x86_64")]
        if let Some((avx2, pv8)) = q.avx2 {
            let mut pairs = packets.chunks_exact(2);
            for pair in &mut pairs {
                let (lo, hi) = (&pair[0], &pair[1]);
                debug_assert_eq!(hi.first, lo.first + 4);
                if distance_squared > visitor.bound() * CULL_FROM {
                    // Skipped when no triangle's box is within reach: the
                    // reach allows for a computed closest point lying a
                    // little outside its triangle's box and for the rounding
                    // of both distances (see `WideTree::cull_slack`), so
                    // every triangle skipped would have failed `within`.
                    let reach = visitor.bound().sqrt() + self.cull_slack;
                    let live = lo.fast | lo.slow | (hi.fast | hi.slow) << 4;
                    if live & !avx2.box_beyond(lo, hi, &pv8, reach * reach * (1.0 + 1e-4)) == 0 {
                        // Not tested, so not counted as tested either.
                        counter.skip_primitives(u64::from(live.count_ones()));
                        continue;
                    }
                }
                let (point, d2, far) = avx2.closest_pair(lo, hi, &pv8);
                let fast = lo.fast | hi.fast << 4;
                let bits = avx2.within(d2, visitor.bound()) & fast & !far;
                self.offer_lanes(
                    lo.first,
                    bits,
                    |lane| if lane < 4 { lo.index[lane] } else { hi.index[lane - 4] },
                    |lane| (Vec3A::from_array(point.lane(lane)), super::avx2::lane_of(d2, lane)),
                    visitor,
                );
                self.visit_slow(lo.first, lo.slow | hi.slow << 4 | (fast & far), q, visitor);
            }
            for packet in pairs.remainder() {
                self.visit_packet(packet, q, visitor);
            }
            return;
        }
        for packet in packets {
            self.visit_packet(packet, q, visitor);
        }
    }

    /// Tests the four lanes of `packet`.
    #[inline(always)]
    fn visit_packet<V: LaneVisitor<T>>(&self, packet: &super::packet::TrianglePacket, q: &Query, visitor: &mut V) {
        let (point, d2, far) = packet.closest(&q.pv);
        let bits = d2.simd_le(f32x4::splat(visitor.bound())).to_bitmask() & packet.fast & !far;
        self.offer_lanes(
            packet.first,
            bits,
            |lane| packet.index[lane],
            |lane| (point.lane(lane), d2.as_array()[lane]),
            visitor,
        );
        self.visit_slow(packet.first, packet.slow | (packet.fast & far), q, visitor);
    }

    /// Offers the lanes set in `bits` (those that can change the answer),
    /// lane `l` being the primitive at slot `first + l`.
    #[inline(always)]
    fn offer_lanes<V: LaneVisitor<T>>(
        &self,
        first: u32,
        mut bits: u32,
        index: impl Fn(usize) -> u32,
        lane: impl Fn(usize) -> (Vec3A, f32),
        visitor: &mut V,
    ) {
        while bits != 0 {
            let l = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let (point, d2) = lane(l);
            visitor.offer(first as usize + l, index(l), point, d2);
        }
    }

    /// Hands the lanes set in `bits` to the scalar routine: slivers, and
    /// queries far enough for it to take its `f64` path.
    #[inline(always)]
    fn visit_slow<V: LaneVisitor<T>>(&self, first: u32, mut bits: u32, q: &Query, visitor: &mut V) {
        while bits != 0 {
            let slot = first as usize + bits.trailing_zeros() as usize;
            bits &= bits - 1;
            visitor.visit(slot, &self.primitives[slot], q.p);
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
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(NearestFirst {
                slices: self.slices(),
                p,
                depth: self.depth,
                visitor,
                counter,
            });
        }
        self.slices().nearest_first(p, self.depth, None, visitor, counter);
    }
}

/// [`Slices::nearest_first`] as a task compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct NearestFirst<'a, 'b, T, V, C> {
    slices: Slices<'a, T>,
    p: Vec3A,
    depth: u32,
    visitor: &'b mut V,
    counter: &'b mut C,
}

#[cfg(target_arch = "x86_64")]
impl<T, V: LaneVisitor<T>, C: Counter> Avx2Task for NearestFirst<'_, '_, T, V, C> {
    type Output = ();
    #[inline(always)]
    fn call(self, avx2: Avx2) {
        self.slices
            .nearest_first(self.p, self.depth, Some(avx2), self.visitor, self.counter);
    }
}

impl<T> Slices<'_, T> {
    /// [`WideTree::nearest_first`] on these arrays. Each wide node on the
    /// current path has at most three children waiting, so a tree of depth
    /// `d` needs `3 (d + 1)` stack entries: shallow trees (all but those of
    /// extreme meshes) get a small stack, whose initialization costs far less
    /// than the full one's (it was 13% of a query's instructions).
    #[inline(always)]
    fn nearest_first<V: LaneVisitor<T>, C: Counter>(
        &self,
        p: Vec3A,
        depth: u32,
        avx2: Option<Avx2>,
        visitor: &mut V,
        counter: &mut C,
    ) {
        if depth < SHALLOW {
            self.nearest_first_with::<V, C, SMALL_STACK>(p, avx2, visitor, counter);
        } else {
            self.nearest_first_with::<V, C, STACK>(p, avx2, visitor, counter);
        }
    }

    #[inline(always)]
    fn nearest_first_with<V: LaneVisitor<T>, C: Counter, const N: usize>(
        &self,
        p: Vec3A,
        avx2: Option<Avx2>,
        visitor: &mut V,
        counter: &mut C,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let q = Query::new(p, avx2);
        let mut stack = Stack::<N>::EMPTY;
        let mut next = Some(Pending::ROOT);
        while let Some(pending) = next {
            next = if pending.count & LEAF == 0 {
                self.enter_node(pending.child, &q, visitor, &mut stack, counter)
            } else {
                self.visit_leaf(pending, &q, visitor, counter);
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
    next: Option<Pending>,
}

impl<V> Walk<V> {
    /// A walk for `p` from the root (none for an empty tree).
    #[inline(always)]
    pub(crate) fn new<T>(tree: &Slices<'_, T>, p: Vec3A, avx2: Option<Avx2>, visitor: V) -> Self {
        if let Some(root) = tree.nodes.first() {
            prefetch(&root.min_x);
            prefetch(&root.max_y);
        }
        Self {
            query: Query::new(p, avx2),
            visitor,
            stack: Stack::EMPTY,
            next: (!tree.nodes.is_empty()).then_some(Pending::ROOT),
        }
    }

    /// Starts over for `p` with `visitor`, reusing the stack's memory.
    #[inline(always)]
    pub(crate) fn restart<T>(&mut self, tree: &Slices<'_, T>, p: Vec3A, avx2: Option<Avx2>, visitor: V) {
        if let Some(root) = tree.nodes.first() {
            prefetch(&root.min_x);
            prefetch(&root.max_y);
        }
        self.query = Query::new(p, avx2);
        self.visitor = visitor;
        self.stack.top = 0;
        self.next = (!tree.nodes.is_empty()).then_some(Pending::ROOT);
    }
}

impl<T> Slices<'_, T> {
    /// Advances `walk` by one node or leaf; `false` once it is finished. The
    /// next node or leaf it will visit has been prefetched (when its parent
    /// was entered), so a caller that steps other walks in between finds it
    /// in cache.
    #[inline(always)]
    pub(crate) fn step<V: LaneVisitor<T>>(&self, walk: &mut Walk<V>) -> bool {
        let Some(pending) = walk.next else {
            return false;
        };
        walk.next = if pending.count & LEAF == 0 {
            self.enter_node(pending.child, &walk.query, &walk.visitor, &mut walk.stack, &mut ())
        } else {
            self.visit_leaf(pending, &walk.query, &mut walk.visitor, &mut ());
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
        for _ in 0..500 {
            let p = Vec3A::from(v() * 1.5);
            let mut small = Best::new(&wide.tree.indices, f32::INFINITY);
            let mut full = Best::new(&wide.tree.indices, f32::INFINITY);
            let (mut small_stats, mut full_stats) =
                (crate::bvh::QueryStats::default(), crate::bvh::QueryStats::default());
            slices.nearest_first_with::<_, _, SMALL_STACK>(p, wide.avx2, &mut small, &mut small_stats);
            slices.nearest_first_with::<_, _, STACK>(p, wide.avx2, &mut full, &mut full_stats);
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
