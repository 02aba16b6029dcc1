//! Closest-primitive queries.

use super::traverse::{Counter, DistanceVisitor, QueryStats};
use super::{AabbTree, ClosestHit, PRUNE_SLACK};
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Keeps the best candidate; ties in distance go to the lower input index, so
/// the answer is the same as a linear scan's, primitive for primitive.
/// Shared with the wide tree, whose answers must be the same.
pub(crate) struct Best<'a> {
    indices: &'a [u32],
    pub(crate) slot: usize,
    /// The input index of `slot`, or [`UNKNOWN`] until a tie needs it.
    index: u32,
    pub(crate) point: Vec3A,
    pub(crate) distance_squared: f32,
    bound: f32,
    pub(crate) found: bool,
}

impl<'a> Best<'a> {
    pub(crate) fn new(indices: &'a [u32], max_distance_squared: f32) -> Self {
        Self {
            indices,
            slot: 0,
            index: UNKNOWN,
            point: Vec3A::ZERO,
            distance_squared: max_distance_squared,
            bound: max_distance_squared * PRUNE_SLACK,
            found: false,
        }
    }

    /// The input index of the best so far (read from the index array only
    /// when a tie first needs it).
    #[inline(always)]
    pub(crate) fn index(&self) -> u32 {
        if self.index == UNKNOWN {
            self.indices[self.slot]
        } else {
            self.index
        }
    }

    /// Considers the point `q` at squared distance `d2` of the primitive at
    /// `slot`; its input index is read only if it ties with the best.
    #[inline(always)]
    pub(crate) fn offer(&mut self, slot: usize, q: Vec3A, d2: f32) {
        if d2 < self.distance_squared
            || (d2 == self.distance_squared && (!self.found || self.indices[slot] < self.index()))
        {
            self.take(slot, UNKNOWN, q, d2);
        }
    }

    /// [`offer`](Self::offer) for a primitive whose input index is known.
    #[inline(always)]
    pub(crate) fn offer_indexed(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        if d2 < self.distance_squared || (d2 == self.distance_squared && (!self.found || index < self.index())) {
            self.take(slot, index, q, d2);
        }
    }

    #[inline(always)]
    fn take(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        self.index = index;
        self.slot = slot;
        self.point = q;
        self.distance_squared = d2;
        self.bound = d2 * PRUNE_SLACK;
        self.found = true;
    }
}

/// No input index is this large: there are fewer than 2^32 primitives.
const UNKNOWN: u32 = u32::MAX;

impl<T: ClosestPoint> DistanceVisitor<T> for Best<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }
    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A) {
        let q = primitive.closest_point(p);
        self.offer(slot, q, (q - p).length_squared());
    }
}

impl<T: ClosestPoint> AabbTree<T> {
    /// The primitive closest to `p`, or `None` for an empty tree, a
    /// non-finite `p`, or distances beyond `f32` range. Ties go to the lowest input index.
    ///
    /// ```
    /// use proxima::{AabbTree, Point, Vec3};
    /// let points = vec![Point(Vec3::ZERO), Point(Vec3::X), Point(Vec3::Y)];
    /// let tree = AabbTree::build(points, &Default::default()).unwrap();
    /// let hit = tree.closest(Vec3::new(0.9, 0.2, 0.0)).unwrap();
    /// assert_eq!(hit.primitive, 1);
    /// ```
    #[inline]
    pub fn closest(&self, p: Vec3) -> Option<ClosestHit> {
        self.closest_within(p, f32::INFINITY)
    }

    /// The closest primitive at distance at most `max_distance` from `p`, or
    /// `None` if there is none. A good upper bound (for instance a neighbouring
    /// query's answer plus the distance between the queries) speeds the search
    /// up without changing its answer.
    #[inline]
    pub fn closest_within(&self, p: Vec3, max_distance: f32) -> Option<ClosestHit> {
        self.closest_counted(p, max_distance, &mut ())
    }

    /// [`closest`](Self::closest), also counting the nodes and primitives visited.
    pub fn closest_with_stats(&self, p: Vec3) -> (Option<ClosestHit>, QueryStats) {
        let mut stats = QueryStats::default();
        let hit = self.closest_counted(p, f32::INFINITY, &mut stats);
        (hit, stats)
    }

    #[inline]
    fn closest_counted<C: Counter>(&self, p: Vec3, max_distance: f32, counter: &mut C) -> Option<ClosestHit> {
        if !crate::bvh::answerable(p) {
            return None;
        }
        let p = Vec3A::from(p);
        let mut best = Best::new(&self.indices, max_distance * max_distance);
        self.nearest_first(p, &mut best, counter);
        best.found
            .then(|| self.hit(best.slot, best.point, best.distance_squared))
    }

    /// The same answer as [`closest`](Self::closest), found best-first: nodes
    /// are expanded in increasing box distance from a priority queue. Kept as
    /// a tested alternative; the depth-first [`closest`](Self::closest) was
    /// measured faster (see ARCHITECTURE.md). Allocates its queue.
    pub fn closest_best_first(&self, p: Vec3) -> Option<ClosestHit> {
        if !crate::bvh::answerable(p) {
            return None;
        }
        let p = Vec3A::from(p);
        let mut best = Best::new(&self.indices, f32::INFINITY);
        let mut queue = BinaryHeap::with_capacity(64);
        if let Some(root) = self.root() {
            queue.push(Pending {
                distance_squared: root.distance_squared(p),
                node: 0,
            });
        }
        while let Some(Pending { distance_squared, node }) = queue.pop() {
            if distance_squared > best.bound {
                break;
            }
            let n = self.node(node as usize);
            if n.is_leaf() {
                for slot in n.primitive_range() {
                    DistanceVisitor::<T>::visit(&mut best, slot, &self.primitives[slot], p);
                }
            } else {
                for child in n.children() {
                    let d = self.node(child as usize).distance_squared(p);
                    if d <= best.bound {
                        queue.push(Pending {
                            distance_squared: d,
                            node: child,
                        });
                    }
                }
            }
        }
        best.found
            .then(|| self.hit(best.slot, best.point, best.distance_squared))
    }
}

/// A node waiting in the best-first queue; the heap pops the smallest distance.
#[derive(Clone, Copy, PartialEq)]
struct Pending {
    distance_squared: f32,
    node: u32,
}

impl Eq for Pending {}

impl Ord for Pending {
    fn cmp(&self, other: &Self) -> Ordering {
        other.distance_squared.total_cmp(&self.distance_squared)
    }
}

impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
