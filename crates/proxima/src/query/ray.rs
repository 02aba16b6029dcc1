//! Ray queries, written once over any structure's ray walk: the first
//! primitive a ray hits, and whether it hits any.

use super::batch::answer_batch_indexed;
use super::{Counter, Leaves, QueryStats, RayVisitor, SpatialIndex};
use crate::aabb::Aabb;
use crate::error::RayError;
use crate::math::Vec3;
use crate::primitive::{RayIntersect, TriangleHit, WatertightRay};
use crate::ray::Ray;
use rayon::prelude::*;

/// The first primitive a ray hits, as every structure answers it (the trees
/// and the hash grid, [`HashGrid::first_hit`](crate::HashGrid::first_hit)).
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
    /// diagonals before entering it, as it is otherwise (and when it misses,
    /// or when its origin lies within that many diagonals of the box's
    /// centre, which every ray of a batch cast at a mesh usually does: then
    /// no division is made, and when the box is a single point);
    /// `None` when the origin lies more than 2^30 times the box's size from
    /// it, where the `f64` rounding of the move would exceed the box's `f32`
    /// resolution. The size is the larger of the diagonal and the largest
    /// coordinate: `f32` resolves a box far from 0 only to the spacing of its
    /// coordinates, however small the box, and a move placed within that
    /// spacing is as good as any `f32` origin.
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
        let diagonal2: f64 = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum();
        // A box of no extent holds only primitives of no area (every vertex
        // at its one point), which no ray hits from anywhere: there are no
        // hits to tell apart, and the ray is cast as it is.
        if diagonal2 == 0.0 {
            return Some(unmoved);
        }
        // An origin this near the box enters it, if at all, within
        // `FAR_RAY_DIAGONALS · back` (its entry point lies on the box): not
        // moved, and no division needed to know it.
        let from_centre2: f64 = (0..3).map(|k| (o[k] - 0.5 * (lo[k] + hi[k])).powi(2)).sum();
        if from_centre2 <= diagonal2 * (FAR_RAY_DIAGONALS / 2.0).powi(2) {
            return Some(unmoved);
        }
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
        let scale = lo.iter().chain(&hi).fold(0.0f64, |m, x| m.max(x.abs()));
        let reach = o.iter().fold(scale, |m, x| m.max(x.abs()));
        if reach > diagonal.max(scale) * (1u64 << 30) as f64 {
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

/// Checks a ray's input and prepares it for a structure whose primitives lie
/// in `bounds`, moved near them when it starts far out ([`FarRay`]); `None`
/// for an empty structure.
pub(crate) fn prepare_structure_ray(
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
    bounds: Option<crate::aabb::Aabb>,
) -> Result<Option<(WatertightRay, FarRay)>, RayError> {
    Ray::with_range(origin, direction, t_min, t_max)?;
    let Some(bounds) = bounds else { return Ok(None) };
    let far = FarRay::new(origin, direction, t_min, t_max, bounds.min, bounds.max).ok_or(RayError::OriginTooFar)?;
    if far.shift != 0.0 {
        // The moved ray's range may have become invalid (the move rounds).
        Ray::with_range(far.origin, direction, far.t_min, far.t_max)?;
    }
    let ray = WatertightRay::new(far.origin, direction).ok_or(RayError::Direction)?;
    Ok(Some((ray, far)))
}

/// Keeps the hit of smallest `t`, ties to the lowest input index.
pub(crate) struct FirstHit<'a, T> {
    pub(crate) leaves: &'a Leaves<T>,
    pub(crate) t_hi: f32,
    pub(crate) best: Option<(usize, TriangleHit)>,
}

impl<'a, T: RayIntersect> FirstHit<'a, T> {
    /// A search of `ray` (prepared by [`prepare_structure_ray`]) in the
    /// structure whose leaves are `leaves`.
    pub(crate) fn new(leaves: &'a Leaves<T>, far: &FarRay) -> Self {
        Self {
            leaves,
            t_hi: far.t_max,
            best: None,
        }
    }

    /// The answer once the walk has ended, in the parameters of the ray as given.
    pub(crate) fn answer(&self, far: &FarRay) -> Option<RayHit> {
        self.best.map(|(slot, hit)| hit_answer(self.leaves, far, slot, &hit))
    }
}

/// The answer for `hit` on the primitive at `slot` of `leaves`, in the
/// parameters of the ray as given (before [`FarRay`] moved it).
#[inline]
pub(crate) fn hit_answer<T: RayIntersect>(leaves: &Leaves<T>, far: &FarRay, slot: usize, hit: &TriangleHit) -> RayHit {
    RayHit {
        primitive: leaves.indices()[slot],
        source: leaves.sources()[slot],
        t: far.original_t(hit.t),
        point: leaves.primitives()[slot].hit_point(hit),
        u: hit.u,
        v: hit.v,
    }
}

