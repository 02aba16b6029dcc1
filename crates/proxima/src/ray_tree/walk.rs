//! The ray walk of the [`RayTree`]: depth first, nearest entry first, on a
//! fixed stack, one step (a node or a leaf) at a time.
//!
//! At a node, the eight child boxes are slab tested at once. One child
//! crossed is entered at once; several are pushed in order of entry, the
//! nearest on top, and the nearest is popped and entered. Every crossed
//! child is prefetched as soon as its node is read, so that the cache
//! misses of a step overlap. A pending child whose entry lies beyond the
//! best hit found meanwhile is dropped when popped. On CPUs with AVX2 the
//! whole walk runs compiled for AVX2, with the 256-bit node and leaf tests.
//!
//! A single ray steps until its walk ends; a batch interleaves the steps of
//! several rays (`batch.rs`), so that one ray's cache miss is waited out
//! while the others compute.

use super::slabs::NodeSlabs;
use super::{LEAF, PACKET_INDEX, PAIR, RayNode, RayTree, WIDTH};
use crate::aabb_tree::RaySlabs;
use crate::build::MAX_DEPTH;
use crate::math::Vec3;
use crate::memory::prefetch;
use crate::primitive::{Triangle, TriangleHit, WatertightRay};
use crate::query::{Counter, RayQuery, RayVisitor};
use crate::simd::{Avx2, TrianglePacket, offer_lanes, offer_packet, prefetch_packet};
use std::ops::ControlFlow;

/// Trees less deep than this walk with a stack of [`SMALL_STACK`] entries
/// (and their batches interleave rays).
pub(super) const SHALLOW: u32 = 10;

/// A node of depth `d` has at most `7 d` entries below it on the stack
/// (each node on its path left at most seven children waiting) and pushes
/// at most eight.
const fn stack_size(depth: u32) -> usize {
    (WIDTH - 1) * depth as usize + WIDTH
}

/// The stack of trees less deep than [`SHALLOW`].
pub(super) const SMALL_STACK: usize = stack_size(SHALLOW);

/// The deepest a node can be: the binary tree's depth (each level of the
/// collapse takes at least one binary level), plus the nodes made of
/// leaves under a binary leaf of up to 2^32 triangles.
pub(super) const MAX_RAY_DEPTH: u32 = MAX_DEPTH + 11;

const FULL_STACK: usize = stack_size(MAX_RAY_DEPTH + 1);

/// `current` of a finished walk: no node or leaf has it (packet indices
/// stay below [`PACKET_INDEX`]).
const DONE: u32 = u32::MAX;

/// Hits of a leaf of two packets: the lanes hit (bits 0–3 the first
/// packet's, 4–7 the second's), their hits, and the lanes left to the
/// scalar test.
type PairHits = (u32, [TriangleHit; 8], u32);

/// How a walk tests a node's eight boxes and a leaf's eight triangles: on
/// 256-bit lanes ([`Avx2`]) or on two halves of four ([`Portable`]), with
/// the same bits.
pub(super) trait Lanes: Copy {
    fn entries(self, slabs: &NodeSlabs, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32);
    fn pair_hits(
        self,
        lo: &TrianglePacket,
        hi: &TrianglePacket,
        ray: &WatertightRay,
        t_min: f32,
        t_max: f32,
    ) -> PairHits;
}

/// Four lanes at a time, on any CPU.
#[derive(Clone, Copy, Debug)]
pub(super) struct Portable;

impl Lanes for Portable {
    #[inline(always)]
    fn entries(self, slabs: &NodeSlabs, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32) {
        slabs.entries(node, t_lo, t_hi)
    }

    #[inline(always)]
    fn pair_hits(
        self,
        lo: &TrianglePacket,
        hi: &TrianglePacket,
        ray: &WatertightRay,
        t_min: f32,
        t_max: f32,
    ) -> PairHits {
        let (lo_bits, lo_hits, lo_scalar) = lo.ray_hits(ray, t_min, t_max);
        let (hi_bits, hi_hits, hi_scalar) = hi.ray_hits(ray, t_min, t_max);
        let hits = std::array::from_fn(|lane| if lane < 4 { lo_hits[lane] } else { hi_hits[lane - 4] });
        (lo_bits | hi_bits << 4, hits, lo_scalar | hi_scalar << 4)
    }
}

