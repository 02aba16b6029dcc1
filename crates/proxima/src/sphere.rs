//! Bounding spheres.
//!
//! Two ways to bound a point set: [`Sphere::from_points`] (Ritter's
//! two-pass approximation, within about 5-20% of the smallest sphere) and
//! [`Sphere::from_points_tight`] (Ritter followed by shrink-and-regrow passes,
//! usually within a few percent). Both return a sphere that contains every point for
//! certain: whatever the center came out as, the radius is recomputed as the
//! largest distance from it, in `f64`, and rounded up to `f32`.

use crate::math::{DVec3, Vec3, Vec3A};

/// A sphere: all points within `radius` of `center`.
///
/// ```
/// use proxima::{Sphere, Vec3};
/// let points = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.3, 0.4, 0.9)];
/// let sphere = Sphere::from_points_tight(&points).unwrap();
/// assert!(points.iter().all(|&p| sphere.contains_point(p))); // for certain, not within rounding
/// assert!(Sphere::from_points(&[]).is_none());
/// ```
// Plain data (`Pod`), as a tree node's volume.
#[derive(Clone, Copy, Debug, PartialEq, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct Sphere {
    /// Center.
    pub center: Vec3,
    /// Radius (0 for a single point).
    pub radius: f32,
}

/// Refinement passes of [`Sphere::from_points_tight`].
const REFINE_PASSES: usize = 4;
/// Each refinement pass starts from the best radius so far times this factor.
const SHRINK: f64 = 0.95;

type V = DVec3;

#[inline]
fn wide(v: Vec3) -> V {
    v.as_dvec3()
}

/// `x` rounded to an `f32` that is at least `x`.
#[inline]
fn round_up(x: f64) -> f32 {
    let r = x as f32;
    if (r as f64) < x { r.next_up() } else { r }
}

impl Sphere {
    /// The sphere of center `center` and radius `radius`.
    #[inline]
    pub const fn new(center: Vec3, radius: f32) -> Self {
        Self { center, radius }
    }

    /// `true` when `p` lies in the closed ball (decided in `f64`, so exactly
    /// up to the rounding of one square root).
    pub fn contains_point(&self, p: Vec3) -> bool {
        wide(p).distance(wide(self.center)) <= self.radius as f64
    }

    /// `true` when `other` lies entirely in this sphere.
    pub fn contains(&self, other: &Sphere) -> bool {
        wide(other.center).distance(wide(self.center)) + other.radius as f64 <= self.radius as f64
    }

    /// Squared distance from `p` to the ball (0 inside).
    #[inline]
    pub fn distance_squared(&self, p: Vec3A) -> f32 {
        let d = (p - Vec3A::from(self.center)).length() - self.radius;
        if d > 0.0 { d * d } else { 0.0 }
    }

    /// The smallest sphere holding both spheres (computed in `f64`; the
    /// result is rounded so that it holds both for certain).
    pub fn merge(&self, other: &Sphere) -> Sphere {
        if self.contains(other) {
            return *self;
        }
        if other.contains(self) {
            return *other;
        }
        let (c1, c2) = (wide(self.center), wide(other.center));
        let (r1, r2) = (self.radius as f64, other.radius as f64);
        let d = c1.distance(c2);
        let radius = 0.5 * (d + r1 + r2);
        let center = if d > 0.0 {
            c1 + (c2 - c1) * ((radius - r1) / d)
        } else {
            c1
        };
        let center = center.as_vec3();
        // The rounded center moved a little: measure again from it.
        let c = wide(center);
        let needed = (c.distance(c1) + r1).max(c.distance(c2) + r2);
        Sphere::new(center, round_up(needed))
    }

    /// The radius a sphere centered at `center` needs to hold every point
    /// (the largest distance, computed in `f64` and rounded up).
    pub fn enclosing_radius(center: Vec3, points: &[Vec3]) -> f32 {
        let c = wide(center);
        let max = points.iter().map(|&p| wide(p).distance_squared(c)).fold(0.0, f64::max);
        round_up(max.sqrt())
    }

