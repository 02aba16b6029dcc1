//! The closest point of a scene, and its signed distance (inside when
//! inside any instance).

use super::Scene;
use crate::aabb_tree::AabbNode;
use crate::build::{BinaryQuery, walk};
use crate::math::{DVec3, Vec3, Vec3A};
use crate::primitive::Triangle;
use crate::query::{NearestQuery, SpatialIndex};
use crate::sdf::Sign;
use rayon::prelude::*;
use std::ops::{ControlFlow, Range};

/// Relative slack on distances compared across instances: each is computed
/// in its own frame from a rounded query, so a box is pruned, or an
/// instance's search bounded, only beyond the best distance by this much.
pub(super) const ACROSS_FRAMES: f32 = 1e-5;

/// The closest point of a scene to a query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit {
    /// The instance.
    pub instance: u32,
    /// The face of the instance's mesh.
    pub face: u32,
    /// The fan triangle of that face (its index in the mesh's triangles).
    pub triangle: u32,
    /// The closest point, in the world's frame.
    pub point: DVec3,
    /// Its distance from the query.
    pub distance: f32,
}

/// A scene's signed distance: negative inside any instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneSignedDistance {
    /// The distance to the closest point, negative where the query is inside
    /// some instance (by that instance's own sign).
    pub distance: f32,
    /// The closest point.
    pub closest: SceneHit,
}

/// The top-level walk for the closest point: boxes by distance, each
/// instance's tree asked within the best distance so far.
struct Closest<'a> {
    scene: &'a Scene,
    indices: &'a [u32],
    p: Vec3,
    p_a: Vec3A,
    best: Option<SceneHit>,
    bound_squared: f32,
}

impl BinaryQuery<AabbNode> for Closest<'_> {
    const TOUCH_GRANDCHILDREN: bool = false;
    #[inline]
    fn key(&self, node: &AabbNode) -> f32 {
        node.distance_squared(self.p_a)
    }
    fn bound(&self) -> f32 {
        self.bound_squared
    }
    fn leaf(&mut self, range: Range<usize>) -> ControlFlow<()> {
        for slot in range {
            let index = self.indices[slot];
            let instance = &self.scene.instances[index as usize];
            let tree = instance.mesh.tree::<Triangle>().expect("a scene's meshes have faces");
            let max = self.best.map_or(f32::INFINITY, |b| b.distance * (1.0 + ACROSS_FRAMES));
            let Some(hit) = tree.closest_within(instance.to_local(self.p), max) else {
                continue;
            };
            let better = self
                .best
                .is_none_or(|b| (hit.distance, index) < (b.distance, b.instance));
            if better {
                self.best = Some(SceneHit {
                    instance: index,
                    face: hit.source,
                    triangle: hit.primitive,
                    point: instance.pose.apply(hit.point),
                    distance: hit.distance,
                });
                let bound = hit.distance * (1.0 + ACROSS_FRAMES);
                self.bound_squared = bound * bound;
            }
        }
        ControlFlow::Continue(())
    }
}

/// The top-level walk for the side: every instance whose box holds the
/// query, until one holds it inside.
struct Inside<'a> {
    scene: &'a Scene,
    indices: &'a [u32],
    p: Vec3,
    p_a: Vec3A,
    sign: Sign,
    inside: bool,
}

impl BinaryQuery<AabbNode> for Inside<'_> {
    const TOUCH_GRANDCHILDREN: bool = false;
    #[inline]
    fn key(&self, node: &AabbNode) -> f32 {
        node.distance_squared(self.p_a)
    }
    fn bound(&self) -> f32 {
        0.0
    }
    fn leaf(&mut self, range: Range<usize>) -> ControlFlow<()> {
        for slot in range {
            let instance = &self.scene.instances[self.indices[slot] as usize];
            let field = instance.mesh.field(self.sign).expect("a scene's meshes have faces");
            let local = instance.to_local(self.p);
            let inside = match self.sign {
                Sign::WindingNumber => field.contains(local),
                Sign::Pseudonormal => field.signed_distance(local).is_some_and(|s| s.is_inside()),
            };
            if inside {
                self.inside = true;
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }
}

impl Scene {
    /// The closest point of any instance to `p` (world), or `None` for an
    /// empty scene or a `p` that is not finite. Ties between instances go
    /// to the lower instance index; within an instance, as its tree's
    /// [`closest`](crate::query::NearestQuery::closest).
    pub fn closest(&self, p: Vec3) -> Option<SceneHit> {
        let top = self.top.as_ref()?;
        if !p.is_finite() {
            return None;
        }
        let mut query = Closest {
            scene: self,
            indices: top.leaves().indices(),
            p,
            p_a: p.into(),
            best: None,
            bound_squared: f32::INFINITY,
        };
        walk::<AabbNode, _, _>(top.pairs(), top.depth(), &mut query, &mut ());
        query.best
    }

    /// [`closest`](Self::closest) of every point, on all cores, in input order.
    pub fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<SceneHit>> {
        points.par_iter().with_min_len(64).map(|&p| self.closest(p)).collect()
    }

    /// Whether `p` is inside some instance, each instance signed by `sign`
    /// (its winding number above ½, or its closest feature's pseudonormal).
    pub fn contains(&self, p: Vec3, sign: Sign) -> bool {
        let Some(top) = self.top.as_ref() else { return false };
        if !p.is_finite() {
            return false;
        }
        let mut query = Inside {
            scene: self,
            indices: top.leaves().indices(),
            p,
            p_a: p.into(),
            sign,
            inside: false,
        };
        walk::<AabbNode, _, _>(top.pairs(), top.depth(), &mut query, &mut ());
        query.inside
    }

    /// The signed distance of the scene at `p`: the distance to the
    /// closest point of any instance, negative where `p` is inside any
    /// instance (the union of the instances' solids), each instance signed
    /// by `sign`. `None` as [`closest`](Self::closest).
    pub fn signed_distance(&self, p: Vec3, sign: Sign) -> Option<SceneSignedDistance> {
        let closest = self.closest(p)?;
        let inside = self.contains(p, sign);
        Some(SceneSignedDistance {
            distance: if inside { -closest.distance } else { closest.distance },
            closest,
        })
    }

    /// [`signed_distance`](Self::signed_distance) of every point, on all
    /// cores, in input order.
    pub fn signed_distance_batch(&self, points: &[Vec3], sign: Sign) -> Vec<Option<SceneSignedDistance>> {
        points
            .par_iter()
            .with_min_len(64)
            .map(|&p| self.signed_distance(p, sign))
            .collect()
    }
}
