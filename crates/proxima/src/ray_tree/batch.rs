//! First hits of many rays at once, their walks interleaved.
//!
//! A ray's walk through a large tree waits on memory at nearly every step:
//! the next node is rarely in cache. A thread here keeps [`INTERLEAVED`]
//! walks going and advances each by one step (a node or a leaf) in turn;
//! the children a step finds are prefetched at once, so by the time that
//! walk's turn comes again its next node has usually arrived, and the
//! misses of all the walks overlap. Each walk makes exactly the visits of
//! the single ray's walk, in the same order, so each answer is
//! [`first_hit`](crate::query::RayQuery::first_hit)'s.
//!
//! The rays are taken in Morton order of their point nearest the centre of
//! the tree's bounds, so that neighbouring walks share the upper nodes, in
//! chunks of [`CHUNK`] across rayon's threads; answers come back in input
//! order.

use super::RayTree;
use super::slabs::NodeSlabs;
use super::walk::{Arrays, Lanes, Portable, RayWalk, SHALLOW, SMALL_STACK, WalkState};
use crate::bvh::RaySlabs;
use crate::error::RayError;
use crate::math::Vec3;
use crate::memory::prefetch;
use crate::primitive::{Triangle, TriangleHit, WatertightRay};
use crate::query::{
    FarRay, FirstHit, RayHit, first_hit_each, hit_answer, morton_order, prepare_structure_ray, sort_points, unpermute,
};
use crate::wide_tree::Avx2;
use rayon::prelude::*;

/// Walks a thread keeps going at once.
const INTERLEAVED: usize = 8;

/// Rays per parallel task.
const CHUNK: usize = 1024;

/// One walk in progress: the ray, its search, and which answer it fills
/// (where it stands is kept apart, in a [`WalkState`] that never moves).
struct Slot<'a> {
    answer: usize,
    ray: WatertightRay,
    far: FarRay,
    slabs: NodeSlabs,
    search: FirstHit<'a, Triangle>,
}

/// The answers, in chunk order, for the rays `order` picks from `rays`.
type Answers = Vec<Result<Option<RayHit>, RayError>>;

/// A walk's result before its answer is made: the slot hit, the hit, and
/// how its ray was moved.
type Found = Result<Option<(usize, TriangleHit, FarRay)>, RayError>;

/// Answers made this many ahead of the one being made are prefetched.
const RESOLVE_AHEAD: usize = 8;

impl RayTree {
    /// [`first_hit_batch`](crate::query::RayQuery::first_hit_batch) with
    /// interleaved walks (module notes); trees too deep for the small stack
    /// take their rays one at a time.
    pub(super) fn first_hit_batch_interleaved(&self, rays: &[(Vec3, Vec3)], t_min: f32, t_max: f32) -> Answers {
        if self.nodes.is_empty() || self.depth >= SHALLOW {
            return first_hit_each(self, rays, t_min, t_max);
        }
        let order = morton_order(&sort_points(rays, &self.bounds), &self.bounds);
        let answers: Answers = order
            .par_chunks(CHUNK)
            .flat_map_iter(|chunk| self.chunk_answers(rays, chunk, t_min, t_max))
            .collect();
        unpermute(&order, answers)
    }

    /// The answers for the rays `chunk` picks, in its order, on AVX2 lanes
    /// where the tree uses them.
    fn chunk_answers(&self, rays: &[(Vec3, Vec3)], chunk: &[u32], t_min: f32, t_max: f32) -> Answers {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(ChunkTask {
                tree: self,
                rays,
                chunk,
                t_min,
                t_max,
            });
        }
        self.interleave(Portable, rays, chunk, t_min, t_max)
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
    fn interleave<'t, L: Lanes>(
        &'t self,
        lanes: L,
        rays: &[(Vec3, Vec3)],
        chunk: &[u32],
        t_min: f32,
        t_max: f32,
    ) -> Answers {
        let arrays: Arrays<'_> = self.arrays();
        // The chunk's rays gathered first: in Morton order they lie all over
        // the input, and a loop of independent loads overlaps the misses
        // that the walks would otherwise wait on one by one.
        let rays: Vec<(Vec3, Vec3)> = chunk.iter().map(|&i| rays[i as usize]).collect();
        let mut answers: Vec<Found> = vec![Ok(None); chunk.len()];
        let mut slots: [Option<Slot<'t>>; INTERLEAVED] = Default::default();
        let mut states = [WalkState::<SMALL_STACK>::START; INTERLEAVED];
        let mut next = 0;
        // Gives `slot` the next ray that can be cast (errors are answered at
        // once), or leaves it empty when the chunk is done.
        let mut refill = |slot: &mut Option<Slot<'t>>, state: &mut WalkState<SMALL_STACK>, answers: &mut Vec<Found>| {
            *slot = None;
            while next < chunk.len() {
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
                            search: FirstHit::new(&self.leaves, &far),
                        });
                        return;
                    }
                    Err(error) => answers[k] = Err(error),
                }
            }
        };
        for (slot, state) in slots.iter_mut().zip(&mut states) {
            refill(slot, state, &mut answers);
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
                    answers[s.answer] = Ok(s.search.best.map(|(slot, hit)| (slot, hit, s.far)));
                    refill(slot, state, &mut answers);
                }
            }
            if !running {
                return self.resolve(&answers);
            }
        }
    }
}

impl RayTree {
    /// The answers of the walks' results. Each reads the hit slot's input
    /// index, source and triangle: three cache misses, which the walk would
    /// wait on at its end; here they are asked for [`RESOLVE_AHEAD`]
    /// answers ahead, so that they overlap.
    fn resolve(&self, found: &[Found]) -> Answers {
        let leaves = &self.leaves;
        (0..found.len())
            .map(|k| {
                if let Some(Ok(Some((slot, ..)))) = found.get(k + RESOLVE_AHEAD) {
                    prefetch(&leaves.indices()[*slot]);
                    prefetch(&leaves.sources()[*slot]);
                    prefetch(&leaves.primitives()[*slot]);
                }
                match &found[k] {
                    Ok(hit) => Ok(hit.map(|(slot, hit, far)| hit_answer(leaves, &far, slot, &hit))),
                    Err(error) => Err(error.clone()),
                }
            })
            .collect()
    }
}

/// [`RayTree::interleave`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
struct ChunkTask<'a> {
    tree: &'a RayTree,
    rays: &'a [(Vec3, Vec3)],
    chunk: &'a [u32],
    t_min: f32,
    t_max: f32,
}

#[cfg(target_arch = "x86_64")]
impl crate::wide_tree::Avx2Task for ChunkTask<'_> {
    type Output = Answers;
    #[inline(always)]
    fn call(self, avx2: Avx2) -> Answers {
        self.tree
            .interleave(avx2, self.rays, self.chunk, self.t_min, self.t_max)
    }
}
