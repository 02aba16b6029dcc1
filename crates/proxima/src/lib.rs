//! # proxima
//!
//! Spatial acceleration structures for 3D meshes, exact in their answers:
//!
//! - [`AabbTree`]: a bounding volume hierarchy of axis-aligned boxes with
//!   closest-primitive and k-nearest queries;
//! - [`SphereTree`]: the same hierarchy and queries with bounding spheres;
//! - primitives taken from a [`Mesh`]: [`Point`] (vertices), [`LineSegment`]
//!   (edges), [`Triangle`] (faces) and [`ConvexPolygon`] (faces as they
//!   are, when convex and planar), described by small traits
//!   ([`Bounded`], [`ClosestPoint`]);
//! - view [`Frustum`] queries ([`AabbTree::frustum`]), exact for every
//!   primitive ([`FrustumOverlap`]);
//! - mesh loading from OBJ, PLY, STL and OFF files, optionally gzip-compressed
//!   ([`io::load`]).
//!
//! ```
//! use proxima::{AabbTree, Mesh, Vec3};
//! let mesh = Mesh::from_triangles(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
//!     &[[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
//! )
//! .unwrap();
//! let tree = AabbTree::build_set(mesh.triangles(), &Default::default()).unwrap();
//! let hit = tree.closest(Vec3::new(0.2, 0.2, -1.0)).unwrap();
//! assert_eq!(hit.source, 0); // face 0 lies in the z = 0 plane
//! assert_eq!(hit.distance, 1.0);
//! ```
// No unsafe code, except in one module (bvh/wide/avx2.rs) that calls AVX2
// functions once the CPU has been seen to have AVX2; it allows it for itself.
#![deny(unsafe_code)]
#![deny(missing_docs)]

pub mod aabb;
pub mod budget;
pub mod bvh;
pub mod error;
mod exact;
pub mod frustum;
pub mod grid;
pub mod io;
pub mod kind;
pub mod linear;
pub mod math;
pub mod memory;
pub mod mesh;
pub mod prelude;
pub mod primitive;
pub mod sample;
pub mod sphere;
pub mod sphere_tree;
pub mod traversal;

pub use aabb::Aabb;
pub use bvh::{AabbTree, BuildConfig, ClosestHit, RayHit, TreeStats, WideTree};
pub use error::FrustumError;
pub use error::GridError;
pub use error::RayError;
pub use error::{BuildError, LoadError, LoadErrorKind, MeshError, PolygonError, QueryError};
pub use frustum::{Frustum, FrustumOverlap};
pub use grid::{GridConfig, HashGrid, InsertMethod};
pub use kind::{MeshPrimitive, PrimitiveKind};
pub use linear::LinearSearch;
pub use math::{Mat4, Vec3, Vec3A};
pub use mesh::Mesh;
pub use primitive::{
    Bounded, BoundingPoints, BoxOverlap, ClosestPoint, ConvexPolygon, LineSegment, Point, PrimitiveSet, RayIntersect,
    Triangle,
};
pub use sphere::Sphere;
pub use sphere_tree::SphereTree;
pub use traversal::{GridTraversal, TraversalConfig, TraversalStep};
