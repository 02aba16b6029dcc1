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

use super::AabbTree;
use super::config::MAX_DEPTH;
use super::node::Node;
use super::traverse::{Counter, QueryStats};
use super::wide::prefetch;
use crate::error::RayError;
use crate::math::{Vec3, Vec3A};
use crate::primitive::{RayIntersect, TriangleHit, WatertightRay};
use glam::BVec3A;
use rayon::prelude::*;

/// The first primitive a ray hits (the fields match the hash grid's
/// [`GridRayHit`](crate::grid::GridRayHit), without its cell count).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Index of the primitive in the build input.
    pub primitive: u32,
    /// The mesh element it came from (face index for triangles).
    pub source: u32,
    /// Ray parameter of the hit (a distance when the direction is unit length).
    pub t: f32,
    /// The hit point on the primitive (for a triangle `a + u (b − a) + v (c − a)`).
    pub point: Vec3,
    /// Barycentric weight of the triangle's vertex `b`.
    pub u: f32,
    /// Barycentric weight of the triangle's vertex `c`.
    pub v: f32,
}

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
    fn entry(&self, node: &Node, t_lo: f32, t_hi: f32) -> f32 {
        let (enter, exit) = self.interval(node.min, node.max, t_lo, t_hi);
        if enter <= exit { enter } else { f32::INFINITY }
    }
}

/// How many box diagonals (along the ray) an origin may lie outside the
/// structure's bounds before the ray is moved in `f64` ([`FarRay`]).
const FAR_RAY_DIAGONALS: f64 = 1024.0;

/// A ray whose origin lies far outside the bounds it is cast at, moved in
/// `f64` to one box diagonal before it enters them. In `f32`, a parameter
/// near `1e8` has a step of 8: the front and back faces of a mesh of size 10
/// round to one `t`, and the tree could not tell them apart (a ray from
/// `z = 1e8` hit the bunny's back face). The moved ray is the same line up to
/// the `f32` rounding of its new origin, at the mesh's scale.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FarRay {
    /// The origin to cast from.
    pub origin: Vec3,
    /// Parameter range relative to `origin`.
    pub t_min: f32,
    pub t_max: f32,
    /// The parameter of `origin` on the original ray (0 when not moved).
    pub shift: f64,
}

impl FarRay {
    /// The ray `origin + t · direction`, `t ∈ [t_min, t_max]`, cast at the box
    /// `[min, max]`: moved when it starts more than [`FAR_RAY_DIAGONALS`]
    /// diagonals before entering it, as it is otherwise (and when it misses);
    /// `None` when the origin lies more than 2^30 diagonals from the box, where
    /// the `f64` rounding of the move would exceed the box's `f32` resolution.
    pub(crate) fn new(origin: Vec3, direction: Vec3, t_min: f32, t_max: f32, min: Vec3, max: Vec3) -> Option<Self> {
        let unmoved = Self {
            origin,
            t_min,
            t_max,
            shift: 0.0,
        };
        let (o, d) = (
            origin.to_array().map(|x| x as f64),
            direction.to_array().map(|x| x as f64),
        );
        let (lo, hi) = (min.to_array().map(|x| x as f64), max.to_array().map(|x| x as f64));
        let mut enter = f64::NEG_INFINITY;
        for k in 0..3 {
            if d[k] != 0.0 {
                let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
                enter = enter.max(a.min(b));
            }
        }
        let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let diagonal = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
        let back = diagonal.max(f64::MIN_POSITIVE) / length;
        let shift = enter - back;
        if !(shift.is_finite() && shift > FAR_RAY_DIAGONALS * back && shift > t_min as f64) {
            return Some(unmoved);
        }
        let reach = o.iter().chain(&lo).chain(&hi).fold(0.0f64, |m, x| m.max(x.abs()));
        if reach > diagonal * (1u64 << 30) as f64 {
            return None;
        }
        let moved = Vec3::from_array(std::array::from_fn(|k| (o[k] + shift * d[k]) as f32));
        if !moved.is_finite() {
            return Some(unmoved);
        }
        Some(Self {
            origin: moved,
            t_min: (t_min as f64 - shift) as f32,
            t_max: (t_max as f64 - shift) as f32,
            shift,
        })
    }

    /// A parameter of the moved ray on the original one.
    #[inline]
    pub(crate) fn original_t(&self, t: f32) -> f32 {
        if self.shift == 0.0 {
            t
        } else {
            (self.shift + t as f64) as f32
        }
    }
}

/// Checks a ray's input and prepares it for the tree whose root is `root`,
/// moved near the root's box when it starts far out ([`FarRay`]); `None` for
/// an empty tree. Shared by the binary and the wide tree's ray queries.
pub(crate) fn prepare_tree_ray(
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
    root: Option<&Node>,
) -> Result<Option<(WatertightRay, FarRay)>, RayError> {
    prepare_ray(origin, direction, t_min, t_max)?;
    let Some(root) = root else { return Ok(None) };
    let far = FarRay::new(origin, direction, t_min, t_max, root.min, root.max).ok_or(RayError::OriginTooFar)?;
    let ray = prepare_ray(far.origin, direction, far.t_min, far.t_max)?;
    Ok(Some((ray, far)))
}

