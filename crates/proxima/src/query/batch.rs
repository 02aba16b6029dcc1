//! Queries over many points at once, on all cores.

use super::ClosestHit;
use crate::aabb::Aabb;
use crate::math::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// How a batch is processed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BatchOptions {
    /// Process the queries in Morton (Z-curve) order, so consecutive queries
    /// walk mostly the same nodes and find them in cache. Results still come
    /// back in input order.
    pub reorder: bool,
    /// Start each query's search with a radius taken from the previous query
    /// of the same worker: the distance from the new query point to the
    /// previous answer's closest point, which lies on a primitive and so
    /// bounds the new answer's distance. Whole subtrees are then skipped from
    /// the first node on. The answer is still exact: a search within a radius
    /// that finds something has found the true closest primitive (anything
    /// closer would lie within the radius too), and one that finds nothing is
    /// redone without a radius. Pays off with `reorder`, where consecutive
    /// queries are neighbours, and most for points far from the surface,
    /// where the nearest-first walk's first leaves are a poor bound. On by
    /// default (measurements in docs/perf-log.md).
    pub seed_radius: bool,
}

impl Default for BatchOptions {
    fn default() -> Self {
        Self {
            reorder: true,
            seed_radius: true,
        }
    }
}

impl BatchOptions {
    /// Input order, no radius seeding: each query as [`closest`](super::NearestQuery::closest) alone would run it.
    pub const PLAIN: Self = Self {
        reorder: false,
        seed_radius: false,
    };
}

/// The previous answer's closest point, kept by a worker for radius seeding
/// ([`BatchOptions::seed_radius`]).
#[derive(Default)]
pub(crate) struct Seed {
    previous: Option<Vec3>,
}

impl Seed {
    /// The closest primitive to `p` by `closest_within`, searched first within
    /// the distance to the previous answer (slightly enlarged, since that
    /// point was itself rounded), and without a radius if nothing lies within it.
    #[inline]
    pub(crate) fn closest(
        &mut self,
        p: Vec3,
        enabled: bool,
        closest_within: impl Fn(Vec3, f32) -> Option<ClosestHit>,
    ) -> Option<ClosestHit> {
        if enabled && let Some(q) = self.previous {
            let radius = p.distance(q) * (1.0 + 1e-5);
            if radius.is_finite()
                && let Some(hit) = closest_within(p, radius)
            {
                self.previous = Some(hit.point);
                return Some(hit);
            }
        }
        let hit = closest_within(p, f32::INFINITY);
        if let Some(hit) = &hit {
            self.previous = Some(hit.point);
        }
        hit
    }

    /// [`closest`](Self::closest) for each of `points` in turn, into `out`,
    /// each seeded with the answer before it when `enabled`.
    #[inline]
    pub(crate) fn closest_each(
        points: &[Vec3],
        out: &mut [Option<ClosestHit>],
        enabled: bool,
        closest_within: impl Fn(Vec3, f32) -> Option<ClosestHit>,
    ) {
        let mut seed = Self::default();
        for (answer, &p) in out.iter_mut().zip(points) {
            *answer = seed.closest(p, enabled, &closest_within);
        }
    }
}

/// Queries per parallel task of [`closest_in_chunks`]: large enough that
/// radius seeding rarely restarts, small enough to share work between
/// threads.
pub(crate) const CHUNK: usize = 1024;

/// The closest-hit batch of both trees: the points, in Morton order within
/// `bounds` with `reorder`, are cut into chunks of [`CHUNK`] that the
/// threads of rayon's pool take in order from a shared counter, each handing
/// its chunk to `answer_chunk`, which fills the chunk's answers; the answers
/// come back in input order.
///
/// The threads so work on neighbouring chunks, whose queries walk
/// neighbouring parts of the tree, and the shared cache serves both; each
/// ends at most one chunk after the other (rayon's own split left one
/// thread busy longer than the other: docs/perf-log.md).
pub(crate) fn closest_in_chunks(
    points: &[Vec3],
    bounds: &Aabb,
    reorder: bool,
    answer_chunk: impl Fn(&[Vec3], &mut [Option<ClosestHit>]) + Sync + Send,
) -> Vec<Option<ClosestHit>> {
    in_chunks(points, bounds, reorder, None, answer_chunk)
}

