//! The shape and the structural invariants of a binary hierarchy stored as
//! sibling pairs, whatever its bounding volume: statistics, and the checks
//! every such tree's `validate` starts from.

use super::walk::PairedNode;

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

/// Checks what every tree stored as sibling pairs must satisfy, and calls
/// `check(node, ancestors)` on every node (`ancestors` root first): every
/// node reachable once, children at an even index inside the array, the
/// leaves covering `0..primitives` exactly once, the recorded depth right,
/// `indices` a permutation. Shared by the AABB and sphere trees.
pub(crate) fn check_structure<N: PairedNode>(
    pairs: &[N::Pair],
    primitives: usize,
    depth: u32,
    indices: &[u32],
    mut check: impl FnMut(usize, &[usize]) -> Result<(), String>,
) -> Result<(), String> {
    if pairs.is_empty() {
        return if primitives == 0 {
            Ok(())
        } else {
            Err("primitives without nodes".into())
        };
    }
    let mut covered = vec![false; primitives];
    let flat = 2 * pairs.len();
    let mut seen = vec![false; flat];
    seen[1] = true; // padding
    // Depth-first: when a node is popped, the path holds exactly its ancestors.
    let mut stack = vec![(0usize, 0u32)];
    let mut path: Vec<usize> = Vec::new();
    let mut max_depth = 0;
    while let Some((i, node_depth)) = stack.pop() {
        path.truncate(node_depth as usize);
        if std::mem::replace(&mut seen[i], true) {
            return Err(format!("node {i} reached twice"));
        }
        max_depth = max_depth.max(node_depth);
        let n = &pairs[i >> 1].as_ref()[i & 1];
        if n.is_leaf() {
            for slot in n.primitive_range() {
                let Some(c) = covered.get_mut(slot) else {
                    return Err(format!("leaf {i} past the end"));
                };
                if std::mem::replace(c, true) {
                    return Err(format!("primitive slot {slot} in two leaves"));
                }
            }
            check(i, &path)?;
        } else {
            let first = n.first_child() as usize;
            if first + 1 >= flat || !first.is_multiple_of(2) {
                return Err(format!("node {i} has bad children {first}, {}", first + 1));
            }
            check(i, &path)?;
            path.push(i);
            stack.push((first, node_depth + 1));
            stack.push((first + 1, node_depth + 1));
        }
    }
    if let Some(slot) = covered.iter().position(|c| !c) {
        return Err(format!("primitive slot {slot} in no leaf"));
    }
    if let Some(i) = seen.iter().position(|s| !s) {
        return Err(format!("node {i} unreachable"));
    }
    if max_depth != depth {
        return Err(format!("depth is {max_depth}, recorded {depth}"));
    }
    let mut perm = indices.to_vec();
    perm.sort_unstable();
    if perm.iter().enumerate().any(|(i, &v)| v as usize != i) {
        return Err("indices are not a permutation".into());
    }
    Ok(())
}
