//! Rays through a scene: the first hit of any instance, and whether any is hit.

use super::{InstanceBox, Scene};
use crate::aabb::Aabb;
use crate::aabb_tree::RaySlabs;
use crate::error::RayError;
use crate::math::{DVec3, Vec3};
use crate::query::{Counter, RayQuery, SpatialIndex};
use crate::ray::Ray;
use crate::wide_tree::walk::{Pending, Slices, WideQuery};
use crate::wide_tree::{WideNode, WideSlabs, entry_order_bits};
use rayon::prelude::*;
use std::ops::ControlFlow;
use wide::f32x4;

/// Where a ray first hits a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneRayHit {
    /// The instance.
    pub instance: u32,
    /// The face of the instance's mesh.
    pub face: u32,
    /// The fan triangle of that face (its index in the mesh's triangles).
    pub triangle: u32,
    /// The ray parameter (the distance along a unit direction; a rigid pose
    /// keeps lengths, so it is the same in the mesh's frame).
    pub t: f32,
    /// The hit point, in the world's frame.
    pub point: DVec3,
    /// Barycentric weight of the triangle's vertex `b`.
    pub u: f32,
    /// Barycentric weight of the triangle's vertex `c`.
    pub v: f32,
}

/// The top-level walk for rays: the four child boxes of a wide node slab
/// tested at once and entered by entry parameter, each instance's ray tree
/// asked up to the nearest hit so far.
struct Rays<'a> {
    scene: &'a Scene,
    indices: &'a [u32],
    slabs: WideSlabs,
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_hi: f32,
    any: bool,
    found: &'a mut Found,
}

/// What the walk of [`Rays`] found: the nearest hit so far, or the
/// error that ended it.
#[derive(Default)]
struct Found {
    best: Option<SceneRayHit>,
    error: Option<RayError>,
}

impl WideQuery<InstanceBox> for Rays<'_> {
    #[inline(always)]
    fn keys(&self, node: &WideNode) -> (f32x4, u32) {
        self.slabs.entries(node, self.t_min, self.t_hi)
    }

    #[inline(always)]
    fn bound(&self) -> f32 {
        self.t_hi
    }

    #[inline(always)]
    fn order_bits(key: f32) -> u32 {
        entry_order_bits(key)
    }

    fn leaf<C: Counter>(&mut self, _: &Slices<'_, InstanceBox>, leaf: Pending, _: &mut C) -> ControlFlow<()> {
        let first = leaf.child as usize;
        for slot in first..first + leaf.leaf_len() {
            self.visit(self.indices[slot])?;
        }
        ControlFlow::Continue(())
    }
}

impl Rays<'_> {
    /// Asks instance `index`'s ray tree, up to the nearest hit so far.
    #[inline]
    fn visit(&mut self, index: u32) -> ControlFlow<()> {
        let instance = &self.scene.instances[index as usize];
        let tree = instance.mesh.ray_tree().expect("a scene's meshes have faces");
        let (o, d) = (
            instance.to_local(self.origin),
            instance.direction_to_local(self.direction),
        );
        if misses_root(tree.bounds(), o, d, self.t_min, self.t_hi) {
            return ControlFlow::Continue(());
        }
        let hit = if self.any {
            tree.some_hit(o, d, self.t_min, self.t_hi)
        } else {
            tree.first_hit(o, d, self.t_min, self.t_hi)
        };
        match hit {
            Err(error) => {
                self.found.error = Some(error);
                return ControlFlow::Break(());
            }
            Ok(Some(hit)) if self.found.best.is_none_or(|b| (hit.t, index) < (b.t, b.instance)) => {
                self.found.best = Some(SceneRayHit {
                    instance: index,
                    face: hit.source,
                    triangle: hit.primitive,
                    t: hit.t,
                    point: instance.pose.apply(hit.point),
                    u: hit.u,
                    v: hit.v,
                });
                self.t_hi = hit.t;
                if self.any {
                    return ControlFlow::Break(());
                }
            }
            Ok(_) => {}
        }
        ControlFlow::Continue(())
    }
}

/// Whether the ray (in the mesh's frame) misses the mesh's box, by the
/// widened slab test the mesh's tree opens its walk with: most instances a
/// ray's path crosses in the top level are missed, and this spares them
/// the walk's setup (the checks, the far-origin test, the watertight
/// shear). Rays from beyond 512 box diagonals, which the tree moves first
/// (`FarRay`), are left to it.
#[inline]
fn misses_root(b: Aabb, o: Vec3, d: Vec3, t_min: f32, t_hi: f32) -> bool {
    if b.is_empty() || (o - b.center()).abs().max_element() > 512.0 * b.diagonal() {
        return false;
    }
    let (enter, exit) = RaySlabs::new(o, d, b.min, b.max).interval(b.min, b.max, t_min, t_hi);
    // A NaN (none expected: the slabs turn 0 · ∞ into ±∞) rejects nothing.
    enter > exit
}

impl Scene {
    fn cast(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        any: bool,
    ) -> Result<Option<SceneRayHit>, RayError> {
        Ray::with_range(origin, direction, t_min, t_max)?;
        let Some(top) = self.top.as_ref() else { return Ok(None) };
        let bounds = top.tree().bounds();
        let mut found = Found::default();
        let query = Rays {
            scene: self,
            indices: top.tree().leaves().indices(),
            slabs: WideSlabs::new(&RaySlabs::new(origin, direction, bounds.min, bounds.max)),
            origin,
            direction,
            t_min,
            t_hi: t_max,
            any,
            found: &mut found,
        };
        top.walk(|_| query, &mut ());
        match found.error {
            Some(error) => Err(error),
            None => Ok(found.best),
        }
    }

    /// The first hit of the ray `origin + t · direction`, `t` in
    /// `[t_min, t_max]`, on any instance: the smallest `t`, ties to the
    /// lower instance index, then as the instance's ray tree breaks them.
    /// Fails as [`RayQuery::first_hit`] does for a ray that is not one.
    pub fn first_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<Option<SceneRayHit>, RayError> {
        self.cast(origin, direction, t_min, t_max, false)
    }

    /// Whether the ray hits any instance with `t` in `[t_min, t_max]`
    /// (stops at the first hit found).
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<bool, RayError> {
        Ok(self.some_hit(origin, direction, t_min, t_max)?.is_some())
    }

    /// The hit [`any_hit`](Self::any_hit) stops at: some hit with `t` in
    /// `[t_min, t_max]`, not always the first, or `None`.
    pub fn some_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<Option<SceneRayHit>, RayError> {
        self.cast(origin, direction, t_min, t_max, true)
    }

    /// [`first_hit`](Self::first_hit) of every `(origin, direction)`, on
    /// all cores, in input order.
    pub fn first_hit_batch(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<Option<SceneRayHit>, RayError>> {
        rays.par_iter()
            .with_min_len(64)
            .map(|&(o, d)| self.first_hit(o, d, t_min, t_max))
            .collect()
    }

    /// [`any_hit`](Self::any_hit) of every ray, on all cores, in input order.
    pub fn any_hit_batch(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Vec<Result<bool, RayError>> {
        rays.par_iter()
            .with_min_len(64)
            .map(|&(o, d)| self.any_hit(o, d, t_min, t_max))
            .collect()
    }
}
