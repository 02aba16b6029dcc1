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

/// Asks for the cache line holding `x` without waiting for it.
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = x;
}

impl<T> WideTree<T> {
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
        let primitives = self.tree.primitives();
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

impl<T> WideTree<T> {
    /// Depth-first, nearest child first, with a fixed stack. At each wide
    /// node the four child box distances are computed at once; the children
    /// within the radius are ordered by distance, the nearest is entered at
    /// once and the others are pushed farthest first with their distances, to
    /// be dropped when popped if the radius has shrunk meanwhile.
    #[inline]
    pub(crate) fn nearest_first<V: LaneVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C) {
        if self.nodes.is_empty() {
            return;
        }
        let (px, py, pz) = (f32x4::splat(p.x), f32x4::splat(p.y), f32x4::splat(p.z));
        let primitives = self.tree.primitives();
        let packets = &self.packets[..];
        let pv = V3::splat(p);
        let mut stack = [Pending {
            child: 0,
            count: 0,
            distance_squared: 0.0,
        }; STACK];
        let mut top = 0usize;
        // The root, entered unconditionally: its lanes are tested below.
        let (mut child, mut count) = (0u32, 0u32);
        loop {
            if count == 0 {
                let node = &self.nodes[child as usize];
                counter.nodes(1);
                let d2 = node.distances_squared(px, py, pz);
                let mask = d2.simd_le(f32x4::splat(visitor.bound())).to_bitmask();
                if mask != 0 {
                    let d = d2.to_array();
                    let (order, n) = self.lanes_nearest_first(node, mask, &d);
                    for &lane in order[1..n].iter().rev() {
                        stack[top] = Pending {
                            child: node.children[lane],
                            count: node.counts[lane],
                            distance_squared: d[lane],
                        };
                        top += 1;
                    }
                    (child, count) = (node.children[order[0]], node.counts[order[0]]);
                    continue;
                }
            } else {
                let n = (count & !LEAF) as usize;
                counter.primitives(n as u64);
                if packets.is_empty() {
                    let first = child as usize;
                    for (slot, primitive) in (first..).zip(&primitives[first..first + n]) {
                        visitor.visit(slot, primitive, p);
                    }
                } else {
                    for packet in &packets[child as usize..child as usize + n.div_ceil(4)] {
                        let (q, d2, far) = packet.closest(&pv);
                        // Only lanes that can change the answer are offered.
                        let mut bits = d2.simd_le(f32x4::splat(visitor.bound())).to_bitmask() & packet.fast & !far;
                        while bits != 0 {
                            let lane = bits.trailing_zeros() as usize;
                            bits &= bits - 1;
                            visitor.offer(packet.first as usize + lane, q.lane(lane), d2.as_array()[lane]);
                        }
                        let mut slow = packet.slow | (packet.fast & far);
                        while slow != 0 {
                            let slot = packet.first as usize + slow.trailing_zeros() as usize;
                            slow &= slow - 1;
                            visitor.visit(slot, &primitives[slot], p);
                        }
                    }
                }
            }
            // Pop the next subtree still within reach.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let next = stack[top];
                if next.distance_squared <= visitor.bound() {
                    (child, count) = (next.child, next.count);
                    break;
                }
            }
        }
    }
}