/// Checks a ray's input and prepares it; shared by every tree's ray queries.
pub(crate) fn prepare_ray(origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<WatertightRay, RayError> {
    if !origin.is_finite() {
        return Err(RayError::Origin);
    }
    // A direction so small that 1 / its largest component overflows would
    // make every parameter infinite: refuse it like a zero direction.
    if !(1.0 / direction.abs().max_element()).is_finite() {
        return Err(RayError::Direction);
    }
    let ray = WatertightRay::new(origin, direction).ok_or(RayError::Direction)?;
    if !(t_min.is_finite() && t_min <= t_max) {
        return Err(RayError::Range { t_min, t_max });
    }
    Ok(ray)
}

/// What a ray query does with the primitives of the leaves it reaches.
/// Shared with the wide tree, whose answers must be the same.
pub(crate) trait RayVisitor<T> {
    /// The end of the parameter range still of interest.
    fn t_hi(&self) -> f32;
    /// Tests the primitive at leaf-order slot `slot`; `true` ends the query.
    fn visit(&mut self, slot: usize, primitive: &T, ray: &WatertightRay, t_min: f32) -> bool;
    /// Considers a hit of the primitive at `slot` computed elsewhere (four
    /// triangles at a time), exactly as `visit` would have found it; `true`
    /// ends the query.
    fn offer(&mut self, slot: usize, hit: TriangleHit) -> bool;
}

/// Keeps the hit of smallest `t`, ties to the lowest input index.
pub(crate) struct FirstHit<'a> {
    pub(crate) indices: &'a [u32],
    pub(crate) t_hi: f32,
    pub(crate) best: Option<(usize, TriangleHit)>,
}

impl<T: RayIntersect> RayVisitor<T> for FirstHit<'_> {
    #[inline(always)]
    fn t_hi(&self) -> f32 {
        self.t_hi
    }

    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, ray: &WatertightRay, t_min: f32) -> bool {
        if let Some(hit) = primitive.intersect_ray(ray, t_min, self.t_hi) {
            RayVisitor::<T>::offer(self, slot, hit);
        }
        false
    }

    #[inline(always)]
    fn offer(&mut self, slot: usize, hit: TriangleHit) -> bool {
        let better = match self.best {
            None => true,
            Some((best_slot, best)) => {
                hit.t < best.t || (hit.t == best.t && self.indices[slot] < self.indices[best_slot])
            }
        };
        if better {
            self.best = Some((slot, hit));
            self.t_hi = hit.t;
        }
        false
    }
}

/// Stops at the first hit in range.
pub(crate) struct AnyHit {
    pub(crate) t_max: f32,
    pub(crate) found: bool,
}

impl<T: RayIntersect> RayVisitor<T> for AnyHit {
    #[inline(always)]
    fn t_hi(&self) -> f32 {
        self.t_max
    }

    #[inline(always)]
    fn visit(&mut self, _: usize, primitive: &T, ray: &WatertightRay, t_min: f32) -> bool {
        self.found = primitive.intersect_ray(ray, t_min, self.t_max).is_some();
        self.found
    }

    #[inline(always)]
    fn offer(&mut self, _: usize, _: TriangleHit) -> bool {
        self.found = true;
        true
    }
}

impl<T: RayIntersect> AabbTree<T> {
    /// The first primitive hit by `origin + t · direction` with `t` in
    /// `[t_min, t_max]`, or `None`. Of several primitives hit at the same `t`,
    /// the one of lowest input index is returned, so the answer equals a scan
    /// of every primitive with [`RayIntersect::intersect_ray`].
    ///
    /// Errors for a non-finite origin, a zero or non-finite direction, and a
    /// range that is NaN, starts at an infinity or is reversed.
    ///
    /// ```
    /// use proxima::{AabbTree, Mesh, Vec3};
    /// let mesh = Mesh::from_triangles(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.0, 0.0, 3.0), Vec3::new(0.0, 1.0, 3.0)],
    ///     &[[3, 4, 5], [0, 1, 2]],
    /// )
    /// .unwrap();
    /// let tree = AabbTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    /// let hit = tree.first_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap();
    /// assert_eq!((hit.source, hit.t), (1, 1.0));
    /// assert!(tree.any_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, 3.5).unwrap());
    /// assert!(!tree.any_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, 0.5).unwrap());
    /// assert!(tree.first_hit(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0).is_err());
    /// ```
    #[inline]
    pub fn first_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<Option<RayHit>, RayError> {
        self.first_hit_counted(origin, direction, t_min, t_max, &mut ())
    }

