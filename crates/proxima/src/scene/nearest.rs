//! The `k` nearest faces of a scene.

use super::closest::bound_squared;
use super::{Scene, SceneHit};
use crate::math::Vec3;
use crate::primitive::Triangle;
use crate::query::{NearestQuery, SpatialIndex};
use rayon::prelude::*;
use std::ops::ControlFlow;

impl Scene {
    /// The `k` faces of any instances nearest to `p` (world), nearest first;
    /// ties by instance, then face. A face is listed once, at its nearest
    /// point. Fewer when the scene has fewer faces; none for `k = 0`, an
    /// empty scene or a `p` that is not finite.
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<SceneHit> {
        if k == 0 || !p.is_finite() || self.is_empty() {
            return Vec::new();
        }
        let mut best: Vec<SceneHit> = Vec::with_capacity(k.min(1 << 16) + 1);
        self.walk_near(p, f32::INFINITY, |index| {
            let instance = &self.instances[index as usize];
            let tree = instance.mesh.tree::<Triangle>().expect("a scene's meshes have faces");
            let local = instance.to_local(p);
            // Faces, each once (a polygon's fan triangles are one face).
            let hits = if tree.leaves().one_part_each() {
                tree.k_nearest(local, k)
            } else {
                tree.k_nearest_sources_batch(&[local], k).swap_remove(0)
            };
            let key = |h: &SceneHit| (h.distance, h.instance, h.face);
            for hit in hits {
                let candidate = SceneHit {
                    instance: index,
                    face: hit.source,
                    triangle: hit.primitive,
                    point: instance.pose.apply(hit.point),
                    distance: hit.distance,
                };
                let at = best.partition_point(|h| key(h) < key(&candidate));
                if at < k {
                    best.insert(at, candidate);
                    best.truncate(k);
                }
            }
            ControlFlow::Continue(if best.len() == k {
                bound_squared(best[k - 1].distance)
            } else {
                f32::INFINITY
            })
        });
        best
    }

    /// [`k_nearest`](Self::k_nearest) of every point, on all cores, in input order.
    pub fn k_nearest_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<SceneHit>> {
        points
            .par_iter()
            .with_min_len(16)
            .map(|&p| self.k_nearest(p, k))
            .collect()
    }
}
