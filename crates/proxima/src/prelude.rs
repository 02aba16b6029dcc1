//! The names most programs need, in one import: `use proxima::prelude::*;`
//! brings the structures, the primitives, and the traits whose methods
//! answer the queries.

pub use crate::kind::{KindTask, MeshPrimitive, PrimitiveKind};
pub use crate::{
    Aabb, AabbTree, Bounded, BoundingPoints, BoxOverlap, BuildConfig, ClosestHit, ClosestPoint, ConvexPolygon, Frustum,
    FrustumOverlap, GridConfig, HashGrid, LineSegment, LinearSearch, Mat4, Mesh, Point, PrimitiveSet, RayHit,
    RayIntersect, SphereTree, Triangle, Vec3, Vec3A, WideTree,
};
