//! Top-down build of a binary hierarchy: the classic median split, or
//! binned SAH; subtrees are built in parallel and joined. The AABB tree is
//! this hierarchy as built; the other trees are made from it.

use super::config::{BuildConfig, MAX_COORDINATE, SplitMethod};
use super::median::{CentreItem, Counts, SMALL_NODE, median_partition, median_small};
use super::node::{Node, NodePair};

/// The nodes this build makes: boxes.
type BoxNode = Node<Aabb>;
/// Two of them in a cache line.
type BoxPair = NodePair<Aabb>;
use crate::aabb::Aabb;
use crate::error::BuildError;
use crate::math::{Vec3, Vec4};
use crate::memory::{HugePageArray, HugePageVec};
use crate::primitive::Bounded;
use crate::query::Leaves;
use rayon::prelude::*;

/// A primitive's box and input index, for the binned SAH split, which weighs
/// the boxes of its bins. Two 16-byte lanes, so that an item moves in two
/// vector stores and its corners enter box unions as they are.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub(super) struct BoxItem {
    /// The lower corner, and in `w` the input index (its bits).
    lower: Vec4,
    /// The upper corner; `w` is 0.
    upper: Vec4,
}

impl BoxItem {
    fn new(bounds: Aabb, index: u32) -> Self {
        Self {
            lower: bounds.min.extend(f32::from_bits(index)),
            upper: bounds.max.extend(0.0),
        }
    }

    fn min(&self) -> Vec3 {
        self.lower.truncate()
    }

    fn max(&self) -> Vec3 {
        self.upper.truncate()
    }

    /// Twice the box center along `axis` (the factor 2 does not change the order).
    #[inline(always)]
    fn key(&self, axis: usize) -> f32 {
        self.lower[axis] + self.upper[axis]
    }
}

/// What the build needs of the items it moves: the input index, and how a
/// node of them is split.
pub(super) trait BuildItem: Copy + Default + Send + Sync {
    /// The primitive's input index.
    fn index(&self) -> u32;

    /// Splits a node that is to be split (it has more items than the
    /// minimum leaf size and is not at the maximum depth), in place or
    /// into `target`. `bounds` is what the parent's split returned for this
    /// node.
    fn split(source: &mut [Self], target: &mut [Self], bounds: &Aabb, counts: &mut Counts) -> Split;
}

impl BuildItem for CentreItem {
    #[inline(always)]
    fn index(&self) -> u32 {
        CentreItem::index(self)
    }

    /// The median split along the largest extent of the node's centres
    /// (`bounds`), as PBRT chooses the axis; the halves' bounds are those
    /// of their centres.
    fn split(source: &mut [Self], target: &mut [Self], bounds: &Aabb, counts: &mut Counts) -> Split {
        let axis = bounds.largest_axis();
        let (left, right) = if source.len() <= SMALL_NODE {
            median_small(source, target, axis)
        } else {
            median_partition(source, target, axis, bounds, counts)
        };
        Split {
            cut: source.len() / 2,
            left,
            right,
            moved: true,
        }
    }
}

impl BuildItem for BoxItem {
    #[inline(always)]
    fn index(&self) -> u32 {
        self.lower.w.to_bits()
    }

    /// The binned SAH split; when all centres coincide, every order is the
    /// median order, and the node is cut in halves as it lies.
    fn split(source: &mut [Self], _: &mut [Self], _: &Aabb, _: &mut Counts) -> Split {
        sah_split(source).unwrap_or(Split {
            cut: source.len() / 2,
            left: Aabb::EMPTY,
            right: Aabb::EMPTY,
            moved: false,
        })
    }
}

/// Widens a node box by a few ulps of its largest coordinate. Closest points
/// are computed with rounding and may land a hair outside the exact box of
/// their primitive; the widened box keeps the box distance a true lower bound,
/// which is what makes pruning exact.
#[inline]
pub(crate) fn widen(b: Aabb) -> Aabb {
    let scale = b.min.abs().max(b.max.abs()).max_element();
    b.inflate(scale * 8.0 * f32::EPSILON)
}

