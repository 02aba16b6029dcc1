//! Queries over many points at once on the wide tree, on all cores.

use super::{WideKnnScratch, WideTree};
use crate::bvh::batch::morton_code;
use crate::bvh::{BatchOptions, ClosestHit};
use crate::math::Vec3;
use crate::primitive::ClosestPoint;
use rayon::prelude::*;

impl<T: ClosestPoint + Sync> WideTree<T> {
    /// The order in which to process `points`: input order, or Morton order
    /// in the root box.
    fn processing_order(&self, points: &[Vec3], options: BatchOptions) -> Vec<u32> {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        if let (true, Some(root)) = (options.reorder, self.tree.root()) {
            let bounds = root.bounds();
            let codes: Vec<u32> = points.par_iter().map(|&p| morton_code(p, &bounds)).collect();
            order.par_sort_unstable_by_key(|&i| codes[i as usize]);
        }
        order
    }

    /// [`closest`](Self::closest) for every point, in parallel on rayon's
    /// pool, in Morton order; results in input order. No allocation per query.
    pub fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<ClosestHit>> {
        self.closest_batch_with(points, BatchOptions::default())
    }

    /// [`closest_batch`](Self::closest_batch) with explicit options.
    pub fn closest_batch_with(&self, points: &[Vec3], options: BatchOptions) -> Vec<Option<ClosestHit>> {
        if !options.reorder {
            return points.par_iter().map(|&p| self.closest(p)).collect();
        }
        let order = self.processing_order(points, options);
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
        let order = self.processing_order(points, BatchOptions::default());
        let answers: Vec<Vec<ClosestHit>> = order
            .par_iter()
            .map_init(WideKnnScratch::new, |scratch, &i| {
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
