//! Scenes of rigid instances: many meshes, each placed by a pose, asked as
//! one (closest point, k nearest faces, signed distance, first and any hit).
//!
//! An [`Instance`] is a [`MeshIndex`] (shared: the same mesh placed several
//! times keeps one set of trees) and a [`RigidPose`] from the mesh's frame
//! to the world's. A top-level tree over the instances' world boxes sends
//! each query to the instances it may concern; there the query is carried
//! into the mesh's frame (in `f64`, rounded once to `f32`) and answered by
//! the mesh's own trees, and the answer carried back. Moving an instance
//! ([`Scene::set_pose`]) refits the top level only.
//!
//! Answers are brute force's over every instance's triangles placed in
//! `f64`, up to that one rounding of the query into the instance's frame
//! (a few ulps of its coordinates); ties between instances go to the lower
//! instance index. A mirroring pose is refused ([`RigidPose`] takes
//! rotations only): the mesh's inside would become its outside.
//!
//! ```
//! use proxima::prelude::*;
//! use proxima::index::MeshIndex;
//! use proxima::pair::RigidPose;
//! use proxima::scene::Scene;
//! use std::sync::Arc;
//! let sphere = Arc::new(MeshIndex::new(proxima::mesh::generate::noisy_icosphere(8, 1)));
//! let at = |x: f64| RigidPose::translation_only(proxima::DVec3::new(x, 0.0, 0.0)).unwrap();
//! let mut scene = Scene::new(vec![(sphere.clone(), at(0.0)), (sphere, at(5.0))]).unwrap();
//! let hit = scene.closest(Vec3::new(4.0, 0.0, 0.0)).unwrap();
//! assert_eq!(hit.instance, 1);
//! let ray = scene.first_hit(Vec3::new(-10.0, 0.01, 0.0), Vec3::X, 0.0, f32::INFINITY).unwrap().unwrap();
//! assert_eq!(ray.instance, 0);
//! scene.set_pose(1, at(-5.0)).unwrap();
//! assert_eq!(scene.first_hit(Vec3::new(-10.0, 0.01, 0.0), Vec3::X, 0.0, f32::INFINITY).unwrap().unwrap().instance, 1);
//! ```

mod closest;
mod error;
mod nearest;
mod ray;

pub use closest::{SceneHit, SceneSignedDistance};
pub use error::SceneError;
pub use ray::SceneRayHit;

use crate::aabb::Aabb;
use crate::aabb_tree::AabbTree;
use crate::build::BuildConfig;
use crate::index::IndexError;
use crate::index::{MeshIndex, Updated};
use crate::kind::PrimitiveKind;
use crate::math::{DVec3, Vec3};
use crate::pair::RigidPose;
use crate::primitive::Triangle;
use crate::primitive::{Bounded, BoundingPoints, PrimitiveSet};
use crate::query::SpatialIndex;
use crate::wide_tree::{WideChild, WidePrimitive, WideTree};
use std::collections::HashMap;
use std::sync::Arc;

/// A mesh placed in the scene: its index (shared between instances of the
/// same mesh) and its pose, from the mesh's frame to the world's.
#[derive(Clone)]
pub struct Instance {
    mesh: Arc<MeshIndex>,
    pose: RigidPose,
    inverse: RigidPose,
    /// The corners of the boxes two levels under the root of the mesh's
    /// faces tree (shared by the instances of one mesh): placed, their
    /// box is much tighter than the placed root box's, at a few dozen
    /// points to move.
    hull: Arc<[Vec3]>,
}

impl Instance {
    /// The mesh and its structures.
    pub fn mesh(&self) -> &Arc<MeshIndex> {
        &self.mesh
    }

    /// The pose, from the mesh's frame to the world's.
    pub fn pose(&self) -> &RigidPose {
        &self.pose
    }

    /// `p` (world) in the mesh's frame, rounded once to `f32`.
    #[inline]
    pub(crate) fn to_local(&self, p: Vec3) -> Vec3 {
        self.inverse.apply(p).as_vec3()
    }