/// A built binary hierarchy: the node pairs (node 0 the root, node 1
/// padding, children after their parent) with their widened boxes, the
/// primitives in leaf order with their input indices and sources, and the
/// depth of the deepest leaf. What every binary tree is made from.
pub(crate) struct Hierarchy<T> {
    pub(crate) nodes: HugePageArray<BoxPair>,
    pub(crate) leaves: Leaves<T>,
    pub(crate) depth: u32,
}

/// Builds the hierarchy over `primitives`, where `sources[i]` is the mesh
/// element that `primitives[i]` came from.
///
/// Fails when the configuration is invalid, a primitive has a non-finite
/// coordinate or one beyond [`MAX_COORDINATE`], there are 2^32 or more
/// primitives, or `sources` is not as long as `primitives`. Large builds use
/// all threads of rayon's current pool; the hierarchy is the same on any
/// number of threads.
pub(crate) fn build_hierarchy<T: Bounded + Copy + Send + Sync>(
    primitives: Vec<T>,
    sources: Vec<u32>,
    config: &BuildConfig,
) -> Result<Hierarchy<T>, BuildError> {
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
    let (mut nodes, depth, indices) = match config.split {
        SplitMethod::Median => {
            let items = centre_items(&primitives);
            let Some(bounds) = centre_bounds(&items) else {
                return Err(input_error(primitives.iter().map(Bounded::bounds)));
            };
            build_nodes(items, bounds, config)
        }
        SplitMethod::BinnedSah => {
            let items: Vec<BoxItem> = primitives
                .par_iter()
                .enumerate()
                .map(|(index, p)| BoxItem::new(p.bounds(), index as u32))
                .collect();
            check_boxes(&items)?;
            build_nodes(items, Aabb::EMPTY, config)
        }
    };
    // A random gather: the primitive a few slots ahead is asked for
    // early, so that the misses overlap (the distance ahead was measured:
    // docs/perf-log.md).
    let (ordered, sources): (Vec<T>, Vec<u32>) = indices
        .par_iter()
        .enumerate()
        .map(|(k, &i)| {
            if let Some(&next) = indices.get(k + GATHER_AHEAD) {
                crate::memory::prefetch(&primitives[next as usize]);
            }
            (primitives[i as usize], sources[i as usize])
        })
        .unzip();
    refit(nodes.as_mut_slice(), &ordered);
    Ok(Hierarchy {
        nodes: nodes.finish(),
        leaves: Leaves::new(ordered, indices, sources),
        depth,
    })
}

/// The centre items of `primitives`. A primitive with a coordinate that is
/// not finite, or beyond [`MAX_COORDINATE`], gets a NaN centre, which
/// [`centre_bounds`] then rejects: the centre alone could hide either (the
/// centre of -1e30 and 1e30 is 0).
fn centre_items<T: Bounded + Sync>(primitives: &[T]) -> Vec<CentreItem> {
    let limit = Vec3::splat(MAX_COORDINATE);
    let invalid = Aabb::new(Vec3::NAN, Vec3::NAN);
    primitives
        .par_iter()
        .enumerate()
        .map(|(index, p)| {
            let b = p.bounds();
            // `!(m <= limit)` also catches NaN and infinities.
            let valid = b.min.abs().max(b.max.abs()).cmple(limit).all();
            CentreItem::new(if valid { b } else { invalid }, index as u32)
        })
        .collect()
}

/// The bounds of all items' centres, or `None` if one of them is invalid
/// (see [`centre_items`]).
fn centre_bounds(items: &[CentreItem]) -> Option<Aabb> {
    let (low, high, valid) = items
        .par_chunks(1 << 16)
        .map(|chunk| {
            let (mut low, mut high, mut valid) = (Vec4::INFINITY, Vec4::NEG_INFINITY, true);
            for it in chunk {
                low = low.min(it.centre);
                high = high.max(it.centre);
                valid &= !it.centre.truncate().is_nan();
            }
            (low, high, valid)
        })
        .reduce(
            || (Vec4::INFINITY, Vec4::NEG_INFINITY, true),
            |a, b| (a.0.min(b.0), a.1.max(b.1), a.2 && b.2),
        );
    valid.then(|| Aabb::new(low.truncate(), high.truncate()))
}