    /// [`first_hit`](Self::first_hit), also counting the nodes whose box was
    /// tested and the primitives whose ray test ran.
    pub fn first_hit_with_stats(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<(Option<RayHit>, QueryStats), RayError> {
        let mut stats = QueryStats::default();
        let hit = self.first_hit_counted(origin, direction, t_min, t_max, &mut stats)?;
        Ok((hit, stats))
    }

    /// `true` when the ray hits some primitive with `t` in `[t_min, t_max]`
    /// (an occlusion test). Stops at the first hit found, whichever it is.
    /// Errors as [`first_hit`](Self::first_hit).
    #[inline]
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<bool, RayError> {
        let Some((ray, far)) = prepare_tree_ray(origin, direction, t_min, t_max, self.root())? else {
            return Ok(false);
        };
        let mut any = AnyHit {
            t_max: far.t_max,
            found: false,
        };
        self.ray_walk(&ray, direction, far.t_min, &mut any, &mut ());
        Ok(any.found)
    }

    /// [`first_hit`](Self::first_hit) for many rays `(origin, direction)`
    /// on all cores, answers in input order.
    pub fn first_hit_batch(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<Option<RayHit>, RayError>>
    where
        T: Sync,
    {
        rays.par_iter()
            .with_min_len(64)
            .map(|&(o, d)| self.first_hit(o, d, t_min, t_max))
            .collect()
    }

    /// [`any_hit`](Self::any_hit) for many rays `(origin, direction)` on all
    /// cores, answers in input order.
    pub fn any_hit_batch(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Vec<Result<bool, RayError>>
    where
        T: Sync,
    {
        rays.par_iter()
            .with_min_len(64)
            .map(|&(o, d)| self.any_hit(o, d, t_min, t_max))
            .collect()
    }

    #[inline]
    fn first_hit_counted<C: Counter>(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        counter: &mut C,
    ) -> Result<Option<RayHit>, RayError> {
        let Some((ray, far)) = prepare_tree_ray(origin, direction, t_min, t_max, self.root())? else {
            return Ok(None);
        };
        let mut first = FirstHit {
            indices: &self.indices,
            t_hi: far.t_max,
            best: None,
        };
        self.ray_walk(&ray, direction, far.t_min, &mut first, counter);
        Ok(first.best.map(|(slot, hit)| {
            let mut answer = self.ray_hit(slot, &hit);
            answer.t = far.original_t(answer.t);
            answer
        }))
    }

    /// The answer for a hit of the primitive at leaf-order slot `slot`.
    pub(crate) fn ray_hit(&self, slot: usize, hit: &TriangleHit) -> RayHit {
        RayHit {
            primitive: self.indices[slot],
            source: self.sources[slot],
            t: hit.t,
            point: self.primitives[slot].hit_point(hit),
            u: hit.u,
            v: hit.v,
        }
    }

    /// Depth-first, nearer child first, on a fixed stack: the nearer child is
    /// descended at once, the farther one kept with its entry parameter and
    /// dropped when popped if a hit has come before it meanwhile.
    #[inline]
    fn ray_walk<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) {
        let Some(root) = self.root() else { return };
        let slabs = RaySlabs::new(ray.origin(), direction, root.min, root.max);
        counter.nodes(1);
        if slabs.entry(root, t_min, visitor.t_hi()) == f32::INFINITY {
            return;
        }
        // Each inner node on the current path pushes at most one entry, and
        // the build never goes deeper than MAX_DEPTH.
        let mut stack = [(0u32, 0f32); MAX_DEPTH as usize + 1];
        let mut top = 0usize;
        let mut node = 0usize;
        loop {
            let n = self.node(node);
            if n.is_leaf() {
                let range = n.primitive_range();
                counter.primitives(range.len() as u64);
                for slot in range {
                    if visitor.visit(slot, &self.primitives[slot], ray, t_min) {
                        return;
                    }
                }
            } else {
                let [left, right] = n.children();
                let pair = self.children_of(n);
                let t_hi = visitor.t_hi();
                let el = slabs.entry(&pair[0], t_min, t_hi);
                let er = slabs.entry(&pair[1], t_min, t_hi);
                counter.nodes(2);
                // Ask for the children of each child crossed, so that their
                // cache misses overlap. (Touching every grandchild, as the
                // closest-point walk does, stalled on lines a ray mostly
                // never visits.)
                for (child, entry) in [(&pair[0], el), (&pair[1], er)] {
                    if entry != f32::INFINITY {
                        if child.is_leaf() {
                            prefetch(&self.primitives[child.primitive_range().start]);
                        } else {
                            prefetch(self.children_of(child));
                        }
                    }
                }
                let (near, e_near, far, e_far) = if el <= er {
                    (left, el, right, er)
                } else {
                    (right, er, left, el)
                };
                if e_near != f32::INFINITY {
                    if e_far != f32::INFINITY {
                        stack[top] = (far, e_far);
                        top += 1;
                    }
                    node = near as usize;
                    continue;
                }
            }
            // Pop the next subtree not yet passed by a hit.
            loop {
                if top == 0 {
                    return;
                }
                top -= 1;
                let (next, entry) = stack[top];
                if entry <= visitor.t_hi() {
                    node = next as usize;
                    break;
                }
            }
        }
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
