//! The slab test of a node's eight child boxes, without AVX2: two halves of
//! four lanes, with the AVX2 path's operations in the same order, so that
//! both give the same bits.

use super::{RayNode, WIDTH};
use crate::aabb_tree::RaySlabs;
use wide::f32x4;

/// A ray as a node test needs it: per axis, the rows of [`RayNode::bounds`]
/// that hold its near and far planes, and the terms of
/// `((plane − origin) + shift) · (1 / direction)`, the binary tree's slab
/// test with its per-ray widening (`aabb_tree/ray.rs`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct NodeSlabs {
    pub(crate) near_row: [usize; 3],
    pub(crate) far_row: [usize; 3],
    pub(crate) origin: [f32; 3],
    pub(crate) inv_direction: [f32; 3],
    pub(crate) near_shift: [f32; 3],
    pub(crate) far_shift: [f32; 3],
}

impl NodeSlabs {
    pub(crate) fn new(slabs: &RaySlabs) -> Self {
        let negative = slabs.negative.bitmask();
        let near_row = std::array::from_fn(|k| 2 * k + ((negative >> k) & 1) as usize);
        Self {
            near_row,
            far_row: near_row.map(|row| row ^ 1),
            origin: slabs.origin.to_array(),
            inv_direction: slabs.inv_direction.to_array(),
            near_shift: slabs.near_shift.to_array(),
            far_shift: slabs.far_shift.to_array(),
        }
    }

    /// Entry parameters into the eight child boxes of `node`, and the lanes
    /// whose box the ray crosses within `[t_lo, t_hi]`.
    ///
    /// Each bound is taken as the SSE and AVX `max`/`min` instructions take
    /// it, `a > b ? a : b` with the plane's parameter as `a`: a NaN parameter
    /// (0 · ∞, the origin on a plane the ray runs along) leaves the running
    /// value unchanged, so the plane belongs to the box, as in the binary
    /// tree's test.
    #[inline(always)]
    pub(crate) fn entries(&self, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32) {
        let mut enter = [f32x4::splat(t_lo); 2];
        let mut exit = [f32x4::splat(t_hi); 2];
        for axis in 0..3 {
            let o = f32x4::splat(self.origin[axis]);
            let inv = f32x4::splat(self.inv_direction[axis]);
            let (near_shift, far_shift) = (f32x4::splat(self.near_shift[axis]), f32x4::splat(self.far_shift[axis]));
            let near: [[f32; 4]; 2] = bytemuck::cast(node.bounds[self.near_row[axis]]);
            let far: [[f32; 4]; 2] = bytemuck::cast(node.bounds[self.far_row[axis]]);
            for half in 0..2 {
                let t_near = ((f32x4::new(near[half]) - o) + near_shift) * inv;
                let t_far = ((f32x4::new(far[half]) - o) + far_shift) * inv;
                enter[half] = t_near.simd_gt(enter[half]).select(t_near, enter[half]);
                exit[half] = t_far.simd_lt(exit[half]).select(t_far, exit[half]);
            }
        }
        let mask = enter[0].simd_le(exit[0]).to_bitmask() | enter[1].simd_le(exit[1]).to_bitmask() << 4;
        (bytemuck::cast([enter[0].to_array(), enter[1].to_array()]), mask)
    }
}
