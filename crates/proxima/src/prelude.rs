//! The names most programs need, in one import: `use proxima::prelude::*;`
//! brings the structures, the primitives, and the traits whose methods
//! answer the queries.

pub use crate::kind::{KindTask, MeshPrimitive, PrimitiveKind};
pub use crate::query::{FrustumQuery, NearestQuery, RayQuery, SpatialIndex};
pub use crate::{
    Aabb, AabbTree, BatchOptions, Bounded, BoundingPoints, BoxOverlap, BuildConfig, ClosestHit, ClosestPoint,
    ConvexPolygon, Frustum, FrustumOverlap, GridConfig, HashGrid, KnnScratch, LineSegment, LinearSearch, Mat4, Mesh,
    Point, PrimitiveSet, QueryStats, RayHit, RayIntersect, RayTree, SdfConfig, Sign, SignedDistance,
    SignedDistanceField, SphereTree, Triangle, Vec3, Vec3A, WideTree,
};
