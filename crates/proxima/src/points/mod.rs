//! Point clouds: k-nearest, radius (ball) search, the self-join within a
//! radius, and the Chamfer and Hausdorff distances between clouds.
//!
//! A [`PointCloud`] is the 4-wide tree over its points (the one
//! [`WideTree`] every structure here is made from); every query is written
//! once over that tree's nearest-first walk ([`NearestQuery::nearest_walk`]):
//!
//! | question | one query | many, on all cores |
//! |---|---|---|
//! | the `k` nearest points | [`PointCloud::k_nearest`] | [`PointCloud::k_nearest_batch`] ([`KNearest`], padded rows) |
//! | the points within `r` (optionally the nearest `m` of them) | [`PointCloud::within`] | [`PointCloud::within_batch`] ([`Neighbours`], compressed rows) |
//! | how many within `r` | — | [`PointCloud::count_within_batch`] |
//! | every pair of points within `r` | — | [`PointCloud::pairs_within`] |
//! | how far apart two clouds are | [`chamfer`], [`hausdorff`] | (batched inside) |
//!
//! **Within `r` is exact**: a point is in the ball when `|q - p| <= r`
//! holds for the `f32` coordinates and the `f64` radius as real numbers
//! (decided in integers where rounding could change it), so points exactly
//! on the sphere are in and points one ulp outside are out. Orders are
//! nearest first, ties by index, as everywhere in proxima; distances are
//! reported as `f32`.

mod ball;
mod error;
mod metrics;
mod neighbours;

pub use error::PointsError;
pub use metrics::{Chamfer, Directed, chamfer, hausdorff};
pub use neighbours::{KNearest, Neighbours};

use crate::budget::check_fits;
use crate::math::{Vec3, Vec3A};
use crate::primitive::{Point, PrimitiveSet};
use crate::query::knn::{Candidate, KBest};
use crate::query::{NearestQuery, SpatialIndex, answer_batch_indexed, check_query_point, morton_order};
use crate::{BuildConfig, WideTree};
use ball::{Ball, CappedBall, walk_bound};
use rayon::prelude::*;
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// One neighbour of a query: its index in the cloud and its distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neighbour {
    /// The point's index in the cloud.
    pub index: u32,
    /// Its distance to the query.
    pub distance: f32,
}

/// A point cloud and its tree, for neighbour queries.
///
/// ```
/// use proxima::points::PointCloud;
/// use proxima::Vec3;
/// let points: Vec<Vec3> = (0..10).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
/// let cloud = PointCloud::new(&points).unwrap();
/// let near = cloud.k_nearest(Vec3::new(3.2, 0.0, 0.0), 2).unwrap();
/// assert_eq!(near.iter().map(|n| n.index).collect::<Vec<_>>(), [3, 4]);
/// // Exactly on the sphere counts: 2 and 4 are at distance 1 from 3.
/// let ball = cloud.within(Vec3::new(3.0, 0.0, 0.0), 1.0, None).unwrap();
/// assert_eq!(ball.iter().map(|n| n.index).collect::<Vec<_>>(), [3, 2, 4]);
/// ```
#[derive(Clone, Debug)]
pub struct PointCloud {
    tree: WideTree<Point>,
    points: Vec<Vec3>,
}

/// Queries answered per task of a batch.
const CHUNK: usize = 1024;

/// Scratch memory of one worker, reused from query to query.
#[derive(Default)]
struct Scratch {
    found: Vec<Candidate>,
    heap: BinaryHeap<Candidate>,
}

impl PointCloud {
    /// The cloud of `points` (at least one, each finite and within
    /// [`MAX_COORDINATE`](crate::build::MAX_COORDINATE)), its tree built on
    /// all cores of rayon's pool.
    pub fn new(points: &[Vec3]) -> Result<Self, PointsError> {
        if points.is_empty() {
            return Err(PointsError::Empty { argument: "points" });
        }
        let set = PrimitiveSet::from_primitives(points.iter().map(|&p| Point(p)).collect());
        let tree = WideTree::build_set(set, &BuildConfig::default()).map_err(|source| PointsError::Build {
            argument: "points",
            source,
        })?;
        Ok(Self {
            tree,
            points: points.to_vec(),
        })
    }

