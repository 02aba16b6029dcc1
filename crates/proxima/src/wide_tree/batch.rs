//! An experiment kept for comparison (`experimental` feature): closest-point
//! batches whose thread advances several walks in turn, so that while one
//! waits for the memory it asked for, the others compute. In Morton order,
//! where consecutive queries find their nodes in cache anyway, it was
//! measured slower than one walk after the other (docs/perf-log.md).

#[cfg(target_arch = "x86_64")]
use super::avx2::Avx2Task;
use super::nearest::Nearest;
use super::walk::{Avx2, Walk};
use super::{WidePrimitive, WideTree};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;
use crate::query::{Best, ClosestHit, SpatialIndex, closest_in_chunks};

impl<T: ClosestPoint + WidePrimitive + Sync> WideTree<T> {
    /// The closest primitive to every point, as
    /// [`closest_batch`](crate::query::NearestQuery::closest_batch) with
    /// `reorder` chosen, each thread interleaving `walks` walks (rounded
    /// down to 1, 2, 4, 8 or 16). The answers are `closest`'s, query by query.
    pub fn closest_batch_interleaved(&self, points: &[Vec3], reorder: bool, walks: usize) -> Vec<Option<ClosestHit>> {
        closest_in_chunks(points, &self.bounds(), reorder, |points, out| match walks {
            0 | 1 => self.closest_interleaved::<1>(points, out),
            2..4 => self.closest_interleaved::<2>(points, out),
            4..8 => self.closest_interleaved::<4>(points, out),
            8..16 => self.closest_interleaved::<8>(points, out),
            _ => self.closest_interleaved::<16>(points, out),
        })
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
        let leaves = self.leaves();
        let slices = self.slices();
        // Each walk owns its visitor; the query borrows it for each step.
        let mut bests: [Best<'_>; K] = std::array::from_fn(|_| Best::new(leaves.indices(), f32::INFINITY));
        let mut walks: [Walk<(Vec3A, Option<Avx2>)>; K] =
            std::array::from_fn(|_| Walk::new(&slices, (Vec3A::ZERO, avx2)));
        // The query each walk answers, if any.
        let mut serving = [usize::MAX; K];
        let mut next = 0;
        let mut busy = 0;
        loop {
            for ((walk, best), query) in walks.iter_mut().zip(&mut bests).zip(&mut serving) {
                if *query == usize::MAX {
                    // Points out of range have no answer, as in `closest`.
                    while next < points.len() && !crate::bvh::answerable(points[next]) {
                        out[next] = None;
                        next += 1;
                    }
                    if next == points.len() {
                        continue;
                    }
                    *best = Best::new(leaves.indices(), f32::INFINITY);
                    walk.restart(&slices, (Vec3A::from(points[next]), avx2));
                    (*query, next, busy) = (next, next + 1, busy + 1);
                }
                let (p, token) = walk.query;
                if !slices.step_with(walk, &mut Nearest::new(p, token, best)) {
                    out[*query] = best
                        .found
                        .then(|| leaves.hit(best.slot, best.point, best.distance_squared));
                    (*query, busy) = (usize::MAX, busy - 1);
                }
            }
            if busy == 0 && next == points.len() {
                return;
            }
        }
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
impl<T: ClosestPoint + WidePrimitive + Sync, const K: usize> Avx2Task for Interleaved<'_, T, K> {
    type Output = ();
    #[inline(always)]
    fn call(self, avx2: Avx2) {
        self.tree
            .closest_interleaved_with::<K>(self.points, self.out, Some(avx2));
    }
}
