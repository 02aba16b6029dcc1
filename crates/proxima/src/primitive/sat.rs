//! The 1D projection step of the separating axis test (SAT).
//!
//! Two convex shapes are disjoint exactly when some axis exists along which
//! their *shadows* — the intervals obtained by projecting every point of each
//! shape onto the axis — are disjoint. For a polytope the shadow is spanned by
//! the projections of its vertices; for a box it is `center·axis ± half·|axis|`.
//!
//! Projections are computed in `f64`: the product of two `f32` values is exact
//! in `f64`, so for coordinates of moderate dynamic range the intervals carry
//! no rounding at all and *touching* shapes (closed sets sharing only boundary
//! points) produce intervals that share an end point, which [`Interval::overlaps`]
//! counts as overlap. A zero axis projects everything to `[0, 0]`, so it never
//! separates anything: callers need not filter degenerate axes out.
//!
//! ```
//! use proxima::primitive::sat::{Interval, Project};
//! use proxima::{Aabb, Triangle, Vec3};
//!
//! let tri = Triangle::new(Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 0.0, 2.0));
//! let unit = Aabb::new(Vec3::ZERO, Vec3::ONE);
//! let far = Aabb::new(Vec3::splat(0.7), Vec3::splat(1.0));
//! let n = tri.scaled_normal(); // (4, 4, 4): the triangle lies in x + y + z = 2
//! assert_eq!(tri.project(n), Interval::new(8.0, 8.0));
//! assert_eq!(unit.project(n), Interval::new(0.0, 12.0));
//! assert!(tri.project(n).overlaps(&unit.project(n))); // not separated by n
//! assert!(!tri.project(n).overlaps(&far.project(n))); // x + y + z >= 2.1 on `far`
//! assert!(proxima::primitive::sat::separated_along(&tri, &far, n));
//! // Touching counts: this box's corner (1, 1, 0) lies on the triangle's edge.
//! let touching = Aabb::new(Vec3::new(1.0, 1.0, 0.0), Vec3::new(2.0, 2.0, 1.0));
//! assert_eq!(touching.project(n), Interval::new(8.0, 20.0));
//! assert!(tri.project(n).overlaps(&touching.project(n)));
//! ```

use crate::aabb::Aabb;
use crate::math::Vec3;
use crate::primitive::{LineSegment, Point, Triangle};

/// A closed interval `[min, max]` of an axis: the shadow of a shape on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower end.
    pub min: f64,
    /// Upper end.
    pub max: f64,
}

impl Interval {
    /// The interval `[min, max]` (not reordered).
    #[inline]
    pub const fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// The smallest interval holding every value (empty, `min > max`, when there are none).
    #[inline]
    pub fn from_values(values: impl IntoIterator<Item = f64>) -> Self {
        values
            .into_iter()
            .fold(Self::new(f64::INFINITY, f64::NEG_INFINITY), |i, v| {
                Self::new(i.min.min(v), i.max.max(v))
            })
    }

    /// `true` when the closed intervals share at least one value (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Interval) -> bool {
        self.min <= other.max && other.min <= self.max
    }

    /// `true` when the intervals are disjoint: the axis separates the shapes.
    #[inline]
    pub fn separated_from(&self, other: &Interval) -> bool {
        !self.overlaps(other)
    }
}

/// `a · b` in `f64` (each product exact).
#[inline]
pub(crate) fn dot64(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The vector in `f64` (exact).
#[inline]
pub(crate) fn to64(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// The shadow of the points `points` on `axis`.
pub fn project_points(points: &[Vec3], axis: Vec3) -> Interval {
    let a = to64(axis);
    Interval::from_values(points.iter().map(|&p| dot64(to64(p), a)))
}

/// A convex shape that can say its shadow on an axis.
pub trait Project {
    /// The interval spanned by `axis · p` over every point `p` of the shape.
    /// The axis need not be normalized; a zero axis gives `[0, 0]`.
    fn project(&self, axis: Vec3) -> Interval;
}

impl Project for Aabb {
    /// Computed from the box's corners: `Σ min(lo·a, hi·a)` and `Σ max(lo·a, hi·a)`.
    #[inline]
    fn project(&self, axis: Vec3) -> Interval {
        let (lo, hi, a) = (to64(self.min), to64(self.max), to64(axis));
        let mut out = Interval::new(0.0, 0.0);
        for k in 0..3 {
            let (p, q) = (lo[k] * a[k], hi[k] * a[k]);
            out.min += p.min(q);
            out.max += p.max(q);
        }
        out
    }
}

impl Project for Triangle {
    #[inline]
    fn project(&self, axis: Vec3) -> Interval {
        project_points(&self.vertices(), axis)
    }
}

impl Project for LineSegment {
    #[inline]
    fn project(&self, axis: Vec3) -> Interval {
        project_points(&[self.a, self.b], axis)
    }
}

impl Project for Point {
    #[inline]
    fn project(&self, axis: Vec3) -> Interval {
        let v = dot64(to64(self.0), to64(axis));
        Interval::new(v, v)
    }
}

/// `true` when `axis` separates the two shapes (their shadows are disjoint).
/// `false` says nothing by itself: other axes may still separate them.
#[inline]
pub fn separated_along(a: &impl Project, b: &impl Project, axis: Vec3) -> bool {
    a.project(axis).separated_from(&b.project(axis))
}
