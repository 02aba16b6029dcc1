//! Many rays at once, their walks interleaved: first hits and any hits.
//!
//! A ray's walk through a large tree waits on memory at nearly every step:
//! the next node is rarely in cache. A thread here keeps [`INTERLEAVED`]
//! walks going and advances each by one step (a node or a leaf) in turn;
//! the children a step finds are prefetched at once, so by the time that
//! walk's turn comes again its next node has usually arrived, and the
//! misses of all the walks overlap. Each walk makes exactly the visits of
//! the single ray's walk, in the same order, so each answer is
//! [`first_hit`](crate::query::RayQuery::first_hit)'s (or
//! [`any_hit`](crate::query::RayQuery::any_hit)'s).
//!
//! Rays that come in no useful order are taken in Morton order of their
//! point nearest the centre of the tree's bounds, so that neighbouring walks
//! share the upper nodes; rays already as coherent (a camera's, row by row)
//! are taken as they come ([`already_coherent`]). They go in chunks of
//! [`CHUNK`](crate::query::CHUNK) across rayon's threads, and the answers
//! come back in input order.

use super::RayTree;
use super::slabs::NodeSlabs;
use super::walk::{Arrays, Lanes, Portable, RayWalk, SHALLOW, SMALL_STACK, WalkState};
use crate::aabb_tree::RaySlabs;
use crate::error::RayError;
use crate::math::Vec3;
use crate::memory::prefetch;
use crate::primitive::{Triangle, TriangleHit, WatertightRay};
use crate::query::{
    AnyHit, FarRay, FirstHit, Leaves, RayHit, RayQuery, RayVisitor, already_coherent, hit_answer, in_chunks_ordered,
    morton_order, nearest_to, prepare_structure_ray, sort_points,
};
use crate::simd::Avx2;

/// Walks a thread keeps going at once (4 and 16 were slower: docs/rays.md).
const INTERLEAVED: usize = 8;

/// Answers made this many ahead of the one being made are prefetched.
const RESOLVE_AHEAD: usize = 8;

/// What the walks of a batch look for.
trait Search<'a>: RayVisitor<Triangle> + Sized {
    /// What a finished walk leaves before its answer is made.
    type Found: Copy;
    /// The answer for one ray (its default: no hit).
    type Answer: Copy + Default + Send;
    /// A search along a ray prepared by `prepare_structure_ray`.
    fn new(leaves: &'a Leaves<Triangle>, far: &FarRay) -> Self;
    /// What the search found, once its walk has ended.
    fn found(&self, far: &FarRay) -> Self::Found;
    /// The answers of a chunk's walks, in the same order, into `out`.
    fn resolve(
        leaves: &'a Leaves<Triangle>,
        found: &[Result<Self::Found, RayError>],
        out: &mut [Result<Self::Answer, RayError>],
    );
}

impl<'a> Search<'a> for FirstHit<'a, Triangle> {
    /// The slot hit, the hit, and how the ray was moved.
    type Found = Option<(usize, TriangleHit, FarRay)>;
    type Answer = Option<RayHit>;

    fn new(leaves: &'a Leaves<Triangle>, far: &FarRay) -> Self {
        FirstHit::new(leaves, far)
    }

    fn found(&self, far: &FarRay) -> Self::Found {
        self.best.map(|(slot, hit)| (slot, hit, *far))
    }

    /// Each answer reads the hit slot's input index, source and triangle:
    /// three cache misses, which the walk would wait on at its end; here
    /// they are asked for [`RESOLVE_AHEAD`] answers ahead, so that they overlap.
    fn resolve(
        leaves: &'a Leaves<Triangle>,
        found: &[Result<Self::Found, RayError>],
        out: &mut [Result<Self::Answer, RayError>],
    ) {
        for (k, answer) in out.iter_mut().enumerate() {
            if let Some(Ok(Some((slot, ..)))) = found.get(k + RESOLVE_AHEAD) {
                prefetch(&leaves.indices()[*slot]);
                prefetch(&leaves.sources()[*slot]);
                prefetch(&leaves.primitives()[*slot]);
            }
            *answer = found[k].map(|hit| hit.map(|(slot, hit, far)| hit_answer(leaves, &far, slot, &hit)));
        }
    }
}

impl<'a> Search<'a> for AnyHit {
    type Found = bool;
    type Answer = bool;

    fn new(_: &'a Leaves<Triangle>, far: &FarRay) -> Self {
        AnyHit {
            t_max: far.t_max,
            found: None,
        }
    }

