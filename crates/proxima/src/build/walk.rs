//! The one walk of a binary tree, behind its distance and ray queries.
//!
//! Depth-first, the child of smaller key first, with a fixed stack: the
//! nearer child is descended at once and the farther one is kept with its
//! key, so that when it is popped it can be dropped if the query's bound has
//! shrunk meanwhile. The key is what the query orders and prunes by: the
//! squared distance from the query point to the node's volume, or the
//! parameter at which a ray enters its box.

use super::config::MAX_DEPTH;
use crate::math::Vec3A;
use crate::memory::prefetch;
use crate::query::{Counter, NearestVisitor};
use std::ops::{ControlFlow, Range};

/// A node of a binary tree stored as sibling pairs (flat node `i` at
/// `pairs[i / 2][i % 2]`, an inner node's children at `first_child` and
/// `first_child + 1`): what [`nearest_walk`] needs to walk it. The AABB tree
/// and the sphere tree differ only in their bounding volume.
pub(crate) trait PairedNode: Sized {
    /// The pair type the tree stores.
    type Pair: AsRef<[Self; 2]>;
    /// `true` for a leaf.
    fn is_leaf(&self) -> bool;
    /// For a leaf, its range of leaf-order primitive slots.
    fn primitive_range(&self) -> std::ops::Range<usize>;
    /// For an inner node, the flat index of its first child (even).
    fn first_child(&self) -> u32;
    /// A lower bound of the squared distance from `p` to anything the node holds.
    fn distance_squared(&self, p: Vec3A) -> f32;
    /// Where the node's volume lies against the planes of `frustum` still in `mask`.
    fn classify(&self, frustum: &crate::frustum::Frustum, mask: crate::frustum::PlaneMask) -> crate::frustum::Cull;
}

/// What the walk of a binary tree asks of the query it serves.
pub(crate) trait BinaryQuery<N> {
    /// `true`: touch the grandchildren of both children at each step (their
    /// misses then overlap with the step's work; distance queries, which
    /// visit most of them). `false`: prefetch only what the crossed children
    /// hold (rays, which mostly never visit the rest).
    const TOUCH_GRANDCHILDREN: bool;
    /// The node's key: a lower bound of what it can give the query; NaN or
    /// above [`bound`](Self::bound) when it can give nothing.
    fn key(&self, node: &N) -> f32;
    /// Nodes of larger key are skipped.
    fn bound(&self) -> f32;
    /// Tests the primitives of the leaf-order slots `range`; `Break` ends the walk.
    fn leaf(&mut self, range: Range<usize>) -> ControlFlow<()>;
    /// Starts loading the first primitives of a leaf about to be visited.
    #[inline(always)]
    fn prefetch_leaf(&self, _range: Range<usize>) {}
}

/// Walks the tree stored as `pairs` (see the module notes). Each inner node
/// on the current path pushes at most one entry, so a tree whose deepest
/// leaf is at `depth` needs `depth + 1` entries: trees less deep than 32
/// (all but extreme ones) get a stack of 32, cheaper to set up than the
/// full `MAX_DEPTH + 1`.
#[inline(always)]
pub(crate) fn walk<N: PairedNode, Q: BinaryQuery<N>, C: Counter>(
    pairs: &[N::Pair],
    depth: u32,
    query: &mut Q,
    counter: &mut C,
) {
    if depth < SHALLOW as u32 {
        walk_with::<N, Q, C, SHALLOW>(pairs, query, counter);
    } else {
        walk_with::<N, Q, C, { MAX_DEPTH as usize + 1 }>(pairs, query, counter);
    }
}

/// Trees less deep than this walk with a stack of this many entries.
const SHALLOW: usize = 32;

