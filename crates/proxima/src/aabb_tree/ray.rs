//! Ray queries: the first primitive a ray hits, and whether it hits any.
//!
//! One depth-first loop serves both, nearer child first, on a fixed stack. A
//! node is entered when the ray's parameter interval inside its box meets
//! `[t_min, t_hi]`, where `t_hi` is `t_max` until a hit shrinks it to the hit's
//! `t`. The test is a slab test with the reciprocal direction computed once
//! per ray (Williams et al. 2005; Ize, "Robust BVH Ray Traversal", JCGT 2013).
//!
//! # Exactness
//!
//! The answer equals a scan of every primitive with the same ray test
//! (smallest `t`, ties to the lowest input index), as the closest-point
//! queries do. That needs the box test to be conservative for *computed*
//! hits, whose `t` and position carry rounding errors of the order of
//! `ε · |p − origin|`. So every box is widened, per ray, by
//! `16 ε · M`, with `M` the largest distance (per axis) from the origin to the
//! root box; that covers the rounding of the watertight test's shear and of
//! its `t`, and the rounding of the slab test itself (Ize scales the exit by
//! `1 + 2γ₃` for the latter alone). Only a box whose entry lies strictly after
//! the best hit is skipped, so an equal-`t` hit of lower index is still seen.
//!
//! A zero direction component gives an infinite reciprocal. The slab is then
//! `(−∞, +∞)` or empty depending on which side of it the origin lies; an origin
//! exactly on the (widened) plane gives `0 · ∞ = NaN`, which is replaced by the
//! unbounded value (the plane belongs to the box). The near and far planes are
//! chosen by the sign bit of the direction, so `−0.0` works like `+0.0`.

use super::{AabbNode, AabbTree};
use crate::build::{BinaryQuery, walk};
use crate::math::{BVec3A, Vec3, Vec3A};
use crate::memory::prefetch;
use crate::primitive::{RayIntersect, WatertightRay};
use crate::query::{Counter, RayQuery, RayVisitor, SpatialIndex};
use std::ops::{ControlFlow, Range};

/// A ray as the box tests need it: origin, reciprocal direction, which planes
/// are near, and the per-ray widening (see the module notes).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RaySlabs {
    pub(crate) origin: Vec3A,
    pub(crate) inv_direction: Vec3A,
    /// Axes along which the direction's sign bit is set: the near plane is the max.
    pub(crate) negative: BVec3A,
    /// Added to `near plane − origin`: moves the near planes outwards.
    pub(crate) near_shift: Vec3A,
    /// Added to `far plane − origin`: moves the far planes outwards.
    pub(crate) far_shift: Vec3A,
}

impl RaySlabs {
    /// `root_min`, `root_max`: a box holding every primitive (the root's).
    pub(crate) fn new(origin: Vec3, direction: Vec3, root_min: Vec3, root_max: Vec3) -> Self {
        let origin = Vec3A::from(origin);
        let reach = (Vec3A::from(root_min) - origin)
            .abs()
            .max((Vec3A::from(root_max) - origin).abs())
            .max_element();
        let widen = 16.0 * f32::EPSILON * reach;
        let negative = BVec3A::new(
            direction.x.is_sign_negative(),
            direction.y.is_sign_negative(),
            direction.z.is_sign_negative(),
        );
        let outwards = Vec3A::select(negative, Vec3A::splat(widen), Vec3A::splat(-widen));
        Self {
            origin,
            inv_direction: Vec3A::from(direction).recip(),
            negative,
            near_shift: outwards,
            far_shift: -outwards,
        }
    }

    /// Entry and exit parameters of the ray in the widened box `min`–`max`,
    /// clipped to `[t_lo, t_hi]`; the box is crossed when entry ≤ exit.
    #[inline(always)]
    pub(crate) fn interval(&self, min: Vec3, max: Vec3, t_lo: f32, t_hi: f32) -> (f32, f32) {
        let (min, max) = (Vec3A::from(min), Vec3A::from(max));
        let near = Vec3A::select(self.negative, max, min);
        let far = Vec3A::select(self.negative, min, max);
        let t_near = ((near - self.origin) + self.near_shift) * self.inv_direction;
        let t_far = ((far - self.origin) + self.far_shift) * self.inv_direction;
        // 0 · ∞ (origin on a plane the ray is parallel to) is NaN: unbounded.
        let t_near = Vec3A::select(t_near.cmpeq(t_near), t_near, Vec3A::NEG_INFINITY);
        let t_far = Vec3A::select(t_far.cmpeq(t_far), t_far, Vec3A::INFINITY);
        let enter = t_near.max(Vec3A::splat(t_lo)).max_element();
        let exit = t_far.min(Vec3A::splat(t_hi)).min_element();
        (enter, exit)
    }

