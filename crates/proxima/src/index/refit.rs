//! A mesh that moves: new vertex positions, the same faces, and every
//! structure built so far refit to them (or rebuilt, as the policy says).

use super::{IndexError, MeshIndex};
use crate::build::MAX_COORDINATE;
use crate::kind::{KindGeneric, MeshPrimitive, PrimitiveKind};
use crate::math::Vec3;
use crate::mesh::MeshError;
use crate::sdf::SignedDistanceField;
use crate::{RayTree, Triangle, WideTree};
use std::collections::HashMap;
use std::sync::Arc;

/// Whether [`MeshIndex::update_vertices`] refits a tree or rebuilds it.
/// Answers never depend on it (every query equals a fresh build's on the
/// same positions, whatever the tree's shape); only speed does: a refit
/// keeps the shape built for the old positions, and queries slow down as
/// its boxes come to overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefitPolicy {
    /// Always refit: the cheapest update, for small motions.
    Refit,
    /// Always rebuild: what a fresh index would hold.
    Rebuild,
    /// Refit, then rebuild each tree whose surface-area cost
    /// ([`WideTree::surface_area_cost`]) has grown past this many times its
    /// cost when it was built.
    RebuildPast(f64),
}

impl RefitPolicy {
    /// The default ratio of [`RebuildPast`](Self::RebuildPast).
    pub const DEFAULT_RATIO: f64 = 1.5;

    fn rebuilds(self, ratio: f64) -> bool {
        match self {
            Self::Refit => false,
            Self::Rebuild => true,
            Self::RebuildPast(limit) => ratio.is_nan() || ratio > limit,
        }
    }
}

impl Default for RefitPolicy {
    fn default() -> Self {
        Self::RebuildPast(Self::DEFAULT_RATIO)
    }
}

/// What [`MeshIndex::update_vertices`] did to one structure.
#[derive(Clone, Debug, PartialEq)]
pub struct Updated {
    /// The structure, named as in [`MeshIndex::built`].
    pub structure: &'static str,
    /// `true` when it was built anew; `false` when refit (trees) or
    /// recomputed over the same tree (winding numbers, pseudonormals,
    /// oriented boxes, normals).
    pub rebuilt: bool,
    /// For a tree, its surface-area cost after the refit over its cost at
    /// build; `NaN` where it was not refit (the `Rebuild` policy, or a set
    /// of primitives the tree could not take). For the other structures, 1.
    pub cost_ratio: f64,
}

