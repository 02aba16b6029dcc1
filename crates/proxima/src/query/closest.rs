//! The visitor behind closest-primitive queries.

use super::{ClosestHit, Leaves, NearestVisitor, PRUNE_SLACK};
use crate::math::Vec3A;
use crate::primitive::ClosestPoint;

/// Keeps the best candidate; ties in distance go to the lower input index, so
/// the answer is the same as a linear scan's, primitive for primitive.
/// Shared by every structure, whose answers must be the same.
pub(crate) struct Best<'a> {
    indices: &'a [u32],
    pub(crate) slot: usize,
    /// The input index of `slot`, or [`UNKNOWN`] until a tie needs it.
    index: u32,
    pub(crate) point: Vec3A,
    pub(crate) distance_squared: f32,
    pub(crate) bound: f32,
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

    /// The answer of the best found, its primitive in `leaves` (the walked
    /// structure's).
    #[inline]
    pub(crate) fn hit<T>(&self, leaves: &Leaves<T>) -> ClosestHit {
        leaves.hit(self.slot, self.index(), self.point, self.distance_squared)
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

impl<T: ClosestPoint> NearestVisitor<T> for Best<'_> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.bound
    }
    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A) {
        let q = primitive.closest_point(p);
        Best::offer(self, slot, q, (q - p).length_squared());
    }
    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        Best::offer_indexed(self, slot, index, q, d2);
    }
}

/// [`Best`], handing the input index of each new best to `on_better` as the
/// walk finds it: a caller that reads something of the answer's primitive
/// afterwards (a signed distance, its pseudonormal record) can ask the cache
/// for it while the rest of the walk runs, instead of waiting on it after.
pub(crate) struct Announcing<'a, F> {
    pub(crate) best: Best<'a>,
    pub(crate) on_better: F,
}

impl<F: FnMut(u32)> Announcing<'_, F> {
    #[inline(always)]
    fn announce_if_taken(&mut self, before: (bool, usize)) {
        if (self.best.found, self.best.slot) != before {
            (self.on_better)(self.best.index());
        }
    }
}

impl<T: ClosestPoint, F: FnMut(u32)> NearestVisitor<T> for Announcing<'_, F> {
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.best.bound
    }
    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A) {
        let before = (self.best.found, self.best.slot);
        NearestVisitor::<T>::visit(&mut self.best, slot, primitive, p);
        self.announce_if_taken(before);
    }
    #[inline(always)]
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32) {
        let before = (self.best.found, self.best.slot);
        self.best.offer_indexed(slot, index, q, d2);
        self.announce_if_taken(before);
    }
}
