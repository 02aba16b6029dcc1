//! One mesh and every structure that answers queries on it, each built on
//! first use and kept: the one place the command line, the viewer and the
//! Python package ask, so a query is dispatched once, here.
//!
//! A [`MeshIndex`] owns a 4-wide tree per [`PrimitiveKind`] (typed by its
//! primitive, in a [`PerKind`]), the signed-distance fields of both signs
//! (sharing the faces' tree) and the 8-wide ray tree of the faces. Queries
//! by a kind chosen at run time go through [`MeshIndex::on_tree`] with a
//! [`TreeTask`], or the ready-made [`closest`](MeshIndex::closest),
//! [`k_nearest`](MeshIndex::k_nearest) and [`frustum`](MeshIndex::frustum).
//!
//! ```
//! use proxima::index::MeshIndex;
//! use proxima::{Mesh, PrimitiveKind, Vec3};
//! let mesh = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]).unwrap();
//! let index = MeshIndex::new(mesh);
//! let hits = index.k_nearest(PrimitiveKind::Faces, &[Vec3::new(0.5, 0.5, 1.0)], 3).unwrap();
//! assert_eq!(hits[0].len(), 1); // one quad: one face, though two triangles
//! assert_eq!(index.built(), ["faces"]);
//! ```

mod error;
mod lazy;
mod refit;

pub use error::IndexError;
pub use lazy::Lazy;
pub use refit::{RefitPolicy, Updated};

use crate::frustum::Frustum;
use crate::kind::{KindFamily, KindGeneric, MeshPrimitive, PerKind, PrimitiveKind};
use crate::math::Vec3;
use crate::mesh::Mesh;
use crate::primitive::polygon::DEFAULT_PLANARITY_TOLERANCE;
use crate::query::{ClosestHit, FrustumQuery, NearestAnswers, NearestQuery, RayHit};
use crate::sdf::{Pseudonormals, SdfConfig, SdfGradient, Sign, SignedDistanceField, signed_distance_gradients};
use crate::surface::{
    Attributes, Located, SurfaceAnswer, TriangleOrdered, answer_groups, in_triangle_order_blocks, vertex_normals,
};
use crate::wide_tree::OrientedBounds;
use crate::{BuildConfig, RayTree, Triangle, WideTree};
use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Arc;

/// How a [`MeshIndex`] builds its trees.
#[derive(Clone, Debug)]
pub struct IndexConfig {
    /// How every tree is split (the answers are the same either way).
    pub build: BuildConfig,
    /// The relative planarity tolerance of [`PrimitiveKind::Polygons`] (see
    /// [`Mesh::extract_polygons`]).
    pub planarity: f32,
    /// Whether [`MeshIndex::update_vertices`] refits the trees or
    /// rebuilds them.
    pub refit: RefitPolicy,
    /// Whether the winding-number field proves its sides from the closest
    /// query where it can ([`SdfConfig::certify`]): signed distances at
    /// about the closest query's cost, for a build of about 1 µs per
    /// triangle (made again by each [`update_vertices`](MeshIndex::update_vertices)).
    /// Off for a mesh that moves every frame and is asked few signed
    /// distances per frame. The sides are the same either way.
    pub certify_sign: bool,
}

impl Default for IndexConfig {
    fn default() -> Self {
        Self {
            build: BuildConfig::default(),
            planarity: DEFAULT_PLANARITY_TOLERANCE,
            refit: RefitPolicy::default(),
            certify_sign: true,
        }
    }
}

/// A lazily built, shareable 4-wide tree per primitive type.
struct LazyTrees;

impl KindFamily for LazyTrees {
    type Of<T: MeshPrimitive> = Lazy<Arc<WideTree<T>>>;
}

/// Work on the tree of one kind of primitive, written once for the four
/// types and run by [`MeshIndex::on_tree`] on the tree of the kind asked.
pub trait TreeTask {
    /// What the work gives.
    type Output;
    /// Does the work on `tree`.
    fn run<T: MeshPrimitive>(self, tree: &WideTree<T>) -> Self::Output;
}