impl MeshIndex {
    /// Moves the mesh's vertices to `positions` (one per vertex, in order;
    /// the faces unchanged) and brings every structure built so far up to
    /// date, as the configuration's [`RefitPolicy`] says: the trees of each
    /// primitive kind and the ray tree are refit in place (or rebuilt); the
    /// signed-distance fields' winding-number expansions are refit over the
    /// refit faces' tree, their pseudonormals computed again (with the weld
    /// and edges of the last update while no vertices meet or part); the
    /// sign certificate is made again only once the signed distances asked
    /// since number half the triangles
    /// ([`certificate`](crate::sdf::SignedDistanceField::certificate));
    /// the oriented boxes and the vertex normals are computed again.
    /// Structures not built yet stay so. The file's corner normals are
    /// dropped ([`Mesh::set_positions`](crate::Mesh::set_positions)).
    ///
    /// Afterwards every query gives what a new index over the moved mesh
    /// would. Returns what was done to each structure.
    ///
    /// Fails, changing nothing, when `positions` is not one finite position
    /// per vertex ([`IndexError::Positions`]) or holds a coordinate beyond
    /// [`MAX_COORDINATE`] ([`IndexError::PositionTooLarge`]).
    ///
    /// ```
    /// use proxima::prelude::*;
    /// use proxima::index::MeshIndex;
    /// let mesh = proxima::mesh::generate::noisy_icosphere(3, 1);
    /// let mut index = MeshIndex::new(mesh.clone());
    /// let p = Vec3::new(0.2, 0.1, 3.0);
    /// index.closest(PrimitiveKind::Faces, &[p]).unwrap();
    /// let moved: Vec<Vec3> = mesh.positions().iter().map(|v| *v * 2.0).collect();
    /// let updated = index.update_vertices(&moved).unwrap();
    /// assert_eq!(updated[0].structure, "faces");
    /// let fresh = MeshIndex::new(index.mesh().clone());
    /// assert_eq!(index.closest(PrimitiveKind::Faces, &[p]), fresh.closest(PrimitiveKind::Faces, &[p]));
    /// ```
    pub fn update_vertices(&mut self, positions: &[Vec3]) -> Result<Vec<Updated>, IndexError> {
        let vertices = self.mesh.vertex_count();
        if positions.len() != vertices {
            return Err(MeshError::VertexCount {
                count: positions.len(),
                vertices,
            }
            .into());
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFiniteVertex { index }.into());
        }
        if let Some(vertex) = positions.iter().position(|p| p.abs().max_element() > MAX_COORDINATE) {
            return Err(IndexError::PositionTooLarge {
                vertex,
                bound: MAX_COORDINATE,
            });
        }
        self.mesh.set_positions(positions)?;
        let policy = self.config.refit;
        let mut report = Vec::new();
        // The fields and oriented boxes hold or read the faces' tree: out of
        // the way first, so that the refit finds the tree unshared.
        let winding = self.winding.take().map(SignedDistanceField::detach);
        let pseudonormal = self.pseudonormal.take().map(SignedDistanceField::detach);
        let oriented = self.oriented.take().is_some();
        let normals = self.normals.take().is_some();
        for kind in PrimitiveKind::ALL {
            kind.dispatch(UpdateTree {
                index: self,
                policy,
                report: &mut report,
            })?;
        }
        let recomputed = |structure| Updated {
            structure,
            rebuilt: false,
            cost_ratio: 1.0,
        };
        let faces_rebuilt = report
            .iter()
            .any(|u| u.structure == PrimitiveKind::Faces.name() && u.rebuilt);
        for (structure, detached, slot) in [
            ("winding", winding, &mut self.winding),
            ("pseudonormal", pseudonormal, &mut self.pseudonormal),
        ] {
            // A field's faces' tree was built with it and updated above; a
            // field without one would be made again on its next use.
            if let (Some(detached), Some(tree)) = (detached, self.trees.get::<Triangle>().get()) {
                slot.put(detached.attach(tree.clone(), &self.mesh, faces_rebuilt));
                report.push(recomputed(structure));
            }
        }
        self.update_ray_tree(policy, &mut report)?;
        if oriented {
            self.oriented_bounds()?;
            report.push(recomputed("oriented"));
        }
        if normals {
            self.vertex_normals();
            report.push(recomputed("normals"));
        }
        Ok(report)
    }

    /// Sets how later [`update_vertices`](Self::update_vertices) calls
    /// bring the trees up to date (the configuration's
    /// [`refit`](super::IndexConfig::refit)). The structures already built
    /// stay as they are; answers do not depend on the policy.
    ///
    /// ```
    /// use proxima::prelude::*;
    /// use proxima::index::{MeshIndex, RefitPolicy};
    /// let mesh = proxima::mesh::generate::noisy_icosphere(2, 1);
    /// let mut index = MeshIndex::new(mesh.clone());
    /// index.closest(PrimitiveKind::Faces, &[Vec3::ZERO]).unwrap();
    /// index.set_refit_policy(RefitPolicy::Rebuild);
    /// let updated = index.update_vertices(mesh.positions()).unwrap();
    /// assert!(updated[0].rebuilt && updated[0].cost_ratio.is_nan());
    /// ```
    pub fn set_refit_policy(&mut self, policy: RefitPolicy) {
        self.config.refit = policy;
    }

    fn update_ray_tree(&mut self, policy: RefitPolicy, report: &mut Vec<Updated>) -> Result<(), IndexError> {
        let Some(tree) = self.rays.get_mut() else {
            return Ok(());
        };
        let mesh = &self.mesh;
        let (ratio, rebuilt) = refit_or_rebuild(
            &mut self.build_costs,
            "rays",
            policy,
            tree,
            RayTree::surface_area_cost,
            |tree| {
                // The faces' triangles, moved within the checked coordinates.
                tree.refit_trusted_by(|triangle, face| mesh.fan_triangle(triangle, face));
                true
            },
        );
        if rebuilt {
            self.rays.take();
            let tree = RayTree::build_set(self.mesh.triangles(), &RayTree::config())?;
            self.rays.put(tree);
        }
        report.push(Updated {
            structure: "rays",
            rebuilt,
            cost_ratio: ratio,
        });
        Ok(())
    }
}