#[inline(always)]
fn walk_with<N: PairedNode, Q: BinaryQuery<N>, C: Counter, const STACK: usize>(
    pairs: &[N::Pair],
    query: &mut Q,
    counter: &mut C,
) {
    let Some(root) = pairs.first().map(|pair| &pair.as_ref()[0]) else {
        return;
    };
    let children_of = |n: &N| pairs[(n.first_child() >> 1) as usize].as_ref();
    counter.nodes(1);
    // A NaN key (a NaN query) visits nothing.
    let key = query.key(root);
    if key.is_nan() || key > query.bound() {
        return;
    }
    let mut stack = [(0u32, 0f32); STACK];
    let mut top = 0usize;
    let mut node = 0usize;
    loop {
        let n = &pairs[node >> 1].as_ref()[node & 1];
        if n.is_leaf() {
            let range = n.primitive_range();
            counter.primitives(range.len() as u64);
            if query.leaf(range).is_break() {
                return;
            }
        } else {
            let left = n.first_child();
            let right = left + 1;
            let pair = children_of(n);
            if Q::TOUCH_GRANDCHILDREN {
                // Ask for the grandchild pairs now, so that their cache misses
                // overlap with this step's work instead of following it.
                for child in pair {
                    if !child.is_leaf() {
                        prefetch(children_of(child));
                    }
                }
            }
            let kl = query.key(&pair[0]);
            let kr = query.key(&pair[1]);
            counter.nodes(2);
            let bound = query.bound();
            if !Q::TOUCH_GRANDCHILDREN {
                for (child, key) in [(&pair[0], kl), (&pair[1], kr)] {
                    if key <= bound {
                        if child.is_leaf() {
                            query.prefetch_leaf(child.primitive_range());
                        } else {
                            prefetch(children_of(child));
                        }
                    }
                }
            }
            let (near, k_near, far, k_far) = if kl <= kr {
                (left, kl, right, kr)
            } else {
                (right, kr, left, kl)
            };
            if k_near <= bound {
                if k_far <= bound {
                    stack[top] = (far, k_far);
                    top += 1;
                }
                node = near as usize;
                continue;
            }
        }
        // Pop the next subtree still within reach.
        loop {
            if top == 0 {
                return;
            }
            top -= 1;
            let (next, key) = stack[top];
            if key <= query.bound() {
                node = next as usize;
                break;
            }
        }
    }
}

/// A distance query on a binary tree: keys are squared distances to the
/// node volumes; each leaf's primitives go to the visitor.
pub(crate) struct Nearest<'a, T, V> {
    pub(crate) p: Vec3A,
    pub(crate) primitives: &'a [T],
    pub(crate) visitor: &'a mut V,
}

impl<N: PairedNode, T, V: NearestVisitor<T>> BinaryQuery<N> for Nearest<'_, T, V> {
    const TOUCH_GRANDCHILDREN: bool = true;
    #[inline(always)]
    fn key(&self, node: &N) -> f32 {
        node.distance_squared(self.p)
    }
    #[inline(always)]
    fn bound(&self) -> f32 {
        self.visitor.bound()
    }
    #[inline(always)]
    fn leaf(&mut self, range: Range<usize>) -> ControlFlow<()> {
        for slot in range {
            self.visitor.visit(slot, &self.primitives[slot], self.p);
        }
        ControlFlow::Continue(())
    }
}

/// [`walk`] with a [`Nearest`] query: what a binary tree's
/// [`nearest_walk`](crate::query::NearestQuery::nearest_walk) is.
#[inline(always)]
pub(crate) fn nearest_walk<N: PairedNode, T, V: NearestVisitor<T>, C: Counter>(
    pairs: &[N::Pair],
    depth: u32,
    primitives: &[T],
    p: Vec3A,
    visitor: &mut V,
    counter: &mut C,
) {
    walk::<N, _, C>(pairs, depth, &mut Nearest { p, primitives, visitor }, counter);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::Aabb;
    use crate::build::{BuildConfig, Node, build_hierarchy};
    use crate::math::Vec3;
    use crate::query::{Best, QueryStats};

    /// The small stack and the full one make the same walk (real trees are
    /// too shallow to reach the full one, so it is tested directly).
    #[test]
    fn small_and_full_stacks_walk_alike() {
        let triangles = crate::sample::small_triangles(3000, 9);
        let mut rng = crate::sample::Rng::new(109);
        let mut v = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let sources = (0..triangles.len() as u32).collect();
        let tree = build_hierarchy(triangles, sources, &BuildConfig::default()).unwrap();
        assert!(tree.depth < SHALLOW as u32);
        let leaves = &tree.leaves;
        for _ in 0..500 {
            let p = Vec3A::from(v() * 1.5);
            let mut small = Best::new(leaves.indices(), f32::INFINITY);
            let mut full = Best::new(leaves.indices(), f32::INFINITY);
            let (mut small_stats, mut full_stats) = (QueryStats::default(), QueryStats::default());
            let primitives = leaves.primitives();
            walk_with::<Node<Aabb>, _, _, SHALLOW>(
                &tree.nodes,
                &mut Nearest {
                    p,
                    primitives,
                    visitor: &mut small,
                },
                &mut small_stats,
            );
            walk_with::<Node<Aabb>, _, _, { MAX_DEPTH as usize + 1 }>(
                &tree.nodes,
                &mut Nearest {
                    p,
                    primitives,
                    visitor: &mut full,
                },
                &mut full_stats,
            );
            assert!(small.found && full.found);
            assert_eq!(
                (small.slot, small.point, small.distance_squared),
                (full.slot, full.point, full.distance_squared)
            );
            assert_eq!(small_stats, full_stats);
        }
    }
}
