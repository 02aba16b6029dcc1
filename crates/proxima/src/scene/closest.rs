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
const ACROSS_FRAMES: f32 = 1e-5;

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

/// The one top-level walk of the point queries (closest, inside, k
/// nearest): instance boxes by squared distance from the query, nearer
/// first, pruned beyond `bound_squared`. `visit` answers for one instance
/// (by index) and gives the new bound, or breaks the walk.
struct NearBoxes<'a, F> {
    indices: &'a [u32],
    p: Vec3A,
    bound_squared: f32,
    visit: F,
}

impl<F: FnMut(u32) -> ControlFlow<(), f32>> BinaryQuery<AabbNode> for NearBoxes<'_, F> {
    const TOUCH_GRANDCHILDREN: bool = false;
    #[inline]
    fn key(&self, node: &AabbNode) -> f32 {
        node.distance_squared(self.p)
    }
    fn bound(&self) -> f32 {
        self.bound_squared
    }
    fn leaf(&mut self, range: Range<usize>) -> ControlFlow<()> {
        for slot in range {
            self.bound_squared = (self.visit)(self.indices[slot])?;
        }
        ControlFlow::Continue(())
    }
}

/// The squared bound that admits instances up to `distance` away, with
/// the slack of comparisons across frames.
pub(super) fn bound_squared(distance: f32) -> f32 {
    let bound = distance * (1.0 + ACROSS_FRAMES);
    bound * bound
}

impl Scene {
    /// Walks the instances whose boxes lie within `bound_squared` of `p`
    /// (finite), nearest box first, with `visit` (see [`NearBoxes`]).
    pub(super) fn walk_near(&self, p: Vec3, bound_squared: f32, visit: impl FnMut(u32) -> ControlFlow<(), f32>) {
        let Some(top) = self.top.as_ref().map(|t| t.tree()) else {
            return;
        };
        let mut query = NearBoxes {
            indices: top.leaves().indices(),
            p: p.into(),
            bound_squared,
            visit,
        };
        walk::<AabbNode, _, _>(top.pairs(), top.depth(), &mut query, &mut ());
    }
}

impl Scene {
    /// The closest point of any instance to `p` (world), or `None` for an
    /// empty scene or a `p` that is not finite. Ties between instances go
    /// to the lower instance index; within an instance, as its tree's
    /// [`closest`](crate::query::NearestQuery::closest).
    pub fn closest(&self, p: Vec3) -> Option<SceneHit> {
        if !p.is_finite() {
            return None;
        }
        let mut best: Option<SceneHit> = None;
        self.walk_near(p, f32::INFINITY, |index| {
            let instance = &self.instances[index as usize];
            let tree = instance.mesh.tree::<Triangle>().expect("a scene's meshes have faces");
            let max = best.map_or(f32::INFINITY, |b| b.distance * (1.0 + ACROSS_FRAMES));
            if let Some(hit) = tree.closest_within(instance.to_local(p), max)
                && best.is_none_or(|b| (hit.distance, index) < (b.distance, b.instance))
            {
                best = Some(SceneHit {
                    instance: index,
                    face: hit.source,
                    triangle: hit.primitive,
                    point: instance.pose.apply(hit.point),
                    distance: hit.distance,
                });
            }
            ControlFlow::Continue(best.map_or(f32::INFINITY, |b| bound_squared(b.distance)))
        });
        best
    }

    /// [`closest`](Self::closest) of every point, on all cores, in input order.
    pub fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<SceneHit>> {
        points.par_iter().with_min_len(64).map(|&p| self.closest(p)).collect()
    }

    /// Whether `p` is inside some instance, each instance signed by `sign`
    /// (its winding number above ½, or its closest feature's pseudonormal).
    pub fn contains(&self, p: Vec3, sign: Sign) -> bool {
        if !p.is_finite() {
            return false;
        }
        // Only boxes that hold `p` (at distance 0), until one instance does.
        let mut inside = false;
        self.walk_near(p, 0.0, |index| {
            let instance = &self.instances[index as usize];
            let field = instance.mesh.field(sign).expect("a scene's meshes have faces");
            let local = instance.to_local(p);
            inside = match sign {
                Sign::WindingNumber => field.contains(local),
                Sign::Pseudonormal => field.signed_distance(local).is_some_and(|s| s.is_inside()),
            };
            if inside {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(0.0)
            }
        });
        inside
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
