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

/// The order in which to process `points`: input order, or Morton order.
fn processing_order(points: &[Vec3], bounds: &Aabb, options: BatchOptions) -> Vec<u32> {
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    if options.reorder {
        let codes: Vec<u32> = points.par_iter().map(|&p| morton_code(p, bounds)).collect();
        order.par_sort_unstable_by_key(|&i| codes[i as usize]);
    }
    order
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
        if !options.reorder {
            return points.par_iter().map(|&p| self.closest(p)).collect();
        }
        let order = processing_order(points, &self.root_bounds(), options);
        let answers: Vec<Option<ClosestHit>> = order.par_iter().map(|&i| self.closest(points[i as usize])).collect();
        let mut out = vec![None; points.len()];
        for (&i, answer) in order.iter().zip(answers) {
            out[i as usize] = answer;
        }
        out
    }

    /// [`k_nearest`](Self::k_nearest) for every point, in parallel, in Morton
    /// order; results in input order. Scratch memory is allocated once per
    /// worker, not per query.
    pub fn k_nearest_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>> {
        let order = processing_order(points, &self.root_bounds(), BatchOptions::default());
        let answers: Vec<Vec<ClosestHit>> = order
            .par_iter()
            .map_init(KnnScratch::new, |scratch, &i| {
                let mut out = Vec::with_capacity(k.min(self.len()));
                self.k_nearest_into(points[i as usize], k, scratch, &mut out);
                out
            })
            .collect();
        let mut out = vec![Vec::new(); points.len()];
        for (&i, answer) in order.iter().zip(answers) {
            out[i as usize] = answer;
        }
        out
    }
}
