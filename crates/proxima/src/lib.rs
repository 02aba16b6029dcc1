//! # proxima
//!
//! Spatial acceleration structures for 3D meshes, exact in their answers:
//! every query equals brute force, field for field.
//!
//! ```
//! use proxima::prelude::*;
//! let mesh = Mesh::from_triangles(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
//!     &[[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
//! )
//! .unwrap();
//! let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
//! let hit = tree.closest(Vec3::new(0.2, 0.2, -1.0)).unwrap();
//! assert_eq!((hit.source, hit.distance), (0, 1.0)); // face 0 lies in the z = 0 plane
//! ```
//!
//! ## Contents
//!
//! | Layer | Modules |
//! |---|---|
//! | Input | [`io`] (OBJ, PLY, STL, OFF, GLB, gzip; limits), [`mesh`] ([`Mesh`]), [`kind`] ([`PrimitiveKind`]: vertices, edges, faces, polygons) |
//! | Primitives | [`primitive`] ([`Point`], [`LineSegment`], [`Triangle`], [`ConvexPolygon`]; traits [`Bounded`], [`ClosestPoint`], [`BoxOverlap`], [`RayIntersect`]), [`frustum`] ([`Frustum`], [`FrustumOverlap`]), [`ray`] ([`Ray`]) |
//! | Mesh index | [`index`] ([`MeshIndex`]: one mesh and every structure on it, built on first use; what the command line, viewer and Python package ask; [`MeshIndex::update_vertices`] refits them for a deforming mesh) |
//! | Scenes | [`scene`] ([`scene::Scene`]: meshes placed by rigid poses, sharing their indices; closest point, signed distance of the union, first and any hit; [`scene::Scene::set_pose`] refits the top level) |
//! | Point clouds | [`points`] ([`points::PointCloud`]: k-nearest, exact radius search and the ball query in compressed rows, the self-join within a radius; [`points::chamfer`], [`points::hausdorff`]) |
//! | Surface answers | [`surface`] ([`surface::SurfacePoint`]: the triangle, barycentrics and feature of a closest point or ray hit; [`surface::vertex_normals`]; interpolated and face normals) |
//! | Two meshes | [`pair`] ([`pair::distance`], [`pair::intersects`], [`pair::intersecting_pairs`], [`pair::pairs_within`], [`pair::self_intersections`], pose batches; [`pair::hausdorff`] between surfaces, as bounds within a tolerance; [`pair::RigidPose`]): one descent of both faces' trees, exact triangle-pair tests |
//! | Queries | [`sdf`] ([`SignedDistanceField`]: signed distance, winding numbers, inside tests, grids, samples), [`query`]: [`NearestQuery`], [`RayQuery`], [`FrustumQuery`], each written once over a structure's walk; answers [`ClosestHit`], [`RayHit`] |
//! | Structures | [`aabb_tree`] ([`AabbTree`]), [`build`] (the binary build every tree starts from: [`BuildConfig`]), [`wide_tree`] ([`WideTree`], 4-wide, SIMD leaves), [`ray_tree`] ([`RayTree`], 8-wide, for rays), [`sphere_tree`] ([`SphereTree`]), [`linear`] ([`LinearSearch`], brute force), [`grid`] ([`HashGrid`], [`GridTraversal`]) |
//! | Support | `simd` (private: the AVX2 token, triangle packets and lane kernels the wide trees and `sdf` share), [`aabb`], [`sphere`], [`math`], [`memory`] (huge-page arrays), [`budget`] (memory, thread and work limits), [`error`] (typed errors), [`sample`] (seeded samplers: tests, benchmarks, training sets) |
//!
//! `use proxima::prelude::*;` brings the structures, primitives and query traits.
// No unsafe code, except in the two AVX2 modules (simd/avx2.rs: the token
// and the triangle packet kernels; ray_tree/avx2.rs: the ray tree's node
// test) that call AVX2 functions once the CPU has been seen to have AVX2;
// each allows it for itself.
#![deny(unsafe_code)]
#![deny(missing_docs)]

pub mod aabb;
pub mod aabb_tree;
pub mod budget;
pub mod build;
mod build_error;
pub mod error;
mod exact;
pub mod frustum;
pub mod grid;
pub mod index;
pub mod io;
pub mod kind;
pub mod linear;
pub mod math;
pub mod memory;
pub mod mesh;
pub mod pair;
pub mod points;
pub mod prelude;
pub mod primitive;
pub mod query;
pub mod ray;
pub mod ray_tree;
pub mod sample;
pub mod scene;
pub mod sdf;
mod simd;
pub mod sphere;
pub mod sphere_tree;
pub mod surface;
pub mod wide_tree;

pub use aabb::Aabb;
pub use aabb_tree::AabbTree;
pub use build::{BuildConfig, TreeStats};
pub use error::FrustumError;
pub use error::GridError;
pub use error::RayError;
pub use error::{BuildError, LoadError, LoadErrorKind, MeshError, PolygonError, QueryError, SdfError};
pub use frustum::{Frustum, FrustumOverlap};
pub use grid::{GridConfig, GridTraversal, HashGrid, InsertMethod, TraversalConfig, TraversalStep};
pub use index::{IndexConfig, IndexError, MeshIndex};
pub use kind::{MeshPrimitive, PrimitiveKind};
pub use linear::LinearSearch;
pub use math::{DVec3, Mat4, Vec3, Vec3A};
pub use mesh::Mesh;
pub use primitive::{
    Bounded, BoundingPoints, BoxOverlap, ClosestPoint, ConvexPolygon, LineSegment, Point, PrimitiveSet, RayIntersect,
    Triangle,
};
pub use query::{
    BatchOptions, ClosestHit, FrustumQuery, KnnScratch, Leaves, NearestQuery, QueryStats, RayHit, RayQuery,
    SpatialIndex, check_query_point,
};
pub use ray::Ray;
pub use ray_tree::RayTree;
pub use sdf::{SdfConfig, Sign, SignedDistance, SignedDistanceField};
pub use sphere::Sphere;
pub use sphere_tree::SphereTree;
pub use wide_tree::WideTree;
