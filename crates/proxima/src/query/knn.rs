//! The visitor behind k-nearest queries, and its reusable memory.

use super::{ClosestHit, NearestVisitor, PRUNE_SLACK};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A candidate ordered by (squared distance, input index): the heap's top is
/// the current k-th best, whose distance is the pruning radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Candidate {
    pub(crate) distance_squared: f32,
    pub(crate) index: u32,
    pub(crate) slot: u32,
    pub(crate) point: Vec3A,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        self.distance_squared
            .total_cmp(&other.distance_squared)
            .then(self.index.cmp(&other.index))
    }
}

/// Reusable memory for k-nearest queries, so a loop of queries allocates once.
#[derive(Clone, Debug, Default)]
pub struct KnnScratch {
    pub(crate) heap: BinaryHeap<Candidate>,
}

impl KnnScratch {
    /// Empty scratch space.
    pub fn new() -> Self {
        Self::default()
    }
}

/// Bounded max-heap of the k best candidates so far.
pub(crate) struct KBest<'a> {
    pub(crate) heap: &'a mut BinaryHeap<Candidate>,
    pub(crate) k: usize,
    pub(crate) indices: &'a [u32],
    pub(crate) bound: f32,
}

impl<'a> KBest<'a> {
    pub(crate) fn new(heap: &'a mut BinaryHeap<Candidate>, k: usize, indices: &'a [u32]) -> Self {
        Self {
            heap,
            k,
            indices,
            bound: f32::INFINITY,
        }
    }

    #[inline]
    pub(crate) fn offer(&mut self, candidate: Candidate) {
        if self.heap.len() < self.k {
            self.heap.push(candidate);
        } else if let Some(mut worst) = self.heap.peek_mut() {
            if candidate < *worst {
                *worst = candidate;
            } else {
                return;
            }
        }
        if self.heap.len() == self.k {
            self.bound = self
                .heap
                .peek()
                .map_or(f32::INFINITY, |w| w.distance_squared * PRUNE_SLACK);
        }
    }
}

impl<T: ClosestPoint> NearestVisitor<T> for KBest<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }
    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A) {
        let q = primitive.closest_point(p);
        let d2 = (q - p).length_squared();
        // The input index is read only for candidates within reach.
        if d2 <= self.bound {
            NearestVisitor::<T>::offer(self, slot, self.indices[slot], q, d2);
        }
    }
    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        if d2 <= self.bound {
            KBest::offer(
                self,
                Candidate {
                    distance_squared: d2,
                    index,
                    slot: slot as u32,
                    point: q,
                },
            );
        }
    }
}

/// Drains the heap into `out`, nearest first.
pub(crate) fn drain_sorted(heap: &mut BinaryHeap<Candidate>, out: &mut Vec<ClosestHit>, sources: &[u32]) {
    out.clear();
    out.extend(heap.drain().map(|c| ClosestHit {
        primitive: c.index,
        source: sources[c.slot as usize],
        point: c.point.into(),
        distance: c.distance_squared,
    }));
    out.sort_unstable_by(|a, b| a.distance.total_cmp(&b.distance).then(a.primitive.cmp(&b.primitive)));
    for hit in out.iter_mut() {
        hit.distance = hit.distance.sqrt();
    }
}

/// The `k` nearest primitives as the user counts them: a face split into
/// several triangles (a fan) or polygons is one face, listed once, at its
/// nearest part's distance.
///
/// `answers` holds the `k` nearest parts per query, nearest first (ties by
/// part index, and the parts of a face are consecutive, so ties go to the
/// lower face). The first occurrence of each source in that order is the
/// source at its own distance, so keeping first occurrences gives the nearest
/// sources in order; when that leaves fewer than `k`, the query is asked
/// again for twice as many parts, until `k` sources are found or every part
/// has been seen. The queries are treated in parallel.
///
/// `answers[i]` are the `k` nearest parts of `points[i]` by `k_nearest`
/// (the structure's [`NearestQuery::k_nearest`](super::NearestQuery::k_nearest)),
/// `parts` the number of parts.
pub fn distinct_sources(
    mut answers: Vec<Vec<ClosestHit>>,
    points: &[Vec3],
    k: usize,
    parts: usize,
    k_nearest: &(dyn Fn(Vec3, usize) -> Vec<ClosestHit> + Sync),
) -> Vec<Vec<ClosestHit>> {
    let first_occurrences = |hits: &mut Vec<ClosestHit>| {
        let mut seen = std::collections::HashSet::with_capacity(hits.len());
        hits.retain(|h| seen.insert(h.source));
    };
    use rayon::prelude::*;
    answers.par_iter_mut().zip(points).for_each(|(hits, &p)| {
        let mut asked = k;
        first_occurrences(hits);
        while hits.len() < k && asked < parts {
            asked = asked.saturating_mul(2).min(parts);
            *hits = k_nearest(p, asked);
            first_occurrences(hits);
        }
        hits.truncate(k);
    });
    answers
}

/// The answers of a chunk of queries of
/// [`NearestQuery::k_nearest_sources_chunks`](super::NearestQuery::k_nearest_sources_chunks),
/// in input order: one closest hit each (`k = 1`) or up to `k` hits each,
/// nearest first.
#[derive(Clone, Debug, PartialEq)]
pub enum NearestAnswers {
    /// The closest hit of each query (`None` only for an empty structure).
    Closest(Vec<Option<ClosestHit>>),
    /// The nearest hits of each query, nearest first.
    KNearest(Vec<Vec<ClosestHit>>),
}

impl NearestAnswers {
    /// The number of queries answered.
    pub fn len(&self) -> usize {
        match self {
            Self::Closest(hits) => hits.len(),
            Self::KNearest(hits) => hits.len(),
        }
    }

    /// `true` when no query was answered.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The hits of query `i` of the chunk, nearest first.
    pub fn hits(&self, i: usize) -> &[ClosestHit] {
        match self {
            Self::Closest(hits) => hits[i].as_slice(),
            Self::KNearest(hits) => &hits[i],
        }
    }
}
