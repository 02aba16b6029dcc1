//! The AVX2 token, and two triangle packets at once on 256-bit AVX2 lanes,
//! chosen at run time.
//!
//! [`closest_pair`] is [`TrianglePacket::closest`] on eight lanes, and
//! [`ray_hits_pair`] is [`TrianglePacket::ray_hits`]: lanes 0–3 are the
//! first packet's, lanes 4–7 the second's. Each repeats the four-lane
//! routine operation for operation (no fused multiply-add, the same order of
//! every sum), so each lane's answer is bit for bit the scalar routine's;
//! the test below checks the closest points against
//! [`Triangle::closest_point`], the ray tree's tests the hits.
//!
//! The crate is compiled for baseline x86-64 (SSE2). With the ray tree's
//! node test (`ray_tree/avx2.rs`), this module is the only place with
//! `unsafe` code: calls into functions compiled for AVX2, made only through
//! an [`Avx2`] token, which exists only once the running CPU has been seen
//! to support AVX2.
//!
//! [`Triangle::closest_point`]: crate::primitive::ClosestPoint::closest_point
#![allow(unsafe_code)]

use super::packet::TrianglePacket;
use crate::primitive::closest_triangle::FAST_REACH2;
use crate::primitive::{TriangleHit, WatertightRay};
use core::arch::x86_64::{
    __m128, __m256, _CMP_EQ_OQ, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _CMP_NEQ_UQ, _mm256_add_ps,
    _mm256_and_ps, _mm256_andnot_ps, _mm256_blendv_ps, _mm256_cmp_ps, _mm256_div_ps, _mm256_max_ps, _mm256_min_ps,
    _mm256_movemask_ps, _mm256_mul_ps, _mm256_or_ps, _mm256_set_m128, _mm256_set1_ps, _mm256_setzero_ps, _mm256_sub_ps,
};

/// Proof that the running CPU supports AVX2: made only by [`Avx2::detect`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2(());

impl Avx2 {
    /// The token, if this CPU supports AVX2.
    pub(crate) fn detect() -> Option<Self> {
        std::is_x86_feature_detected!("avx2").then_some(Self(()))
    }

    /// Runs `task` inside a function compiled for AVX2, so that the task
    /// (`#[inline(always)]` all the way down) and the [`closest_pair`] calls
    /// inlined into it use 256-bit lanes and VEX encodings. A trait rather
    /// than a closure: a closure's body is not certain to be inlined.
    #[inline(always)]
    pub(crate) fn run<K: Avx2Task>(self, task: K) -> K::Output {
        #[target_feature(enable = "avx2")]
        #[inline]
        fn with_avx2<K: Avx2Task>(token: Avx2, task: K) -> K::Output {
            task.call(token)
        }
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { with_avx2(self, task) }
    }

    /// [`closest_pair`] for the pair of packets `(lo, hi)`.
    #[inline(always)]
    pub(crate) fn closest_pair(self, lo: &TrianglePacket, hi: &TrianglePacket, p: &V8) -> (V8, __m256, u32) {
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { closest_pair(lo, hi, p) }
    }

    /// The query point on eight lanes.
    #[inline(always)]
    pub(crate) fn splat(self, x: f32, y: f32, z: f32) -> V8 {
        #[target_feature(enable = "avx2")]
        #[inline]
        fn splat(x: f32, y: f32, z: f32) -> V8 {
            V8 {
                x: _mm256_set1_ps(x),
                y: _mm256_set1_ps(y),
                z: _mm256_set1_ps(z),
            }
        }
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { splat(x, y, z) }
    }

    /// [`box_beyond`] for the pair of packets `(lo, hi)`.
    #[inline(always)]
    pub(crate) fn box_beyond(self, lo: &TrianglePacket, hi: &TrianglePacket, p: &V8, threshold: f32) -> u32 {
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { box_beyond(lo, hi, p, threshold) }
    }

    /// Lanes where `d2 <= bound`, as bits.
    #[inline(always)]
    pub(crate) fn within(self, d2: __m256, bound: f32) -> u32 {
        #[target_feature(enable = "avx2")]
        #[inline]
        fn within(d2: __m256, bound: f32) -> u32 {
            _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(d2, _mm256_set1_ps(bound))) as u32
        }
        // SAFETY: `self` exists, so `detect` saw AVX2 on this CPU.
        unsafe { within(d2, bound) }
    }
}

/// Work to run compiled for AVX2 ([`Avx2::run`]); `call` must be `#[inline(always)]`.
pub(crate) trait Avx2Task {
    /// What the task returns.
    type Output;
    /// Runs the task.
    fn call(self, avx2: Avx2) -> Self::Output;
}

/// Three `__m256`: one 3D vector per lane.
#[derive(Clone, Copy)]
pub(crate) struct V8 {
    x: __m256,
    y: __m256,
    z: __m256,
}

