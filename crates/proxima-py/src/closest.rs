//! `Mesh.closest_points`, `Mesh.k_nearest` and `Mesh.frustum`: one task
//! each over the tree of the kind asked for.

use crate::structures::TreeTask;
use proxima::kind::MeshPrimitive;
use proxima::prelude::*;
use proxima::query::distinct_sources;

/// The closest point of each query point: closest points (x, y, z per
/// point), distances and source indices, in input order.
pub struct Closest<'a> {
    /// The query points, checked answerable.
    pub points: &'a [Vec3],
}

/// What `closest_points` returns, before it becomes numpy arrays.
#[derive(Default)]
pub struct ClosestAnswers {
    /// x, y, z of each closest point.
    pub closest: Vec<f64>,
    /// Each distance.
    pub distance: Vec<f64>,
    /// Each source element.
    pub index: Vec<i64>,
}

impl TreeTask for Closest<'_> {
    type Output = ClosestAnswers;

    fn run<T: MeshPrimitive>(self, tree: &WideTree<T>, _: bool) -> ClosestAnswers {
        let hits = tree.closest_batch(self.points);
        let n = hits.len();
        let mut out = ClosestAnswers {
            closest: Vec::with_capacity(3 * n),
            distance: Vec::with_capacity(n),
            index: Vec::with_capacity(n),
        };
        for hit in &hits {
            // Every point was checked answerable and the tree is not empty.
            match hit {
                Some(hit) => {
                    out.closest.extend(hit.point.to_array().map(f64::from));
                    out.distance.push(hit.distance as f64);
                    out.index.push(hit.source as i64);
                }
                None => {
                    out.closest.extend([f64::NAN; 3]);
                    out.distance.push(f64::NAN);
                    out.index.push(-1);
                }
            }
        }
        out
    }
}

/// The `k` nearest source elements of each query point.
pub struct KNearest<'a> {
    /// The query points, checked answerable.
    pub points: &'a [Vec3],
    /// How many per point (at least 1).
    pub k: usize,
}

impl TreeTask for KNearest<'_> {
    /// Distances and indices, `k` per point, padded with `inf` and -1.
    type Output = (Vec<f64>, Vec<i64>);

    fn run<T: MeshPrimitive>(self, tree: &WideTree<T>, one_part_each: bool) -> (Vec<f64>, Vec<i64>) {
        let Self { points, k } = self;
        let mut distance = Vec::with_capacity(points.len() * k);
        let mut index = Vec::with_capacity(points.len() * k);
        // In chunks, so that the hits held at once stay near 2^20 whatever k.
        let chunk = ((1usize << 20) / k.min(tree.len()).max(1)).max(1);
        for points in points.chunks(chunk) {
            let mut answers = tree.k_nearest_batch(points, k);
            if !one_part_each {
                answers = distinct_sources(answers, points, k, tree.len(), &|p, k| tree.k_nearest(p, k));
            }
            for hits in &answers {
                distance.extend(hits.iter().map(|h| h.distance as f64));
                index.extend(hits.iter().map(|h| h.source as i64));
                let missing = k - hits.len();
                distance.extend(std::iter::repeat_n(f64::INFINITY, missing));
                index.extend(std::iter::repeat_n(-1, missing));
            }
        }
        (distance, index)
    }
}

/// The source elements sharing a point with a frustum, increasing.
pub struct InFrustum<'a> {
    /// The frustum.
    pub frustum: &'a Frustum,
}

impl TreeTask for InFrustum<'_> {
    type Output = Vec<i64>;

    fn run<T: MeshPrimitive>(self, tree: &WideTree<T>, _: bool) -> Vec<i64> {
        let found = tree.frustum(self.frustum);
        // The walk gives build-input indices; the leaves map slots to both.
        let leaves = tree.leaves();
        let mut source_of_input = vec![0u32; leaves.len()];
        for (&input, &source) in leaves.indices().iter().zip(leaves.sources()) {
            source_of_input[input as usize] = source;
        }
        let mut out: Vec<i64> = found.iter().map(|&i| source_of_input[i as usize] as i64).collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}