/// A mesh and the structures built on it so far. Every structure is built
/// on first use, once, even when several threads ask at the same time; a
/// failed build leaves nothing behind.
pub struct MeshIndex {
    mesh: Mesh,
    config: IndexConfig,
    trees: PerKind<LazyTrees>,
    winding: Lazy<SignedDistanceField>,
    pseudonormal: Lazy<SignedDistanceField>,
    rays: Lazy<RayTree>,
    oriented: Lazy<OrientedBounds>,
    normals: Lazy<Vec<Vec3>>,
    /// Each tree's surface-area cost when it was built, recorded by the
    /// first update of its positions (until then the tree is as built).
    build_costs: HashMap<&'static str, f64>,
}

/// Fails with [`IndexError::EmptyMesh`] when `mesh` has no vertices: no
/// query of any kind could be answered on it (loaders call it before they
/// hand a mesh on).
pub fn check_not_empty(mesh: &Mesh) -> Result<(), IndexError> {
    if mesh.vertex_count() == 0 {
        return Err(IndexError::EmptyMesh);
    }
    Ok(())
}

/// Fails with [`IndexError::NoPrimitives`] unless `mesh` has primitives of
/// `kind`.
pub fn check_primitives(mesh: &Mesh, kind: PrimitiveKind) -> Result<(), IndexError> {
    if kind.available(mesh) == 0 {
        return Err(IndexError::NoPrimitives {
            kind,
            vertices: mesh.vertex_count(),
            faces: mesh.face_count(),
        });
    }
    Ok(())
}

impl MeshIndex {
    /// An index over `mesh` with the default configuration; nothing built.
    pub fn new(mesh: Mesh) -> Self {
        Self::with_config(mesh, IndexConfig::default())
    }

