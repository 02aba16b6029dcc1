//! Queries over many points at once on the wide tree, on all cores.

#[cfg(target_arch = "x86_64")]
use super::avx2::Avx2Task;
use super::traverse::{Avx2, Walk};
use super::{WideKnnScratch, WideTree};
use crate::aabb::Aabb;
use crate::bvh::batch::{Seed, answer_batch, closest_in_chunks};
use crate::bvh::closest::Best;
use crate::bvh::{BatchOptions, ClosestHit};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;

impl<T: ClosestPoint + Sync> WideTree<T> {
    fn root_bounds(&self) -> Aabb {
        self.tree.root().map_or(Aabb::EMPTY, |n| n.bounds())
    }

    /// [`closest`](Self::closest) for every point, in parallel on rayon's
    /// pool, in Morton order; results in input order. No allocation per query.
    pub fn closest_batch(&self, points: &[Vec3]) -> Vec<Option<ClosestHit>> {
        self.closest_batch_with(points, BatchOptions::default())
    }

    /// [`closest_batch`](Self::closest_batch) with explicit options.
    ///
    /// Each thread takes chunks of the (sorted) queries. Within a chunk it
    /// answers one query after the other, each seeded with the previous
    /// answer ([`seed_radius`](BatchOptions::seed_radius)), or with
    /// [`interleave`](BatchOptions::interleave) above 1 it interleaves that
    /// many walks: it advances each by one node or leaf in turn, so that the
    /// cache misses of one overlap the work of the others. Either way the
    /// answers are those of [`closest`](Self::closest), query by query.
    pub fn closest_batch_with(&self, points: &[Vec3], options: BatchOptions) -> Vec<Option<ClosestHit>> {
        closest_in_chunks(
            points,
            &self.root_bounds(),
            options.reorder,
            |points, out| match options.interleave {
                // The sources are looked up once the chunk is answered, all
                // together: against looking each up as its query ends,
                // 1.04–1.06x on near-surface batches and 1.01–1.02x on
                // uniform ones (dragon and ico1m, one thread, median of 21
                // alternating rounds, two runs).
                0 | 1 => {
                    Seed::closest_each(points, out, options.seed_radius, |p, r| {
                        self.closest_within_deferred(p, r)
                    });
                    self.tree.resolve_sources(out);
                }
                2..4 => self.closest_interleaved::<2>(points, out),
                4..8 => self.closest_interleaved::<4>(points, out),
                8..16 => self.closest_interleaved::<8>(points, out),
                _ => self.closest_interleaved::<16>(points, out),
            },
        )
    }

    /// The closest primitive to each of `points`, into `out`, with `K` walks
    /// advanced in turn.
    fn closest_interleaved<const K: usize>(&self, points: &[Vec3], out: &mut [Option<ClosestHit>]) {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(Interleaved::<T, K> {
                tree: self,
                points,
                out,
            });
        }
        self.closest_interleaved_with::<K>(points, out, None);
    }

    /// [`closest_interleaved`](Self::closest_interleaved), with leaves tested
    /// on eight lanes when `avx2` is given.
    #[inline(always)]
    fn closest_interleaved_with<const K: usize>(
        &self,
        points: &[Vec3],
        out: &mut [Option<ClosestHit>],
        avx2: Option<Avx2>,
    ) {
        let fresh = || Best::new(&self.tree.indices, f32::INFINITY);
        let slices = self.slices();
        let mut walks: [Walk<Best<'_>>; K] = std::array::from_fn(|_| Walk::new(&slices, Vec3A::ZERO, avx2, fresh()));
        // The query each walk answers, if any.
        let mut serving = [usize::MAX; K];
        let mut next = 0;
        let mut busy = 0;
        loop {
            for (walk, query) in walks.iter_mut().zip(&mut serving) {
                if *query == usize::MAX {
                    // Points out of range have no answer, as in `closest`.
                    while next < points.len() && !crate::bvh::answerable(points[next]) {
                        out[next] = None;
                        next += 1;
                    }
                    if next == points.len() {
                        continue;
                    }
                    walk.restart(&slices, Vec3A::from(points[next]), avx2, fresh());
                    (*query, next, busy) = (next, next + 1, busy + 1);
                }
                if !slices.step(walk) {
                    let best = &walk.visitor;
                    out[*query] = best
                        .found
                        .then(|| self.tree.hit(best.slot, best.point, best.distance_squared));
                    (*query, busy) = (usize::MAX, busy - 1);
                }
            }
            if busy == 0 && next == points.len() {
                return;
            }
        }
    }

    /// [`k_nearest`](Self::k_nearest) for every point, in parallel, in Morton
    /// order; results in input order. Scratch memory is allocated once per
    /// worker, not per query.
    pub fn k_nearest_batch(&self, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>> {
        answer_batch(points, &self.root_bounds(), true, WideKnnScratch::new, |scratch, p| {
            let mut out = Vec::with_capacity(k.min(self.len()));
            self.k_nearest_into(p, k, scratch, &mut out);
            out
        })
    }
}

/// [`WideTree::closest_interleaved_with`] as a task compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct Interleaved<'a, T, const K: usize> {
    tree: &'a WideTree<T>,
    points: &'a [Vec3],
    out: &'a mut [Option<ClosestHit>],
}

#[cfg(target_arch = "x86_64")]
impl<T: ClosestPoint + Sync, const K: usize> Avx2Task for Interleaved<'_, T, K> {
    type Output = ();
    #[inline(always)]
    fn call(self, avx2: Avx2) {
        self.tree
            .closest_interleaved_with::<K>(self.points, self.out, Some(avx2));
    }
}