/// Checks every item's box: the error of [`input_error`] if one is invalid.
fn check_boxes(items: &[BoxItem]) -> Result<(), BuildError> {
    // One pass for the common case: `!(m <= bound)` also catches NaN and infinities.
    let limit = Vec4::splat(MAX_COORDINATE);
    let beyond = items.iter().any(|it| {
        let magnitude = it.lower.abs().max(it.upper.abs()).truncate();
        !magnitude.cmple(limit.truncate()).all()
    });
    if beyond {
        return Err(input_error(items.iter().map(|it| Aabb::new(it.min(), it.max()))));
    }
    Ok(())
}

/// The error for the first box with a non-finite coordinate or, when all
/// are finite, the first beyond [`MAX_COORDINATE`] (for input already known
/// to hold one or the other).
fn input_error(boxes: impl Iterator<Item = Aabb> + Clone) -> BuildError {
    let finite = |b: &Aabb| b.min.is_finite() && b.max.is_finite();
    if let Some(index) = boxes.clone().position(|b| !finite(&b)) {
        return BuildError::NonFinite { index };
    }
    let beyond = |b: Aabb| b.min.abs().max(b.max.abs()).max_element() > MAX_COORDINATE;
    BuildError::CoordinateTooLarge {
        index: boxes.clone().position(beyond).unwrap_or(0),
        bound: MAX_COORDINATE,
    }
}

/// Sets every node's box, from the leaves up: a leaf's is the box of its
/// primitives, widened ([`widen`]); an inner node's, the union of its
/// children's. The union of widened boxes holds every point the widening
/// was meant to cover, so parents need no widening of their own.
///
/// Children always come after their parent in the array, so one pass
/// backwards meets every child before its parent. Node 1 is padding.
pub(crate) fn refit<T: Bounded + Sync>(pairs: &mut [BoxPair], primitives: &[T]) {
    let set = |node: &mut BoxNode, b: Aabb| node.set_volume(b);
    // Leaves first, in parallel: they read every primitive once.
    pairs.par_iter_mut().for_each(|pair| {
        for node in pair.nodes_mut() {
            // The padding node has no primitives: not a leaf.
            if node.is_leaf() {
                let b = primitives[node.primitive_range()]
                    .iter()
                    .fold(Aabb::EMPTY, |acc, q| acc.merge(&q.bounds()));
                set(node, widen(b));
            }
        }
    });
    for i in (0..2 * pairs.len()).rev() {
        let node = pairs[i / 2].nodes()[i % 2];
        // The padding node looks like an inner node whose children are 0 and 1.
        if i == 1 || node.is_leaf() {
            continue;
        }
        let [left, right] = *pairs[node.children()[0] as usize / 2].nodes();
        set(
            &mut pairs[i / 2].nodes_mut()[i % 2],
            left.bounds().merge(&right.bounds()),
        );
    }
}

/// A built subtree: its root, and its other nodes as pairs numbered from 0
/// (inner nodes refer to flat indices within the subtree's pairs).
struct Subtree {
    root: BoxNode,
    /// The pairs in layout order, as the pieces the threads built: each with
    /// the amount to add to its inner nodes' child indices. Joining subtrees
    /// only adjusts these amounts; the pairs are copied once, at the end.
    pieces: Vec<(Vec<BoxPair>, u32)>,
    pair_count: usize,
    depth: u32,
}

/// How many slots ahead the final gather of primitives prefetches.
const GATHER_AHEAD: usize = 32;

/// Below this many primitives a subtree is built on one thread by a loop.
const PARALLEL_THRESHOLD: usize = 32 * 1024;

/// The item arrays of a subtree: `main` ends up in leaf order; `scratch`, of
/// the same length, receives the items of nodes split by moving them.
struct Buffers<'a, I> {
    main: &'a mut [I],
    scratch: &'a mut [I],
}

impl<I> Buffers<'_, I> {
    /// The items `range` of the buffer they are in, and the same range of the other.
    fn source_and_target(&mut self, range: std::ops::Range<usize>, in_scratch: bool) -> (&mut [I], &mut [I]) {
        let (main, scratch) = (&mut self.main[range.clone()], &mut self.scratch[range]);
        if in_scratch { (scratch, main) } else { (main, scratch) }
    }
}

