//! Watertight ray / triangle intersection (Woop, Benthin and Wald, "Watertight
//! Ray/Triangle Intersection", JCGT 2013).
//!
//! The ray is turned once into a shear that maps its direction onto +z; each
//! triangle vertex is then translated and sheared the same way whichever
//! triangle it belongs to, and the three 2D edge functions decide whether the
//! ray's foot (the origin of the sheared plane) is inside. Two triangles
//! sharing an edge compute the *same* edge function for it, with opposite
//! signs, so a ray through the shared edge hits at least one of them: no ray
//! slips through the cracks of a closed mesh. Edge functions that come out
//! exactly zero are recomputed in `f64`, as the paper recommends. A ray
//! through an edge or a vertex counts as a hit; both faces count (no culling);
//! a degenerate (zero-area) triangle is never hit.

use super::Triangle;
use crate::math::Vec3;

/// A ray prepared for [`WatertightRay::intersect`].
///
/// ```
/// use proxima::primitive::WatertightRay;
/// use proxima::{Triangle, Vec3};
/// let ray = WatertightRay::new(Vec3::new(0.25, 0.25, -1.0), Vec3::Z).unwrap();
/// let tri = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
/// let hit = ray.intersect(&tri, 0.0, f32::INFINITY).unwrap();
/// assert_eq!((hit.t, hit.u, hit.v), (1.0, 0.25, 0.25));
/// // Through the shared edge of two triangles: both report the hit.
/// let edge = WatertightRay::new(Vec3::new(0.5, 0.5, 1.0), -Vec3::Z).unwrap();
/// assert!(edge.intersect(&tri, 0.0, 2.0).is_some());
/// assert!(edge.intersect(&Triangle::new(Vec3::X, Vec3::ONE.with_z(0.0), Vec3::Y), 0.0, 2.0).is_some());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WatertightRay {
    origin: Vec3,
    /// Permutation putting the direction's largest component last.
    kx: usize,
    ky: usize,
    kz: usize,
    /// Shear constants.
    sx: f32,
    sy: f32,
    sz: f32,
}

/// Where a ray meets a triangle: the hit point is `a + u (b − a) + v (c − a)`,
/// at `origin + t · direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weight of vertex `b`.
    pub u: f32,
    /// Barycentric weight of vertex `c`.
    pub v: f32,
    /// Which triangle of the primitive was hit: 0 for a triangle, the fan
    /// triangle `(v0, v[piece + 1], v[piece + 2])` for a
    /// [`ConvexPolygon`](crate::primitive::ConvexPolygon).
    pub piece: u32,
}

impl TriangleHit {
    /// The hits of a packet test's lanes (`t`, `u`, `v` lane by lane), on
    /// triangles (`piece` 0).
    #[inline(always)]
    pub(crate) fn lanes<const N: usize>(t: [f32; N], u: [f32; N], v: [f32; N]) -> [Self; N] {
        std::array::from_fn(|lane| Self {
            t: t[lane],
            u: u[lane],
            v: v[lane],
            piece: 0,
        })
    }
}

impl WatertightRay {
    /// Prepares the ray `origin + t · direction`; `None` when the direction is
    /// zero or either vector is not finite.
    pub fn new(origin: Vec3, direction: Vec3) -> Option<Self> {
        if !origin.is_finite() || !direction.is_finite() || direction == Vec3::ZERO {
            return None;
        }
        let abs = direction.abs();
        let kz = if abs.x >= abs.y && abs.x >= abs.z {
            0
        } else if abs.y >= abs.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if direction[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let dz = direction[kz];
        Some(Self {
            origin,
            kx,
            ky,
            kz,
            sx: direction[kx] / dz,
            sy: direction[ky] / dz,
            sz: 1.0 / dz,
        })
    }

    /// The ray's origin.
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The axis permutation `[kx, ky, kz]` (the direction's largest component
    /// last) and the shear `[sx, sy, sz]`, for tests written lane by lane.
    #[inline(always)]
    pub(crate) fn shear(&self) -> ([usize; 3], [f32; 3]) {
        ([self.kx, self.ky, self.kz], [self.sx, self.sy, self.sz])
    }

    /// The hit of the ray with `tri` at a parameter in `[t_min, t_max]`, if any.
    #[inline]
    pub fn intersect(&self, tri: &Triangle, t_min: f32, t_max: f32) -> Option<TriangleHit> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a = tri.a - self.origin;
        let b = tri.b - self.origin;
        let c = tri.c - self.origin;
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let f = |p: f32, q: f32, r: f32, s: f32| (p as f64 * q as f64 - r as f64 * s as f64) as f32;
            u = f(cx, by, cy, bx);
            v = f(ax, cy, ay, cx);
            w = f(bx, ay, by, ax);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let (az, bz, cz) = (self.sz * a[kz], self.sz * b[kz], self.sz * c[kz]);
        let mut t = (u * az + v * bz + w * cz) / det;
        if !t.is_finite() {
            // Products of coordinates near 1e17 overflow f32 although t does
            // not: the same expression in f64 (a hit at t = ∞ is no hit).
            let wide = |x: f32| x as f64;
            t = ((wide(u) * wide(az) + wide(v) * wide(bz) + wide(w) * wide(cz)) / wide(det)) as f32;
            if !t.is_finite() {
                return None;
            }
        }
        if !(t >= t_min && t <= t_max) {
            return None;
        }
        Some(TriangleHit {
            t,
            u: v / det,
            v: w / det,
            piece: 0,
        })
    }
}
