//! Top-down build: the classic median split, or binned SAH; subtrees are built
//! in parallel and joined.

use super::AabbTree;
use super::config::{BuildConfig, MAX_COORDINATE, SplitMethod};
use super::node::{Node, NodePair};
use crate::aabb::Aabb;
use crate::error::BuildError;
use crate::math::Vec3;
use crate::primitive::{Bounded, PrimitiveSet};
use rayon::prelude::*;

/// A primitive's box and input index, moved around during the build instead of
/// the primitive itself: the partition step then touches 28 contiguous bytes
/// per primitive and never chases an index.
#[derive(Clone, Copy)]
#[repr(C)]
struct Item {
    min: Vec3,
    index: u32,
    max: Vec3,
}

impl Item {
    /// Twice the box center along `axis` (the factor 2 does not change the order).
    #[inline]
    fn key(&self, axis: usize) -> f32 {
        self.min[axis] + self.max[axis]
    }
}

/// Widens a node box by a few ulps of its largest coordinate. Closest points
/// are computed with rounding and may land a hair outside the exact box of
/// their primitive; the widened box keeps the box distance a true lower bound,
/// which is what makes pruning exact.
#[inline]
fn widen(b: Aabb) -> Aabb {
    let scale = b.min.abs().max(b.max.abs()).max_element();
    b.inflate(scale * 8.0 * f32::EPSILON)
}

impl<T: Bounded + Copy + Send + Sync> AabbTree<T> {
    /// Builds a tree over `primitives`; the source of each is its input index.
    ///
    /// Fails when the configuration is invalid, a primitive has a non-finite
    /// coordinate or one beyond [`MAX_COORDINATE`](super::MAX_COORDINATE), or there are 2^32 or more primitives. Large builds use all
    /// threads of rayon's current pool; run it inside a one-thread pool for a
    /// single-thread build (the tree is the same either way).
    pub fn build(primitives: Vec<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        let sources = (0..primitives.len() as u32).collect();
        Self::build_with_sources(primitives, sources, config)
    }

    /// Builds a tree over primitives extracted from a mesh, keeping their sources.
    pub fn build_set(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        Self::build_with_sources(set.primitives, set.sources, config)
    }

    /// Builds a tree over `primitives`, where `sources[i]` is the mesh element
    /// that `primitives[i]` came from.
    pub fn build_with_sources(primitives: Vec<T>, sources: Vec<u32>, config: &BuildConfig) -> Result<Self, BuildError> {
        config.validate()?;
        let n = primitives.len();
        if n >= u32::MAX as usize {
            return Err(BuildError::TooMany { count: n });
        }
        if sources.len() != n {
            return Err(BuildError::SourceCount {
                primitives: n,
                sources: sources.len(),
            });
        }
        let mut items: Vec<Item> = primitives
            .par_iter()
            .enumerate()
            .map(|(index, p)| {
                let b = p.bounds();
                Item {
                    min: b.min,
                    index: index as u32,
                    max: b.max,
                }
            })
            .collect();
        if let Some(index) = items.iter().position(|it| !(it.min.is_finite() && it.max.is_finite())) {
            return Err(BuildError::NonFinite { index });
        }
        let beyond = |it: &Item| it.min.abs().max(it.max.abs()).max_element() > MAX_COORDINATE;
        if let Some(index) = items.iter().position(beyond) {
            return Err(BuildError::CoordinateTooLarge {
                index,
                bound: MAX_COORDINATE,
            });
        }
        let (nodes, depth) = build_nodes(&mut items, config);
        let indices: Vec<u32> = items.par_iter().map(|it| it.index).collect();
        let ordered = indices.par_iter().map(|&i| primitives[i as usize]).collect();
        let sources = indices.par_iter().map(|&i| sources[i as usize]).collect();
        Ok(Self {
            nodes,
            primitives: ordered,
            indices,
            sources,
            depth,
        })
    }
}

/// A built subtree: its root, and its other nodes as pairs numbered from 0
/// (inner nodes refer to flat indices within `pairs`).
struct Subtree {
    root: Node,
    pairs: Vec<NodePair>,
    depth: u32,
}