#[cfg(target_arch = "x86_64")]
impl Lanes for Avx2 {
    #[inline(always)]
    fn entries(self, slabs: &NodeSlabs, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32) {
        super::avx2::node_entries(self, slabs, node, t_lo, t_hi)
    }

    #[inline(always)]
    fn pair_hits(
        self,
        lo: &TrianglePacket,
        hi: &TrianglePacket,
        ray: &WatertightRay,
        t_min: f32,
        t_max: f32,
    ) -> PairHits {
        self.ray_hits_pair(lo, hi, ray, t_min, t_max)
    }
}

/// One ray as its walk sees it.
pub(super) struct RayWalk<'a, V> {
    pub(super) ray: &'a WatertightRay,
    pub(super) slabs: &'a NodeSlabs,
    pub(super) t_min: f32,
    pub(super) visitor: &'a mut V,
}

/// Where one walk stands: the children waiting (child, entry parameter;
/// descending entry from the bottom of each node's pushes, so the nearest
/// is popped first) and the node or leaf to visit next.
#[derive(Clone, Copy)]
pub(super) struct WalkState<const S: usize> {
    stack: [(u32, f32); S],
    top: usize,
    current: u32,
}

impl<const S: usize> WalkState<S> {
    /// A walk about to visit the root.
    pub(super) const START: Self = Self {
        stack: [(0, 0.0); S],
        top: 0,
        current: 0,
    };

    /// Starts over from the root, keeping the stack's memory.
    #[inline(always)]
    pub(super) fn restart(&mut self) {
        self.top = 0;
        self.current = 0;
    }
}

/// The arrays a walk reads.
#[derive(Clone, Copy)]
pub(super) struct Arrays<'a> {
    nodes: &'a [RayNode],
    packets: &'a [TrianglePacket],
    triangles: &'a [Triangle],
}

impl RayTree {
    #[inline(always)]
    pub(super) fn arrays(&self) -> Arrays<'_> {
        Arrays {
            nodes: &self.nodes,
            packets: &self.packets,
            triangles: self.leaves.primitives(),
        }
    }
}

