//! Four triangles tested at once: the closest point on each, branch free in
//! `f32x4`, bit for bit the same as [`Triangle::closest_point`].
//!
//! The lanes repeat the scalar routine's arithmetic (`closest_triangle.rs`)
//! operation for operation: the same differences, the same dot products
//! summed in the same order (`(x + y) + z`, as `Vec3A::dot`), the same
//! cross product (fused exactly where `Vec3A::cross` fuses it), the same
//! divisions, and the Voronoi regions chosen with the same priority (vertex
//! a, vertex b, edge ab, vertex c, edge ac, edge bc, face). IEEE arithmetic
//! is deterministic, so each lane gives the scalar answer. Slivers and
//! degenerate triangles, which the scalar routine sends to its `f64` path,
//! are marked at build time and answered by the scalar routine itself.

use crate::aabb::Aabb;
use crate::math::{Vec3, Vec3A};
use crate::memory::prefetch;
use crate::primitive::closest_triangle::{FAST_REACH2, takes_f64_path_x4};
use crate::primitive::{Triangle, TriangleHit, WatertightRay};
use wide::f32x4;

/// Up to four triangles of one leaf in structure of arrays form, with the
/// leaf-order slot of the first and each lane's input index (so that a tie
/// in distance, common where triangles share a vertex, is broken without a
/// cache miss on the tree's index array). Lanes past the leaf's end repeat
/// a real triangle and are masked out.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(16))]
pub(crate) struct TrianglePacket {
    /// Slot of lane 0 in the tree's leaf-order primitive array.
    pub(crate) first: u32,
    /// Lanes answered in `f32x4`.
    pub(crate) fast: u32,
    /// Lanes answered by the scalar routine (slivers, degenerate triangles).
    pub(crate) slow: u32,
    _pad: u32,
    /// Input index of each lane's triangle.
    pub(crate) index: [u32; 4],
    pub(crate) a: [[f32; 4]; 3],
    pub(crate) b: [[f32; 4]; 3],
    pub(crate) c: [[f32; 4]; 3],
}

const _: () = assert!(std::mem::size_of::<TrianglePacket>() == 176);

/// Three `f32x4`: one 3D vector per lane.
#[derive(Clone, Copy)]
pub(crate) struct V3 {
    pub(crate) x: f32x4,
    pub(crate) y: f32x4,
    pub(crate) z: f32x4,
}

impl V3 {
    #[inline(always)]
    pub(crate) fn splat(p: Vec3A) -> Self {
        Self {
            x: f32x4::splat(p.x),
            y: f32x4::splat(p.y),
            z: f32x4::splat(p.z),
        }
    }

