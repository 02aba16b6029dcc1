//! The AABB tree's statistics and invariant checks.

use super::{AabbNode, AabbTree};
use crate::build::{TreeStats, check_structure};
use crate::primitive::Bounded;

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
            std::mem::size_of_val(&self.nodes[..]) + self.leaves.memory_bytes(),
        )
    }

    /// Checks the tree's invariants: every node reachable once; every node's
    /// box holds its children's boxes or its primitives' boxes; the leaves
    /// cover the primitive array exactly once, in order; the recorded depth is
    /// right; `indices` is a permutation. Returns a description of the first
    /// violation.
    pub fn validate(&self) -> Result<(), String> {
        check_structure::<AabbNode>(
            &self.nodes,
            self.len(),
            self.depth,
            self.leaves.indices(),
            |i, ancestors| {
                let n = self.node(i);
                if let Some(&parent) = ancestors.last()
                    && !self.node(parent).bounds().contains(&n.bounds())
                {
                    return Err(format!("node {parent} does not hold child {i}"));
                }
                let outside = n.is_leaf().then(|| {
                    n.primitive_range()
                        .find(|&slot| !n.bounds().contains(&self.leaves.primitives()[slot].bounds()))
                });
                match outside.flatten() {
                    Some(slot) => Err(format!("leaf {i} does not hold primitive slot {slot}")),
                    None => Ok(()),
                }
            },
        )
    }
}
