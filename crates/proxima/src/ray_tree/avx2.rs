//! The ray tree's work on 256-bit AVX2 lanes: the slab test of a node's
//! eight child boxes (the operations of [`NodeSlabs::entries`] in the same
//! order) and the watertight test of a leaf's eight triangles (those of
//! [`TrianglePacket::ray_hits`]), so the same bits as without AVX2.
//!
//! Like `wide_tree/avx2.rs`, the only `unsafe` is the call into a function
//! compiled for AVX2, made through the [`Avx2`] token, which exists only
//! once the running CPU has been seen to support AVX2.
#![allow(unsafe_code)]

use super::slabs::NodeSlabs;
use super::{RayNode, WIDTH};
use crate::primitive::{TriangleHit, WatertightRay};
use crate::wide_tree::Avx2;
use crate::wide_tree::packet::TrianglePacket;
use core::arch::x86_64::{
    __m256, _CMP_EQ_OQ, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _CMP_NEQ_UQ, _mm256_add_ps, _mm256_and_ps,
    _mm256_andnot_ps, _mm256_cmp_ps, _mm256_div_ps, _mm256_max_ps, _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps,
    _mm256_or_ps, _mm256_set_m128, _mm256_set1_ps, _mm256_setzero_ps, _mm256_sub_ps,
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

impl Avx2 {
    /// [`NodeSlabs::entries`] on 256-bit lanes: the same bits.
    #[inline(always)]
    pub(crate) fn node_entries(self, slabs: &NodeSlabs, node: &RayNode, t_lo: f32, t_hi: f32) -> ([f32; WIDTH], u32) {
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { entries(slabs, node, t_lo, t_hi) }
    }
}

/// Lanes 0–3 from `lo`, 4–7 from `hi`.
#[target_feature(enable = "avx2")]
#[inline]
fn pair(lo: &[f32; 4], hi: &[f32; 4]) -> __m256 {
    _mm256_set_m128(bytemuck::cast(*hi), bytemuck::cast(*lo))
}

/// [`TrianglePacket::ray_hits`] for two packets at once: the operations of
/// the four-lane test in the same order on eight lanes (lanes 0–3 are
/// `lo`'s, 4–7 `hi`'s), so each lane's hit is bit for bit the same.
#[target_feature(enable = "avx2")]
#[inline]
fn ray_hits_pair(
    lo: &TrianglePacket,
    hi: &TrianglePacket,
    ray: &WatertightRay,
    t_min: f32,
    t_max: f32,
) -> (u32, [TriangleHit; 8], u32) {
    let ([kx, ky, kz], [sx, sy, sz]) = ray.shear();
    let origin = ray.origin().to_array();
    let o = origin.map(|x| _mm256_set1_ps(x));
    let (sx, sy, sz) = (_mm256_set1_ps(sx), _mm256_set1_ps(sy), _mm256_set1_ps(sz));
    let sheared = |lo: &[[f32; 4]; 3], hi: &[[f32; 4]; 3]| {
        let px = _mm256_sub_ps(pair(&lo[kx], &hi[kx]), o[kx]);
        let py = _mm256_sub_ps(pair(&lo[ky], &hi[ky]), o[ky]);
        let pz = _mm256_sub_ps(pair(&lo[kz], &hi[kz]), o[kz]);
        (
            _mm256_sub_ps(px, _mm256_mul_ps(sx, pz)),
            _mm256_sub_ps(py, _mm256_mul_ps(sy, pz)),
            pz,
        )
    };
    let (ax, ay, a_z) = sheared(&lo.a, &hi.a);
    let (bx, by, b_z) = sheared(&lo.b, &hi.b);
    let (cx, cy, c_z) = sheared(&lo.c, &hi.c);
    let u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
    let v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
    let w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
    let zero = _mm256_setzero_ps();
    let (eq, lt, gt, ne) = (
        |a, b| _mm256_cmp_ps::<_CMP_EQ_OQ>(a, b),
        |a, b| _mm256_cmp_ps::<_CMP_LT_OQ>(a, b),
        |a, b| _mm256_cmp_ps::<_CMP_GT_OQ>(a, b),
        |a, b| _mm256_cmp_ps::<_CMP_NEQ_UQ>(a, b),
    );
    let bits = |m: __m256| _mm256_movemask_ps(m) as u32;
    let lanes = (lo.fast | lo.slow) | (hi.fast | hi.slow) << 4;
    let exact_zero = bits(_mm256_or_ps(_mm256_or_ps(eq(u, zero), eq(v, zero)), eq(w, zero))) & lanes;
    let negative = _mm256_or_ps(_mm256_or_ps(lt(u, zero), lt(v, zero)), lt(w, zero));
    let positive = _mm256_or_ps(_mm256_or_ps(gt(u, zero), gt(v, zero)), gt(w, zero));
    let det = _mm256_add_ps(_mm256_add_ps(u, v), w);
    let t = _mm256_div_ps(
        _mm256_add_ps(
            _mm256_add_ps(
                _mm256_mul_ps(u, _mm256_mul_ps(sz, a_z)),
                _mm256_mul_ps(v, _mm256_mul_ps(sz, b_z)),
            ),
            _mm256_mul_ps(w, _mm256_mul_ps(sz, c_z)),
        ),
        det,
    );
    let det_nonzero = ne(det, zero);
    let in_range = _mm256_and_ps(
        _mm256_cmp_ps::<_CMP_GE_OQ>(t, _mm256_set1_ps(t_min)),
        _mm256_cmp_ps::<_CMP_LE_OQ>(t, _mm256_set1_ps(t_max)),
    );
    let inside = _mm256_and_ps(
        _mm256_andnot_ps(_mm256_and_ps(negative, positive), det_nonzero),
        in_range,
    );
    let infinite = _mm256_or_ps(
        eq(t, _mm256_set1_ps(f32::INFINITY)),
        eq(t, _mm256_set1_ps(f32::NEG_INFINITY)),
    );
    let overflow = bits(_mm256_or_ps(ne(t, t), infinite)) & lanes & bits(det_nonzero);
    let exact_zero = exact_zero | overflow;
    let hit_lanes = bits(inside) & lanes & !exact_zero;
    let (t, bu, bv): ([f32; 8], [f32; 8], [f32; 8]) = (
        bytemuck::cast(t),
        bytemuck::cast(_mm256_div_ps(v, det)),
        bytemuck::cast(_mm256_div_ps(w, det)),
    );
    (hit_lanes, TriangleHit::lanes(t, bu, bv), exact_zero)
}

impl Avx2 {
    /// [`TrianglePacket::ray_hits`] of `lo` (lanes 0–3) and `hi` (lanes
    /// 4–7) at once, both within `[t_min, t_max]`: the same bits.
    #[inline(always)]
    pub(crate) fn ray_hits_pair(
        self,
        lo: &TrianglePacket,
        hi: &TrianglePacket,
        ray: &WatertightRay,
        t_min: f32,
        t_max: f32,
    ) -> (u32, [TriangleHit; 8], u32) {
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { ray_hits_pair(lo, hi, ray, t_min, t_max) }
    }
}