    #[inline(always)]
    fn load(v: &[[f32; 4]; 3]) -> Self {
        Self {
            x: f32x4::new(v[0]),
            y: f32x4::new(v[1]),
            z: f32x4::new(v[2]),
        }
    }

    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }

    #[inline(always)]
    fn scale(self, s: f32x4) -> Self {
        Self {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// `(x x' + y y') + z z'`, the order of `Vec3A::dot`.
    #[inline(always)]
    pub(crate) fn dot(self, o: Self) -> f32x4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `Vec3A::cross` on SSE2: `(self.zxy * o - o.zxy * self).zxy`, the
    /// second product fused into the difference where the target has FMA.
    #[inline(always)]
    fn cross(self, o: Self) -> Self {
        Self {
            x: o.y.mul_neg_add(self.z, self.y * o.z),
            y: o.z.mul_neg_add(self.x, self.z * o.x),
            z: o.x.mul_neg_add(self.y, self.x * o.y),
        }
    }

    /// The three coordinates' lanes, as stored in a packet.
    #[inline(always)]
    fn rows(&self) -> [[f32; 4]; 3] {
        [self.x.to_array(), self.y.to_array(), self.z.to_array()]
    }

    /// Lane by lane, `t` where `mask` is set, else `self`.
    #[inline(always)]
    fn replace(self, mask: f32x4, t: Self) -> Self {
        Self {
            x: mask.select(t.x, self.x),
            y: mask.select(t.y, self.y),
            z: mask.select(t.z, self.z),
        }
    }

    /// Lane `lane` as a vector.
    #[inline(always)]
    pub(crate) fn lane(&self, lane: usize) -> Vec3A {
        Vec3A::new(
            self.x.as_array()[lane],
            self.y.as_array()[lane],
            self.z.as_array()[lane],
        )
    }
}

impl TrianglePacket {
    /// Packs `triangles` (1 to 4), the first of which sits at slot `first`,
    /// with their input indices `indices`.
    pub(crate) fn new(triangles: &[Triangle], indices: &[u32], first: u32) -> Self {
        assert!((1..=4).contains(&triangles.len()) && indices.len() == triangles.len());
        let last = triangles.len() - 1;
        let t: [&Triangle; 4] = std::array::from_fn(|lane| &triangles[lane.min(last)]);
        // The lanes are built in registers: written to the packet first and
        // loaded back as vectors, each load would wait on four scalar stores
        // (figures in docs/perf-log.md).
        let lanes = |vertex: fn(&Triangle) -> Vec3| -> V3 {
            let v = t.map(vertex);
            V3 {
                x: f32x4::new(v.map(|v| v.x)),
                y: f32x4::new(v.map(|v| v.y)),
                z: f32x4::new(v.map(|v| v.z)),
            }
        };
        let (a, b, c) = (lanes(|t| t.a), lanes(|t| t.b), lanes(|t| t.c));
        // The scalar routine's own test (`takes_f64_path`), on the same
        // values in the lanes: a lane is answered here exactly when the
        // scalar routine would take its fast path, whose arithmetic the
        // lanes repeat. Four lanes at once, because lane by lane with the
        // scalar function made the whole collapse measurably slower
        // (docs/perf-log.md).
        let (ab, ac) = (b.sub(a), c.sub(a));
        let (ab2, ac2) = (ab.dot(ab), ac.dot(ac));
        let n = ab.cross(ac);
        let slow = takes_f64_path_x4(ab2, ac2, n.dot(n)).to_bitmask();
        let real = (1u32 << triangles.len()) - 1;
        Self {
            first,
            fast: !slow & real,
            slow: slow & real,
            _pad: 0,
            index: std::array::from_fn(|lane| indices[lane.min(last)]),
            a: a.rows(),
            b: b.rows(),
            c: c.rows(),
        }
    }

    /// The box of the packet's triangles: what their boxes merged one by
    /// one give (the lanes past a leaf's end repeat a real triangle, so
    /// they add nothing). A refit reads a leaf's box from its packets, just
    /// made, instead of from its triangles again.
    #[inline]
    pub(crate) fn bounds(&self) -> Aabb {
        let axis = |k: usize| {
            let (a, b, c) = (f32x4::new(self.a[k]), f32x4::new(self.b[k]), f32x4::new(self.c[k]));
            let (low, high) = (a.min(b).min(c).to_array(), a.max(b).max(c).to_array());
            (
                low.into_iter().fold(f32::INFINITY, f32::min),
                high.into_iter().fold(f32::NEG_INFINITY, f32::max),
            )
        };
        let [x, y, z] = [0, 1, 2].map(axis);
        Aabb::new(Vec3::new(x.0, y.0, z.0), Vec3::new(x.1, y.1, z.1))
    }

    /// Which lanes of a packet a ray hits within `[t_min, t_max]`, with their hit,
    /// and which lanes need the scalar test (an edge function exactly zero, or a
    /// `t` beyond `f32`).
    #[inline(always)]
    pub(crate) fn ray_hits(&self, ray: &WatertightRay, t_min: f32, t_max: f32) -> (u32, [TriangleHit; 4], u32) {
        let packet = self;
        let ([kx, ky, kz], [sx, sy, sz]) = ray.shear();
        let origin = ray.origin().to_array();
        let o = [
            f32x4::splat(origin[0]),
            f32x4::splat(origin[1]),
            f32x4::splat(origin[2]),
        ];
        let (sx, sy, sz) = (f32x4::splat(sx), f32x4::splat(sy), f32x4::splat(sz));
        // (x, y, z) of one vertex in the ray's sheared frame, before z is scaled.
        let sheared = |v: &[[f32; 4]; 3]| {
            let px = f32x4::new(v[kx]) - o[kx];
            let py = f32x4::new(v[ky]) - o[ky];
            let pz = f32x4::new(v[kz]) - o[kz];
            (px - sx * pz, py - sy * pz, pz)
        };
        let (ax, ay, a_z) = sheared(&packet.a);
        let (bx, by, b_z) = sheared(&packet.b);
        let (cx, cy, c_z) = sheared(&packet.c);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = f32x4::ZERO;
        let lanes = packet.fast | packet.slow;
        let exact_zero = (u.simd_eq(zero) | v.simd_eq(zero) | w.simd_eq(zero)).to_bitmask() & lanes;
        let negative = u.simd_lt(zero) | v.simd_lt(zero) | w.simd_lt(zero);
        let positive = u.simd_gt(zero) | v.simd_gt(zero) | w.simd_gt(zero);
        let det = u + v + w;
        let t = (u * (sz * a_z) + v * (sz * b_z) + w * (sz * c_z)) / det;
        let inside = !(negative & positive)
            & det.simd_ne(zero)
            & t.simd_ge(f32x4::splat(t_min))
            & t.simd_le(f32x4::splat(t_max));
        // Lanes whose t overflowed f32 (coordinates near 1e17) go to the scalar
        // test too, which computes t again in f64.
        let overflow = (t.simd_ne(t) | t.abs().simd_eq(f32x4::splat(f32::INFINITY))).to_bitmask()
            & lanes
            & det.simd_ne(zero).to_bitmask();
        let exact_zero = exact_zero | overflow;
        let hit_lanes = inside.to_bitmask() & lanes & !exact_zero;
        let (t, bu, bv) = (t.to_array(), (v / det).to_array(), (w / det).to_array());
        (hit_lanes, TriangleHit::lanes(t, bu, bv), exact_zero)
    }

    /// The closest point of each lane's triangle to `p`, its squared
    /// distance, and the lanes where `p` is so far that the scalar routine
    /// may take its `f64` path (a superset); those and lanes outside
    /// [`fast`](Self::fast) are meaningless.
    #[inline(always)]
    pub(crate) fn closest(&self, p: &V3) -> (V3, f32x4, u32) {
        let zero = f32x4::ZERO;
        let (a, b, c) = (V3::load(&self.a), V3::load(&self.b), V3::load(&self.c));
        let ab = b.sub(a);
        let ac = c.sub(a);
        let n = ab.cross(ac);
        let ap = p.sub(a);
        let d1 = ab.dot(ap);
        let d2 = ac.dot(ap);
        let bp = p.sub(b);
        let d3 = ab.dot(bp);
        let d4 = ac.dot(bp);
        let cp = p.sub(c);
        let d5 = ab.dot(cp);
        let d6 = ac.dot(cp);
        let vc = d1 * d4 - d3 * d2;
        let vb = d5 * d2 - d1 * d6;
        let va = d3 * d6 - d5 * d4;
        let e = d4 - d3;
        let f = d5 - d6;
        // Regions, each with the priority the scalar routine's early returns give it.
        let in_a = d1.simd_le(zero) & d2.simd_le(zero);
        let in_b = d3.simd_ge(zero) & d4.simd_le(d3);
        let in_ab = vc.simd_le(zero) & d1.simd_ge(zero) & d3.simd_le(zero);
        let in_c = d6.simd_ge(zero) & d5.simd_le(d6);
        let in_ac = vb.simd_le(zero) & d2.simd_ge(zero) & d6.simd_le(zero);
        let in_bc = va.simd_le(zero) & e.simd_ge(zero) & f.simd_ge(zero);
        // Face, then the others from the lowest priority up.
        let mut q = p.sub(n.scale(n.dot(ap) / n.dot(n)));
        q = q.replace(in_bc, b.add(c.sub(b).scale(e / (e + f))));
        q = q.replace(in_ac, a.add(ac.scale(d2 / (d2 - d6))));
        q = q.replace(in_c, c);
        q = q.replace(in_ab, a.add(ab.scale(d1 / (d1 - d3))));
        q = q.replace(in_b, b);
        q = q.replace(in_a, a);
        let d = q.sub(*p);
        let far = ap.dot(ap).simd_gt(f32x4::splat(FAST_REACH2 / 4.0)).to_bitmask();
        (q, d.dot(d), far)
    }
}

/// Asks for every cache line of a triangle packet (176 bytes at a 16-byte
/// boundary: three or four lines).
#[inline(always)]
pub(crate) fn prefetch_packet(packet: &TrianglePacket) {
    prefetch(packet);
    prefetch(&packet.a[2]);
    prefetch(&packet.b[2]);
    prefetch(&packet.c[2]);
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::primitive::ClosestPoint;
    use crate::sample::Rng;

    fn vec(rng: &mut Rng, scale: f32) -> Vec3 {
        Vec3::new(
            rng.range(-scale, scale),
            rng.range(-scale, scale),
            rng.range(-scale, scale),
        )
    }

    /// A packet's box is its triangles' boxes merged, for packets of one to
    /// four triangles of every shape (the lanes past the end repeat one).
    #[test]
    fn packet_bounds_are_the_triangles_bounds() {
        use crate::primitive::Bounded;
        let mut rng = Rng::new(17);
        let all = triangles(&mut rng, 400);
        for (k, chunk) in all.chunks(4).enumerate() {
            let chunk = &chunk[..1 + k % 4];
            let indices: Vec<u32> = (0..chunk.len() as u32).collect();
            let packet = TrianglePacket::new(chunk, &indices, 0);
            let expected = chunk.iter().fold(Aabb::EMPTY, |b, t| b.merge(&t.bounds()));
            assert_eq!(packet.bounds(), expected, "{chunk:?}");
        }
    }

    /// Triangles of every shape: ordinary, thin across the sliver bound
    /// (sin² of the angle at `a` from 1e-7 to 1e-1), degenerate, tiny, huge.
    pub(crate) fn triangles(rng: &mut Rng, n: usize) -> Vec<Triangle> {
        (0..n)
            .map(|i| {
                let a = vec(rng, 1.0);
                let (b, c) = (a + vec(rng, 0.5), a + vec(rng, 0.5));
                match i % 8 {
                    0..=2 => Triangle::new(a, b, c),
                    3 | 4 => {
                        // Angle at a with sin² = 10^-(1 + 6u): c off the line ab.
                        let sin = 10f32.powf(-(1.0 + 6.0 * rng.unit() as f32) / 2.0);
                        let ab = b - a;
                        let off = ab.any_orthonormal_vector() * ab.length() * sin;
                        let t = rng.range(0.2, 1.5);
                        Triangle::new(a, b, a + ab * t + off * t)
                    }
                    5 => Triangle::new(a, b, if rng.unit() < 0.5 { a } else { a + (b - a) * 2.5 }),
                    6 => Triangle::new(a * 1e-20, b * 1e-20, c * 1e-20),
                    _ => Triangle::new(a * 1e18, b * 1e18, c * 1e18),
                }
            })
            .collect()
    }

    #[test]
    fn packets_equal_the_scalar_routine() {
        let mut rng = Rng::new(17);
        let tris = triangles(&mut rng, 4000);
        let mut slow = 0;
        for (k, chunk) in tris.chunks(4).enumerate() {
            // Leaves of 1 to 4 triangles.
            let chunk = &chunk[..1 + k % 4];
            let packet = TrianglePacket::new(chunk, &[0, 1, 2, 3][..chunk.len()], 0);
            assert_eq!(packet.fast | packet.slow, (1 << chunk.len()) - 1);
            assert_eq!(packet.fast & packet.slow, 0);
            // The lanes' sliver test decides as the scalar routine's own.
            for (lane, t) in chunk.iter().enumerate() {
                let (a, b, c) = (Vec3A::from(t.a), Vec3A::from(t.b), Vec3A::from(t.c));
                let (ab, ac) = (b - a, c - a);
                let scalar = crate::primitive::closest_triangle::takes_f64_path(ab, ac, ab.cross(ac));
                assert_eq!(packet.slow & (1 << lane) != 0, scalar, "{t:?}");
            }
            slow += packet.slow.count_ones();
            for j in 0..40 {
                let scale = [1e-20, 1.0, 3.0, 1e18][j % 4];
                let p = Vec3A::from(vec(&mut rng, scale));
                let (q, d2, far) = packet.closest(&V3::splat(p));
                for (lane, t) in chunk.iter().enumerate() {
                    if (packet.fast & !far) & (1 << lane) == 0 {
                        continue;
                    }
                    let expected = t.closest_point(p);
                    let got = q.lane(lane);
                    assert_eq!(
                        got.to_array().map(f32::to_bits),
                        expected.to_array().map(f32::to_bits),
                        "{t:?} at {p}"
                    );
                    assert_eq!(d2.as_array()[lane].to_bits(), (expected - p).length_squared().to_bits());
                }
            }
        }
        // Some lanes went to the scalar routine, most did not.
        assert!(slow > 100 && slow < 1500, "{slow} slow lanes");
    }
}