impl V8 {
    /// Lane `lane`'s x, y, z.
    #[inline(always)]
    pub(crate) fn lane(&self, lane: usize) -> [f32; 3] {
        let (x, y, z): ([f32; 8], [f32; 8], [f32; 8]) =
            (bytemuck::cast(self.x), bytemuck::cast(self.y), bytemuck::cast(self.z));
        [x[lane], y[lane], z[lane]]
    }
}

/// Lane `lane` of `v`.
#[inline(always)]
pub(crate) fn lane_of(v: __m256, lane: usize) -> f32 {
    bytemuck::cast::<__m256, [f32; 8]>(v)[lane]
}

#[target_feature(enable = "avx2")]
#[inline]
fn load(lo: &[[f32; 4]; 3], hi: &[[f32; 4]; 3]) -> V8 {
    let half = |v: [f32; 4]| bytemuck::cast::<[f32; 4], __m128>(v);
    V8 {
        x: _mm256_set_m128(half(hi[0]), half(lo[0])),
        y: _mm256_set_m128(half(hi[1]), half(lo[1])),
        z: _mm256_set_m128(half(hi[2]), half(lo[2])),
    }
}

#[target_feature(enable = "avx2")]
#[inline]
fn sub(a: V8, b: V8) -> V8 {
    V8 {
        x: _mm256_sub_ps(a.x, b.x),
        y: _mm256_sub_ps(a.y, b.y),
        z: _mm256_sub_ps(a.z, b.z),
    }
}

#[target_feature(enable = "avx2")]
#[inline]
fn add(a: V8, b: V8) -> V8 {
    V8 {
        x: _mm256_add_ps(a.x, b.x),
        y: _mm256_add_ps(a.y, b.y),
        z: _mm256_add_ps(a.z, b.z),
    }
}

#[target_feature(enable = "avx2")]
#[inline]
fn scale(a: V8, s: __m256) -> V8 {
    V8 {
        x: _mm256_mul_ps(a.x, s),
        y: _mm256_mul_ps(a.y, s),
        z: _mm256_mul_ps(a.z, s),
    }
}

/// `(x x' + y y') + z z'`, the order of `Vec3A::dot`.
#[target_feature(enable = "avx2")]
#[inline]
fn dot(a: V8, b: V8) -> __m256 {
    _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(a.x, b.x), _mm256_mul_ps(a.y, b.y)),
        _mm256_mul_ps(a.z, b.z),
    )
}

/// As the four-lane `cross` without FMA: `y z' - y' z`, and so on.
#[target_feature(enable = "avx2")]
#[inline]
fn cross(a: V8, b: V8) -> V8 {
    V8 {
        x: _mm256_sub_ps(_mm256_mul_ps(a.y, b.z), _mm256_mul_ps(b.y, a.z)),
        y: _mm256_sub_ps(_mm256_mul_ps(a.z, b.x), _mm256_mul_ps(b.z, a.x)),
        z: _mm256_sub_ps(_mm256_mul_ps(a.x, b.y), _mm256_mul_ps(b.x, a.y)),
    }
}

/// Lane by lane, `t` where `mask` is set, else `v`.
#[target_feature(enable = "avx2")]
#[inline]
fn replace(v: V8, mask: __m256, t: V8) -> V8 {
    V8 {
        x: _mm256_blendv_ps(v.x, t.x, mask),
        y: _mm256_blendv_ps(v.y, t.y, mask),
        z: _mm256_blendv_ps(v.z, t.z, mask),
    }
}

#[target_feature(enable = "avx2")]
#[inline]
fn le(a: __m256, b: __m256) -> __m256 {
    _mm256_cmp_ps::<_CMP_LE_OQ>(a, b)
}

#[target_feature(enable = "avx2")]
#[inline]
fn ge(a: __m256, b: __m256) -> __m256 {
    _mm256_cmp_ps::<_CMP_GE_OQ>(a, b)
}