    /// An index over `mesh` building its trees as `config` says.
    pub fn with_config(mesh: Mesh, config: IndexConfig) -> Self {
        Self {
            mesh,
            config,
            trees: PerKind::default(),
            winding: Lazy::default(),
            pseudonormal: Lazy::default(),
            rays: Lazy::default(),
            oriented: Lazy::default(),
            normals: Lazy::default(),
            build_costs: HashMap::new(),
        }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The configuration the trees are built with.
    pub fn config(&self) -> &IndexConfig {
        &self.config
    }

    /// Fails with [`IndexError::NoPrimitives`] unless the mesh has
    /// primitives of `kind`.
    pub fn require(&self, kind: PrimitiveKind) -> Result<(), IndexError> {
        check_primitives(&self.mesh, kind)
    }

    /// The tree over primitives of type `T`, built if needed, shareable.
    pub fn shared_tree<T: MeshPrimitive>(&self) -> Result<&Arc<WideTree<T>>, IndexError> {
        self.require(T::KIND)?;
        self.trees.get::<T>().get_or_try_init(|| {
            let set = T::extract(&self.mesh, self.config.planarity);
            Ok(Arc::new(WideTree::build_set(set, &self.config.build)?))
        })
    }

    /// The tree over primitives of type `T`, built if needed.
    pub fn tree<T: MeshPrimitive>(&self) -> Result<&WideTree<T>, IndexError> {
        self.shared_tree::<T>().map(|tree| &**tree)
    }

    /// Runs `task` on the tree of `kind`, built if needed.
    pub fn on_tree<F: TreeTask>(&self, kind: PrimitiveKind, task: F) -> Result<F::Output, IndexError> {
        struct OnTree<'a, F> {
            index: &'a MeshIndex,
            task: F,
        }
        impl<F: TreeTask> KindGeneric for OnTree<'_, F> {
            type Output = Result<F::Output, IndexError>;
            fn call<T: MeshPrimitive>(self) -> Self::Output {
                Ok(self.task.run(self.index.tree::<T>()?))
            }
        }
        kind.dispatch(OnTree { index: self, task })
    }

    /// The closest primitive of `kind` to every point, on all cores, in
    /// input order ([`NearestQuery::closest_batch`]).
    pub fn closest(&self, kind: PrimitiveKind, points: &[Vec3]) -> Result<Vec<Option<ClosestHit>>, IndexError> {
        struct Closest<'a>(&'a [Vec3]);
        impl TreeTask for Closest<'_> {
            type Output = Vec<Option<ClosestHit>>;
            fn run<T: MeshPrimitive>(self, tree: &WideTree<T>) -> Self::Output {
                tree.closest_batch(self.0)
            }
        }
        self.on_tree(kind, Closest(points))
    }

    /// The `k` nearest sources (mesh elements) of `kind` of every point,
    /// nearest first, a face split in several parts listed once
    /// ([`NearestQuery::k_nearest_sources_batch`]).
    pub fn k_nearest(
        &self,
        kind: PrimitiveKind,
        points: &[Vec3],
        k: usize,
    ) -> Result<Vec<Vec<ClosestHit>>, IndexError> {
        struct KNearest<'a>(&'a [Vec3], usize);
        impl TreeTask for KNearest<'_> {
            type Output = Vec<Vec<ClosestHit>>;
            fn run<T: MeshPrimitive>(self, tree: &WideTree<T>) -> Self::Output {
                tree.k_nearest_sources_batch(self.0, self.1)
            }
        }
        self.on_tree(kind, KNearest(points, k))
    }

    /// [`k_nearest`](Self::k_nearest) in chunks of queries, in input order,
    /// memory holding one chunk's answers whatever `k`
    /// ([`NearestQuery::k_nearest_sources_chunks`]).
    pub fn k_nearest_chunks<E: From<IndexError>>(
        &self,
        kind: PrimitiveKind,
        points: &[Vec3],
        k: usize,
        each: impl FnMut(&NearestAnswers) -> Result<(), E>,
    ) -> Result<(), E> {
        struct Chunks<'a, F>(&'a [Vec3], usize, F);
        impl<E, F: FnMut(&NearestAnswers) -> Result<(), E>> TreeTask for Chunks<'_, F> {
            type Output = Result<(), E>;
            fn run<T: MeshPrimitive>(self, tree: &WideTree<T>) -> Self::Output {
                tree.k_nearest_sources_chunks(self.0, self.1, self.2)
            }
        }
        self.on_tree(kind, Chunks(points, k, each))?
    }

    /// The sources (mesh elements) of `kind` sharing a point with
    /// `frustum`, increasing, each once ([`FrustumQuery::frustum_sources`]).
    pub fn frustum(&self, kind: PrimitiveKind, frustum: &Frustum) -> Result<Vec<u32>, IndexError> {
        struct InFrustum<'a>(&'a Frustum);
        impl TreeTask for InFrustum<'_> {
            type Output = Vec<u32>;
            fn run<T: MeshPrimitive>(self, tree: &WideTree<T>) -> Vec<u32> {
                tree.frustum_sources(self.0)
            }
        }
        self.on_tree(kind, InFrustum(frustum))
    }

    /// The signed-distance field signed by `sign`, on the faces' tree.
    pub fn field(&self, sign: Sign) -> Result<&SignedDistanceField, IndexError> {
        self.field_for(sign, usize::MAX)
    }

    /// [`field`](Self::field), for a caller about to ask it `queries`
    /// signed distances (a grid, a set of training samples): a field made
    /// now for fewer than [`certificate_pays`](crate::sdf::certificate_pays)
    /// makes its sign certificate only once the signed distances answered
    /// without it have paid for it. The answers are the same either way.
    pub fn field_for(&self, sign: Sign, queries: usize) -> Result<&SignedDistanceField, IndexError> {
        let lazy = match sign {
            Sign::WindingNumber => &self.winding,
            Sign::Pseudonormal => &self.pseudonormal,
        };
        let field = lazy.get_or_try_init(|| {
            let tree = self.shared_tree::<Triangle>()?.clone();
            let config = SdfConfig {
                sign,
                certify: self.config.certify_sign,
                ..SdfConfig::default()
            };
            let field = if crate::sdf::certificate_pays(queries, self.mesh.triangle_count()) {
                SignedDistanceField::with_tree(tree, &self.mesh, &config)
            } else {
                SignedDistanceField::with_tree_deferring(tree, &self.mesh, &config)
            };
            Ok::<_, IndexError>(field)
        })?;
        field.certify_when_due(&self.mesh);
        Ok(field)
    }

    /// Where on the surface each closest-point answer of
    /// [`closest`](Self::closest) on [`PrimitiveKind::Faces`] lies (triangle,
    /// barycentrics, feature; [`SurfacePoint::closest`](crate::surface::SurfacePoint::closest)),
    /// with the attributes `asked`, computed after the query on all cores,
    /// in the order of the answers' triangles ([`in_triangle_order_blocks`])
    /// and read in input order; `None` where the query had no answer.
    pub fn closest_surface(
        &self,
        points: &[Vec3],
        hits: &[Option<ClosestHit>],
        asked: Attributes,
    ) -> TriangleOrdered<Option<SurfaceAnswer>> {
        self.surface_answers(Located::Closest { points, hits }, asked)
    }

    /// [`closest_surface`](Self::closest_surface) for the first hits of rays
    /// on [`ray_tree`](Self::ray_tree) ([`SurfacePoint::of_ray_hit`](crate::surface::SurfacePoint::of_ray_hit)).
    pub fn ray_surface(&self, hits: &[Option<RayHit>], asked: Attributes) -> TriangleOrdered<Option<SurfaceAnswer>> {
        self.surface_answers(Located::Rays(hits), asked)
    }

    /// The surface answers of the batch `located`.
    fn surface_answers(&self, located: Located<'_>, asked: Attributes) -> TriangleOrdered<Option<SurfaceAnswer>> {
        let triangles = located.triangles();
        // The vertex normals are read only where corner normals are missing,
        // and not made for a batch without answers.
        let normals = match asked.normals && !triangles.is_empty() && self.mesh.corner_normals().is_none() {
            true => self.vertex_normals(),
            false => &[],
        };
        let work = |block: &[u32], out: &mut [_]| answer_groups(&self.mesh, normals, asked, located, block, out);
        in_triangle_order_blocks(&triangles, None, work)
    }

    /// The signed distance of every point, signed by `sign`, with its
    /// gradient with respect to the point and where its closest point lies
    /// ([`signed_distance_gradients`]; points on the surface take the
    /// pseudonormal field's normals, built for them when there are any).
    /// `None` where [`SignedDistanceField::signed_distance`] has no answer.
    pub fn signed_distance_gradients(
        &self,
        sign: Sign,
        points: &[Vec3],
    ) -> Result<Vec<Option<SdfGradient>>, IndexError> {
        let answers = self.field(sign)?.signed_distance_batch(points);
        signed_distance_gradients(&self.mesh, points, &answers, || {
            Ok(match self.field(Sign::Pseudonormal)?.pseudonormals() {
                Some(normals) => Cow::Borrowed(normals),
                None => Cow::Owned(Pseudonormals::new(&self.mesh)),
            })
        })
    }

    /// Every vertex's angle-weighted unit normal ([`vertex_normals`]),
    /// computed on first use.
    pub fn vertex_normals(&self) -> &[Vec3] {
        let Ok(normals) = self
            .normals
            .get_or_try_init(|| Ok::<_, std::convert::Infallible>(vertex_normals(&self.mesh)));
        normals
    }

    /// The 8-wide ray tree of the faces.
    pub fn ray_tree(&self) -> Result<&RayTree, IndexError> {
        self.require(PrimitiveKind::Faces)?;
        self.rays.get_or_try_init(|| Ok(RayTree::build(&self.mesh)?))
    }

    /// The oriented boxes of the faces' tree's children (two-mesh distances,
    /// [`crate::pair`]), built with the tree if needed.
    pub fn oriented_bounds(&self) -> Result<&OrientedBounds, IndexError> {
        let tree = self.tree::<Triangle>()?;
        self.oriented.get_or_try_init(|| Ok(OrientedBounds::build(tree)))
    }

    /// The names of the structures built so far, in a fixed order
    /// (`vertices`, `edges`, `faces`, `polygons`, `winding`,
    /// `pseudonormal`, `rays`, `oriented`).
    pub fn built(&self) -> Vec<&'static str> {
        let trees = &self.trees;
        [
            ("vertices", trees.vertices.get().is_some()),
            ("edges", trees.edges.get().is_some()),
            ("faces", trees.faces.get().is_some()),
            ("polygons", trees.polygons.get().is_some()),
            ("winding", self.winding.get().is_some()),
            ("pseudonormal", self.pseudonormal.get().is_some()),
            ("rays", self.rays.get().is_some()),
            ("oriented", self.oriented.get().is_some()),
            ("normals", self.normals.get().is_some()),
        ]
        .into_iter()
        .filter_map(|(name, built)| built.then_some(name))
        .collect()
    }
}
