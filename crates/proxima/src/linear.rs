//! Brute force: every query tests every primitive. The reference answer for
//! the trees, and the baseline they are measured against.

use crate::aabb::Aabb;
use crate::frustum::{Frustum, FrustumOverlap};
use crate::math::{Vec3, Vec3A};
use crate::primitive::{Bounded, ClosestPoint, PrimitiveSet, RayIntersect, WatertightRay};
use crate::query::{Counter, FrustumQuery, Leaves, NearestQuery, NearestVisitor, RayQuery, RayVisitor, SpatialIndex};

/// A linear scan over primitives, answering the same queries as the trees
/// ([`NearestQuery`], [`RayQuery`], [`FrustumQuery`]): its "walk" hands the
/// visitor every primitive, in input order.
///
/// ```
/// use proxima::prelude::*;
/// let linear = LinearSearch::new(PrimitiveSet::from_primitives(vec![Point(Vec3::ZERO), Point(Vec3::X)]));
/// assert_eq!(linear.closest(Vec3::new(0.8, 0.0, 0.0)).unwrap().primitive, 1);
/// ```
#[derive(Clone, Debug)]
pub struct LinearSearch<T> {
    /// The primitives in input order (slot = input index).
    leaves: Leaves<T>,
    bounds: Aabb,
}

impl<T: Bounded> LinearSearch<T> {
    /// A scan over `set`, in its order.
    pub fn new(set: PrimitiveSet<T>) -> Self {
        let bounds = set.primitives.iter().fold(Aabb::EMPTY, |b, p| b.merge(&p.bounds()));
        let indices = (0..set.primitives.len() as u32).collect();
        Self {
            leaves: Leaves::new(set.primitives, indices, set.sources),
            bounds,
        }
    }
}

impl<T> LinearSearch<T> {
    /// The primitives, in input order.
    pub fn primitives(&self) -> &[T] {
        self.leaves.primitives()
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// `true` when there is no primitive.
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }
}

impl<T> SpatialIndex<T> for LinearSearch<T> {
    #[inline(always)]
    fn leaves(&self) -> &Leaves<T> {
        &self.leaves
    }
    fn bounds(&self) -> Aabb {
        self.bounds
    }
}

impl<T: ClosestPoint> NearestQuery<T> for LinearSearch<T> {
    fn nearest_walk<V: NearestVisitor<T>, C: Counter>(&self, p: Vec3A, visitor: &mut V, counter: &mut C) {
        counter.primitives(self.len() as u64);
        for (slot, primitive) in self.primitives().iter().enumerate() {
            visitor.visit(slot, primitive, p);
        }
    }
}

impl<T: RayIntersect> RayQuery<T> for LinearSearch<T> {
    fn ray_walk<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        _direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) {
        counter.primitives(self.len() as u64);
        for (slot, primitive) in self.primitives().iter().enumerate() {
            if visitor.visit(slot, primitive, ray, t_min) {
                return;
            }
        }
    }
}

impl<T: FrustumOverlap> FrustumQuery<T> for LinearSearch<T> {
    fn frustum_walk<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        counter.primitives(self.len() as u64);
        out.clear();
        out.extend(
            self.primitives()
                .iter()
                .enumerate()
                .filter(|(_, p)| p.overlaps_frustum(frustum))
                .map(|(i, _)| i as u32),
        );
    }
}
