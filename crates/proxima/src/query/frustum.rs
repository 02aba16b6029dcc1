//! View frustum queries, written once over any structure's frustum walk.

use super::{Counter, QueryStats, SpatialIndex};
use crate::frustum::{Frustum, FrustumOverlap};

/// Frustum queries: every primitive sharing a point with a view frustum,
/// exactly ([`FrustumOverlap`]).
///
/// ```
/// use proxima::prelude::*;
/// let points: Vec<Point> = (0..10).map(|i| Point(Vec3::new(i as f32, 0.0, -5.0))).collect();
/// let tree = AabbTree::build(points, &Default::default()).unwrap();
/// // A camera at the origin looking down -z, 90° field of view.
/// let view_projection = Mat4::perspective_rh_gl(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 100.0);
/// let frustum = Frustum::from_view_projection(view_projection).unwrap();
/// assert_eq!(tree.frustum(&frustum), [0, 1, 2, 3, 4, 5]);
/// ```
pub trait FrustumQuery<T: FrustumOverlap>: SpatialIndex<T> {
    /// Clears `out`, then writes into it the input index of every primitive
    /// that shares a point with `frustum`, in increasing order, reporting
    /// the work to `counter`.
    fn frustum_walk<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C);

    /// The input indices of the primitives sharing a point with `frustum`,
    /// in increasing order.
    fn frustum(&self, frustum: &Frustum) -> Vec<u32> {
        let mut out = Vec::new();
        self.frustum_walk(frustum, &mut out, &mut ());
        out
    }

    /// [`frustum`](Self::frustum) into `out` (cleared first), so repeated
    /// queries do not allocate.
    fn frustum_into(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        self.frustum_walk(frustum, out, &mut ());
    }

    /// The sources (mesh elements) of the primitives sharing a point with
    /// `frustum`, increasing, each once: a face split in several triangles
    /// counts once.
    fn frustum_sources(&self, frustum: &Frustum) -> Vec<u32> {
        self.leaves().sources_of_inputs(&self.frustum(frustum))
    }

    /// [`frustum`](Self::frustum), also counting the nodes and primitives tested.
    fn frustum_with_stats(&self, frustum: &Frustum) -> (Vec<u32>, QueryStats) {
        let mut out = Vec::new();
        let mut stats = QueryStats::default();
        self.frustum_walk(frustum, &mut out, &mut stats);
        (out, stats)
    }
}