/// [`closest_in_chunks`] for answers of any plain type, `empty` filling
/// the answers until `answer_chunk` writes them: batches that compute more
/// than the closest hit (a signed distance) while the chunk is in cache.
pub(crate) fn in_chunks<R: Copy + Send>(
    points: &[Vec3],
    bounds: &Aabb,
    reorder: bool,
    empty: R,
    answer_chunk: impl Fn(&[Vec3], &mut [R]) + Sync + Send,
) -> Vec<R> {
    let order = reorder.then(|| morton_order(points, bounds));
    in_chunks_ordered(points, order.as_deref(), empty, answer_chunk)
}

/// [`in_chunks`] for queries of any plain type (points, rays), taken in
/// `order` (all of `0..items.len()`, each once) or, without one, in input
/// order; the answers come back in input order. Two arrays the size of the
/// batch are allocated (the answers, and a copy of them in input order when
/// there is an order), so a batch of a million queries does not fault in
/// fresh pages for every intermediate list.
pub(crate) fn in_chunks_ordered<Q: Copy + Sync, R: Copy + Send>(
    items: &[Q],
    order: Option<&[u32]>,
    empty: R,
    answer_chunk: impl Fn(&[Q], &mut [R]) + Sync + Send,
) -> Vec<R> {
    let sorted: std::borrow::Cow<'_, [Q]> = match order {
        Some(order) => order.iter().map(|&i| items[i as usize]).collect(),
        None => std::borrow::Cow::Borrowed(items),
    };
    let mut answers = vec![empty; items.len()];
    // Each chunk is taken exactly once, so its lock is never waited on.
    let chunks: Vec<Mutex<(&mut [_], &[Q])>> = answers
        .chunks_mut(CHUNK)
        .zip(sorted.chunks(CHUNK))
        .map(Mutex::new)
        .collect();
    let next = AtomicUsize::new(0);
    let work = || {
        while let Some(chunk) = chunks.get(next.fetch_add(1, Ordering::Relaxed)) {
            let mut chunk = chunk.lock().unwrap_or_else(PoisonError::into_inner);
            let (out, items) = &mut *chunk;
            answer_chunk(items, out);
        }
    };
    // One task per thread, at most one per chunk; a task that finds the
    // chunks all taken ends at once, so no thread has to join in.
    rayon::scope(|scope| {
        for _ in 1..rayon::current_num_threads().min(chunks.len()) {
            scope.spawn(|_| work());
        }
        work();
    });
    drop(chunks);
    match order {
        Some(order) => unpermute_copied(order, &answers),
        None => answers,
    }
}

/// Whether the `n` sort points of a batch, `point(i)` in input order, are
/// already as coherent as Morton order would make them: the mean distance
/// between consecutive points (over at most 4,096 pairs spread across the
/// batch) is below the spacing that `n` points spread through `bounds`
/// would have (its diagonal over the cube root of `n`). Rays of a camera
/// image, row after row, pass; rays in random order do not. Sorting
/// coherent input costs more than it saves (docs/perf-log.md).
pub(crate) fn already_coherent(n: usize, bounds: &Aabb, point: impl Fn(usize) -> Vec3) -> bool {
    if n < 2 {
        return true;
    }
    let pairs = (n - 1).min(4096);
    let step = (n - 1) / pairs;
    // Pairs with a point that is not finite (a ray the batch refuses) are
    // left out, so that one bad ray does not change the order of the rest.
    let (total, counted) = (0..pairs)
        .map(|k| point(k * step).distance(point(k * step + 1)) as f64)
        .filter(|d| d.is_finite())
        .fold((0.0, 0usize), |(total, counted), d| (total + d, counted + 1));
    let spacing = bounds.size().length() as f64 / (n as f64).cbrt();
    counted > 0 && total / (counted as f64) < spacing
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

/// The order in which a batch is processed: Morton order of the points
/// within `bounds`, ties in input order. The codes are computed on rayon's
/// pool and sorted by [`sort_by_code`], a radix sort, which measured faster
/// than a comparison sort (docs/perf-log.md).
pub(crate) fn morton_order(points: &[Vec3], bounds: &Aabb) -> Vec<u32> {
    let coded: Vec<(u32, u32)> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (morton_code(p, bounds), i as u32))
        .collect();
    sort_by_code(coded, 30).into_iter().map(|(_, i)| i).collect()
}

