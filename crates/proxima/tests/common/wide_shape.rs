//! The shape of a wide tree against the binary tree it was made from, shared
//! by `tests/structures.rs` (the wide tree's invariants in the suite) and
//! `tests/wide.rs`. Included with `#[path = "common/wide_shape.rs"] mod
//! wide_shape;` so that the other test files do not compile it.

use proxima::wide_tree::WideChild;
use proxima::{AabbTree, WideTree};

/// The wide leaves tile the primitive slots. Each is a binary leaf with its
/// box, or, where leaves are tested eight at a time (AVX2, `merged_leaves`),
/// a binary subtree of at most eight primitives with that subtree's root box;
/// every wide node but the root is referenced once.
pub fn check_structure<T>(wide: &WideTree<T>, merged_leaves: bool) {
    let tree = wide.tree();
    // Every binary node's (range, box), leaves and inner nodes alike: an
    // inner node's range runs from its leftmost leaf to its rightmost.
    let mut ranges = vec![None; tree.node_count() + 1]; // index 1 is padding
    fn range_of<T>(tree: &AabbTree<T>, i: usize, ranges: &mut [Option<(usize, usize)>]) -> (usize, usize) {
        let node = tree.node(i);
        let r = if node.is_leaf() {
            (node.primitive_range().start, node.primitive_range().end)
        } else {
            let [a, b] = node.children();
            let (ra, rb) = (range_of(tree, a as usize, ranges), range_of(tree, b as usize, ranges));
            assert_eq!(ra.1, rb.0, "children's slots are contiguous");
            (ra.0, rb.1)
        };
        ranges[i] = Some(r);
        r
    }
    if tree.root().is_some() {
        range_of(tree, 0, &mut ranges);
    }
    let binary: std::collections::HashMap<(usize, usize), (proxima::Aabb, bool)> = tree
        .nodes()
        .map(|(i, n)| (ranges[i].unwrap(), (n.bounds(), n.is_leaf())))
        .collect();
    let mut leaves = Vec::new();
    let mut referenced = vec![0u32; wide.node_count()];
    for (index, node) in wide.nodes().iter().enumerate() {
        let mut lanes = 0;
        for lane in 0..4 {
            match wide.child(index, lane) {
                WideChild::Empty => assert!(node.child_bounds(lane).is_empty()),
                WideChild::Inner(i) => {
                    assert!(i > 0 && i < wide.node_count());
                    referenced[i] += 1;
                    lanes += 1;
                }
                WideChild::Leaf(r) => {
                    let &(bounds, is_leaf) = binary.get(&(r.start, r.end)).expect("a wide leaf is a binary subtree");
                    assert_eq!(bounds, node.child_bounds(lane));
                    assert!(is_leaf || (merged_leaves && r.len() <= 8), "{r:?}");
                    leaves.push(r);
                    lanes += 1;
                }
            }
        }
        // Only a root that is a single leaf has fewer than two children.
        assert!(lanes >= 2 || wide.node_count() == 1);
    }
    assert!(referenced.iter().skip(1).all(|&r| r == 1));
    leaves.sort_by_key(|r| r.start);
    let mut end = 0;
    for r in &leaves {
        assert_eq!(r.start, end, "wide leaves tile the slots");
        end = r.end;
    }
    assert_eq!(end, wide.len());
    assert!(wide.depth() <= tree.depth());
}