    /// A direction (world) in the mesh's frame.
    #[inline]
    pub(crate) fn direction_to_local(&self, d: Vec3) -> Vec3 {
        (self.inverse.rotation() * d.as_dvec3()).as_vec3()
    }

    /// The world box of the instance: its hull points placed in `f64`,
    /// rounded outwards, and widened by a few ulps of the largest
    /// coordinate (and of the mesh's size), so that it holds every point
    /// the mesh's queries may give back (each computed in the mesh's frame
    /// from a rounded query).
    fn world_bounds(&self) -> Aabb {
        let (mut min, mut max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for p in self.hull.iter() {
            let w = self.pose.apply(*p);
            (min, max) = (min.min(w), max.max(w));
        }
        let b = Aabb::new(min.as_vec3(), max.as_vec3());
        let size = (max - min).length() as f32;
        let scale = b.min.abs().max(b.max.abs()).max_element().max(size);
        b.inflate(scale * 32.0 * f32::EPSILON)
    }
}

/// The corners of the boxes two levels under the root of `mesh`'s faces
/// tree (see [`Instance`]), built if needed.
fn hull_points(mesh: &MeshIndex) -> Result<Vec<Vec3>, IndexError> {
    let tree = mesh.tree::<Triangle>()?;
    let mut boxes = Vec::new();
    if tree.node_count() > 0 {
        for lane in 0..4 {
            match tree.child(0, lane) {
                WideChild::Inner(child) => boxes.extend((0..4).map(|l| tree.nodes()[child].child_bounds(l))),
                WideChild::Leaf(_) => boxes.push(tree.nodes()[0].child_bounds(lane)),
                WideChild::Empty => {}
            }
        }
    }
    Ok(boxes
        .into_iter()
        .filter(|b| !b.is_empty())
        .flat_map(|b| corners(&b))
        .collect())
}

/// The eight corners of `b`.
fn corners(b: &Aabb) -> [Vec3; 8] {
    std::array::from_fn(|c| {
        Vec3::new(
            if c & 1 == 0 { b.min.x } else { b.max.x },
            if c & 2 == 0 { b.min.y } else { b.max.y },
            if c & 4 == 0 { b.min.z } else { b.max.z },
        )
    })
}

/// An instance's world box: the top-level tree's primitive.
#[derive(Clone, Copy, Debug)]
pub(crate) struct InstanceBox(Aabb);

/// Tested one box at a time at the leaves.
impl WidePrimitive for InstanceBox {}

impl Bounded for InstanceBox {
    fn bounds(&self) -> Aabb {
        self.0
    }
}

impl BoundingPoints for InstanceBox {
    fn push_bounding_points(&self, out: &mut Vec<Vec3>) {
        out.extend([self.0.min, self.0.max]);
    }
}

/// Rebuild the top-level tree when refits have made it this many times
/// costlier than built (as [`RefitPolicy`](crate::index::RefitPolicy)'s default).
const TOP_REBUILD_RATIO: f64 = 1.5;

/// Many meshes, each placed by a rigid pose, asked as one (see the module
/// notes).
pub struct Scene {
    instances: Vec<Instance>,
    /// Each instance's world box, in instance order.
    boxes: PrimitiveSet<InstanceBox>,
    /// Over the instances' world boxes, 4-wide (rays test a node's four
    /// boxes at once); `None` for an empty scene.
    top: Option<WideTree<InstanceBox>>,
    /// The top tree's surface-area cost when built.
    top_cost: f64,
}

impl Scene {
    /// A scene of `instances`, each a mesh index and its pose. Builds the
    /// top level now and each mesh's trees on first use (the faces' tree,
    /// the ray tree, the signed-distance fields), once per mesh however
    /// many times it is placed. Fails when a mesh has no faces, or a placed
    /// box lies beyond the coordinates a tree takes.
    pub fn new(instances: Vec<(Arc<MeshIndex>, RigidPose)>) -> Result<Self, SceneError> {
        // One hull per mesh, however many times it is placed.
        let mut hulls: HashMap<*const MeshIndex, Arc<[Vec3]>> = HashMap::new();
        let instances: Vec<Instance> = instances
            .into_iter()
            .enumerate()
            .map(|(i, (mesh, pose))| {
                let error = |source| SceneError::Mesh { instance: i, source };
                mesh.require(PrimitiveKind::Faces).map_err(error)?;
                let hull = match hulls.get(&Arc::as_ptr(&mesh)) {
                    Some(hull) => hull.clone(),
                    None => {
                        let hull: Arc<[Vec3]> = hull_points(&mesh).map_err(error)?.into();
                        hulls.insert(Arc::as_ptr(&mesh), hull.clone());
                        hull
                    }
                };
                Ok(Instance {
                    inverse: pose.inverse(),
                    mesh,
                    pose,
                    hull,
                })
            })
            .collect::<Result<_, SceneError>>()?;
        if instances.len() >= u32::MAX as usize {
            return Err(SceneError::TooMany { count: instances.len() });
        }
        let boxes = PrimitiveSet::from_primitives(instances.iter().map(|i| InstanceBox(i.world_bounds())).collect());
        let mut scene = Self {
            instances,
            boxes,
            top: None,
            top_cost: 0.0,
        };
        scene.build_top()?;
        Ok(scene)
    }