/// Below this many primitives a subtree is built on one thread by a loop.
const PARALLEL_THRESHOLD: usize = 32 * 1024;

/// Builds the node array over `items`, reordering them into leaf order.
/// Returns the nodes and the depth of the deepest leaf.
fn build_nodes(items: &mut [Item], config: &BuildConfig) -> (Vec<NodePair>, u32) {
    if items.is_empty() {
        return (Vec::new(), 0);
    }
    let tree = build_subtree(items, 0, 0, config);
    // Pair 0 holds the root and a padding node; the rest follow, shifted by one pair.
    let mut nodes = Vec::with_capacity(tree.pairs.len() + 1);
    nodes.push(NodePair([tree.root.shifted(2), PADDING]));
    nodes.extend(tree.pairs.iter().map(|pair| NodePair(pair.0.map(|n| n.shifted(2)))));
    (nodes, tree.depth)
}

/// Builds the subtree over `items`, which start at `offset` in the whole item
/// array, with its root at `depth`.
fn build_subtree(items: &mut [Item], offset: usize, depth: u32, config: &BuildConfig) -> Subtree {
    if items.len() < PARALLEL_THRESHOLD {
        return build_sequential(items, offset, depth, config);
    }
    let bounds = bounds_of(items);
    let Some(cut) = split(items, &bounds, depth, config) else {
        return build_sequential(items, offset, depth, config);
    };
    let (left_items, right_items) = items.split_at_mut(cut);
    let (left, right) = rayon::join(
        || build_subtree(left_items, offset, depth + 1, config),
        || build_subtree(right_items, offset + cut, depth + 1, config),
    );
    // Layout: the children pair, then the left subtree's pairs, then the right's.
    let left_shift = 2;
    let right_shift = 2 + 2 * left.pairs.len() as u32;
    let mut pairs = Vec::with_capacity(1 + left.pairs.len() + right.pairs.len());
    pairs.push(NodePair([
        left.root.shifted(left_shift),
        right.root.shifted(right_shift),
    ]));
    pairs.extend(left.pairs.iter().map(|p| NodePair(p.0.map(|n| n.shifted(left_shift)))));
    pairs.extend(
        right
            .pairs
            .iter()
            .map(|p| NodePair(p.0.map(|n| n.shifted(right_shift)))),
    );
    Subtree {
        root: Node::inner(widen(bounds), 0),
        pairs,
        depth: left.depth.max(right.depth),
    }
}

/// The box of all items.
fn bounds_of(items: &[Item]) -> Aabb {
    items
        .iter()
        .fold(Aabb::EMPTY, |b, it| b.merge(&Aabb::new(it.min, it.max)))
}

/// Decides whether the node over `items` is split and, if so, reorders the
/// items and returns the size of the first part.
fn split(items: &mut [Item], bounds: &Aabb, depth: u32, config: &BuildConfig) -> Option<usize> {
    if items.len() <= config.min_size as usize || depth >= config.max_depth {
        return None;
    }
    Some(match config.split {
        SplitMethod::Median => median_split(items, bounds),
        SplitMethod::BinnedSah => sah_split(items).unwrap_or_else(|| median_split(items, bounds)),
    })
}

