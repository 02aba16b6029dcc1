//! The ray tree's node test on 256-bit AVX2 lanes: the slab test of a
//! node's eight child boxes, the operations of [`NodeSlabs::entries`] in the
//! same order, so the same bits as without AVX2. (The leaf test, on triangle
//! packets, is in `simd/avx2.rs`.)
//!
//! Like `simd/avx2.rs`, the only `unsafe` is the call into a function
//! compiled for AVX2, made with an [`Avx2`] token, which exists only once
//! the running CPU has been seen to support AVX2.
#![allow(unsafe_code)]

use super::slabs::NodeSlabs;
use super::{RayNode, WIDTH};
use crate::simd::Avx2;
use core::arch::x86_64::{
    __m256, _CMP_LE_OQ, _mm256_add_ps, _mm256_cmp_ps, _mm256_max_ps, _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps,
    _mm256_set1_ps, _mm256_sub_ps,
};

/// [`NodeSlabs::entries`] on 256-bit lanes.
#[target_feature(enable = "avx2")]
#[inline]
fn entries(slabs: &NodeSlabs, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32) {
    let mut enter = _mm256_set1_ps(t_lo);
    let mut exit = _mm256_set1_ps(t_hi);
    for axis in 0..3 {
        let o = _mm256_set1_ps(slabs.origin[axis]);
        let inv = _mm256_set1_ps(slabs.inv_direction[axis]);
        let near: __m256 = bytemuck::cast(node.bounds[slabs.near_row[axis]]);
        let far: __m256 = bytemuck::cast(node.bounds[slabs.far_row[axis]]);
        let t_near = _mm256_mul_ps(
            _mm256_add_ps(_mm256_sub_ps(near, o), _mm256_set1_ps(slabs.near_shift[axis])),
            inv,
        );
        let t_far = _mm256_mul_ps(
            _mm256_add_ps(_mm256_sub_ps(far, o), _mm256_set1_ps(slabs.far_shift[axis])),
            inv,
        );
        // `vmaxps a, b` is `a > b ? a : b` (a NaN `a` gives `b`), and
        // `vminps` likewise: what the portable path spells out.
        enter = _mm256_max_ps(t_near, enter);
        exit = _mm256_min_ps(t_far, exit);
    }
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(enter, exit)) as u32;
    (bytemuck::cast(enter), mask)
}

/// [`NodeSlabs::entries`] on 256-bit lanes: the same bits. The token is
/// the proof that this CPU has AVX2.
#[inline(always)]
pub(super) fn node_entries(_: Avx2, slabs: &NodeSlabs, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32) {
    // SAFETY: an `Avx2` token exists, so `detect` saw AVX2 on this CPU.
    unsafe { entries(slabs, node, t_lo, t_hi) }
}
