//! Closest-primitive and k-nearest queries, written once over any
//! structure's nearest-first walk.

use super::batch::{BatchOptions, Seed, answer_batch, closest_in_chunks};
use super::knn::{KBest, KnnScratch, NearestAnswers, distinct_sources, drain_sorted};
use super::{Announcing, Best, ClosestHit, Counter, NearestVisitor, QueryStats, SpatialIndex};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;

/// Distance queries: the closest primitive, the `k` nearest, in batches on
/// all cores. A structure provides one walk; every query is built on it, and
/// answers equal a scan of every primitive field for field (ties to the
/// lowest input index).
///
/// ```
/// use proxima::prelude::*;
/// let points = vec![Point(Vec3::ZERO), Point(Vec3::X), Point(Vec3::Y)];
/// let tree = AabbTree::build(points, &Default::default()).unwrap();
/// let hit = tree.closest(Vec3::new(0.9, 0.2, 0.0)).unwrap();
/// assert_eq!(hit.primitive, 1);
/// assert_eq!(tree.closest_within(Vec3::new(0.9, 0.2, 0.0), 0.1), None);
/// ```
pub trait NearestQuery<T: ClosestPoint>: SpatialIndex<T> {
    /// Hands `visitor` every primitive that may lie within its
    /// [`bound`](NearestVisitor::bound) of `p` (which shrinks as it finds
    /// nearer ones), nearest subtrees first, and reports its work to
    /// `counter`. `p` is finite.
    fn nearest_walk<V: NearestVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C);

    /// The primitive closest to `p`, or `None` for an empty structure or a
    /// `p` that is not finite or beyond
    /// [`MAX_QUERY_COORDINATE`](crate::build::MAX_QUERY_COORDINATE). Ties go to
    /// the lowest input index.
    #[inline]
    fn closest(&self, p: Vec3) -> Option<ClosestHit> {
        self.closest_within(p, f32::INFINITY)
    }

    /// The closest primitive at distance at most `max_distance` from `p`, or
    /// `None` if there is none. A good upper bound (for instance a
    /// neighbouring query's answer plus the distance between the queries)
    /// speeds the search up without changing its answer.
    #[inline]
    fn closest_within(&self, p: Vec3, max_distance: f32) -> Option<ClosestHit> {
        Some(best_within(self, p, max_distance, &mut ())?.hit(self.leaves()))
    }

    /// [`closest`](Self::closest), also counting the nodes and primitives visited.
    fn closest_with_stats(&self, p: Vec3) -> (Option<ClosestHit>, QueryStats) {
        let mut stats = QueryStats::default();
        let best = best_within(self, p, f32::INFINITY, &mut stats);
        (best.map(|best| best.hit(self.leaves())), stats)
    }

    /// The `k` primitives closest to `p`, nearest first (ties by input
    /// index). All primitives when `k` exceeds their number, none when
    /// `k == 0` or `p` is not answerable (as for [`closest`](Self::closest)).
    ///
    /// ```
    /// use proxima::prelude::*;
    /// let points = (0..10).map(|i| Point(Vec3::new(i as f32, 0.0, 0.0))).collect();
    /// let tree = AabbTree::build(points, &Default::default()).unwrap();
    /// let hits = tree.k_nearest(Vec3::new(3.2, 1.0, 0.0), 3);
    /// let order: Vec<u32> = hits.iter().map(|h| h.primitive).collect();
    /// assert_eq!(order, [3, 4, 2]);
    /// ```
    fn k_nearest(&self, p: Vec3, k: usize) -> Vec<ClosestHit> {
        let mut out = Vec::new();
        self.k_nearest_into(p, k, &mut KnnScratch::new(), &mut out);
        out
    }

    /// [`k_nearest`](Self::k_nearest) writing into `out` (cleared first) and
    /// reusing `scratch`, so repeated queries do not allocate.
    fn k_nearest_into(&self, p: Vec3, k: usize, scratch: &mut KnnScratch, out: &mut Vec<ClosestHit>) {
        let leaves = self.leaves();
        let k = k.min(leaves.len());
        scratch.heap.clear();
        if k > 0 && super::answerable(p) {
            let mut best = KBest::new(&mut scratch.heap, k, leaves.indices());
            self.nearest_walk(Vec3A::from(p), &mut best, &mut ());
        }
        drain_sorted(&mut scratch.heap, out, leaves.sources());
    }

    /// [`closest`](Self::closest) for every point, on all cores of rayon's
    /// pool, in Morton order, each query seeded with its neighbour's answer;
    /// the answers come back in input order and are `closest`'s. No
    /// allocation per query.
    fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<ClosestHit>>
    where
        Self: Sync,
    {
        self.closest_batch_with(points, BatchOptions::default())
    }

    /// [`closest_batch`](Self::closest_batch) with explicit options.
    fn closest_batch_with(&self, points: &[Vec3], options: BatchOptions) -> Vec<Option<ClosestHit>>
    where
        Self: Sync,
    {
        closest_in_chunks(points, &self.bounds(), options.reorder, |points, out| {
            closest_chunk(self, points, out, options.seed_radius);
        })
    }

    /// [`k_nearest`](Self::k_nearest) for every point, on all cores, in
    /// Morton order; answers in input order. Scratch memory is allocated
    /// once per worker, not per query.
    fn k_nearest_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>>
    where
        Self: Sync,
    {
        answer_batch(points, &self.bounds(), true, KnnScratch::new, |scratch, p| {
            let mut out = Vec::with_capacity(k.min(self.leaves().len()));
            self.k_nearest_into(p, k, scratch, &mut out);
            out
        })
    }

    /// The `k` nearest *sources* (mesh elements) of every point, on all
    /// cores: a face split into several parts (a fan of triangles) is listed
    /// once, at its nearest part's distance (see [`distinct_sources`]);
    /// where every source is one primitive, [`k_nearest_batch`](Self::k_nearest_batch)'s
    /// answers.
    ///
    /// ```
    /// use proxima::prelude::*;
    /// // One quad, split in two triangles: one face.
    /// let mesh = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]).unwrap();
    /// let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    /// let answers = tree.k_nearest_sources_batch(&[Vec3::new(0.5, 0.5, 1.0)], 2);
    /// assert_eq!(answers[0].len(), 1);
    /// assert_eq!(tree.k_nearest_batch(&[Vec3::new(0.5, 0.5, 1.0)], 2)[0].len(), 2);
    /// ```
    fn k_nearest_sources_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>>
    where
        Self: Sync,
    {
        let answers = self.k_nearest_batch(points, k);
        if self.leaves().one_part_each() {
            return answers;
        }
        distinct_sources(answers, points, k, self.leaves().len(), &|p, k| self.k_nearest(p, k))
    }

    /// [`k_nearest_sources_batch`](Self::k_nearest_sources_batch) in chunks
    /// of queries, in input order, so that memory holds one chunk's answers
    /// (about 2^20 hits) whatever `k`: `each` gets every chunk's answers
    /// and may stop the work with an error. With `k = 1` the chunks come
    /// from [`closest_batch`](Self::closest_batch) (the same hits: one hit
    /// has no repeated source, and ties go to the lowest input index
    /// either way), which is faster than the k-nearest heap.
    fn k_nearest_sources_chunks<E>(
        &self,
        points: &[Vec3],
        k: usize,
        mut each: impl FnMut(&NearestAnswers) -> Result<(), E>,
    ) -> Result<(), E>
    where
        Self: Sync,
    {
        let parts = self.leaves().len();
        let chunk = (NEAREST_CHUNK_HITS / k.min(parts).max(1)).max(1);
        let one_part_each = k == 1 || self.leaves().one_part_each();
        for points in points.chunks(chunk) {
            let answers = if k == 1 {
                NearestAnswers::Closest(self.closest_batch(points))
            } else {
                let mut answers = self.k_nearest_batch(points, k);
                if !one_part_each {
                    answers = distinct_sources(answers, points, k, parts, &|p, k| self.k_nearest(p, k));
                }
                NearestAnswers::KNearest(answers)
            };
            each(&answers)?;
        }
        Ok(())
    }
}