/// Builds the node array over `items` (`bounds` being what the root's split
/// takes, see [`BuildItem::split`]), without their boxes, which [`refit`]
/// sets. Returns the nodes, the depth of the deepest leaf, and the input
/// indices of the items in leaf order.
fn build_nodes<I: BuildItem>(
    mut items: Vec<I>,
    bounds: Aabb,
    config: &BuildConfig,
) -> (HugePageVec<BoxPair>, u32, Vec<u32>) {
    if items.is_empty() {
        return (HugePageVec::with_capacity(0), 0, Vec::new());
    }
    // Filled in parallel: touching every byte of fresh memory is mostly
    // page faults, which the threads then share.
    let mut scratch: Vec<I> = (0..items.len()).into_par_iter().map(|_| I::default()).collect();
    let buffers = Buffers {
        main: &mut items,
        scratch: &mut scratch,
    };
    let tree = build_subtree(buffers, false, bounds, 0, 0, config);
    // Pair 0 holds the root and a padding node; the rest follow, shifted by
    // one pair. Written straight to their final array (a mapping advised
    // for huge pages once written, when large), not to a `Vec` copied there
    // afterwards.
    let mut nodes = HugePageVec::with_capacity(tree.pair_count + 1);
    nodes.push(NodePair::new([tree.root.shifted(2), PADDING]));
    for (pairs, shift) in &tree.pieces {
        let shift = shift + 2;
        for pair in pairs {
            nodes.push(NodePair::new(pair.nodes().map(|n| n.shifted(shift))));
        }
    }
    drop(scratch);
    let indices = items.par_iter().map(I::index).collect();
    (nodes, tree.depth, indices)
}

/// A node's split: the size of the first part, what each part's own split
/// takes ([`BuildItem::split`]), and whether the items moved to the other buffer.
pub(super) struct Split {
    cut: usize,
    left: Aabb,
    right: Aabb,
    moved: bool,
}

/// Builds the subtree over the items of `buffers` (in `scratch` when
/// `in_scratch`), which start at `offset` in the whole item array, with its
/// root at `depth`; `bounds` is the box of the items.
fn build_subtree<I: BuildItem>(
    mut buffers: Buffers<I>,
    in_scratch: bool,
    bounds: Aabb,
    offset: usize,
    depth: u32,
    config: &BuildConfig,
) -> Subtree {
    let len = buffers.main.len();
    if len < PARALLEL_THRESHOLD {
        return build_sequential(buffers, in_scratch, bounds, offset, depth, config);
    }
    let mut counts = Counts::default();
    let (source, target) = buffers.source_and_target(0..len, in_scratch);
    let Some(split) = split(source, target, &bounds, depth, config, &mut counts) else {
        return build_sequential(buffers, in_scratch, bounds, offset, depth, config);
    };
    let cut = split.cut;
    let (left_main, right_main) = buffers.main.split_at_mut(cut);
    let (left_scratch, right_scratch) = buffers.scratch.split_at_mut(cut);
    let children_in_scratch = in_scratch ^ split.moved;
    let (left, right) = rayon::join(
        || {
            let buffers = Buffers {
                main: left_main,
                scratch: left_scratch,
            };
            build_subtree(buffers, children_in_scratch, split.left, offset, depth + 1, config)
        },
        || {
            let buffers = Buffers {
                main: right_main,
                scratch: right_scratch,
            };
            build_subtree(
                buffers,
                children_in_scratch,
                split.right,
                offset + cut,
                depth + 1,
                config,
            )
        },
    );
    // Layout: the children pair, then the left subtree's pairs, then the right's.
    let left_shift = 2;
    let right_shift = 2 + 2 * left.pair_count as u32;
    let children = NodePair::new([left.root.shifted(left_shift), right.root.shifted(right_shift)]);
    let mut pieces = Vec::with_capacity(1 + left.pieces.len() + right.pieces.len());
    pieces.push((vec![children], 0));
    pieces.extend(
        left.pieces
            .into_iter()
            .map(|(pairs, shift)| (pairs, shift + left_shift)),
    );
    pieces.extend(
        right
            .pieces
            .into_iter()
            .map(|(pairs, shift)| (pairs, shift + right_shift)),
    );
    Subtree {
        root: BoxNode::inner(Aabb::EMPTY, 0),
        pieces,
        pair_count: 1 + left.pair_count + right.pair_count,
        depth: left.depth.max(right.depth),
    }
}