    fn found(&self, _: &FarRay) -> bool {
        self.found.is_some()
    }

    /// Nothing to look up: an occlusion test answers from the walk alone
    /// (hits are made by [`SomeHit`], whose answers need the leaves).
    fn resolve(_: &'a Leaves<Triangle>, found: &[Result<bool, RayError>], out: &mut [Result<bool, RayError>]) {
        out.copy_from_slice(found);
    }
}

/// [`AnyHit`]'s walk, answered with the hit it stopped at
/// ([`some_hit`](crate::query::RayQuery::some_hit)).
struct SomeHit(AnyHit);

impl RayVisitor<Triangle> for SomeHit {
    #[inline(always)]
    fn t_hi(&self) -> f32 {
        RayVisitor::<Triangle>::t_hi(&self.0)
    }

    #[inline(always)]
    fn visit(&mut self, slot: usize, primitive: &Triangle, ray: &WatertightRay, t_min: f32) -> bool {
        self.0.visit(slot, primitive, ray, t_min)
    }

    #[inline(always)]
    fn offer(&mut self, slot: usize, hit: TriangleHit) -> bool {
        RayVisitor::<Triangle>::offer(&mut self.0, slot, hit)
    }
}

impl<'a> Search<'a> for SomeHit {
    /// As [`FirstHit`]'s: the slot hit, the hit, and how the ray was moved.
    type Found = Option<(usize, TriangleHit, FarRay)>;
    type Answer = Option<RayHit>;