/// Hits held at once by [`NearestQuery::k_nearest_sources_chunks`] (about
/// 32 MiB). Bigger chunks answer `k = 1` a little faster: each query of a
/// batch is seeded by its Morton-order neighbour's answer, nearer in a
/// bigger batch.
const NEAREST_CHUNK_HITS: usize = 1 << 20;

/// The walk's best primitive within `max_distance` of `p`, if any.
#[inline(always)]
pub(crate) fn best_within<'a, T: ClosestPoint + 'a, S: NearestQuery<T> + ?Sized, C: Counter>(
    structure: &'a S,
    p: Vec3,
    max_distance: f32,
    counter: &mut C,
) -> Option<Best<'a>> {
    if !super::answerable(p) {
        return None;
    }
    let mut best = Best::new(structure.leaves().indices(), max_distance * max_distance);
    structure.nearest_walk(Vec3A::from(p), &mut best, counter);
    best.found.then_some(best)
}

/// [`NearestQuery::closest`], handing each better candidate's input index to
/// `on_better` during the walk (see [`Announcing`]).
#[inline]
pub(crate) fn closest_announcing<T: ClosestPoint, S: NearestQuery<T> + ?Sized>(
    structure: &S,
    p: Vec3,
    on_better: impl FnMut(u32),
) -> Option<ClosestHit> {
    if !super::answerable(p) {
        return None;
    }
    let mut visitor = Announcing {
        best: Best::new(structure.leaves().indices(), f32::INFINITY),
        on_better,
    };
    structure.nearest_walk(Vec3A::from(p), &mut visitor, &mut ());
    let best = visitor.best;
    best.found.then(|| best.hit(structure.leaves()))
}