    /// The entry parameter into `node`'s box, or `+∞` when the ray misses it
    /// within `[t_lo, t_hi]`.
    #[inline(always)]
    fn entry(&self, node: &AabbNode, t_lo: f32, t_hi: f32) -> f32 {
        let b = node.bounds();
        let (enter, exit) = self.interval(b.min, b.max, t_lo, t_hi);
        if enter <= exit { enter } else { f32::INFINITY }
    }
}

impl<T: RayIntersect> RayQuery<T> for AabbTree<T> {
    #[inline(always)]
    fn ray_walk<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) {
        let Some(root) = self.root() else { return };
        let mut query = Rays {
            slabs: RaySlabs::new(ray.origin(), direction, root.bounds().min, root.bounds().max),
            ray,
            t_min,
            primitives: self.leaves().primitives(),
            visitor,
        };
        walk::<AabbNode, _, C>(self.pairs(), self.depth(), &mut query, counter);
    }
}

/// A ray query on the binary tree: keys are the ray's entry parameters into
/// the (per-ray widened) node boxes, `+∞` for a box missed within
/// `[t_min, t_hi]`; each leaf's primitives go to the visitor.
struct Rays<'a, T, V> {
    slabs: RaySlabs,
    ray: &'a WatertightRay,
    t_min: f32,
    primitives: &'a [T],
    visitor: &'a mut V,
}

impl<T, V: RayVisitor<T>> BinaryQuery<AabbNode> for Rays<'_, T, V> {
    const TOUCH_GRANDCHILDREN: bool = false;
    #[inline(always)]
    fn key(&self, node: &AabbNode) -> f32 {
        self.slabs.entry(node, self.t_min, self.visitor.t_hi())
    }
    /// `t_hi`, but finite: a missed box's `+∞` entry is never within it.
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.visitor.t_hi().min(f32::MAX)
    }
    #[inline(always)]
    fn leaf(&mut self, range: Range<usize>) -> ControlFlow<()> {
        for slot in range {
            if self.visitor.visit(slot, &self.primitives[slot], self.ray, self.t_min) {
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    }
    #[inline(always)]
    fn prefetch_leaf(&self, range: Range<usize>) {
        prefetch(&self.primitives[range.start]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The slab test on an unwidened box (widening 0, as for an origin at the
    /// root's corner ... forced here by zero shifts).
    fn unwidened(origin: Vec3, direction: Vec3) -> RaySlabs {
        let mut slabs = RaySlabs::new(origin, direction, origin, origin);
        slabs.near_shift = Vec3A::ZERO;
        slabs.far_shift = Vec3A::ZERO;
        slabs
    }

    #[test]
    fn zero_components_and_origins_on_planes() {
        let (min, max) = (Vec3::ZERO, Vec3::ONE);
        for d in [Vec3::X, -Vec3::X, Vec3::new(1.0, 0.0, -0.0), Vec3::new(1.0, -0.0, 0.0)] {
            // On the y = 0 and z = 0 planes, parallel to both: 0 · ∞.
            for o in [
                Vec3::new(-1.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 1.0),
                Vec3::new(0.5, 0.0, 1.0),
            ] {
                let (enter, exit) = unwidened(o, d).interval(min, max, f32::NEG_INFINITY, f32::INFINITY);
                assert!(enter <= exit, "{o} {d}: {enter} {exit}");
                assert!(enter.is_finite() && exit.is_finite());
            }
            // Just outside a parallel slab: missed.
            let o = Vec3::new(-1.0, -1e-30, 0.5);
            let (enter, exit) = unwidened(o, d).interval(min, max, f32::NEG_INFINITY, f32::INFINITY);
            assert!(enter > exit, "{o} {d}");
        }
    }

    #[test]
    fn widening_is_outwards_for_both_signs() {
        for d in [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-1.0, -2.0, -3.0),
            Vec3::new(1.0, -0.0, 0.5),
        ] {
            let o = Vec3::new(-5.0, 0.5, 0.5) * d.signum();
            let slabs = RaySlabs::new(o, d, Vec3::ZERO, Vec3::ONE);
            let plain = unwidened(o, d);
            let (e, x) = slabs.interval(Vec3::ZERO, Vec3::ONE, f32::NEG_INFINITY, f32::INFINITY);
            let (pe, px) = plain.interval(Vec3::ZERO, Vec3::ONE, f32::NEG_INFINITY, f32::INFINITY);
            assert!(e <= pe && x >= px, "{d}: widened [{e}, {x}] plain [{pe}, {px}]");
        }
    }
}
