//! The frustum walk of the binary trees: every primitive sharing a point
//! with a view frustum.

use super::config::MAX_DEPTH;
use super::walk::PairedNode;
use crate::frustum::{Cull, Frustum, FrustumOverlap, PlaneMask};
use crate::query::Counter;

/// The frustum query of a tree stored as sibling pairs (the AABB tree and the
/// sphere tree share it; only the node classification differs).
///
/// Depth first with a fixed stack of `(node, planes still to test)`. A node
/// inside every plane hands over its whole subtree at once: the build lays a
/// subtree's primitives out contiguously, so that is the range from its
/// leftmost to its rightmost leaf.
pub(crate) fn frustum_walk<N: PairedNode, T: FrustumOverlap, C: Counter>(
    pairs: &[N::Pair],
    primitives: &[T],
    indices: &[u32],
    frustum: &Frustum,
    out: &mut Vec<u32>,
    counter: &mut C,
) {
    out.clear();
    let node_at = |i: usize| &pairs[i >> 1].as_ref()[i & 1];
    if pairs.is_empty() {
        return;
    }
    counter.nodes(1);
    let mut mask = match node_at(0).classify(frustum, PlaneMask::ALL) {
        Cull::Outside => return,
        Cull::Inside => {
            out.extend_from_slice(indices);
            sort_indices(out, indices.len());
            return;
        }
        Cull::Partial(mask) => mask,
    };
    // One entry per level at most: each inner node on the path pushes one child.
    let mut stack = [(0u32, PlaneMask::NONE); MAX_DEPTH as usize + 1];
    let mut top = 0usize;
    let mut node = 0usize;
    loop {
        let n = node_at(node);
        if n.is_leaf() {
            let range = n.primitive_range();
            counter.primitives(range.len() as u64);
            for slot in range {
                if primitives[slot].overlaps_frustum(frustum) {
                    out.push(indices[slot]);
                }
            }
        } else {
            let left = n.first_child();
            let pair = pairs[(left >> 1) as usize].as_ref();
            counter.nodes(2);
            let mut next = None;
            for (child, child_node) in [(left, &pair[0]), (left + 1, &pair[1])] {
                match child_node.classify(frustum, mask) {
                    Cull::Outside => {}
                    Cull::Inside => out.extend_from_slice(&indices[subtree_slots::<N>(pairs, child as usize)]),
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
    sort_indices(out, indices.len());
}

/// The leaf-order slots of the subtree under `node`: from its leftmost leaf's
/// first slot to its rightmost leaf's last.
fn subtree_slots<N: PairedNode>(pairs: &[N::Pair], node: usize) -> std::ops::Range<usize> {
    let node_at = |i: usize| &pairs[i >> 1].as_ref()[i & 1];
    let mut first = node_at(node);
    while !first.is_leaf() {
        first = node_at(first.first_child() as usize);
    }
    let mut last = node_at(node);
    while !last.is_leaf() {
        last = node_at(last.first_child() as usize + 1);
    }
    first.primitive_range().start..last.primitive_range().end
}

/// Digits of the radix sort: 2^11 counters fit in 8 KB of stack.
const RADIX_BITS: u32 = 11;

/// Sorts `out` (values below `bound`) ascending. The traversal reports
/// primitives in leaf order, and sorting that list with `sort_unstable` was
/// most of the query time on large answers (docs/perf-log.md); a
/// least-significant-digit radix sort takes one pass per
/// 11 bits of `bound` (two for the dragon) and uses the second half of the
/// vector itself as scratch, so a reused vector does not allocate.
fn sort_indices(out: &mut Vec<u32>, bound: usize) {
    let len = out.len();
    if len < 1024 {
        out.sort_unstable();
        return;
    }
    let bits = usize::BITS - bound.saturating_sub(1).max(1).leading_zeros();
    let passes = bits.div_ceil(RADIX_BITS);
    out.resize(2 * len, 0);
    for pass in 0..passes {
        let (first, second) = out.split_at_mut(len);
        let shift = pass * RADIX_BITS;
        if pass % 2 == 0 {
            radix_pass(first, second, shift);
        } else {
            radix_pass(second, first, shift);
        }
    }
    if passes % 2 == 1 {
        out.copy_within(len.., 0);
    }
    out.truncate(len);
}

/// One stable counting-sort pass of `source` into `target` on the digit at `shift`.
fn radix_pass(source: &[u32], target: &mut [u32], shift: u32) {
    let digit = |v: u32| ((v >> shift) & ((1 << RADIX_BITS) - 1)) as usize;
    let mut starts = [0u32; 1 << RADIX_BITS];
    for &v in source {
        starts[digit(v)] += 1;
    }
    let mut sum = 0;
    for start in &mut starts {
        (*start, sum) = (sum, sum + *start);
    }
    for &v in source {
        let d = digit(v);
        target[starts[d] as usize] = v;
        starts[d] += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::sort_indices;
    use crate::sample::Rng;

    #[test]
    fn radix_sort_sorts_like_sort_unstable() {
        let mut rng = Rng::new(5);
        for (len, bound) in [
            (0, 1),
            (1500, 1500),
            (5000, 3_000_000),
            (3000, 1 << 31),
            (2048, 2),
            (4096, 1 << 11),
        ] {
            let mut values: Vec<u32> = (0..len).map(|_| rng.below(bound) as u32).collect();
            let mut expected = values.clone();
            expected.sort_unstable();
            sort_indices(&mut values, bound);
            assert_eq!(values, expected, "len {len}, bound {bound}");
        }
        let mut all_max = vec![u32::MAX; 2000];
        sort_indices(&mut all_max, u32::MAX as usize + 1);
        assert!(all_max.iter().all(|&v| v == u32::MAX) && all_max.len() == 2000);
    }
}
