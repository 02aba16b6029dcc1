//! What a walk hands to the query at its leaves, and where it counts its work.

use crate::math::Vec3A;
use crate::primitive::{TriangleHit, WatertightRay};

/// What a distance query (closest, k-nearest, ...) does at the leaves, and
/// how far it still looks. A structure's
/// [`nearest_walk`](super::NearestQuery::nearest_walk) visits every
/// primitive that may lie within [`bound`](Self::bound), nearest subtrees
/// first, and skips the rest.
pub trait NearestVisitor<T> {
    /// Squared pruning radius, slack included: a node whose bounding volume
    /// lies farther is skipped.
    fn bound(&self) -> f32;
    /// Tests the primitive at leaf-order slot `slot` against the query `p`.
    fn visit(&mut self, slot: usize, primitive: &T, p: Vec3A);
    /// Considers the point `q` at squared distance `d2` of the primitive at
    /// `slot` (of input index `index`), computed elsewhere (several
    /// triangles at a time) exactly as [`visit`](Self::visit) would have.
    fn offer(&mut self, slot: usize, index: u32, q: Vec3A, d2: f32);
}

/// What a ray query does with the primitives of the leaves it reaches.
pub trait RayVisitor<T> {
    /// The end of the parameter range still of interest (a hit shrinks it).
    fn t_hi(&self) -> f32;
    /// Tests the primitive at leaf-order slot `slot`; `true` ends the query.
    fn visit(&mut self, slot: usize, primitive: &T, ray: &WatertightRay, t_min: f32) -> bool;
    /// Considers a hit of the primitive at `slot` computed elsewhere (four
    /// triangles at a time), exactly as [`visit`](Self::visit) would have
    /// found it; `true` ends the query.
    fn offer(&mut self, slot: usize, hit: TriangleHit) -> bool;
}

/// Counts of the work a query did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryStats {
    /// Nodes whose bounding volume was tested (wide trees: wide nodes).
    pub nodes_visited: u64,
    /// Primitives tested.
    pub primitives_tested: u64,
}

/// Where a walk reports its work: [`QueryStats`] counts, the no-op `()`
/// compiles away, so queries without statistics pay nothing for them.
pub trait Counter {
    /// `n` more nodes tested.
    fn nodes(&mut self, n: u64);
    /// `n` more primitives tested.
    fn primitives(&mut self, n: u64);
    /// Takes back `n` primitives counted with their leaf but skipped.
    fn skip_primitives(&mut self, n: u64);
}

impl Counter for () {
    #[inline(always)]
    fn nodes(&mut self, _: u64) {}
    #[inline(always)]
    fn primitives(&mut self, _: u64) {}
    #[inline(always)]
    fn skip_primitives(&mut self, _: u64) {}
}

impl Counter for QueryStats {
    #[inline(always)]
    fn nodes(&mut self, n: u64) {
        self.nodes_visited += n;
    }
    #[inline(always)]
    fn primitives(&mut self, n: u64) {
        self.primitives_tested += n;
    }
    #[inline(always)]
    fn skip_primitives(&mut self, n: u64) {
        self.primitives_tested -= n;
    }
}