/// [`TrianglePacket::closest`] for two packets at once: the closest point of
/// each lane's triangle to `p`, its squared distance, and the lanes (bits 0–3
/// of `lo`, 4–7 of `hi`) where `p` is so far that the scalar routine may take
/// its `f64` path. Lanes outside the packets' `fast` masks are meaningless.
#[target_feature(enable = "avx2")]
#[inline]
fn closest_pair(lo: &TrianglePacket, hi: &TrianglePacket, p: &V8) -> (V8, __m256, u32) {
    let zero = _mm256_setzero_ps();
    let (a, b, c) = (load(&lo.a, &hi.a), load(&lo.b, &hi.b), load(&lo.c, &hi.c));
    let p = *p;
    let ab = sub(b, a);
    let ac = sub(c, a);
    let n = cross(ab, ac);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    let vc = _mm256_sub_ps(_mm256_mul_ps(d1, d4), _mm256_mul_ps(d3, d2));
    let vb = _mm256_sub_ps(_mm256_mul_ps(d5, d2), _mm256_mul_ps(d1, d6));
    let va = _mm256_sub_ps(_mm256_mul_ps(d3, d6), _mm256_mul_ps(d5, d4));
    let e = _mm256_sub_ps(d4, d3);
    let f = _mm256_sub_ps(d5, d6);
    let and = _mm256_and_ps;
    let in_a = and(le(d1, zero), le(d2, zero));
    let in_b = and(ge(d3, zero), le(d4, d3));
    let in_ab = and(and(le(vc, zero), ge(d1, zero)), le(d3, zero));
    let in_c = and(ge(d6, zero), le(d5, d6));
    let in_ac = and(and(le(vb, zero), ge(d2, zero)), le(d6, zero));
    let in_bc = and(and(le(va, zero), ge(e, zero)), ge(f, zero));
    let mut q = sub(p, scale(n, _mm256_div_ps(dot(n, ap), dot(n, n))));
    q = replace(
        q,
        in_bc,
        add(b, scale(sub(c, b), _mm256_div_ps(e, _mm256_add_ps(e, f)))),
    );
    q = replace(q, in_ac, add(a, scale(ac, _mm256_div_ps(d2, _mm256_sub_ps(d2, d6)))));
    q = replace(q, in_c, c);
    q = replace(q, in_ab, add(a, scale(ab, _mm256_div_ps(d1, _mm256_sub_ps(d1, d3)))));
    q = replace(q, in_b, b);
    q = replace(q, in_a, a);
    let d = sub(q, p);
    let far = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(
        dot(ap, ap),
        _mm256_set1_ps(FAST_REACH2 / 4.0),
    )) as u32;
    (q, dot(d, d), far)
}

/// The lanes (bits 0–3 of `lo`, 4–7 of `hi`) whose triangle's box lies
/// farther than `threshold` from `p`, in squared distance: about a quarter
/// of the work of [`closest_pair`], and enough to skip a pair none of whose
/// triangles can be within reach.
#[target_feature(enable = "avx2")]
#[inline]
fn box_beyond(lo: &TrianglePacket, hi: &TrianglePacket, p: &V8, threshold: f32) -> u32 {
    let zero = _mm256_setzero_ps();
    let (a, b, c) = (load(&lo.a, &hi.a), load(&lo.b, &hi.b), load(&lo.c, &hi.c));
    let axis = |a: __m256, b: __m256, c: __m256, p: __m256| {
        let low = _mm256_min_ps(_mm256_min_ps(a, b), c);
        let high = _mm256_max_ps(_mm256_max_ps(a, b), c);
        let d = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(low, p), _mm256_sub_ps(p, high)), zero);
        _mm256_mul_ps(d, d)
    };
    let d2 = _mm256_add_ps(
        _mm256_add_ps(axis(a.x, b.x, c.x, p.x), axis(a.y, b.y, c.y, p.y)),
        axis(a.z, b.z, c.z, p.z),
    );
    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(d2, _mm256_set1_ps(threshold))) as u32
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3A;
    use crate::primitive::ClosestPoint;
    use crate::sample::Rng;

    /// Each lane of the pair routine equals the four-lane routine and the
    /// scalar one, bit for bit, on triangles of every shape.
    #[test]
    fn pairs_equal_the_four_lane_and_scalar_routines() {
        let Some(avx2) = Avx2::detect() else {
            eprintln!("note: this CPU has no AVX2; the eight-lane routine is not used here and not tested");
            return;
        };
        let mut rng = Rng::new(29);
        let tris = super::super::triangles(&mut rng, 4000);
        let mut checked = 0;
        for chunk in tris.chunks(8) {
            let (lo, hi) = (
                TrianglePacket::new(&chunk[..4], &[0, 1, 2, 3], 0),
                TrianglePacket::new(&chunk[4..], &[4, 5, 6, 7], 4),
            );
            for j in 0..40 {
                let s = [1e-20, 1.0, 3.0, 1e18][j % 4];
                let p = Vec3A::new(rng.range(-s, s), rng.range(-s, s), rng.range(-s, s));
                let v = avx2.splat(p.x, p.y, p.z);
                let (q, d2, far) = avx2.closest_pair(&lo, &hi, &v);
                let (q4, d4, far4) = lo.closest(&super::super::V3::splat(p));
                assert_eq!(far & 0xf, far4);
                for (lane, t) in chunk.iter().enumerate() {
                    let packet = if lane < 4 { &lo } else { &hi };
                    if (packet.fast >> (lane % 4)) & 1 == 0 || (far >> lane) & 1 == 1 {
                        continue;
                    }
                    let expected = t.closest_point(p);
                    let got = q.lane(lane);
                    assert_eq!(
                        got.map(f32::to_bits),
                        expected.to_array().map(f32::to_bits),
                        "{t:?} at {p}"
                    );
                    assert_eq!(lane_of(d2, lane).to_bits(), (expected - p).length_squared().to_bits());
                    if lane < 4 {
                        assert_eq!(got, q4.lane(lane).to_array());
                        assert_eq!(lane_of(d2, lane).to_bits(), d4.as_array()[lane].to_bits());
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked > 40_000, "{checked} lanes checked");
    }
}
