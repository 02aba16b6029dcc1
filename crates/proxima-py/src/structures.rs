//! The structures a Python `Mesh` builds on first use and keeps: one tree
//! per kind of primitive, the signed-distance fields (sharing the faces'
//! tree) and the ray tree.

use crate::lazy::Lazy;
use proxima::BuildError;
use proxima::kind::MeshPrimitive;
use proxima::prelude::*;
use proxima::sdf::{SdfConfig, Sign, SignedDistanceField};
use std::sync::Arc;

/// The relative planarity tolerance of `primitives="polygons"` (the
/// command line's default `--planarity`).
pub const PLANARITY: f32 = 1e-5;

/// Everything built for one mesh, each on first use.
#[derive(Default)]
pub struct Structures {
    vertices: Lazy<WideTree<Point>>,
    edges: Lazy<WideTree<LineSegment>>,
    faces: Lazy<Arc<WideTree<Triangle>>>,
    polygons: Lazy<WideTree<ConvexPolygon>>,
    winding: Lazy<SignedDistanceField>,
    pseudonormal: Lazy<SignedDistanceField>,
    rays: Lazy<RayTree>,
}

/// Work on the tree of one kind of primitive, written once for the four
/// types (as [`proxima::kind::KindTask`], on a kept tree).
pub trait TreeTask {
    /// What the work gives.
    type Output;
    /// Does the work on `tree`; `one_part_each` is true when every source
    /// element is one primitive (no face split in several triangles).
    fn run<T: MeshPrimitive>(self, tree: &WideTree<T>, one_part_each: bool) -> Self::Output;
}

fn build<T: MeshPrimitive>(set: PrimitiveSet<T>) -> Result<WideTree<T>, BuildError> {
    WideTree::build_set(set, &BuildConfig::default())
}

impl Structures {
    /// Runs `task` on the tree of `kind` over `mesh`, building it first if
    /// needed. The caller has checked that `mesh` has such primitives.
    pub fn on_tree<F: TreeTask>(&self, mesh: &Mesh, kind: PrimitiveKind, task: F) -> Result<F::Output, BuildError> {
        Ok(match kind {
            PrimitiveKind::Vertices => task.run(self.vertices.get_or_try_init(|| build(mesh.vertices()))?, true),
            PrimitiveKind::Edges => task.run(self.edges.get_or_try_init(|| build(mesh.edges()))?, true),
            PrimitiveKind::Faces => task.run(self.faces(mesh)?, mesh.triangle_count() == mesh.face_count()),
            PrimitiveKind::Polygons => {
                let tree = self
                    .polygons
                    .get_or_try_init(|| build(mesh.extract_polygons(PLANARITY).set))?;
                task.run(tree, tree.len() == mesh.face_count())
            }
        })
    }

    /// The faces' tree (fan-triangulated), shared with the fields.
    pub fn faces(&self, mesh: &Mesh) -> Result<&Arc<WideTree<Triangle>>, BuildError> {
        self.faces.get_or_try_init(|| build(mesh.triangles()).map(Arc::new))
    }

    /// The signed-distance field with `sign`, on the faces' tree.
    pub fn field(&self, mesh: &Mesh, sign: Sign) -> Result<&SignedDistanceField, BuildError> {
        let lazy = match sign {
            Sign::WindingNumber => &self.winding,
            Sign::Pseudonormal => &self.pseudonormal,
        };
        lazy.get_or_try_init(|| {
            let tree = self.faces(mesh)?.clone();
            let config = SdfConfig {
                sign,
                ..SdfConfig::default()
            };
            Ok(SignedDistanceField::with_tree(tree, mesh, &config))
        })
    }

    /// The ray tree of the faces.
    pub fn rays(&self, mesh: &Mesh) -> Result<&RayTree, BuildError> {
        self.rays.get_or_try_init(|| RayTree::build(mesh))
    }

    /// Which structures exist, by name (for tests and `repr`).
    pub fn built(&self) -> Vec<&'static str> {
        let mut names = Vec::new();
        let mut add = |built: bool, name| {
            if built {
                names.push(name);
            }
        };
        add(self.vertices.get().is_some(), "vertices");
        add(self.edges.get().is_some(), "edges");
        add(self.faces.get().is_some(), "faces");
        add(self.polygons.get().is_some(), "polygons");
        add(self.winding.get().is_some(), "winding");
        add(self.pseudonormal.get().is_some(), "pseudonormal");
        add(self.rays.get().is_some(), "rays");
        names
    }
}