    fn new(leaves: &'a Leaves<Triangle>, far: &FarRay) -> Self {
        SomeHit(<AnyHit as Search<'a>>::new(leaves, far))
    }

    fn found(&self, far: &FarRay) -> Self::Found {
        self.0.found.map(|(slot, hit)| (slot, hit, *far))
    }

    fn resolve(
        leaves: &'a Leaves<Triangle>,
        found: &[Result<Self::Found, RayError>],
        out: &mut [Result<Self::Answer, RayError>],
    ) {
        FirstHit::resolve(leaves, found, out)
    }
}

/// One walk in progress: the ray, its search, and which answer it fills
/// (where it stands is kept apart, in a [`WalkState`] that never moves).
struct Slot<S> {
    answer: usize,
    ray: WatertightRay,
    far: FarRay,
    slabs: NodeSlabs,
    search: S,
}

impl RayTree {
    /// [`first_hit_batch`](crate::query::RayQuery::first_hit_batch) with
    /// interleaved walks (module notes).
    pub(super) fn first_hit_batch_interleaved(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<Option<RayHit>, RayError>> {
        self.batch::<FirstHit<'_, Triangle>>(rays, t_min, t_max, |o, d| self.first_hit(o, d, t_min, t_max))
    }

    /// [`some_hit_batch`](crate::query::RayQuery::some_hit_batch) with
    /// interleaved walks (module notes).
    pub(super) fn some_hit_batch_interleaved(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<Option<RayHit>, RayError>> {
        self.batch::<SomeHit>(rays, t_min, t_max, |o, d| self.some_hit(o, d, t_min, t_max))
    }

    /// [`any_hit_batch`](crate::query::RayQuery::any_hit_batch) with
    /// interleaved walks (module notes).
    pub(super) fn any_hit_batch_interleaved(
        &self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<bool, RayError>> {
        self.batch::<AnyHit>(rays, t_min, t_max, |o, d| self.any_hit(o, d, t_min, t_max))
    }

    /// The batch of searches `S`; trees too deep for the small stack (no
    /// real mesh makes one) take their rays one at a time with `single`.
    fn batch<'t, S: Search<'t>>(
        &'t self,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
        single: impl Fn(Vec3, Vec3) -> Result<S::Answer, RayError> + Sync,
    ) -> Vec<Result<S::Answer, RayError>> {
        // Rays already coherent (a camera's, row by row) are taken as they
        // come; others in Morton order of their point nearest the centre.
        let centre = self.bounds.center();
        let coherent = already_coherent(rays.len(), &self.bounds, |i| nearest_to(rays[i], centre));
        let order = (!coherent).then(|| morton_order(&sort_points(rays, &self.bounds), &self.bounds));
        let empty = Ok(S::Answer::default());
        if self.nodes.is_empty() || self.depth >= SHALLOW {
            return in_chunks_ordered(rays, order.as_deref(), empty, |chunk, out| {
                for (answer, &(o, d)) in out.iter_mut().zip(chunk) {
                    *answer = single(o, d);
                }
            });
        }
        in_chunks_ordered(rays, order.as_deref(), empty, |chunk, out| {
            S::resolve(&self.leaves, &self.chunk_found::<S>(chunk, t_min, t_max), out)
        })
    }

    /// What the walks of the rays of `chunk` found, in its order, on AVX2
    /// lanes where the tree uses them.
    fn chunk_found<'t, S: Search<'t>>(
        &'t self,
        chunk: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<S::Found, RayError>> {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(ChunkTask::<S> {
                tree: self,
                rays: chunk,
                t_min,
                t_max,
                search: std::marker::PhantomData,
            });
        }
        self.interleave::<Portable, S>(Portable, chunk, t_min, t_max)
    }

    /// Prepares a ray for a walk, or gives its error.
    #[inline(always)]
    fn start(
        &self,
        (origin, direction): (Vec3, Vec3),
        t_min: f32,
        t_max: f32,
    ) -> Result<(WatertightRay, FarRay, NodeSlabs), RayError> {
        let (ray, far) = prepare_structure_ray(origin, direction, t_min, t_max, Some(self.bounds))?
            .expect("a tree with nodes has bounds");
        let slabs = NodeSlabs::new(&RaySlabs::new(
            ray.origin(),
            direction,
            self.bounds.min,
            self.bounds.max,
        ));
        Ok((ray, far, slabs))
    }

    #[inline(always)]
    fn interleave<'t, L: Lanes, S: Search<'t>>(
        &'t self,
        lanes: L,
        rays: &[(Vec3, Vec3)],
        t_min: f32,
        t_max: f32,
    ) -> Vec<Result<S::Found, RayError>> {
        let arrays: Arrays<'_> = self.arrays();
        let mut found: Vec<Option<Result<S::Found, RayError>>> = vec![None; rays.len()];
        let mut slots: [Option<Slot<S>>; INTERLEAVED] = std::array::from_fn(|_| None);
        let mut states = [WalkState::<SMALL_STACK>::START; INTERLEAVED];
        let mut next = 0;
        // Gives `slot` the next ray that can be cast (errors are answered at
        // once), or leaves it empty when the chunk is done.
        let mut refill = |slot: &mut Option<Slot<S>>,
                          state: &mut WalkState<SMALL_STACK>,
                          found: &mut Vec<Option<Result<S::Found, RayError>>>| {
            *slot = None;
            while next < rays.len() {
                let k = next;
                next += 1;
                match self.start(rays[k], t_min, t_max) {
                    Ok((ray, far, slabs)) => {
                        state.restart();
                        *slot = Some(Slot {
                            answer: k,
                            ray,
                            far,
                            slabs,
                            search: S::new(&self.leaves, &far),
                        });
                        return;
                    }
                    Err(error) => found[k] = Some(Err(error)),
                }
            }
        };
        for (slot, state) in slots.iter_mut().zip(&mut states) {
            refill(slot, state, &mut found);
        }
        loop {
            let mut running = false;
            for (slot, state) in slots.iter_mut().zip(&mut states) {
                let Some(s) = slot else { continue };
                running = true;
                let mut walk = RayWalk {
                    ray: &s.ray,
                    slabs: &s.slabs,
                    t_min: s.far.t_min,
                    visitor: &mut s.search,
                };
                if !arrays.step(lanes, &mut walk, state, &mut ()) {
                    found[s.answer] = Some(Ok(s.search.found(&s.far)));
                    refill(slot, state, &mut found);
                }
            }
            if !running {
                // Every ray was either cast or refused.
                return found.into_iter().flatten().collect();
            }
        }
    }
}

/// [`RayTree::interleave`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct ChunkTask<'a, 'r, S> {
    tree: &'a RayTree,
    rays: &'r [(Vec3, Vec3)],
    t_min: f32,
    t_max: f32,
    search: std::marker::PhantomData<S>,
}

#[cfg(target_arch = "x86_64")]
impl<'a, S: Search<'a>> crate::simd::Avx2Task for ChunkTask<'a, '_, S> {
    type Output = Vec<Result<S::Found, RayError>>;
    #[inline(always)]
    fn call(self, avx2: Avx2) -> Self::Output {
        self.tree.interleave::<Avx2, S>(avx2, self.rays, self.t_min, self.t_max)
    }
}