    /// The points, in input order.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// How many points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Never: a cloud has at least one point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The tree over the points.
    pub fn tree(&self) -> &WideTree<Point> {
        &self.tree
    }

    /// The `k` points nearest to `query`, nearest first (all of them when
    /// the cloud has fewer).
    pub fn k_nearest(&self, query: Vec3, k: usize) -> Result<Vec<Neighbour>, PointsError> {
        check_k(k)?;
        check_queries(&[query], "query")?;
        Ok(self.tree.k_nearest(query, k).iter().map(neighbour).collect())
    }

    /// [`k_nearest`](Self::k_nearest) of every query, on all cores, in
    /// rows of `k` ([`KNearest`]); the answers' memory is checked against
    /// the budget before it is allocated.
    pub fn k_nearest_batch(&self, queries: &[Vec3], k: usize) -> Result<KNearest, PointsError> {
        check_k(k)?;
        check_queries(queries, "queries")?;
        // The rows in processing order, then in input order: 16 bytes per
        // entry at the peak.
        check_fits("k", k, (queries.len() as u128) * (k as u128), 16)?;
        let order = morton_order(queries, &self.tree.bounds());
        let mut ordered_indices = vec![u32::MAX; queries.len() * k];
        let mut ordered_distances = vec![f32::INFINITY; queries.len() * k];
        ordered_indices
            .par_chunks_mut(k * CHUNK)
            .zip(ordered_distances.par_chunks_mut(k * CHUNK))
            .zip(order.par_chunks(CHUNK))
            .for_each_init(
                || (crate::query::KnnScratch::new(), Vec::new()),
                |(scratch, out), ((rows, row_distances), chunk)| {
                    for (i, &q) in chunk.iter().enumerate() {
                        self.tree.k_nearest_into(queries[q as usize], k, scratch, out);
                        for (j, hit) in out.iter().enumerate() {
                            rows[i * k + j] = hit.primitive;
                            row_distances[i * k + j] = hit.distance;
                        }
                    }
                },
            );
        let at = inverse(&order);
        let mut indices = vec![0; queries.len() * k];
        indices
            .par_chunks_mut(k)
            .enumerate()
            .for_each(|(row, out)| out.copy_from_slice(&ordered_indices[at[row] as usize * k..][..k]));
        drop(ordered_indices);
        let mut distances = vec![0.0; queries.len() * k];
        distances
            .par_chunks_mut(k)
            .enumerate()
            .for_each(|(row, out)| out.copy_from_slice(&ordered_distances[at[row] as usize * k..][..k]));
        Ok(KNearest { k, indices, distances })
    }

    /// The points within `radius` of `query` (exactly: see the module
    /// doc), nearest first; with `max_neighbors`, only the nearest that
    /// many of them (the ball query of PointNet++).
    pub fn within(
        &self,
        query: Vec3,
        radius: f64,
        max_neighbors: Option<usize>,
    ) -> Result<Vec<Neighbour>, PointsError> {
        check_radius(radius, max_neighbors)?;
        check_queries(&[query], "query")?;
        let mut scratch = Scratch::default();
        self.ball(query, radius, max_neighbors, &mut scratch);
        Ok(scratch.found.iter().map(candidate).collect())
    }

