//! Axis-aligned bounding boxes.

use crate::math::{DVec3, Vec3, Vec3A};

/// An axis-aligned box, closed: points on its faces belong to it.
///
/// The empty box ([`Aabb::EMPTY`]) has `min = +inf`, `max = -inf`, so that
/// growing it by a point gives the box of that point.
///
/// ```
/// use proxima::{Aabb, Vec3};
/// let mut b = Aabb::EMPTY;
/// b.grow(Vec3::new(0.0, 1.0, 2.0));
/// b.grow(Vec3::new(2.0, -1.0, 2.0));
/// assert_eq!(b.center(), Vec3::new(1.0, 0.0, 2.0));
/// assert_eq!(b.largest_axis(), 0);
/// assert!(b.contains_point(Vec3::new(2.0, 1.0, 2.0)));
/// ```
// Plain data (`Pod`), so that tree nodes holding one can live in typed
// huge-page arrays.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The empty box: contains nothing, and is the identity of [`Aabb::merge`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box with corners `min` and `max` (not reordered).
    #[inline]
    pub const fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The smallest box holding every point of `points` (empty when there are none).
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        let mut b = Self::EMPTY;
        for p in points {
            b.grow(p);
        }
        b
    }

    /// `true` for a box with `min > max` on some axis (such as [`Aabb::EMPTY`]).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// `true` when both corners are finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// Middle of the box.
    #[inline]
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Side lengths (`max - min`).
    #[inline]
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    /// Half the side lengths.
    #[inline]
    pub fn extents(&self) -> Vec3 {
        self.size() * 0.5
    }

    /// Length of the diagonal (0 for a point box).
    #[inline]
    pub fn diagonal(&self) -> f32 {
        if self.is_empty() { 0.0 } else { self.size().length() }
    }

    /// Index (0 = x, 1 = y, 2 = z) of the longest side; ties go to the lower axis.
    #[inline]
    pub fn largest_axis(&self) -> usize {
        let s = self.size();
        if s.x >= s.y && s.x >= s.z {
            0
        } else if s.y >= s.z {
            1
        } else {
            2
        }
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The smallest `f32` box holding the `f64` box `[min, max]`: each bound
    /// rounded outward where it is not an `f32` (a grid's exact cell planes,
    /// for example).
    ///
    /// ```
    /// use proxima::{Aabb, DVec3, Vec3};
    /// let third = 1.0 / 3.0;
    /// let b = Aabb::enclosing(DVec3::splat(third), DVec3::splat(1.0));
    /// // The largest f32 at most 1/3, and exactly 1 above.
    /// assert!((b.min.x as f64) <= third && (b.min.x.next_up() as f64) > third);
    /// assert_eq!(b.max, Vec3::ONE);
    /// ```
    pub fn enclosing(min: DVec3, max: DVec3) -> Aabb {
        let down = |x: f64| {
            let r = x as f32;
            if r as f64 > x { r.next_down() } else { r }
        };
        let up = |x: f64| {
            let r = x as f32;
            if (r as f64) < x { r.next_up() } else { r }
        };
        Aabb::new(
            Vec3::new(down(min.x), down(min.y), down(min.z)),
            Vec3::new(up(max.x), up(max.y), up(max.z)),
        )
    }

    /// The smallest box holding both boxes.
    #[inline]
    pub fn merge(&self, other: &Aabb) -> Aabb {
        Aabb::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// The box grown by `margin` on every side.
    #[inline]
    pub fn inflate(&self, margin: f32) -> Aabb {
        Aabb::new(self.min - Vec3::splat(margin), self.max + Vec3::splat(margin))
    }

    /// `true` when `p` lies in the closed box.
    #[inline]
    pub fn contains_point(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// `true` when `other` lies entirely inside this box.
    #[inline]
    pub fn contains(&self, other: &Aabb) -> bool {
        other.min.cmpge(self.min).all() && other.max.cmple(self.max).all()
    }

    /// `true` when the closed boxes share at least one point (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// The overlap of the two boxes (empty when they are disjoint).
    #[inline]
    pub fn intersection(&self, other: &Aabb) -> Aabb {
        Aabb::new(self.min.max(other.min), self.max.min(other.max))
    }

    /// Squared distance from `p` to the closest point of the box (0 inside).
    #[inline]
    pub fn distance_squared(&self, p: Vec3) -> f32 {
        self.distance_squared_a(Vec3A::from(p))
    }

    /// [`Aabb::distance_squared`] with a SIMD-friendly query point.
    #[inline]
    pub fn distance_squared_a(&self, p: Vec3A) -> f32 {
        let min = Vec3A::from(self.min);
        let max = Vec3A::from(self.max);
        let d = (min - p).max(p - max).max(Vec3A::ZERO);
        d.length_squared()
    }

    /// The point of the box closest to `p`.
    #[inline]
    pub fn closest_point(&self, p: Vec3) -> Vec3 {
        p.clamp(self.min, self.max)
    }

    /// Surface area (0 for an empty box).
    #[inline]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let s = self.size();
        2.0 * (s.x * s.y + s.y * s.z + s.z * s.x)
    }

    /// Volume (0 for an empty box).
    #[inline]
    pub fn volume(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let s = self.size();
        s.x * s.y * s.z
    }

    /// The eight corners; bit 0 of the index picks max x, bit 1 max y, bit 2 max z.
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// Slab test: the parameter interval `[t_enter, t_exit]` within `[t_min, t_max]`
    /// where the ray `origin + t * direction` is inside the closed box, or `None`.
    ///
    /// `inv_direction` is `1 / direction` per component (infinite for a zero
    /// component); precompute it once per ray. A ray lying exactly in a slab's
    /// boundary plane counts as inside.
    ///
    /// ```
    /// use proxima::{Aabb, Vec3};
    /// let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    /// let (t0, t1) = b
    ///     .ray_interval(Vec3::new(-1.0, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0).recip(), 0.0, f32::INFINITY)
    ///     .unwrap();
    /// assert_eq!((t0, t1), (1.0, 2.0));
    /// ```
    #[inline]
    pub fn ray_interval(&self, origin: Vec3, inv_direction: Vec3, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        let mut t0 = t_min;
        let mut t1 = t_max;
        for axis in 0..3 {
            let inv = inv_direction[axis];
            let o = origin[axis];
            let (lo, hi) = (self.min[axis], self.max[axis]);
            if inv.is_infinite() {
                // Parallel to this slab: inside for all t or for none.
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let a = (lo - o) * inv;
            let b = (hi - o) * inv;
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            t0 = t0.max(near);
            t1 = t1.min(far);
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }
}
