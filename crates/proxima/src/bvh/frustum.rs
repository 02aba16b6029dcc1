//! Frustum queries: every primitive sharing a point with a view frustum.

use super::AabbTree;
use super::config::MAX_DEPTH;
use super::traverse::{Counter, QueryStats};
use crate::frustum::{Cull, Frustum, FrustumOverlap, PlaneMask};

impl<T: FrustumOverlap> AabbTree<T> {
    /// The build-input indices of the primitives overlapping `frustum`
    /// (closed sets: touching counts), sorted ascending: the same set as
    /// [`LinearSearch::frustum`](crate::LinearSearch::frustum).
    ///
    /// ```
    /// use proxima::frustum::Frustum;
    /// use proxima::{AabbTree, Point, Vec3};
    /// let points: Vec<Point> = (0..10).map(|i| Point(Vec3::new(0.0, 0.0, -(i as f32)))).collect();
    /// let tree = AabbTree::build(points, &Default::default()).unwrap();
    /// let camera = Frustum::look_at(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 1.0, 1.5, 5.5).unwrap();
    /// assert_eq!(tree.frustum(&camera), [2, 3, 4, 5]);
    /// ```
    pub fn frustum(&self, frustum: &Frustum) -> Vec<u32> {
        let mut out = Vec::new();
        self.frustum_counted(frustum, &mut out, &mut ());
        out
    }

    /// [`frustum`](Self::frustum) into a caller-owned vector (cleared first),
    /// so a loop of queries allocates only while the vector grows.
    pub fn frustum_into(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        self.frustum_counted(frustum, out, &mut ());
    }

    /// [`frustum`](Self::frustum), also counting the nodes classified and the
    /// primitives tested exactly (primitives of subtrees entirely inside are
    /// reported without a test).
    pub fn frustum_with_stats(&self, frustum: &Frustum) -> (Vec<u32>, QueryStats) {
        let mut out = Vec::new();
        let mut stats = QueryStats::default();
        self.frustum_counted(frustum, &mut out, &mut stats);
        (out, stats)
    }

    /// Depth first with a fixed stack of `(node, planes still to test)`. A
    /// node inside every plane hands over its whole subtree at once: the
    /// build lays a subtree's primitives out contiguously, so that is the
    /// range from its leftmost to its rightmost leaf.
    fn frustum_counted<C: Counter>(&self, frustum: &Frustum, out: &mut Vec<u32>, counter: &mut C) {
        out.clear();
        let Some(root) = self.root() else { return };
        counter.nodes(1);
        let mut mask = match frustum.classify_box(&root.bounds(), PlaneMask::ALL) {
            Cull::Outside => return,
            Cull::Inside => {
                out.extend_from_slice(&self.indices);
                out.sort_unstable();
                return;
            }
            Cull::Partial(mask) => mask,
        };
        // One entry per level at most: each inner node on the path pushes one child.
        let mut stack = [(0u32, PlaneMask::NONE); MAX_DEPTH as usize + 1];
        let mut top = 0usize;
        let mut node = 0usize;
        loop {
            let n = self.node(node);
            if n.is_leaf() {
                let range = n.primitive_range();
                counter.primitives(range.len() as u64);
                for slot in range {
                    if self.primitives[slot].overlaps_frustum(frustum) {
                        out.push(self.indices[slot]);
                    }
                }
            } else {
                let [left, right] = n.children();
                let pair = self.children_of(n);
                counter.nodes(2);
                let mut next = None;
                for (child, child_node) in [(left, &pair[0]), (right, &pair[1])] {
                    match frustum.classify_box(&child_node.bounds(), mask) {
                        Cull::Outside => {}
                        Cull::Inside => out.extend_from_slice(&self.indices[self.subtree_slots(child as usize)]),
                        Cull::Partial(child_mask) => {
                            if next.is_none() {
                                next = Some((child, child_mask));
                            } else {
                                stack[top] = (child, child_mask);
                                top += 1;
                            }
                        }
                    }
                }
                if let Some((child, child_mask)) = next {
                    node = child as usize;
                    mask = child_mask;
                    continue;
                }
            }
            if top == 0 {
                break;
            }
            top -= 1;
            (node, mask) = (stack[top].0 as usize, stack[top].1);
        }
        out.sort_unstable();
    }

    /// The leaf-order slots of the subtree under `node`: from its leftmost
    /// leaf's first slot to its rightmost leaf's last.
    fn subtree_slots(&self, node: usize) -> std::ops::Range<usize> {
        let mut first = self.node(node);
        while !first.is_leaf() {
            first = self.node(first.children()[0] as usize);
        }
        let mut last = self.node(node);
        while !last.is_leaf() {
            last = self.node(last.children()[1] as usize);
        }
        first.primitive_range().start..last.primitive_range().end
    }
}