    /// [`within`](Self::within) of every query, on all cores, in compressed
    /// rows ([`Neighbours`]). The rows are gathered a task at a time and
    /// their total is held against the memory budget as they come, so a
    /// radius that finds too much is refused before it can exhaust memory.
    pub fn within_batch(
        &self,
        queries: &[Vec3],
        radius: f64,
        max_neighbors: Option<usize>,
    ) -> Result<Neighbours, PointsError> {
        check_radius(radius, max_neighbors)?;
        check_queries(queries, "queries")?;
        let budget = crate::budget::memory_budget_from_env()
            .map_err(|e| PointsError::Budget(crate::budget::BudgetError::Environment(e)))?;
        // Each neighbour is held twice at the peak (its task's rows, then
        // the answer), 8 bytes each time.
        const BYTES: u64 = 16;
        let total = AtomicUsize::new(0);
        let over = AtomicBool::new(false);
        let order = morton_order(queries, &self.tree.bounds());
        let parts: Vec<(Vec<usize>, Vec<u32>, Vec<f32>)> = order
            .par_chunks(CHUNK)
            .map_init(Scratch::default, |scratch, chunk| {
                let mut offsets = Vec::with_capacity(chunk.len() + 1);
                let (mut indices, mut distances) = (Vec::new(), Vec::new());
                offsets.push(0);
                if over.load(Ordering::Relaxed) {
                    return (offsets, indices, distances);
                }
                for &q in chunk {
                    self.ball(queries[q as usize], radius, max_neighbors, scratch);
                    indices.extend(scratch.found.iter().map(|c| c.index));
                    distances.extend(scratch.found.iter().map(|c| c.distance_squared.sqrt()));
                    offsets.push(indices.len());
                }
                let now = total.fetch_add(indices.len(), Ordering::Relaxed) + indices.len();
                if now as u64 * BYTES > budget {
                    over.store(true, Ordering::Relaxed);
                }
                (offsets, indices, distances)
            })
            .collect();
        let total = total.into_inner();
        if over.into_inner() {
            crate::budget::check_fits_in(budget, "radius", radius, total as u128, u128::from(BYTES))?;
        }
        // Back to input order: query `i` was answered at position `at[i]`,
        // row `at[i] % CHUNK` of part `at[i] / CHUNK`.
        let at = inverse(&order);
        let row = |i: usize| {
            let (part, local) = (at[i] as usize / CHUNK, at[i] as usize % CHUNK);
            let (offsets, indices, distances) = &parts[part];
            let range = offsets[local]..offsets[local + 1];
            (&indices[range.clone()], &distances[range])
        };
        let mut offsets = Vec::with_capacity(queries.len() + 1);
        offsets.push(0);
        for i in 0..queries.len() {
            offsets.push(offsets[i] + row(i).0.len());
        }
        // Rows copied on all cores: the answer split into disjoint blocks of
        // `CHUNK` queries' rows, each filled by one task.
        let mut indices = vec![0u32; total];
        let mut distances = vec![0f32; total];
        let mut blocks = Vec::with_capacity(queries.len().div_ceil(CHUNK));
        let (mut rest_indices, mut rest_distances) = (&mut indices[..], &mut distances[..]);
        for first in (0..queries.len()).step_by(CHUNK) {
            let end = (first + CHUNK).min(queries.len());
            let len = offsets[end] - offsets[first];
            let (block_indices, tail_indices) = rest_indices.split_at_mut(len);
            let (block_distances, tail_distances) = rest_distances.split_at_mut(len);
            blocks.push((first..end, block_indices, block_distances));
            (rest_indices, rest_distances) = (tail_indices, tail_distances);
        }
        blocks
            .into_par_iter()
            .for_each(|(rows, block_indices, block_distances)| {
                let mut at = 0;
                for i in rows {
                    let (found, found_distances) = row(i);
                    block_indices[at..at + found.len()].copy_from_slice(found);
                    block_distances[at..at + found.len()].copy_from_slice(found_distances);
                    at += found.len();
                }
            });
        let answer = Neighbours {
            offsets,
            indices,
            distances,
        };
        Ok(answer)
    }

    /// How many points lie within `radius` of each query (exactly), on all
    /// cores.
    pub fn count_within_batch(&self, queries: &[Vec3], radius: f64) -> Result<Vec<u32>, PointsError> {
        check_radius(radius, None)?;
        check_queries(queries, "queries")?;
        Ok(answer_batch_indexed(
            queries,
            &self.tree.bounds(),
            true,
            Scratch::default,
            |scratch, i| {
                self.ball(queries[i], radius, None, scratch);
                scratch.found.len() as u32
            },
        ))
    }