impl Arrays<'_> {
    /// Starts loading every child in `mask`: a node's four lines, or a
    /// leaf's packets.
    #[inline(always)]
    fn prefetch_children(&self, node: &RayNode, mask: u32) {
        let mut bits = mask;
        while bits != 0 {
            let child = node.children[bits.trailing_zeros() as usize];
            bits &= bits - 1;
            if child & LEAF == 0 {
                let next = &self.nodes[child as usize];
                for row in [0, 2, 4] {
                    prefetch(&next.bounds[row]);
                }
                prefetch(&next.children);
            } else {
                let first = (child & PACKET_INDEX) as usize;
                prefetch_packet(&self.packets[first]);
                if child & PAIR != 0 {
                    prefetch_packet(&self.packets[first + 1]);
                }
            }
        }
    }

    /// Tests the triangles of leaf `leaf`; `Break` ends the walk.
    #[inline(always)]
    fn leaf<L: Lanes, V: RayVisitor<Triangle>, C: Counter>(
        &self,
        leaf: u32,
        lanes: L,
        walk: &mut RayWalk<'_, V>,
        counter: &mut C,
    ) -> ControlFlow<()> {
        let first = (leaf & PACKET_INDEX) as usize;
        if leaf & PAIR == 0 {
            let packet = &self.packets[first];
            counter.primitives(u64::from((packet.fast | packet.slow).count_ones()));
            return offer_packet(packet, self.triangles, walk.ray, walk.t_min, walk.visitor);
        }
        let (lo, hi) = (&self.packets[first], &self.packets[first + 1]);
        counter.primitives(u64::from((lo.fast | lo.slow | (hi.fast | hi.slow) << 4).count_ones()));
        let (bits, hits, scalar) = lanes.pair_hits(lo, hi, walk.ray, walk.t_min, walk.visitor.t_hi());
        let slot = |lane: usize| {
            if lane < 4 {
                lo.first as usize + lane
            } else {
                hi.first as usize + lane - 4
            }
        };
        offer_lanes(
            (bits, &hits, scalar),
            slot,
            self.triangles,
            walk.ray,
            walk.t_min,
            walk.visitor,
        )
    }

    /// Visits the node or leaf the walk stands at and moves it to the next;
    /// `false` once the walk has ended. The tree must not be empty.
    #[inline(always)]
    pub(super) fn step<L: Lanes, V: RayVisitor<Triangle>, C: Counter, const S: usize>(
        &self,
        lanes: L,
        walk: &mut RayWalk<'_, V>,
        state: &mut WalkState<S>,
        counter: &mut C,
    ) -> bool {
        let current = state.current;
        if current & LEAF == 0 {
            let node = &self.nodes[current as usize];
            counter.nodes(1);
            let (t, mask) = lanes.entries(walk.slabs, node, walk.t_min, walk.visitor.t_hi());
            if mask != 0 {
                self.prefetch_children(node, mask);
                if mask & (mask - 1) == 0 {
                    state.current = node.children[mask.trailing_zeros() as usize];
                    return true;
                }
                let base = state.top;
                let mut bits = mask;
                while bits != 0 {
                    let lane = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let entry = (node.children[lane], t[lane]);
                    let mut i = state.top;
                    while i > base && state.stack[i - 1].1 < entry.1 {
                        state.stack[i] = state.stack[i - 1];
                        i -= 1;
                    }
                    state.stack[i] = entry;
                    state.top += 1;
                }
                state.top -= 1;
                state.current = state.stack[state.top].0;
                return true;
            }
        } else if self.leaf(current, lanes, walk, counter).is_break() {
            state.current = DONE;
            return false;
        }
        while state.top > 0 {
            state.top -= 1;
            let (child, entry) = state.stack[state.top];
            if entry <= walk.visitor.t_hi() {
                state.current = child;
                return true;
            }
        }
        state.current = DONE;
        false
    }

    /// A whole walk, with a stack for trees of depth `depth`.
    #[inline(always)]
    fn walk<L: Lanes, V: RayVisitor<Triangle>, C: Counter>(
        &self,
        depth: u32,
        lanes: L,
        walk: &mut RayWalk<'_, V>,
        counter: &mut C,
    ) {
        if depth < SHALLOW {
            let mut state = WalkState::<SMALL_STACK>::START;
            while self.step(lanes, walk, &mut state, counter) {}
        } else {
            let mut state = WalkState::<FULL_STACK>::START;
            while self.step(lanes, walk, &mut state, counter) {}
        }
    }
}

/// [`Arrays::walk`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct Avx2Walk<'a, 'b, V, C> {
    arrays: Arrays<'a>,
    walk: RayWalk<'a, V>,
    depth: u32,
    counter: &'b mut C,
}

#[cfg(target_arch = "x86_64")]
impl<V: RayVisitor<Triangle>, C: Counter> crate::simd::Avx2Task for Avx2Walk<'_, '_, V, C> {
    type Output = ();
    #[inline(always)]
    fn call(mut self, avx2: Avx2) {
        self.arrays.walk(self.depth, avx2, &mut self.walk, self.counter);
    }
}

/// The same answers as brute force's, field for field (module notes of
/// [`ray_tree`](super)). Batches interleave their rays (`batch.rs`).
impl RayQuery<Triangle> for RayTree {
    #[inline(always)]
    fn ray_walk<V: RayVisitor<Triangle>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let slabs = NodeSlabs::new(&RaySlabs::new(
            ray.origin(),
            direction,
            self.bounds.min,
            self.bounds.max,
        ));
        let mut walk = RayWalk {
            ray,
            slabs: &slabs,
            t_min,
            visitor,
        };
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(Avx2Walk {
                arrays: self.arrays(),
                walk,
                depth: self.depth,
                counter,
            });
        }
        self.arrays().walk(self.depth, Portable, &mut walk, counter);
    }

    fn first_hit_batch(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<Option<crate::query::RayHit>, crate::RayError>> {
        self.first_hit_batch_interleaved(rays, t_min, t_max)
    }

    fn any_hit_batch(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Vec<Result<bool, crate::RayError>> {
        self.any_hit_batch_interleaved(rays, t_min, t_max)
    }

    fn some_hit_batch(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<Option<crate::query::RayHit>, crate::RayError>> {
        self.some_hit_batch_interleaved(rays, t_min, t_max)
    }
}