/// Decides whether the node over `source` is split and, if so, splits it,
/// in place or into `target`.
fn split<I: BuildItem>(
    source: &mut [I],
    target: &mut [I],
    bounds: &Aabb,
    depth: u32,
    config: &BuildConfig,
    counts: &mut Counts,
) -> Option<Split> {
    if source.len() <= config.min_size as usize || depth >= config.max_depth {
        return None;
    }
    Some(I::split(source, target, bounds, counts))
}

/// Builds a subtree with an explicit work list, no recursion.
fn build_sequential<I: BuildItem>(
    mut buffers: Buffers<I>,
    in_scratch: bool,
    bounds: Aabb,
    offset: usize,
    depth: u32,
    config: &BuildConfig,
) -> Subtree {
    let len = buffers.main.len();
    let mut pairs: Vec<BoxPair> = Vec::with_capacity(len.div_ceil(config.min_size as usize));
    let mut root = PLACEHOLDER;
    let mut work = vec![(ROOT, 0usize, len, depth, bounds, in_scratch)];
    let mut max_depth = depth;
    let mut counts = Counts::default();
    while let Some((node, begin, end, depth, bounds, in_scratch)) = work.pop() {
        max_depth = max_depth.max(depth);
        let (source, target) = buffers.source_and_target(begin..end, in_scratch);
        let made = match split(source, target, &bounds, depth, config, &mut counts) {
            None => {
                if in_scratch {
                    target.copy_from_slice(source);
                }
                BoxNode::leaf(Aabb::EMPTY, (offset + begin) as u32, (end - begin) as u32)
            }
            Some(split) => {
                let first_child = 2 * pairs.len();
                pairs.push(NodePair::new([PLACEHOLDER, PLACEHOLDER]));
                let cut = begin + split.cut;
                let children_in_scratch = in_scratch ^ split.moved;
                // Left child is popped first, so its subtree is laid out next to it.
                work.push((first_child + 1, cut, end, depth + 1, split.right, children_in_scratch));
                work.push((first_child, begin, cut, depth + 1, split.left, children_in_scratch));
                BoxNode::inner(Aabb::EMPTY, first_child as u32)
            }
        };
        if node == ROOT {
            root = made;
        } else {
            pairs[node >> 1].nodes_mut()[node & 1] = made;
        }
    }
    Subtree {
        root,
        pair_count: pairs.len(),
        pieces: vec![(pairs, 0)],
        depth: max_depth,
    }
}

/// The work list's name for the subtree's root, which has no slot in its pairs.
const ROOT: usize = usize::MAX;

const BINS: usize = 16;

/// Binned SAH split of `range` in place, or `None` when the centroids cannot
/// be separated (all equal on every axis). The parts' boxes are the unions of
/// their bins' boxes.
fn sah_split(range: &mut [BoxItem]) -> Option<Split> {
    // Keys are doubled centroids, so the bounds below are of doubled centroids.
    let mut low = Vec3::splat(f32::INFINITY);
    let mut high = Vec3::splat(f32::NEG_INFINITY);
    for it in range.iter() {
        let c = it.min() + it.max();
        low = low.min(c);
        high = high.max(c);
    }
    let extent = high - low;
    let scale = Vec3::select(extent.cmpgt(Vec3::ZERO), Vec3::splat(BINS as f32) / extent, Vec3::ZERO);
    let bin = |it: &BoxItem, axis: usize| (((it.key(axis) - low[axis]) * scale[axis]) as usize).min(BINS - 1);
    // One pass bins all three axes.
    let mut counts = [[0usize; BINS]; 3];
    let mut boxes = [[Aabb::EMPTY; BINS]; 3];
    for it in range.iter() {
        let b = Aabb::new(it.min(), it.max());
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
    let union = |bins: &[Aabb]| bins.iter().fold(Aabb::EMPTY, |acc, b| acc.merge(b));
    (i > 0 && i < range.len()).then(|| Split {
        cut: i,
        left: union(&boxes[axis][..cut]),
        right: union(&boxes[axis][cut..]),
        moved: false,
    })
}

const PLACEHOLDER: BoxNode = Node::empty_leaf();
/// Node 1: never referenced by any inner node.
const PADDING: BoxNode = Node::empty_leaf();
