//! Statistics and invariant checks.

use super::AabbTree;
use crate::primitive::Bounded;

/// Shape of a built tree.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TreeStats {
    /// Number of primitives.
    pub primitives: usize,
    /// Number of nodes (inner and leaves).
    pub nodes: usize,
    /// Number of leaves.
    pub leaves: usize,
    /// Depth of the deepest leaf (root = 0).
    pub depth: u32,
    /// Fewest primitives in a leaf.
    pub min_leaf_size: usize,
    /// Most primitives in a leaf.
    pub max_leaf_size: usize,
    /// Mean primitives per leaf.
    pub mean_leaf_size: f64,
    /// Bytes used by nodes, primitives and index arrays.
    pub memory_bytes: usize,
}

impl TreeStats {
    /// The statistics of a tree with these leaf sizes (shared by the trees
    /// with the same layout).
    pub(crate) fn of(
        leaf_sizes: impl Iterator<Item = usize>,
        primitives: usize,
        nodes: usize,
        depth: u32,
        memory_bytes: usize,
    ) -> Self {
        let (mut leaves, mut min_leaf_size, mut max_leaf_size) = (0, usize::MAX, 0);
        for size in leaf_sizes {
            leaves += 1;
            min_leaf_size = min_leaf_size.min(size);
            max_leaf_size = max_leaf_size.max(size);
        }
        TreeStats {
            primitives,
            nodes,
            leaves,
            depth,
            min_leaf_size: if leaves == 0 { 0 } else { min_leaf_size },
            max_leaf_size,
            mean_leaf_size: if leaves == 0 {
                0.0
            } else {
                primitives as f64 / leaves as f64
            },
            memory_bytes,
        }
    }
}

impl<T: Bounded> AabbTree<T> {
    /// Counts nodes, leaves and leaf sizes.
    pub fn stats(&self) -> TreeStats {
        TreeStats::of(
            self.nodes()
                .filter(|(_, n)| n.is_leaf())
                .map(|(_, n)| n.primitive_range().len()),
            self.len(),
            self.node_count(),
            self.depth,
            std::mem::size_of_val(&self.nodes[..])
                + std::mem::size_of_val(&self.primitives[..])
                + 4 * (self.indices.len() + self.sources.len()),
        )
    }

    /// Checks the tree's invariants: every node reachable once; every node's
    /// box holds its children's boxes or its primitives' boxes; the leaves
    /// cover the primitive array exactly once, in order; the recorded depth is
    /// right; `indices` is a permutation. Returns a description of the first
    /// violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.nodes.is_empty() {
            return if self.primitives.is_empty() {
                Ok(())
            } else {
                Err("primitives without nodes".into())
            };
        }
        let mut covered = vec![false; self.primitives.len()];
        let flat = 2 * self.nodes.len();
        let mut seen = vec![false; flat];
        seen[1] = true; // padding
        let mut stack = vec![(0usize, 0u32)];
        let mut max_depth = 0;
        while let Some((i, depth)) = stack.pop() {
            if std::mem::replace(&mut seen[i], true) {
                return Err(format!("node {i} reached twice"));
            }
            max_depth = max_depth.max(depth);
            let n = self.node(i);
            if n.is_leaf() {
                for slot in n.primitive_range() {
                    let Some(c) = covered.get_mut(slot) else {
                        return Err(format!("leaf {i} past the end"));
                    };
                    if std::mem::replace(c, true) {
                        return Err(format!("primitive slot {slot} in two leaves"));
                    }
                    if !n.bounds().contains(&self.primitives[slot].bounds()) {
                        return Err(format!("leaf {i} does not hold primitive slot {slot}"));
                    }
                }
            } else {
                for c in n.children() {
                    let c = c as usize;
                    if c >= flat || !n.children()[0].is_multiple_of(2) || !n.bounds().contains(&self.node(c).bounds()) {
                        return Err(format!("node {i} does not hold child {c}"));
                    }
                    stack.push((c, depth + 1));
                }
            }
        }
        if let Some(slot) = covered.iter().position(|c| !c) {
            return Err(format!("primitive slot {slot} in no leaf"));
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return Err(format!("node {i} unreachable"));
        }
        if max_depth != self.depth {
            return Err(format!("depth is {max_depth}, recorded {}", self.depth));
        }
        let mut perm = self.indices.clone();
        perm.sort_unstable();
        if perm.iter().enumerate().any(|(i, &v)| v as usize != i) {
            return Err("indices are not a permutation".into());
        }
        Ok(())
    }
}
