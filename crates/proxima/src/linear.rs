//! Brute force: every query tests every primitive. The reference answer for
//! the trees, and the baseline they are measured against.

use crate::bvh::ClosestHit;
use crate::frustum::{Frustum, FrustumOverlap};
use crate::math::{Vec3, Vec3A};
use crate::primitive::{ClosestPoint, PrimitiveSet};

/// A linear scan over primitives, answering the same queries as the trees.
#[derive(Clone, Debug)]
pub struct LinearSearch<T> {
    set: PrimitiveSet<T>,
}

impl<T: ClosestPoint> LinearSearch<T> {
    /// A scan over `set`.
    pub fn new(set: PrimitiveSet<T>) -> Self {
        Self { set }
    }

    /// The scanned primitives.
    pub fn primitives(&self) -> &[T] {
        &self.set.primitives
    }

    /// The closest primitive, ties to the lowest index; `None` when empty or
    /// when `p` is not finite or beyond
    /// [`MAX_QUERY_COORDINATE`](crate::bvh::MAX_QUERY_COORDINATE).
    pub fn closest(&self, p: Vec3) -> Option<ClosestHit> {
        if !crate::bvh::answerable(p) {
            return None;
        }
        let pa = Vec3A::from(p);
        let mut best: Option<(usize, Vec3A, f32)> = None;
        for (i, prim) in self.set.primitives.iter().enumerate() {
            let q = prim.closest_point(pa);
            let d2 = (q - pa).length_squared();
            if best.is_none_or(|(_, _, bd)| d2 < bd) {
                best = Some((i, q, d2));
            }
        }
        best.filter(|b| b.2.is_finite()).map(|(i, q, d2)| ClosestHit {
            primitive: i as u32,
            source: self.set.sources[i],
            point: q.into(),
            distance: d2.sqrt(),
        })
    }

    /// The `k` closest primitives, nearest first, ties by index.
    pub fn k_nearest(&self, p: Vec3, k: usize) -> Vec<ClosestHit> {
        if !crate::bvh::answerable(p) {
            return Vec::new();
        }
        let pa = Vec3A::from(p);
        let mut all: Vec<(f32, usize, Vec3A)> = self
            .set
            .primitives
            .iter()
            .enumerate()
            .map(|(i, prim)| {
                let q = prim.closest_point(pa);
                ((q - pa).length_squared(), i, q)
            })
            .collect();
        let order = |a: &(f32, usize, Vec3A), b: &(f32, usize, Vec3A)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        if k < all.len() {
            // Selection first: only the k kept need sorting.
            all.select_nth_unstable_by(k, order);
            all.truncate(k);
        }
        all.sort_unstable_by(order);
        all.into_iter()
            .map(|(d2, i, q)| ClosestHit {
                primitive: i as u32,
                source: self.set.sources[i],
                point: q.into(),
                distance: d2.sqrt(),
            })
            .collect()
    }
}

impl<T: FrustumOverlap> LinearSearch<T> {
    /// The indices of the primitives overlapping `frustum` (touching counts),
    /// ascending: every primitive tested exactly.
    pub fn frustum(&self, frustum: &Frustum) -> Vec<u32> {
        let mut out = Vec::new();
        self.frustum_into(frustum, &mut out);
        out
    }

    /// [`frustum`](Self::frustum) into a caller-owned vector (cleared first).
    pub fn frustum_into(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        out.clear();
        out.extend(
            self.set
                .primitives
                .iter()
                .enumerate()
                .filter(|(_, p)| p.overlaps_frustum(frustum))
                .map(|(i, _)| i as u32),
        );
    }
}
