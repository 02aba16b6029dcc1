//! Distance queries on the wide tree: the four child box distances of a
//! node at once, and the triangles of a leaf four (or, with AVX2, eight) at a
//! time, by a routine that repeats the scalar one operation for operation.

use super::walk::{Pending, Slices, WideQuery};
use super::{WideNode, WidePrimitive, WideTree};
use crate::math::Vec3A;
use crate::primitive::ClosestPoint;
use crate::query::{Counter, NearestQuery, NearestVisitor};
#[cfg(target_arch = "x86_64")]
use crate::simd::V8;
use crate::simd::{Avx2, TrianglePacket, V3};
use std::ops::ControlFlow;
use wide::f32x4;

/// A leaf's triangle pairs are first checked against the search radius by
/// their triangles' boxes ([`Avx2::box_beyond`]) only when the leaf's own
/// box lies farther than this fraction of the radius (in squared distance):
/// leaves nearer than that mostly hold triangles within reach, and the
/// check would be wasted (counts in docs/perf-log.md).
const CULL_FROM: f32 = 0.9;

/// A distance query on the wide tree: the query point as a scalar vector and
/// splatted per axis for the node and packet arithmetic (on eight lanes too
/// when the leaves are tested two packets at a time with AVX2), and the
/// visitor its leaves go to.
pub(crate) struct Nearest<'v, V> {
    p: Vec3A,
    px: f32x4,
    py: f32x4,
    pz: f32x4,
    pv: V3,
    #[cfg(target_arch = "x86_64")]
    avx2: Option<(Avx2, V8)>,
    pub(crate) visitor: &'v mut V,
}

impl<'v, V> Nearest<'v, V> {
    #[inline(always)]
    pub(crate) fn new(p: Vec3A, avx2: Option<Avx2>, visitor: &'v mut V) -> Self {
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
            visitor,
        }
    }
}

impl<T, V: NearestVisitor<T>> WideQuery<T> for Nearest<'_, V> {
    #[inline(always)]
    fn keys(&self, node: &WideNode) -> (f32x4, u32) {
        let d2 = node.distances_squared(self.px, self.py, self.pz);
        (d2, d2.simd_le(f32x4::splat(self.visitor.bound())).to_bitmask())
    }

    #[inline(always)]
    fn bound(&self) -> f32 {
        self.visitor.bound()
    }

    /// Tests the primitives of a leaf, four triangles at a time where the
    /// tree has packets; the leaf's box distance decides whether its pairs
    /// are first checked by their triangles' boxes ([`CULL_FROM`]).
    #[inline(always)]
    fn leaf<C: Counter>(&mut self, tree: &Slices<'_, T>, leaf: Pending, counter: &mut C) -> ControlFlow<()> {
        let (primitives, packets) = (tree.primitives, tree.packets);
        let n = leaf.leaf_len();
        let child = leaf.child as usize;
        counter.primitives(n as u64);
        if packets.is_empty() {
            for (slot, primitive) in (child..).zip(&primitives[child..child + n]) {
                self.visitor.visit(slot, primitive, self.p);
            }
            return ControlFlow::Continue(());
        }
        let packets = &packets[child..child + n.div_ceil(4)];
        #[cfg(target_arch = "x86_64")]
        if let Some((avx2, pv8)) = self.avx2 {
            let mut pairs = packets.chunks_exact(2);
            for pair in &mut pairs {
                let (lo, hi) = (&pair[0], &pair[1]);
                debug_assert_eq!(hi.first, lo.first + 4);
                if leaf.key > self.visitor.bound() * CULL_FROM {
                    // Skipped when no triangle's box is within reach: the
                    // reach allows for a computed closest point lying a
                    // little outside its triangle's box and for the rounding
                    // of both distances (see `WideTree::cull_slack`), so
                    // every triangle skipped would have failed `within`.
                    let reach = self.visitor.bound().sqrt() + tree.cull_slack;
                    let live = lo.fast | lo.slow | (hi.fast | hi.slow) << 4;
                    if live & !avx2.box_beyond(lo, hi, &pv8, reach * reach * (1.0 + 1e-4)) == 0 {
                        // Not tested, so not counted as tested either.
                        counter.skip_primitives(u64::from(live.count_ones()));
                        continue;
                    }
                }
                let (point, d2, far) = avx2.closest_pair(lo, hi, &pv8);
                let fast = lo.fast | hi.fast << 4;
                let bits = avx2.within(d2, self.visitor.bound()) & fast & !far;
                self.offer_lanes(
                    lo.first,
                    bits,
                    |lane| if lane < 4 { lo.index[lane] } else { hi.index[lane - 4] },
                    |lane| (Vec3A::from_array(point.lane(lane)), crate::simd::lane_of(d2, lane)),
                );
                self.visit_slow(tree, lo.first, lo.slow | hi.slow << 4 | (fast & far));
            }
            for packet in pairs.remainder() {
                self.visit_packet(tree, packet);
            }
            return ControlFlow::Continue(());
        }
        for packet in packets {
            self.visit_packet(tree, packet);
        }
        ControlFlow::Continue(())
    }
}

impl<V> Nearest<'_, V> {
    /// Tests the four lanes of `packet`.
    #[inline(always)]
    fn visit_packet<T>(&mut self, tree: &Slices<'_, T>, packet: &TrianglePacket)
    where
        V: NearestVisitor<T>,
    {
        let (point, d2, far) = packet.closest(&self.pv);
        let bits = d2.simd_le(f32x4::splat(self.visitor.bound())).to_bitmask() & packet.fast & !far;
        self.offer_lanes(
            packet.first,
            bits,
            |lane| packet.index[lane],
            |lane| (point.lane(lane), d2.as_array()[lane]),
        );
        self.visit_slow(tree, packet.first, packet.slow | (packet.fast & far));
    }

    /// Offers the lanes set in `bits` (those that can change the answer),
    /// lane `l` being the primitive at slot `first + l`.
    #[inline(always)]
    fn offer_lanes<T>(
        &mut self,
        first: u32,
        mut bits: u32,
        index: impl Fn(usize) -> u32,
        lane: impl Fn(usize) -> (Vec3A, f32),
    ) where
        V: NearestVisitor<T>,
    {
        while bits != 0 {
            let l = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let (point, d2) = lane(l);
            self.visitor.offer(first as usize + l, index(l), point, d2);
        }
    }

    /// Hands the lanes set in `bits` to the scalar routine: slivers, and
    /// queries far enough for it to take its `f64` path.
    #[inline(always)]
    fn visit_slow<T>(&mut self, tree: &Slices<'_, T>, first: u32, mut bits: u32)
    where
        V: NearestVisitor<T>,
    {
        while bits != 0 {
            let slot = first as usize + bits.trailing_zeros() as usize;
            bits &= bits - 1;
            self.visitor.visit(slot, &tree.primitives[slot], self.p);
        }
    }
}

/// The same answers as the binary tree's, field for field.
impl<T: ClosestPoint + WidePrimitive> NearestQuery<T> for WideTree<T> {
    #[inline(always)]
    fn nearest_walk<V: NearestVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C) {
        self.walk(|avx2| Nearest::new(p, avx2, visitor), counter);
    }
}