    fn build_top(&mut self) -> Result<(), SceneError> {
        if self.instances.is_empty() {
            self.top = None;
            return Ok(());
        }
        let config = BuildConfig {
            min_size: 1,
            ..BuildConfig::fast_queries()
        };
        let tree = AabbTree::build_set(self.boxes.clone(), &config).map_err(SceneError::Placement)?;
        self.top_cost = tree.surface_area_cost();
        self.top = Some(WideTree::from_tree(tree));
        Ok(())
    }

    /// Moves instance `index` to `pose`: its world box anew, and the top
    /// level refit (rebuilt once refits have made it 1.5 times costlier
    /// than built). The meshes' own trees are not touched. Fails, changing
    /// nothing, for an index out of range or a box beyond the coordinates
    /// a tree takes.
    pub fn set_pose(&mut self, index: usize, pose: RigidPose) -> Result<(), SceneError> {
        let count = self.instances.len();
        let Some(instance) = self.instances.get(index) else {
            return Err(SceneError::InstanceOutOfRange { index, count });
        };
        let moved = Instance {
            mesh: instance.mesh.clone(),
            inverse: pose.inverse(),
            pose,
            hull: instance.hull.clone(),
        };
        let bounds = InstanceBox(moved.world_bounds());
        crate::build::check_primitives(&[bounds]).map_err(SceneError::Placement)?;
        self.instances[index] = moved;
        self.boxes.primitives[index] = bounds;
        let top = self.top.as_mut().expect("a scene with instances has a top level");
        top.refit_trusted(&self.boxes);
        if top.tree().surface_area_cost() > TOP_REBUILD_RATIO * self.top_cost {
            self.build_top()?;
        }
        Ok(())
    }