/// Refits (or rebuilds) the tree of one primitive type, if built.
struct UpdateTree<'a> {
    index: &'a mut MeshIndex,
    policy: RefitPolicy,
    report: &'a mut Vec<Updated>,
}

impl KindGeneric for UpdateTree<'_> {
    type Output = Result<(), IndexError>;
    fn call<T: MeshPrimitive>(self) -> Self::Output {
        let Self { index, policy, report } = self;
        let name = T::KIND.name();
        let Some(shared) = T::of_kind_mut(&mut index.trees).get_mut() else {
            return Ok(());
        };
        let (mesh, planarity) = (&index.mesh, index.config.planarity);
        // Polygons extracted for a refit that refuses them serve the build.
        let mut extracted = None;
        // Cloned only if a caller still holds the tree.
        let tree = Arc::make_mut(shared);
        let (ratio, rebuilt) = refit_or_rebuild(
            &mut index.build_costs,
            name,
            policy,
            tree,
            WideTree::surface_area_cost,
            |tree| {
                // A polygon that is no longer planar is split: another set
                // of primitives, which only a build can take (the refit
                // says so). Vertices, edges and fan triangles come from
                // the faces alone, and the coordinates are checked; the
                // triangles are read from the faces where they sit.
                if T::KIND == PrimitiveKind::Polygons {
                    tree.refit(extracted.insert(T::extract(mesh, planarity))).is_ok()
                } else if let Some(tree) = T::as_triangle_tree(tree) {
                    tree.refit_trusted_by(|triangle, face| mesh.fan_triangle(triangle, face));
                    true
                } else {
                    tree.refit_trusted(&T::extract(mesh, planarity));
                    true
                }
            },
        );
        if rebuilt {
            T::of_kind_mut(&mut index.trees).take();
            let set = extracted.unwrap_or_else(|| T::extract(&index.mesh, planarity));
            let tree = WideTree::build_set(set, &index.config.build)?;
            T::of_kind_mut(&mut index.trees).put(Arc::new(tree));
        }
        report.push(Updated {
            structure: name,
            rebuilt,
            cost_ratio: ratio,
        });
        Ok(())
    }
}

/// Refits a tree whose cost at build is recorded under `name` (recorded
/// now, from the tree as it is, on its first update), unless the policy
/// always rebuilds; `refit` does the refit and says whether the tree took
/// the set. Returns the cost ratio (NaN when not refit) and whether the
/// tree is to be rebuilt, in which case its record is dropped.
fn refit_or_rebuild<X>(
    costs: &mut HashMap<&'static str, f64>,
    name: &'static str,
    policy: RefitPolicy,
    tree: &mut X,
    cost: fn(&X) -> f64,
    refit: impl FnOnce(&mut X) -> bool,
) -> (f64, bool) {
    let at_build = *costs.entry(name).or_insert_with(|| cost(tree));
    let refit = policy != RefitPolicy::Rebuild && refit(tree);
    let ratio = if refit { cost(tree) / at_build } else { f64::NAN };
    let rebuilt = !refit || policy.rebuilds(ratio);
    if rebuilt {
        costs.remove(name);
    }
    (ratio, rebuilt)
}