/// [`NearestQuery::closest_within`], except that the answer's `source`
/// holds its leaf-order slot, for [`Leaves::resolve_sources`](super::Leaves)
/// to replace later; `primitive` is the input index the walk already knows.
#[inline]
/// The closest hits of one chunk of a batch (points in Morton order), each
/// query seeded by its neighbour's answer when `seed_radius`
/// ([`BatchOptions::seed_radius`]).
pub(crate) fn closest_chunk<T: ClosestPoint, S: NearestQuery<T> + ?Sized>(
    structure: &S,
    points: &[Vec3],
    out: &mut [Option<ClosestHit>],
    seed_radius: bool,
) {
    Seed::closest_each(points, out, seed_radius, |p, r| closest_deferred(structure, p, r));
    // The sources are looked up once the chunk is answered, all together.
    structure.leaves().resolve_sources(out);
}

fn closest_deferred<T: ClosestPoint, S: NearestQuery<T> + ?Sized>(
    structure: &S,
    p: Vec3,
    max_distance: f32,
) -> Option<ClosestHit> {
    let best = best_within(structure, p, max_distance, &mut ())?;
    Some(ClosestHit {
        primitive: best.index(),
        source: best.slot as u32,
        point: best.point.into(),
        distance: best.distance_squared.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::{Rng, small_triangles};
    use crate::{AabbTree, WideTree};

    /// The announcing walk answers as `closest` does, ties included, and
    /// its last announcement is the answer's primitive.
    #[test]
    fn announcing_answers_as_closest_and_announces_the_answer_last() {
        let mut triangles = small_triangles(3000, 7);
        // Exact ties: the same triangles again, later in the input.
        triangles.extend_from_within(..200);
        let wide = WideTree::from_tree(AabbTree::build(triangles.clone(), &Default::default()).unwrap());
        let binary = AabbTree::build(triangles, &Default::default()).unwrap();
        let mut rng = Rng::new(3);
        let mut announced_any = 0;
        for k in 0..2000 {
            let p = match k % 3 {
                0 => Vec3::new(rng.range(-1.2, 1.2), rng.range(-1.2, 1.2), rng.range(-1.2, 1.2)),
                // On a vertex of a duplicated triangle: a tie at distance 0.
                1 => wide.leaves().primitives()[rng.below(3200)].a,
                _ => Vec3::splat(rng.range(-4.0, 4.0)),
            };
            for answer in [
                (wide.closest(p), {
                    let mut last = None;
                    (closest_announcing(&wide, p, |t| last = Some(t)), last)
                }),
                (binary.closest(p), {
                    let mut last = None;
                    (closest_announcing(&binary, p, |t| last = Some(t)), last)
                }),
            ] {
                let (expected, (got, last)) = answer;
                assert_eq!(got, expected, "at {p}");
                assert_eq!(last, expected.map(|h| h.primitive), "at {p}");
                announced_any += usize::from(last.is_some());
            }
        }
        assert_eq!(announced_any, 4000);
        assert_eq!(closest_announcing(&wide, Vec3::NAN, |_| panic!("announced")), None);
    }
}
