//! Queries over many points at once, on all cores.

use super::knn::KnnScratch;
use super::{AabbTree, ClosestHit};
use crate::aabb::Aabb;
use crate::math::Vec3;
use crate::primitive::ClosestPoint;
use rayon::prelude::*;

/// How a batch is processed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchOptions {
    /// Process the queries in Morton (Z-curve) order, so consecutive queries
    /// walk mostly the same nodes and find them in cache. Results still come
    /// back in input order.
    pub reorder: bool,
}

impl Default for BatchOptions {
    fn default() -> Self {
        Self { reorder: true }
    }
}

/// Spreads the low 10 bits of `v` so there are two zero bits between each.
#[inline]
fn spread_bits(v: u32) -> u32 {
    let mut x = v & 0x3ff;
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// 30-bit Morton code of `p` within `bounds` (points outside are clamped).
pub(crate) fn morton_code(p: Vec3, bounds: &Aabb) -> u32 {
    let size = bounds.size().max(Vec3::splat(f32::MIN_POSITIVE));
    let t = ((p - bounds.min) / size).clamp(Vec3::ZERO, Vec3::ONE) * 1023.0;
    // NaN casts to 0: a NaN query simply sorts first.
    spread_bits(t.x as u32) | (spread_bits(t.y as u32) << 1) | (spread_bits(t.z as u32) << 2)
}

/// Answers `query` for every point on rayon's pool and returns the answers
/// in input order. With `reorder`, the points are processed in Morton order
/// within `bounds`, so consecutive queries walk mostly the same nodes while
/// they are in cache. `init` makes one scratch value per worker, so queries do
/// not allocate. Shared by every tree's batch queries.
pub(crate) fn answer_batch<S, R: Send>(
    points: &[Vec3],
    bounds: &Aabb,
    reorder: bool,
    init: impl Fn() -> S + Sync + Send,
    query: impl Fn(&mut S, Vec3) -> R + Sync + Send,
) -> Vec<R> {
    if !reorder {
        return points
            .par_iter()
            .map_init(&init, |scratch, &p| query(scratch, p))
            .collect();
    }
    let codes: Vec<u32> = points.par_iter().map(|&p| morton_code(p, bounds)).collect();
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    order.par_sort_unstable_by_key(|&i| codes[i as usize]);
    let answers: Vec<R> = order
        .par_iter()
        .map_init(&init, |scratch, &i| query(scratch, points[i as usize]))
        .collect();
    let mut slots: Vec<Option<R>> = std::iter::repeat_with(|| None).take(points.len()).collect();
    for (&i, answer) in order.iter().zip(answers) {
        slots[i as usize] = Some(answer);
    }
    // `order` is a permutation, so every slot is filled.
    slots.into_iter().flatten().collect()
}

impl<T: ClosestPoint + Sync> AabbTree<T> {
    fn root_bounds(&self) -> Aabb {
        self.root().map_or(Aabb::EMPTY, |n| n.bounds())
    }

    /// [`closest`](Self::closest) for every point, in parallel on rayon's pool,
    /// in Morton order; results in input order. No allocation per query.
    pub fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<ClosestHit>> {
        self.closest_batch_with(points, BatchOptions::default())
    }

    /// [`closest_batch`](Self::closest_batch) with explicit options.
    pub fn closest_batch_with(&self, points: &[Vec3], options: BatchOptions) -> Vec<Option<ClosestHit>> {
        answer_batch(
            points,
            &self.root_bounds(),
            options.reorder,
            || (),
            |_, p| self.closest(p),
        )
    }

    /// [`k_nearest`](Self::k_nearest) for every point, in parallel, in Morton
    /// order; results in input order. Scratch memory is allocated once per
    /// worker, not per query.
    pub fn k_nearest_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>> {
        answer_batch(points, &self.root_bounds(), true, KnnScratch::new, |scratch, p| {
            let mut out = Vec::with_capacity(k.min(self.len()));
            self.k_nearest_into(p, k, scratch, &mut out);
            out
        })
    }
}
