//! A ray, checked once: what every ray query takes.

use crate::math::Vec3;

/// A ray `origin + t · direction` for `t` in `[t_min, t_max]`, checked once
/// by one set of rules, shared by the trees' ray queries, the hash grid's
/// and the grid traversal:
///
/// - the origin is finite ([`RayError::Origin`]);
/// - the direction is finite, not zero, and not so small that the
///   reciprocal of its largest component overflows, which would make every
///   parameter infinite ([`RayError::Direction`]);
/// - the range is not NaN, starts at a finite value and is not reversed
///   ([`RayError::Range`]); it may end at `+∞`.
///
/// ```
/// use proxima::{Ray, RayError, Vec3};
/// let ray = Ray::new(Vec3::ZERO, Vec3::X).unwrap();
/// assert_eq!((ray.t_min(), ray.t_max()), (0.0, f32::INFINITY));
/// assert_eq!(Ray::new(Vec3::ZERO, Vec3::ZERO), Err(RayError::Direction));
/// assert!(Ray::with_range(Vec3::ZERO, Vec3::X, 2.0, 1.0).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
}

impl Ray {
    /// The ray from `origin` along `direction`, for `t` in `[0, +∞]`.
    pub fn new(origin: Vec3, direction: Vec3) -> Result<Self, RayError> {
        Self::with_range(origin, direction, 0.0, f32::INFINITY)
    }

    /// The ray from `origin` along `direction`, for `t` in `[t_min, t_max]`.
    pub fn with_range(origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<Self, RayError> {
        if !origin.is_finite() {
            return Err(RayError::Origin);
        }
        if !(direction.is_finite() && (1.0 / direction.abs().max_element()).is_finite()) {
            return Err(RayError::Direction);
        }
        if !(t_min.is_finite() && t_min <= t_max) {
            return Err(RayError::Range { t_min, t_max });
        }
        Ok(Self {
            origin,
            direction,
            t_min,
            t_max,
        })
    }

    /// Where the ray starts (at `t = 0`).
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The direction (not necessarily of unit length: `t` is in its units).
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// The start of the parameter range.
    pub fn t_min(&self) -> f32 {
        self.t_min
    }

    /// The end of the parameter range (possibly `+∞`).
    pub fn t_max(&self) -> f32 {
        self.t_max
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}

/// A ray that cannot be cast: every ray query returns it instead of
/// answering (the hash grid and the traversal wrap it, as
/// [`GridError::Ray`](crate::GridError::Ray)).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum RayError {
    /// A ray origin with a NaN or infinite coordinate.
    #[error("ray origin must be finite")]
    Origin,
    /// A ray direction that is zero, or has a NaN or infinite component.
    #[error("ray direction must be finite and non-zero")]
    Direction,
    /// A ray origin so far from the structure's bounds (more than 2^30 times
    /// the larger of their diagonal and their largest coordinate) that even
    /// `f64` cannot place the ray near them finely enough to tell their front
    /// from their back. Bounds of a single point (primitives of no area,
    /// which no ray hits) never give it.
    #[error(
        "ray origin lies too far from the mesh (more than 2^30 times the larger of its size and its coordinates) for \
         its hits to be told apart"
    )]
    OriginTooFar,
    /// A ray parameter range that is NaN, starts at an infinity, or has `t_min > t_max`.
    #[error("ray range [{t_min}, {t_max}] is not a valid interval")]
    Range {
        /// Start of the range.
        t_min: f32,
        /// End of the range.
        t_max: f32,
    },
}