/// Sorts `(code, index)` pairs by their code, whose bits from `code_bits`
/// up are all zero, keeping ties in their order: a least-significant-digit
/// radix sort, one pass per 10 bits of code.
pub(crate) fn sort_by_code(items: Vec<(u32, u32)>, code_bits: u32) -> Vec<(u32, u32)> {
    const BITS: u32 = 10;
    const BUCKETS: usize = 1 << BITS;
    let mut from = items;
    let mut to = vec![(0, 0); from.len()];
    for shift in (0..code_bits).step_by(BITS as usize) {
        let bucket = |code: u32| (code >> shift) as usize % BUCKETS;
        let mut next = [0usize; BUCKETS];
        for &(code, _) in &from {
            next[bucket(code)] += 1;
        }
        let mut start = 0;
        for slot in &mut next {
            (*slot, start) = (start, start + *slot);
        }
        for &item in &from {
            let b = bucket(item.0);
            to[next[b]] = item;
            next[b] += 1;
        }
        std::mem::swap(&mut from, &mut to);
    }
    from
}

/// `answers[k]` is the answer for point `order[k]`: the answers in input order.
pub(crate) fn unpermute<R>(order: &[u32], answers: Vec<R>) -> Vec<R> {
    let mut slots: Vec<Option<R>> = std::iter::repeat_with(|| None).take(order.len()).collect();
    for (&i, answer) in order.iter().zip(answers) {
        slots[i as usize] = Some(answer);
    }
    // `order` is a permutation, so every slot is filled.
    slots.into_iter().flatten().collect()
}

/// [`unpermute`] for plain values: one scatter into a copy, with no
/// temporary slots (faster than following the permutation's cycles).
fn unpermute_copied<R: Copy>(order: &[u32], answers: &[R]) -> Vec<R> {
    let mut out = answers.to_vec();
    for (&i, &answer) in order.iter().zip(answers) {
        out[i as usize] = answer;
    }
    out
}

/// Answers `query` for every point on rayon's pool and returns the answers
/// in input order. With `reorder`, the points are processed in Morton order
/// within `bounds`, so consecutive queries walk mostly the same nodes while
/// they are in cache. `init` makes one scratch value per worker, so queries do
/// not allocate. Shared by the trees' k-nearest batches.
pub(crate) fn answer_batch<S, R: Send>(
    points: &[Vec3],
    bounds: &Aabb,
    reorder: bool,
    init: impl Fn() -> S + Sync + Send,
    query: impl Fn(&mut S, Vec3) -> R + Sync + Send,
) -> Vec<R> {
    answer_batch_indexed(points, bounds, reorder, init, |scratch, i| query(scratch, points[i]))
}