    /// Every pair `[i, j]`, `i < j`, of points of the cloud within
    /// `radius` of each other (exactly), sorted.
    pub fn pairs_within(&self, radius: f64) -> Result<Vec<[u32; 2]>, PointsError> {
        let rows = self.within_batch(&self.points, radius, None)?;
        let count = (0..rows.len())
            .map(|i| rows.of(i).0.iter().filter(|&&j| j as usize > i).count())
            .sum::<usize>();
        check_fits("radius", radius, count as u128, 8)?;
        let mut pairs = Vec::with_capacity(count);
        for i in 0..rows.len() {
            let start = pairs.len();
            pairs.extend(rows.of(i).0.iter().filter(|&&j| j as usize > i).map(|&j| [i as u32, j]));
            pairs[start..].sort_unstable();
        }
        Ok(pairs)
    }

    /// The points within `radius` of `query` into `scratch.found`, nearest
    /// first (ties by index), at most `max_neighbors`.
    fn ball(&self, query: Vec3, radius: f64, max_neighbors: Option<usize>, scratch: &mut Scratch) {
        let leaves = self.tree.leaves();
        let bound = walk_bound(radius);
        scratch.found.clear();
        match max_neighbors {
            None => {
                let mut ball = Ball {
                    centre: query,
                    r: radius,
                    bound,
                    indices: leaves.indices(),
                    out: &mut scratch.found,
                };
                self.tree.nearest_walk(Vec3A::from(query), &mut ball, &mut ());
                scratch.found.sort_unstable();
            }
            Some(most) => {
                scratch.heap.clear();
                let mut best = KBest::new(&mut scratch.heap, most, leaves.indices());
                best.bound = bound;
                let mut ball = CappedBall {
                    centre: query,
                    r: radius,
                    best,
                };
                self.tree.nearest_walk(Vec3A::from(query), &mut ball, &mut ());
                scratch.found.extend(scratch.heap.drain());
                scratch.found.sort_unstable();
            }
        }
    }
}

/// Where each query of `order` (a permutation) was answered.
fn inverse(order: &[u32]) -> Vec<u32> {
    let mut at = vec![0; order.len()];
    for (position, &i) in order.iter().enumerate() {
        at[i as usize] = position as u32;
    }
    at
}

fn neighbour(hit: &crate::ClosestHit) -> Neighbour {
    Neighbour {
        index: hit.primitive,
        distance: hit.distance,
    }
}

fn candidate(c: &Candidate) -> Neighbour {
    Neighbour {
        index: c.index,
        distance: c.distance_squared.sqrt(),
    }
}

/// Refuses `k = 0` and `k > 2^31`.
fn check_k(k: usize) -> Result<(), PointsError> {
    if k == 0 || k > 1 << 31 {
        return Err(PointsError::BadArgument {
            argument: "k",
            value: k.to_string(),
            rule: "must be between 1 and 2^31",
        });
    }
    Ok(())
}

/// Refuses a negative or NaN radius (infinity is allowed) and a cap of 0.
fn check_radius(radius: f64, max_neighbors: Option<usize>) -> Result<(), PointsError> {
    if radius.is_nan() || radius < 0.0 {
        return Err(PointsError::BadArgument {
            argument: "radius",
            value: radius.to_string(),
            rule: "must be a non-negative number",
        });
    }
    if max_neighbors == Some(0) {
        return Err(PointsError::BadArgument {
            argument: "max_neighbors",
            value: "0".into(),
            rule: "must be at least 1",
        });
    }
    Ok(())
}

/// Refuses the first query point the tree cannot answer, naming it.
fn check_queries(queries: &[Vec3], argument: &'static str) -> Result<(), PointsError> {
    for (index, &q) in queries.iter().enumerate() {
        if let Err(source) = check_query_point(q) {
            return Err(PointsError::Query {
                argument,
                index,
                source,
            });
        }
    }
    Ok(())
}