/// Builds a subtree with an explicit work list, no recursion.
fn build_sequential(items: &mut [Item], offset: usize, depth: u32, config: &BuildConfig) -> Subtree {
    // Pair 0 holds the root (and a padding node) while building.
    let mut pairs = Vec::with_capacity(items.len().div_ceil(config.min_size as usize) + 1);
    pairs.push(NodePair([PLACEHOLDER, PADDING]));
    let mut work = vec![(0usize, 0usize, items.len(), depth)];
    let mut max_depth = depth;
    while let Some((node, begin, end, depth)) = work.pop() {
        let range = &mut items[begin..end];
        let bounds = bounds_of(range);
        max_depth = max_depth.max(depth);
        let Some(cut) = split(range, &bounds, depth, config) else {
            pairs[node >> 1].0[node & 1] = Node::leaf(widen(bounds), (offset + begin) as u32, range.len() as u32);
            continue;
        };
        let first_child = 2 * pairs.len();
        pairs[node >> 1].0[node & 1] = Node::inner(widen(bounds), first_child as u32);
        pairs.push(NodePair([PLACEHOLDER, PLACEHOLDER]));
        // Left child is popped first, so its subtree is laid out next to it.
        work.push((first_child + 1, begin + cut, end, depth + 1));
        work.push((first_child, begin, begin + cut, depth + 1));
    }
    // Drop pair 0: inner nodes' child indices move down by one pair.
    let root = pairs[0].0[0].shifted_down(2);
    let pairs = pairs[1..]
        .iter()
        .map(|p| NodePair(p.0.map(|n| n.shifted_down(2))))
        .collect();
    Subtree {
        root,
        pairs,
        depth: max_depth,
    }
}

/// Splits `range` into two equal halves along the largest extent of `bounds`;
/// returns the size of the first half.
fn median_split(range: &mut [Item], bounds: &Aabb) -> usize {
    let half = range.len() / 2;
    let axis = bounds.largest_axis();
    // Selection puts the `half` smallest keys first: the same two halves a
    // full sort would give, in linear time per level.
    range.select_nth_unstable_by(half, |a, b| a.key(axis).total_cmp(&b.key(axis)));
    half
}

const BINS: usize = 16;

/// Binned SAH split of `range`; returns the size of the first part, or `None`
/// when the centroids cannot be separated (all equal on every axis).
fn sah_split(range: &mut [Item]) -> Option<usize> {
    // Keys are doubled centroids, so the bounds below are of doubled centroids.
    let mut low = Vec3::splat(f32::INFINITY);
    let mut high = Vec3::splat(f32::NEG_INFINITY);
    for it in range.iter() {
        let c = it.min + it.max;
        low = low.min(c);
        high = high.max(c);
    }
    let extent = high - low;
    let scale = Vec3::select(extent.cmpgt(Vec3::ZERO), Vec3::splat(BINS as f32) / extent, Vec3::ZERO);
    let bin = |it: &Item, axis: usize| (((it.key(axis) - low[axis]) * scale[axis]) as usize).min(BINS - 1);
    // One pass bins all three axes.
    let mut counts = [[0usize; BINS]; 3];
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    for it in range.iter() {
        let b = Aabb::new(it.min, it.max);
        for axis in 0..3 {
            let k = bin(it, axis);
            counts[axis][k] += 1;
            boxes[axis][k] = boxes[axis][k].merge(&b);
        }
    }
    let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, first bin of the right part)
    for axis in 0..3 {
        if scale[axis] == 0.0 {
            continue;
        }
        // Sweep from the right for the right part's area and count at every
        // cut, then from the left to evaluate the cost.
        let mut right_area = [0f64; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in (1..BINS).rev() {
            acc = acc.merge(&boxes[axis][k]);
            n += counts[axis][k];
            right_area[k] = acc.surface_area() as f64;
            right_count[k] = n;
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for cut in 1..BINS {
            acc = acc.merge(&boxes[axis][cut - 1]);
            n += counts[axis][cut - 1];
            if n == 0 || right_count[cut] == 0 {
                continue;
            }
            let cost = acc.surface_area() as f64 * n as f64 + right_area[cut] * right_count[cut] as f64;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, cut));
            }
        }
    }
    let (_, axis, cut) = best?;
    // In-place partition: the left part first.
    let (mut i, mut j) = (0, range.len());
    while i < j {
        if bin(&range[i], axis) < cut {
            i += 1;
        } else {
            j -= 1;
            range.swap(i, j);
        }
    }
    (i > 0 && i < range.len()).then_some(i)
}

const PLACEHOLDER: Node = Node::empty_leaf();
/// Node 1: never referenced by any inner node.
pub(crate) const PADDING: Node = Node::empty_leaf();
