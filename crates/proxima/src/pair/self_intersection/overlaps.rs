//! The walk of one unmoved 4-wide tree against itself: every unordered pair
//! of leaves whose boxes overlap (closed boxes: touching counts), a leaf
//! with itself included, each met once.
//!
//! The tree's boxes hold their subtrees' triangles, so two triangles whose
//! closed boxes overlap lie under child pairs whose boxes overlap all the
//! way down: comparing the stored `f32` boxes drops no pair, and needs no
//! padding (the general walk, [`descent`](super::super::descent), moves
//! boxes by a pose and must pad them).

use crate::wide_tree::{WideChild, WideNode};
use crate::{Aabb, Triangle, WideTree};
use std::ops::{ControlFlow, Range};
use wide::f32x4;

/// What the walk does with each pair of leaves it reaches.
pub(super) trait LeafVisitor {
    /// The slots of two leaves whose boxes overlap; `same` when they are one
    /// leaf (then each unordered pair of its slots is to be met once).
    fn leaves(&mut self, a: Range<usize>, b: Range<usize>, same: bool) -> ControlFlow<()>;
}

/// A subtree: a wide node, or a leaf's slots.
#[derive(Clone, Copy, Debug)]
enum Part {
    Node(u32),
    Leaf(u32, u32),
}

/// A pair of subtrees whose boxes overlap, waiting to be opened.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pending {
    a: Part,
    a_box: Aabb,
    b: Part,
    b_box: Aabb,
    /// `a` and `b` are the same subtree.
    same: bool,
}

/// The self-walk of one tree.
pub(super) struct SelfOverlaps<'t> {
    tree: &'t WideTree<Triangle>,
}

impl<'t> SelfOverlaps<'t> {
    /// The walk of `tree` against itself.
    pub(super) fn new(tree: &'t WideTree<Triangle>) -> Self {
        Self { tree }
    }

    /// At least `tasks` independent pending pairs (fewer when the tree runs
    /// out) that together lead to every overlapping leaf pair once.
    pub(super) fn split(&self, tasks: usize) -> Vec<Pending> {
        use crate::query::SpatialIndex;
        if self.tree.nodes().is_empty() {
            return Vec::new();
        }
        let root = self.tree.bounds();
        let mut queue = std::collections::VecDeque::from([Pending {
            a: Part::Node(0),
            a_box: root,
            b: Part::Node(0),
            b_box: root,
            same: true,
        }]);
        let mut done = Vec::new();
        let mut opened = Vec::new();
        while queue.len() < tasks {
            let Some(next) = queue.pop_front() else { break };
            if let (Part::Leaf(..), Part::Leaf(..)) = (next.a, next.b) {
                done.push(next);
                continue;
            }
            let _ = self.open(next, &mut opened, &mut NoLeaves);
            queue.extend(opened.drain(..));
        }
        queue.extend(done);
        queue.into()
    }

    /// Walks every overlapping pair under `task`, `stack` as scratch.
    pub(super) fn run<V: LeafVisitor>(
        &self,
        task: Pending,
        stack: &mut Vec<Pending>,
        visitor: &mut V,
    ) -> ControlFlow<()> {
        stack.clear();
        stack.push(task);
        while let Some(next) = stack.pop() {
            self.open(next, stack, visitor)?;
        }
        ControlFlow::Continue(())
    }

    /// Opens one pair: its overlapping child pairs go on `stack`; two leaves
    /// go to the visitor.
    fn open<V: LeafVisitor>(&self, next: Pending, stack: &mut Vec<Pending>, visitor: &mut V) -> ControlFlow<()> {
        let nodes = self.tree.nodes();
        match (next.a, next.b) {
            (Part::Leaf(fa, na), Part::Leaf(fb, nb)) => {
                let range = |first: u32, len: u32| first as usize..(first + len) as usize;
                return visitor.leaves(range(fa, na), range(fb, nb), next.same);
            }
            (Part::Node(na), Part::Node(nb)) => {
                let node_a = &nodes[na as usize];
                let node_b = &nodes[nb as usize];
                for j in 0..4 {
                    let Some(b) = self.part(nb, j) else { continue };
                    let b_box = node_b.child_bounds(j);
                    let mut mask = overlapping(node_a, &b_box);
                    if next.same {
                        // One node with itself: child i with child j once, i <= j.
                        mask &= (2u32 << j) - 1;
                    }
                    while mask != 0 {
                        let i = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let Some(a) = self.part(na, i) else { continue };
                        stack.push(Pending {
                            a,
                            a_box: node_a.child_bounds(i),
                            b,
                            b_box,
                            same: next.same && i == j,
                        });
                    }
                }
            }
            (Part::Node(na), Part::Leaf(..)) => {
                let node_a = &nodes[na as usize];
                self.push_children(na, node_a, &next.b_box, stack, |a, a_box| Pending { a, a_box, ..next });
            }
            (Part::Leaf(..), Part::Node(nb)) => {
                let node_b = &nodes[nb as usize];
                self.push_children(nb, node_b, &next.a_box, stack, |b, b_box| Pending { b, b_box, ..next });
            }
        }
        ControlFlow::Continue(())
    }

    /// Pushes `make(child, its box)` for each child of `node` whose box
    /// overlaps `other`.
    #[inline]
    fn push_children(
        &self,
        index: u32,
        node: &WideNode,
        other: &Aabb,
        stack: &mut Vec<Pending>,
        make: impl Fn(Part, Aabb) -> Pending,
    ) {
        let mut mask = overlapping(node, other);
        while mask != 0 {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if let Some(part) = self.part(index, i) {
                stack.push(make(part, node.child_bounds(i)));
            }
        }
    }

    /// What lane `lane` of node `node` holds (`None` when empty).
    #[inline]
    fn part(&self, node: u32, lane: usize) -> Option<Part> {
        match self.tree.child(node as usize, lane) {
            WideChild::Empty => None,
            WideChild::Inner(i) => Some(Part::Node(i as u32)),
            WideChild::Leaf(range) => Some(Part::Leaf(range.start as u32, range.len() as u32)),
        }
    }
}

/// The lanes of `node` whose closed boxes overlap `other`, as a bit mask
/// (an empty lane's box, `min = +inf`, overlaps nothing).
#[inline]
fn overlapping(node: &WideNode, other: &Aabb) -> u32 {
    let axis = |min: [f32; 4], max: [f32; 4], lo: f32, hi: f32| {
        f32x4::new(min).simd_le(f32x4::splat(hi)) & f32x4::splat(lo).simd_le(f32x4::new(max))
    };
    let both = axis(node.min_x, node.max_x, other.min.x, other.max.x)
        & axis(node.min_y, node.max_y, other.min.y, other.max.y)
        & axis(node.min_z, node.max_z, other.min.z, other.max.z);
    both.to_bitmask()
}

/// A visitor for splitting, which never reaches leaves' pairs (they are
/// kept as tasks).
struct NoLeaves;

impl LeafVisitor for NoLeaves {
    fn leaves(&mut self, _: Range<usize>, _: Range<usize>, _: bool) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}
