//! The primitives of a structure in leaf order, with where each came from.

use super::ClosestHit;
use crate::error::BuildError;
use crate::math::Vec3A;
use crate::memory::prefetch;
use crate::primitive::PrimitiveSet;
use rayon::prelude::*;

/// The primitives of a tree in leaf order (each leaf a contiguous range of
/// slots), with for each slot its position in the build input and the mesh
/// element it came from. Every structure keeps one, and every answer is made
/// from it, so the fields of an answer mean the same whichever structure gave it.
#[derive(Clone, Debug, Default)]
pub struct Leaves<T> {
    primitives: Vec<T>,
    /// `indices[slot]`: position in the build input of `primitives[slot]`.
    indices: Vec<u32>,
    /// `sources[slot]`: the mesh element `primitives[slot]` came from.
    sources: Vec<u32>,
}

impl<T> Leaves<T> {
    /// Primitives already in leaf order, with their input indices and
    /// sources; the three have the same length.
    pub(crate) fn new(primitives: Vec<T>, indices: Vec<u32>, sources: Vec<u32>) -> Self {
        debug_assert!(primitives.len() == indices.len() && indices.len() == sources.len());
        Self {
            primitives,
            indices,
            sources,
        }
    }

    /// Puts in every slot the primitive of `set` of the slot's input index:
    /// the same primitives, moved (a refit). Fails with
    /// [`BuildError::RefitMismatch`] unless `set` holds as many primitives
    /// as the slots, each from the source the slot's came from; nothing is
    /// changed then.
    pub(crate) fn refill(&mut self, set: &PrimitiveSet<T>) -> Result<(), BuildError>
    where
        T: Copy + Send + Sync,
    {
        let mismatch = |slot| BuildError::RefitMismatch {
            primitives: set.primitives.len(),
            tree: self.primitives.len(),
            slot,
        };
        if set.primitives.len() != self.primitives.len() || set.sources.len() != set.primitives.len() {
            return Err(mismatch(None));
        }
        let (indices, sources) = (&self.indices, &self.sources);
        if let Some(slot) = (0..indices.len())
            .into_par_iter()
            .find_first(|&slot| set.sources[indices[slot] as usize] != sources[slot])
        {
            return Err(mismatch(Some(slot)));
        }
        self.refill_trusted(set);
        Ok(())
    }

    /// [`refill`](Self::refill) for a `set` known to match (extracted
    /// from the same faces, whose primitives do not depend on the
    /// positions), without the check.
    pub(crate) fn refill_trusted(&mut self, set: &PrimitiveSet<T>)
    where
        T: Copy + Send + Sync,
    {
        debug_assert_eq!(set.primitives.len(), self.primitives.len());
        self.refill_by(|input, _| set.primitives[input as usize]);
    }

    /// Puts in every slot `primitive(input, source)` of the slot's build
    /// input index and source: the primitive moved, read wherever the
    /// caller keeps it (a mesh's faces, without extracting them again).
    pub(crate) fn refill_by(&mut self, primitive: impl Fn(u32, u32) -> T + Sync)
    where
        T: Send,
    {
        self.primitives
            .par_iter_mut()
            .zip(self.indices.par_iter().zip(self.sources.par_iter()))
            .with_min_len(4096)
            .for_each(|(slot, (&input, &source))| *slot = primitive(input, source));
    }

    /// The primitives in leaf order.
    #[inline(always)]
    pub fn primitives(&self) -> &[T] {
        &self.primitives
    }

    /// The build-input index of each slot.
    #[inline(always)]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// The source (vertex, edge or face index) of each slot.
    #[inline(always)]
    pub fn sources(&self) -> &[u32] {
        &self.sources
    }

    /// Number of primitives.
    #[inline]
    pub fn len(&self) -> usize {
        self.primitives.len()
    }

    /// `true` when there is no primitive.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.primitives.is_empty()
    }

    /// Bytes of the three arrays.
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of_val(&self.primitives[..]) + 4 * (self.indices.len() + self.sources.len())
    }

    /// The answer for the point `point` at squared distance `distance_squared`
    /// of the primitive at `slot`, whose input index is `primitive` (the
    /// walk knows it from the packet: reading it again from the index array
    /// was a cache miss per query on large meshes).
    #[inline]
    pub(crate) fn hit(&self, slot: usize, primitive: u32, point: Vec3A, distance_squared: f32) -> ClosestHit {
        debug_assert_eq!(primitive, self.indices[slot]);
        ClosestHit {
            primitive,
            source: self.sources[slot],
            point: point.into(),
            distance: distance_squared.sqrt(),
        }
    }

    /// Replaces the slot that each answer of `hits` holds in `source` by
    /// the slot's source. Looked up at the end of each query, the source was
    /// a cache miss that the query waited on; here, prefetched a few answers
    /// ahead, the misses of many queries overlap.
    pub(crate) fn resolve_sources(&self, hits: &mut [Option<ClosestHit>]) {
        const AHEAD: usize = 8;
        for k in 0..hits.len() {
            if let Some(Some(ahead)) = hits.get(k + AHEAD) {
                prefetch(&self.sources[ahead.source as usize]);
            }
            if let Some(hit) = &mut hits[k] {
                hit.source = self.sources[hit.source as usize];
            }
        }
    }

    /// `true` when no two primitives share a source (vertices, edges, the
    /// faces of a triangle mesh): the k nearest primitives are then the k
    /// nearest sources. Found in one pass over the sources in input order,
    /// which are increasing for every set a [`Mesh`](crate::Mesh) gives; a
    /// set in another order is taken as sharing (the answers stay right,
    /// [`NearestQuery::k_nearest_sources_batch`](super::NearestQuery::k_nearest_sources_batch)
    /// only does more work).
    pub fn one_part_each(&self) -> bool {
        let mut by_input = vec![0u32; self.len()];
        for (&input, &source) in self.indices.iter().zip(&self.sources) {
            by_input[input as usize] = source;
        }
        by_input.windows(2).all(|pair| pair[0] < pair[1])
    }

    /// The sources of the primitives whose input indices are `inputs`,
    /// increasing and without repeats (a face split in several parts is
    /// listed once).
    pub fn sources_of_inputs(&self, inputs: &[u32]) -> Vec<u32> {
        let mut found = vec![false; self.len()];
        for &input in inputs {
            found[input as usize] = true;
        }
        let mut sources: Vec<u32> = (self.indices.iter().zip(&self.sources))
            .filter(|&(&input, _)| found[input as usize])
            .map(|(_, &source)| source)
            .collect();
        sources.sort_unstable();
        sources.dedup();
        sources
    }
}
