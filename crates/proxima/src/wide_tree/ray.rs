//! Ray queries on the wide tree: the four child boxes of a node are slab
//! tested at once, and the triangles of a leaf four at a time.
//!
//! Both repeat the binary tree's arithmetic lane by lane. The slab test uses
//! the same per-ray widening and the same operations as
//! `RaySlabs::interval`, on the binary tree's own boxes. The packet test
//! repeats [`WatertightRay::intersect`] operation for operation (the same
//! shear, edge functions, sums and divisions, none fused), so each lane's hit
//! is bit for bit the scalar one; a lane whose edge function is exactly zero
//! (the scalar test's `f64` path) is answered by the scalar test itself. The
//! answers are therefore the binary tree's, and brute force's.

use super::walk::{Pending, Slices, WideQuery};
use super::{WideNode, WidePrimitive, WideTree};
use crate::aabb_tree::RaySlabs;
use crate::math::Vec3;
use crate::primitive::{RayIntersect, WatertightRay};
use crate::query::{Counter, RayQuery, RayVisitor};
use crate::simd::offer_packet;
use std::ops::ControlFlow;
use wide::f32x4;

/// A ray's slab data splatted over four lanes, near and far planes chosen
/// per axis by the direction's sign bit.
pub(crate) struct WideSlabs {
    origin: [f32x4; 3],
    inv_direction: [f32x4; 3],
    negative: [bool; 3],
    near_shift: [f32x4; 3],
    far_shift: [f32x4; 3],
}

impl WideSlabs {
    pub(crate) fn new(slabs: &RaySlabs) -> Self {
        let s = |v: crate::math::Vec3A| [f32x4::splat(v.x), f32x4::splat(v.y), f32x4::splat(v.z)];
        let negative = slabs.negative.bitmask();
        Self {
            origin: s(slabs.origin),
            inv_direction: s(slabs.inv_direction),
            negative: [negative & 1 != 0, negative & 2 != 0, negative & 4 != 0],
            near_shift: s(slabs.near_shift),
            far_shift: s(slabs.far_shift),
        }
    }

    /// Entry parameters into the four child boxes, and the lanes crossed
    /// within `[t_lo, t_hi]`.
    #[inline(always)]
    pub(crate) fn entries(&self, node: &WideNode, t_lo: f32, t_hi: f32) -> (f32x4, u32) {
        let mins = [&node.min_x, &node.min_y, &node.min_z];
        let maxs = [&node.max_x, &node.max_y, &node.max_z];
        let mut enter = f32x4::splat(t_lo);
        let mut exit = f32x4::splat(t_hi);
        for axis in 0..3 {
            let (near, far) = if self.negative[axis] {
                (maxs[axis], mins[axis])
            } else {
                (mins[axis], maxs[axis])
            };
            let o = self.origin[axis];
            let inv = self.inv_direction[axis];
            let t_near = ((f32x4::new(*near) - o) + self.near_shift[axis]) * inv;
            let t_far = ((f32x4::new(*far) - o) + self.far_shift[axis]) * inv;
            // 0 · ∞ is NaN: the origin lies on a plane the ray runs along.
            let t_near = t_near.simd_eq(t_near).select(t_near, f32x4::splat(f32::NEG_INFINITY));
            let t_far = t_far.simd_eq(t_far).select(t_far, f32x4::splat(f32::INFINITY));
            enter = enter.fast_max(t_near);
            exit = exit.fast_min(t_far);
        }
        (enter, enter.simd_le(exit).to_bitmask())
    }
}

/// Bits of a ray's entry parameter that order entries as the entries do:
/// they may be negative (a range starting before the origin), so the
/// sign's order is restored ([`WideQuery::order_bits`]).
#[inline(always)]
pub(crate) fn entry_order_bits(key: f32) -> u32 {
    let bits = key.to_bits();
    if bits >> 31 == 1 { !bits } else { bits | 1 << 31 }
}

/// A ray query on the wide tree: keys are the ray's entry parameters into
/// the four (per-ray widened) child boxes; leaves are tested four triangles
/// at a time where the tree has packets.
struct Rays<'a, V> {
    slabs: WideSlabs,
    ray: &'a WatertightRay,
    t_min: f32,
    visitor: &'a mut V,
}

impl<T: RayIntersect, V: RayVisitor<T>> WideQuery<T> for Rays<'_, V> {
    #[inline(always)]
    fn keys(&self, node: &WideNode) -> (f32x4, u32) {
        self.slabs.entries(node, self.t_min, self.visitor.t_hi())
    }

    #[inline(always)]
    fn bound(&self) -> f32 {
        self.visitor.t_hi()
    }

    #[inline(always)]
    fn order_bits(key: f32) -> u32 {
        entry_order_bits(key)
    }

    #[inline(always)]
    fn leaf<C: Counter>(&mut self, tree: &Slices<'_, T>, leaf: Pending, counter: &mut C) -> ControlFlow<()> {
        let (primitives, packets) = (tree.primitives, tree.packets);
        let n = leaf.leaf_len();
        let child = leaf.child as usize;
        counter.primitives(n as u64);
        if packets.is_empty() {
            for (slot, primitive) in (child..).zip(&primitives[child..child + n]) {
                if self.visitor.visit(slot, primitive, self.ray, self.t_min) {
                    return ControlFlow::Break(());
                }
            }
            return ControlFlow::Continue(());
        }
        for packet in &packets[child..child + n.div_ceil(4)] {
            offer_packet(packet, primitives, self.ray, self.t_min, self.visitor)?;
        }
        ControlFlow::Continue(())
    }
}

/// The same answers as the binary tree's, field for field.
impl<T: RayIntersect + WidePrimitive> RayQuery<T> for WideTree<T> {
    #[inline(always)]
    fn ray_walk<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) {
        let Some(root) = self.tree.root() else { return };
        let slabs = WideSlabs::new(&RaySlabs::new(
            ray.origin(),
            direction,
            root.bounds().min,
            root.bounds().max,
        ));
        self.walk(
            |_| Rays {
                slabs,
                ray,
                t_min,
                visitor,
            },
            counter,
        );
    }
}