    /// Ritter's bounding sphere: the sphere over the farthest-apart pair of
    /// the six extreme points along the axes, grown in one pass over the
    /// points until it holds them all. `None` for no points.
    pub fn from_points(points: &[Vec3]) -> Option<Sphere> {
        let (center, radius) = ritter(points)?;
        Some(Self::finish(center, radius, points))
    }

    /// A tighter sphere than [`from_points`](Self::from_points): starting from
    /// Ritter's, four passes each shrink the best radius so far
    /// by 5% and grow the sphere again over the points (in alternating
    /// order), keeping the smallest (Ericson, *Real-Time Collision Detection*,
    /// 4.3.4, made deterministic). Never larger than Ritter's. `None` for no points.
    pub fn from_points_tight(points: &[Vec3]) -> Option<Sphere> {
        let (ritter_center, ritter_radius) = ritter(points)?;
        let (mut best_center, mut best_radius) = (ritter_center, ritter_radius);
        let (mut center, mut radius) = (best_center, best_radius);
        for pass in 0..REFINE_PASSES {
            radius *= SHRINK;
            if pass % 2 == 0 {
                points
                    .iter()
                    .rev()
                    .for_each(|&p| grow(&mut center, &mut radius, wide(p)));
            } else {
                points.iter().for_each(|&p| grow(&mut center, &mut radius, wide(p)));
            }
            if radius < best_radius {
                (best_center, best_radius) = (center, radius);
            }
        }
        let refined = Self::finish(best_center, best_radius, points);
        // Rounding the center can cost the refined sphere its small lead.
        let plain = Self::finish(ritter_center, ritter_radius, points);
        Some(if refined.radius <= plain.radius { refined } else { plain })
    }

    /// Rounds the center to `f32` and measures the radius from it exactly.
    fn finish(center: V, radius: f64, points: &[Vec3]) -> Sphere {
        debug_assert!(radius >= 0.0);
        let center = center.as_vec3();
        Sphere::new(center, Self::enclosing_radius(center, points))
    }
}

/// Ritter's sphere in `f64`: center and (approximate) radius.
fn ritter(points: &[Vec3]) -> Option<(V, f64)> {
    let first = wide(*points.first()?);
    // The extreme points along each axis.
    let mut low = [first; 3];
    let mut high = [first; 3];
    for &p in points {
        let p = wide(p);
        for axis in 0..3 {
            if p[axis] < low[axis][axis] {
                low[axis] = p;
            }
            if p[axis] > high[axis][axis] {
                high[axis] = p;
            }
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| {
            low[a]
                .distance_squared(high[a])
                .total_cmp(&low[b].distance_squared(high[b]))
        })
        .unwrap_or(0);
    let mut center = (low[axis] + high[axis]) * 0.5;
    let mut radius = low[axis].distance(high[axis]) * 0.5;
    for &p in points {
        grow(&mut center, &mut radius, wide(p));
    }
    Some((center, radius))
}

/// Ritter's growth step: the smallest sphere holding the current one and `p`.
#[inline]
fn grow(center: &mut V, radius: &mut f64, p: V) {
    // Most points are inside: compare squares, take the root only to grow.
    let d2 = p.distance_squared(*center);
    if d2 > *radius * *radius {
        let d = d2.sqrt();
        let new_radius = 0.5 * (*radius + d);
        *center += (p - *center) * ((new_radius - *radius) / d);
        *radius = new_radius;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_point_and_empty() {
        assert_eq!(Sphere::from_points(&[]), None);
        let s = Sphere::from_points(&[Vec3::new(1.0, 2.0, 3.0)]).unwrap();
        assert_eq!(s, Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.0));
    }

    #[test]
    fn merge_holds_both() {
        let a = Sphere::new(Vec3::ZERO, 1.0);
        let b = Sphere::new(Vec3::new(3.0, 0.0, 0.0), 0.5);
        let m = a.merge(&b);
        assert!(m.contains(&a) && m.contains(&b));
        assert!((m.radius - 2.25).abs() < 1e-6, "{m:?}");
        assert_eq!(a.merge(&Sphere::new(Vec3::X * 0.1, 0.2)), a);
    }
}