/// [`answer_batch`] with the point's index in place of the point, for
/// queries that also read other arrays of the batch.
pub(crate) fn answer_batch_indexed<S, R: Send>(
    points: &[Vec3],
    bounds: &Aabb,
    reorder: bool,
    init: impl Fn() -> S + Sync + Send,
    query: impl Fn(&mut S, usize) -> R + Sync + Send,
) -> Vec<R> {
    if !reorder {
        return (0..points.len())
            .into_par_iter()
            .map_init(&init, |scratch, i| query(scratch, i))
            .collect();
    }
    let order = morton_order(points, bounds);
    let answers: Vec<R> = order
        .par_iter()
        .map_init(&init, |scratch, &i| query(scratch, i as usize))
        .collect();
    unpermute(&order, answers)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AabbTree;
    use crate::query::NearestQuery;
    use crate::sample::Rng;

    /// A camera's rays, row by row, are coherent as they come; the same
    /// rays shuffled are not; a few bad rays do not change the verdict.
    #[test]
    fn camera_rows_are_already_coherent() {
        let bounds = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let mut rows: Vec<Vec3> = (0..256 * 256)
            .map(|k| Vec3::new((k % 256) as f32 / 128.0 - 1.0, (k / 256) as f32 / 128.0 - 1.0, 0.3))
            .collect();
        assert!(already_coherent(rows.len(), &bounds, |i| rows[i]));
        let mut rng = Rng::new(3);
        let mut shuffled = rows.clone();
        for i in (1..shuffled.len()).rev() {
            shuffled.swap(i, rng.below(i + 1));
        }
        assert!(!already_coherent(shuffled.len(), &bounds, |i| shuffled[i]));
        rows[1] = Vec3::NAN;
        rows[5000] = Vec3::INFINITY;
        assert!(already_coherent(rows.len(), &bounds, |i| rows[i]));
        assert!(already_coherent(1, &bounds, |i| rows[i]));
    }

    /// The radix sort gives the order of a stable comparison sort, on codes
    /// with many ties and on codes spread over all 30 or 32 bits, with as
    /// many bits sorted as the codes have (a number of bits that is not a
    /// multiple of the pass's 10 included).
    #[test]
    fn sorting_by_code_is_a_stable_sort() {
        let mut rng = Rng::new(7);
        let cases = [
            (0u32, 1u64, 1),
            (1, 1, 1),
            (5000, 7, 3),
            (5000, 1 << 12, 12),
            (20_000, 1 << 30, 30),
        ];
        for (n, range, bits) in cases.into_iter().chain([(20_000, 1 << 32, 32), (3000, 1 << 21, 21)]) {
            let items: Vec<(u32, u32)> = (0..n).map(|i| ((rng.next_u64() % range) as u32, i)).collect();
            let mut expected = items.clone();
            expected.sort_by_key(|&(code, _)| code);
            assert_eq!(sort_by_code(items, bits), expected, "{n} codes below {range}");
        }
    }

    /// A seed whose radius holds nothing (the previous answer's point is the
    /// query point itself, off the surface) is searched again without a
    /// radius, and the answer is still the unbounded search's.
    #[test]
    fn a_seed_that_bounds_nothing_falls_back_to_an_unbounded_search() {
        let tree = AabbTree::build(crate::sample::small_triangles(500, 3), &Default::default()).unwrap();
        let mut rng = Rng::new(9);
        let mut redone = 0;
        for _ in 0..300 {
            let p = Vec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
            let mut seed = Seed { previous: Some(p) };
            let searches = std::cell::RefCell::new(Vec::new());
            let hit = seed.closest(p, true, |p, r| {
                searches.borrow_mut().push(r);
                tree.closest_within(p, r)
            });
            assert_eq!(hit, tree.closest(p));
            assert_eq!(seed.previous, hit.map(|h| h.point));
            redone += usize::from(*searches.borrow() == [0.0, f32::INFINITY]);
        }
        assert!(redone > 250, "{redone} of 300 searches redone");
    }

    /// Every chunk is answered exactly once, whatever the number of threads
    /// (more or fewer than the chunks, several chunks each), with or without
    /// reordering: each tree's batch is brute force's answers, in input order.
    #[test]
    fn chunks_shared_by_threads_answer_every_point_once() {
        let triangles = crate::sample::small_triangles(400, 21);
        let linear = crate::LinearSearch::new(crate::PrimitiveSet::from_primitives(triangles.clone()));
        let tree = AabbTree::build(triangles, &Default::default()).unwrap();
        let wide = crate::WideTree::from_tree(tree.clone());
        let mut rng = Rng::new(22);
        // Four full chunks and a partial one.
        let points: Vec<Vec3> = (0..4 * CHUNK + 37)
            .map(|_| Vec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)))
            .collect();
        let expected: Vec<_> = points.iter().map(|&p| linear.closest(p)).collect();
        for threads in [1, 2, 3, 8] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            for reorder in [true, false] {
                let options = BatchOptions {
                    reorder,
                    ..Default::default()
                };
                let (binary, wide) = pool.install(|| {
                    (
                        tree.closest_batch_with(&points, options),
                        wide.closest_batch_with(&points, options),
                    )
                });
                assert!(binary == expected, "binary tree, {threads} threads, {options:?}");
                assert!(wide == expected, "wide tree, {threads} threads, {options:?}");
            }
        }
    }

    /// Every code has its three 10-bit digits in place: the order of points
    /// follows `morton_code`, ties by input index.
    #[test]
    fn morton_order_sorts_by_code() {
        let mut rng = Rng::new(8);
        let bounds = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let points: Vec<Vec3> = (0..3000)
            .map(|_| Vec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(-1.5, 1.5)))
            .collect();
        let order = morton_order(&points, &bounds);
        let mut expected: Vec<u32> = (0..points.len() as u32).collect();
        expected.sort_by_key(|&i| (morton_code(points[i as usize], &bounds), i));
        assert_eq!(order, expected);
    }
}