    /// Moves the vertices of instance `index`'s mesh to `positions` (one
    /// per vertex, in order; the faces unchanged): every instance that
    /// shares that mesh deforms with it. When the scene holds the only
    /// references to the mesh, its structures are brought up to date in
    /// place ([`MeshIndex::update_vertices`], under the mesh's
    /// [`RefitPolicy`](crate::index::RefitPolicy)) and what was done is
    /// returned. When the mesh is also held outside the scene (an `Arc` the
    /// caller kept), the scene deforms a copy of its own, whose structures
    /// are built on first use (nothing to report), and the caller's mesh
    /// is left as it was; later updates find the copy unshared and refit
    /// it. Then those instances' world boxes are placed anew and the top
    /// level refit, as [`set_pose`](Self::set_pose) does.
    ///
    /// Answers afterwards equal a new scene's over the moved vertices. Fails,
    /// changing nothing, for an index out of range, positions the mesh
    /// refuses (another count, NaN, beyond its coordinate bound) or a mesh
    /// placed beyond the coordinates a tree takes.
    ///
    /// ```
    /// use proxima::prelude::*;
    /// use proxima::index::MeshIndex;
    /// use proxima::pair::RigidPose;
    /// use proxima::scene::Scene;
    /// use std::sync::Arc;
    /// let sphere = MeshIndex::new(proxima::mesh::generate::noisy_icosphere(8, 1));
    /// let grown: Vec<Vec3> = sphere.mesh().positions().iter().map(|&p| p * 2.0).collect();
    /// let mut scene = Scene::new(vec![(Arc::new(sphere), RigidPose::IDENTITY)]).unwrap();
    /// let before = scene.closest(Vec3::new(3.0, 0.0, 0.0)).unwrap().distance;
    /// scene.update_vertices(0, &grown).unwrap();
    /// let after = scene.closest(Vec3::new(3.0, 0.0, 0.0)).unwrap().distance;
    /// assert!((before - 2.0).abs() < 0.1 && (after - 1.0).abs() < 0.2, "{before} {after}");
    /// ```
    pub fn update_vertices(&mut self, index: usize, positions: &[Vec3]) -> Result<Vec<Updated>, SceneError> {
        let count = self.instances.len();
        let Some(instance) = self.instances.get(index) else {
            return Err(SceneError::InstanceOutOfRange { index, count });
        };
        let sharing: Vec<usize> = (0..count)
            .filter(|&j| Arc::ptr_eq(&self.instances[j].mesh, &instance.mesh))
            .collect();
        // Placed beyond the coordinates a tree takes? Checked on the box of
        // the new positions, which holds the hull the boxes are made from,
        // before anything changes.
        let moved = Aabb::from_points(positions.iter().copied());
        if !moved.is_empty() {
            let hull: Arc<[Vec3]> = corners(&moved).into();
            for &j in &sharing {
                let placed = InstanceBox(
                    Instance {
                        hull: hull.clone(),
                        ..self.instances[j].clone()
                    }
                    .world_bounds(),
                );
                crate::build::check_primitives(&[placed]).map_err(SceneError::Placement)?;
            }
        }
        // The scene's references out of the instances for the update, so
        // that only an outside holder can keep the mesh shared; put back
        // (moved or not) whatever the update gives.
        let empty = Arc::new(MeshIndex::new(crate::mesh::Mesh::default()));
        let mut held: Vec<Arc<MeshIndex>> = sharing
            .iter()
            .map(|&j| std::mem::replace(&mut self.instances[j].mesh, empty.clone()))
            .collect();
        let mut mesh = held.pop().expect("the instance shares its own mesh");
        drop(held);
        let updated = match Arc::get_mut(&mut mesh) {
            Some(unshared) => unshared.update_vertices(positions),
            None => {
                let mut copy = MeshIndex::with_config(mesh.mesh().clone(), mesh.config().clone());
                let report = copy.update_vertices(positions);
                if report.is_ok() {
                    mesh = Arc::new(copy);
                }
                report
            }
        };
        let hull = updated.as_ref().ok().map(|_| hull_points(&mesh));
        for &j in &sharing {
            self.instances[j].mesh = mesh.clone();
        }
        let error = |source| SceneError::Mesh {
            instance: index,
            source,
        };
        let updated = updated.map_err(error)?;
        let hull: Arc<[Vec3]> = hull.expect("made after an update").map_err(error)?.into();
        for &j in &sharing {
            self.instances[j].hull = hull.clone();
            self.boxes.primitives[j] = InstanceBox(self.instances[j].world_bounds());
        }
        let top = self.top.as_mut().expect("a scene with instances has a top level");
        top.refit_trusted(&self.boxes);
        if top.tree().surface_area_cost() > TOP_REBUILD_RATIO * self.top_cost {
            self.build_top()?;
        }
        Ok(updated)
    }

    /// The instances, in the order given.
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Number of instances.
    pub fn len(&self) -> usize {
        self.instances.len()
    }

    /// `true` for a scene without instances.
    pub fn is_empty(&self) -> bool {
        self.instances.is_empty()
    }

    /// The world box of every instance (empty for an empty scene).
    pub fn bounds(&self) -> Aabb {
        self.top.as_ref().map_or(Aabb::EMPTY, |t| t.tree().bounds())
    }
}
