//! k-nearest primitive queries.

use super::traverse::DistanceVisitor;
use super::{AabbTree, ClosestHit, PRUNE_SLACK};
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
    heap: BinaryHeap<Candidate>,
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

impl KBest<'_> {
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

impl<T: ClosestPoint> DistanceVisitor<T> for KBest<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }
    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A) {
        let q = primitive.closest_point(p);
        let d2 = (q - p).length_squared();
        if d2 <= self.bound {
            self.offer(Candidate {
                distance_squared: d2,
                index: self.indices[slot],
                slot: slot as u32,
                point: q,
            });
        }
    }
}

/// Drains the heap into `out`, nearest first.
pub(crate) fn drain_sorted(heap: &mut BinaryHeap<Candidate>, out: &mut Vec<ClosestHit>, source: impl Fn(usize) -> u32) {
    out.clear();
    out.extend(heap.drain().map(|c| ClosestHit {
        primitive: c.index,
        source: source(c.slot as usize),
        point: c.point.into(),
        distance: c.distance_squared,
    }));
    out.sort_unstable_by(|a, b| a.distance.total_cmp(&b.distance).then(a.primitive.cmp(&b.primitive)));
    for hit in out.iter_mut() {
        hit.distance = hit.distance.sqrt();
    }
}

impl<T: ClosestPoint> AabbTree<T> {
    /// The `k` primitives closest to `p`, nearest first (ties by input index).
    /// Gives all primitives when `k` exceeds their number, none when `k == 0`
    /// or `p` is not finite or beyond [`MAX_QUERY_COORDINATE`](crate::bvh::MAX_QUERY_COORDINATE).
    ///
    /// ```
    /// use proxima::{AabbTree, Point, Vec3};
    /// let points = (0..10).map(|i| Point(Vec3::new(i as f32, 0.0, 0.0))).collect();
    /// let tree = AabbTree::build(points, &Default::default()).unwrap();
    /// let hits = tree.k_nearest(Vec3::new(3.2, 1.0, 0.0), 3);
    /// let order: Vec<u32> = hits.iter().map(|h| h.primitive).collect();
    /// assert_eq!(order, [3, 4, 2]);
    /// ```
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<ClosestHit> {
        let mut out = Vec::new();
        self.k_nearest_into(p, k, &mut KnnScratch::new(), &mut out);
        out
    }

    /// [`k_nearest`](Self::k_nearest) writing into `out` (cleared first) and
    /// reusing `scratch`, so repeated queries do not allocate.
    pub fn k_nearest_into(&self, p: Vec3, k: usize, scratch: &mut KnnScratch, out: &mut Vec<ClosestHit>) {
        k_nearest_with(p, k, &self.indices, &self.sources, scratch, out, |p, best| {
            self.nearest_first(p, best, &mut ())
        });
    }
}

/// A k-nearest query over a tree whose leaf-order slots map to `indices` and
/// `sources`: `walk` runs the traversal with the visitor. Shared by the trees
/// whose answers must be the same.
pub(crate) fn k_nearest_with(
    p: Vec3,
    k: usize,
    indices: &[u32],
    sources: &[u32],
    scratch: &mut KnnScratch,
    out: &mut Vec<ClosestHit>,
    walk: impl FnOnce(Vec3A, &mut KBest<'_>),
) {
    let k = k.min(indices.len());
    scratch.heap.clear();
    if k > 0 && crate::bvh::answerable(p) {
        let mut best = KBest {
            heap: &mut scratch.heap,
            k,
            indices,
            bound: f32::INFINITY,
        };
        walk(Vec3A::from(p), &mut best);
    }
    drain_sorted(&mut scratch.heap, out, |slot| sources[slot]);
}
