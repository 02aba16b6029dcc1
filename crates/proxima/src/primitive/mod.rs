//! Geometric primitives taken from a mesh, and the small traits that say what
//! each can do.
//!
//! The acceleration structures are generic over these traits, the way rstar's
//! `RTreeObject` / `PointDistance` work: a primitive that can say its
//! [`Bounded::bounds`] can go into a tree; one that can also say its
//! [`ClosestPoint::closest_point`] answers closest-point queries.

pub mod closest_f64;
mod closest_polygon;
pub(crate) mod closest_triangle;
mod convex_box;
pub(crate) mod exact_sat;
mod point;
mod point_aabb;
pub mod polygon;
mod polygon_aabb;
mod ray_intersect;
pub mod ray_triangle;
pub mod sat;
mod segment;
pub(crate) mod segment_aabb;
mod triangle;
mod triangle_aabb;

pub use convex_box::ConvexBoxTest;
pub use point::Point;
pub use polygon::{ConvexPolygon, PolygonHit};
pub use polygon_aabb::PolygonBoxTest;
pub use ray_intersect::RayIntersect;
pub use ray_triangle::{TriangleHit, WatertightRay};
pub use segment::LineSegment;
pub use triangle::Triangle;
pub use triangle_aabb::TriangleBoxTest;

use crate::aabb::Aabb;
use crate::math::{DVec3, Vec3, Vec3A};

/// A primitive with a bounding box.
pub trait Bounded {
    /// The smallest axis-aligned box holding the primitive.
    fn bounds(&self) -> Aabb;

    /// A representative point used to sort primitives when building trees
    /// (the box center unless a primitive knows better).
    #[inline]
    fn centroid(&self) -> Vec3 {
        self.bounds().center()
    }
}

/// A primitive that knows its exact closest point to a query point.
pub trait ClosestPoint: Bounded {
    /// The point of the primitive closest to `p`.
    fn closest_point(&self, p: Vec3A) -> Vec3A;

    /// Squared Euclidean distance from `p` to the primitive.
    #[inline]
    fn distance_squared(&self, p: Vec3A) -> f32 {
        (self.closest_point(p) - p).length_squared()
    }
}

/// A primitive that can list points whose convex hull contains it (its
/// vertices): what bounding spheres are computed from.
pub trait BoundingPoints: Bounded {
    /// Appends the primitive's hull points to `out`.
    fn push_bounding_points(&self, out: &mut Vec<Vec3>);
}

/// A primitive that can say exactly whether it shares a point with a closed box.
pub trait BoxOverlap: Bounded {
    /// `true` when the primitive and the closed box `b` share at least one
    /// point (touching counts).
    fn overlaps_box(&self, b: &Aabb) -> bool;

    /// [`BoxOverlap::overlaps_box`] for a closed box with `f64` bounds (a
    /// grid's exact cells, whose planes need not be `f32` values). The
    /// crate's primitives decide it exactly; the default tests the enclosing
    /// `f32` box ([`Aabb::enclosing`]), which may accept a box the primitive
    /// only touches after that rounding.
    #[inline]
    fn overlaps_bounds(&self, min: DVec3, max: DVec3) -> bool {
        self.overlaps_box(&Aabb::enclosing(min, max))
    }
}

/// Primitives extracted from a mesh, each with the index of the mesh element it
/// came from (vertex, edge or face index).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PrimitiveSet<T> {
    /// The primitives.
    pub primitives: Vec<T>,
    /// `sources[i]` is the mesh element that `primitives[i]` came from.
    pub sources: Vec<u32>,
}

impl<T> PrimitiveSet<T> {
    /// Primitives whose source is their own index.
    pub fn from_primitives(primitives: Vec<T>) -> Self {
        let sources = (0..primitives.len() as u32).collect();
        Self { primitives, sources }
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.primitives.len()
    }

    /// `true` when there are no primitives.
    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }
}