impl<T: RayIntersect> RayVisitor<T> for FirstHit<'_, T> {
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
                hit.t < best.t || (hit.t == best.t && self.leaves.indices()[slot] < self.leaves.indices()[best_slot])
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
    /// The slot and hit found, if any.
    pub(crate) found: Option<(usize, TriangleHit)>,
}

impl<T: RayIntersect> RayVisitor<T> for AnyHit {
    #[inline(always)]
    fn t_hi(&self) -> f32 {
        self.t_max
    }

    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &T, ray: &WatertightRay, t_min: f32) -> bool {
        self.found = primitive.intersect_ray(ray, t_min, self.t_max).map(|hit| (slot, hit));
        self.found.is_some()
    }

    #[inline(always)]
    fn offer(&mut self, slot: usize, hit: TriangleHit) -> bool {
        self.found = Some((slot, hit));
        true
    }
}

/// Ray queries: the first primitive hit, whether any is hit, in batches on
/// all cores. A structure provides one walk; every query is built on it,
/// and answers equal a scan of every primitive with
/// [`RayIntersect::intersect_ray`] (smallest `t`, ties to the lowest input index).
///
/// ```
/// use proxima::prelude::*;
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
pub trait RayQuery<T: RayIntersect>: SpatialIndex<T> {
    /// Hands `visitor` the primitives of every leaf whose bounding volume
    /// `ray` crosses within `[t_min, visitor.t_hi()]` (which shrinks as hits
    /// are found), nearest entry first, until the visitor ends the query.
    /// `direction` is the direction `ray` was made from.
    fn ray_walk<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    );

    /// The first primitive hit by `origin + t · direction` with `t` in
    /// `[t_min, t_max]`, or `None`. Of several primitives hit at the same
    /// `t`, the one of lowest input index.
    ///
    /// Errors for a non-finite origin, a zero or non-finite direction, a
    /// range that is NaN, starts at an infinity or is reversed, and an
    /// origin too far from the primitives ([`RayError`]).
    #[inline]
    fn first_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<Option<RayHit>, RayError> {
        first_hit_counted(self, origin, direction, t_min, t_max, &mut ())
    }

    /// [`first_hit`](Self::first_hit), also counting the nodes whose volume
    /// was tested and the primitives whose ray test ran.
    fn first_hit_with_stats(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<(Option<RayHit>, QueryStats), RayError> {
        let mut stats = QueryStats::default();
        let hit = first_hit_counted(self, origin, direction, t_min, t_max, &mut stats)?;
        Ok((hit, stats))
    }

    /// `true` when the ray hits some primitive with `t` in `[t_min, t_max]`
    /// (an occlusion test). Stops at the first hit found, whichever it is.
    /// Errors as [`first_hit`](Self::first_hit).
    #[inline]
    fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<bool, RayError> {
        Ok(some_hit_found(self, origin, direction, t_min, t_max)?.is_some())
    }

    /// The hit that [`any_hit`](Self::any_hit) stops at: some primitive hit
    /// with `t` in `[t_min, t_max]`, not always the first, or `None`.
    /// Errors as [`first_hit`](Self::first_hit).
    ///
    /// ```
    /// use proxima::prelude::*;
    /// let mesh = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    /// let tree = RayTree::build(&mesh).unwrap();
    /// let hit = tree.some_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap();
    /// assert_eq!((hit.source, hit.t), (0, 1.0));
    /// ```
    fn some_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Result<Option<RayHit>, RayError> {
        let hit = some_hit_found(self, origin, direction, t_min, t_max)?;
        Ok(hit.map(|(slot, hit, far)| hit_answer(self.leaves(), &far, slot, &hit)))
    }

    /// [`first_hit`](Self::first_hit) for many rays `(origin, direction)`
    /// on all cores, answers in input order. The rays are cast in Morton
    /// order of their point nearest the centre of the structure's bounds
    /// (a ray-space Morton key), so that consecutive rays cross mostly the same
    /// nodes while they are in cache; each answer is the one
    /// [`first_hit`](Self::first_hit) gives.
    fn first_hit_batch(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Vec<Result<Option<RayHit>, RayError>>
    where
        Self: Sync,
    {
        in_ray_order(self, rays, |o, d| self.first_hit(o, d, t_min, t_max))
    }

    /// [`any_hit`](Self::any_hit) for many rays `(origin, direction)` on all
    /// cores, answers in input order, cast in the order of
    /// [`first_hit_batch`](Self::first_hit_batch).
    fn any_hit_batch(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Vec<Result<bool, RayError>>
    where
        Self: Sync,
    {
        in_ray_order(self, rays, |o, d| self.any_hit(o, d, t_min, t_max))
    }

    /// [`some_hit`](Self::some_hit) for many rays `(origin, direction)` on
    /// all cores, answers in input order, cast in the order of
    /// [`first_hit_batch`](Self::first_hit_batch).
    fn some_hit_batch(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Vec<Result<Option<RayHit>, RayError>>
    where
        Self: Sync,
    {
        in_ray_order(self, rays, |o, d| self.some_hit(o, d, t_min, t_max))
    }
}

/// The walk of [`RayQuery::any_hit`]: the slot and hit it stopped at, and
/// how the ray was moved.
#[inline]
fn some_hit_found<T: RayIntersect, S: RayQuery<T> + ?Sized>(
    structure: &S,
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
) -> Result<Option<(usize, TriangleHit, FarRay)>, RayError> {
    let bounds = (!structure.leaves().is_empty()).then(|| structure.bounds());
    let Some((ray, far)) = prepare_structure_ray(origin, direction, t_min, t_max, bounds)? else {
        return Ok(None);
    };
    let mut any = AnyHit {
        t_max: far.t_max,
        found: None,
    };
    structure.ray_walk(&ray, direction, far.t_min, &mut any, &mut ());
    Ok(any.found.map(|(slot, hit)| (slot, hit, far)))
}

/// `cast` of every ray on rayon's pool, in the Morton order of
/// [`sort_points`] within the structure's bounds; answers in input order.
fn in_ray_order<T: RayIntersect, S: RayQuery<T> + ?Sized, R: Send>(
    structure: &S,
    rays: &[(Vec3, Vec3)],
    cast: impl Fn(Vec3, Vec3) -> R + Sync + Send,
) -> Vec<R> {
    let bounds = structure.bounds();
    answer_batch_indexed(
        &sort_points(rays, &bounds),
        &bounds,
        true,
        || (),
        |_, i| cast(rays[i].0, rays[i].1),
    )
}

/// The point of each ray's line nearest the centre of `bounds`: rays whose
/// points are near one another cross the same part of a structure, so
/// Morton order of these points makes a batch coherent. A zero or
/// non-finite direction gives NaN, which sorts first (its ray fails anyway).
pub(crate) fn sort_points(rays: &[(Vec3, Vec3)], bounds: &Aabb) -> Vec<Vec3> {
    let centre = bounds.center();
    rays.par_iter()
        .with_min_len(4096)
        .map(|&ray| nearest_to(ray, centre))
        .collect()
}

/// The point of the line of `ray` nearest to `centre` (a ray's sort point).
#[inline]
pub(crate) fn nearest_to((o, d): (Vec3, Vec3), centre: Vec3) -> Vec3 {
    o + d * ((centre - o).dot(d) / d.length_squared())
}

#[inline]
fn first_hit_counted<T: RayIntersect, S: RayQuery<T> + ?Sized, C: Counter>(
    structure: &S,
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
    counter: &mut C,
) -> Result<Option<RayHit>, RayError> {
    first_hit_by(
        structure,
        origin,
        direction,
        t_min,
        t_max,
        counter,
        |ray, t_min, first, counter| {
            structure.ray_walk(ray, direction, t_min, first, counter);
            Ok(())
        },
    )
}

/// The first hit of `origin + t · direction`, `t ∈ [t_min, t_max]`, in
/// `structure`, walked by `walk` (the prepared ray, the start of its range
/// and the visitor): the one preparation of a ray (checks, the move of a far
/// origin and the check of the moved range) and the one tie rule
/// ([`FirstHit`]) of every first-hit query. `walk` may fail with an error of
/// the structure's own (the hash grid's walk beyond its cell range).
#[inline]
pub(crate) fn first_hit_by<T, S, C, E>(
    structure: &S,
    origin: Vec3,
    direction: Vec3,
    t_min: f32,
    t_max: f32,
    counter: &mut C,
    walk: impl FnOnce(&WatertightRay, f32, &mut FirstHit<'_, T>, &mut C) -> Result<(), E>,
) -> Result<Option<RayHit>, E>
where
    T: RayIntersect,
    S: SpatialIndex<T> + ?Sized,
    C: Counter,
    E: From<RayError>,
{
    let leaves = structure.leaves();
    let bounds = (!leaves.is_empty()).then(|| structure.bounds());
    let Some((ray, far)) = prepare_structure_ray(origin, direction, t_min, t_max, bounds)? else {
        return Ok(None);
    };
    let mut first = FirstHit::new(leaves, &far);
    walk(&ray, far.t_min, &mut first, counter)?;
    Ok(first.answer(&far))
}
