//! The `k` nearest faces of a scene.

use super::{ACROSS_FRAMES, Scene, SceneHit};
use crate::aabb_tree::AabbNode;
use crate::build::{BinaryQuery, walk};
use crate::math::{Vec3, Vec3A};
use crate::primitive::Triangle;
use crate::query::{NearestQuery, SpatialIndex};
use rayon::prelude::*;
use std::ops::{ControlFlow, Range};

/// The top-level walk for the `k` nearest: boxes by distance, each
/// instance asked for its own `k` nearest faces, the best `k` kept.
struct KNearest<'a> {
    scene: &'a Scene,
    indices: &'a [u32],
    p: Vec3,
    p_a: Vec3A,
    k: usize,
    best: Vec<SceneHit>,
    bound_squared: f32,
}

impl BinaryQuery<AabbNode> for KNearest<'_> {
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
            let local = instance.to_local(self.p);
            // Faces, each once (a polygon's fan triangles are one face).
            let hits = if tree.leaves().one_part_each() {
                tree.k_nearest(local, self.k)
            } else {
                tree.k_nearest_sources_batch(&[local], self.k).swap_remove(0)
            };
            for hit in hits {
                let candidate = SceneHit {
                    instance: index,
                    face: hit.source,
                    triangle: hit.primitive,
                    point: instance.pose.apply(hit.point),
                    distance: hit.distance,
                };
                let key = |h: &SceneHit| (h.distance, h.instance, h.face);
                let at = self.best.partition_point(|h| key(h) < key(&candidate));
                if at < self.k {
                    self.best.insert(at, candidate);
                    self.best.truncate(self.k);
                }
            }
            if self.best.len() == self.k {
                let bound = self.best[self.k - 1].distance * (1.0 + ACROSS_FRAMES);
                self.bound_squared = bound * bound;
            }
        }
        ControlFlow::Continue(())
    }
}

impl Scene {
    /// The `k` faces of any instances nearest to `p` (world), nearest first;
    /// ties by instance, then face. A face is listed once, at its nearest
    /// point. Fewer when the scene has fewer faces; none for `k = 0`, an
    /// empty scene or a `p` that is not finite.
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<SceneHit> {
        let Some(top) = self.top.as_ref() else {
            return Vec::new();
        };
        if k == 0 || !p.is_finite() {
            return Vec::new();
        }
        let mut query = KNearest {
            scene: self,
            indices: top.leaves().indices(),
            p,
            p_a: p.into(),
            k,
            best: Vec::with_capacity(k.min(1 << 16) + 1),
            bound_squared: f32::INFINITY,
        };
        walk::<AabbNode, _, _>(top.pairs(), top.depth(), &mut query, &mut ());
        query.best
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
