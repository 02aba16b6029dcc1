//! The median split of the build: a histogram selection that moves a node's
//! items into the other buffer, in halves, and computes the bounds of both
//! halves' centres on the way (the next split's axis and histogram range).
//!
//! A comparison selection (introselect) walks a node's items several times,
//! and the bounds of the two children need one more pass each. Here one pass
//! counts the keys into buckets spread evenly over the node's extent, and a
//! second pass moves every item to its final half (or, for the one bucket that
//! holds the median, to the middle) while growing the halves' bounds. Only the
//! median bucket, a small fraction of the node, is left to a comparison
//! selection.

use crate::aabb::Aabb;
use crate::math::Vec4;
use wide::{f32x4, i32x4};

/// A primitive's centre and input index, moved around by the median split
/// instead of the primitive itself: the partition step then touches 16
/// contiguous bytes per primitive and never chases an index. The split needs
/// only centres (its key, its axis, its histogram's range); node boxes are
/// computed afterwards, from the leaves up (`build::refit`). Against moving
/// 32-byte boxes: see `docs/perf-log.md`.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub(super) struct CentreItem {
    /// Twice the centre of the primitive's box (the factor 2 does not change
    /// the order), and in `w` the input index (its bits).
    pub(super) centre: Vec4,
}

const _: () = assert!(std::mem::size_of::<CentreItem>() == 16);

impl CentreItem {
    pub(super) fn new(bounds: Aabb, index: u32) -> Self {
        Self {
            centre: (bounds.min + bounds.max).extend(f32::from_bits(index)),
        }
    }

    /// The primitive's input index.
    #[inline(always)]
    pub(super) fn index(&self) -> u32 {
        self.centre.w.to_bits()
    }

    /// Twice the box centre along `axis`.
    #[cfg(test)]
    pub(super) fn key(&self, axis: usize) -> f32 {
        self.centre[axis]
    }
}

/// Within this module, the median split's item.
type Item = CentreItem;

/// Most buckets of a histogram: with ~1M items, the median bucket holds about
/// a thousand, and the counts stay in the L1 cache.
const MAX_BUCKETS: usize = 2048;

/// Nodes up to this size keep each item's bucket between the two passes.
const KEEP_BUCKETS: usize = 1 << 16;

/// Reusable histogram space, one per thread of the build.
#[derive(Default)]
pub(super) struct Counts {
    /// Four interleaved histograms.
    counts: Vec<u32>,
    /// Each item's bucket, computed once by the counting pass.
    buckets: Vec<u16>,
}

/// Growing bounds by an item or not, without a branch or a select (for
/// [`Grower::clamped`]): a lane of -inf lets `max(centre, clamp)` through
/// unchanged, while +inf turns it into +inf, which no minimum notices (and
/// `min(centre, -clamp)` does the same for the upper corner). Indexed by
/// whether the item is taken. Faster than selecting with masks made from
/// booleans (docs/perf-log.md).
const CLAMPS: [Vec4; 2] = [Vec4::INFINITY, Vec4::NEG_INFINITY];

/// Bounds of item centres grown item by item, in 16-byte lanes (`w` means
/// nothing: it holds index bits, which min and max carry along unharmed).
#[derive(Clone, Copy)]
struct Grower {
    min: Vec4,
    max: Vec4,
}

impl Grower {
    const EMPTY: Grower = Grower {
        min: Vec4::INFINITY,
        max: Vec4::NEG_INFINITY,
    };

    /// The bounds grown to hold `item`'s centre.
    #[inline(always)]
    fn grown(self, item: &Item) -> Grower {
        Grower {
            min: self.min.min(item.centre),
            max: self.max.max(item.centre),
        }
    }

    /// The bounds grown to hold `item`'s centre clamped: by -inf, which
    /// changes nothing, or by +inf, which leaves the bounds as they were
    /// (see [`CLAMPS`]).
    #[inline(always)]
    fn clamped(self, item: &Item, clamp: Vec4) -> Grower {
        Grower {
            min: self.min.min(item.centre.max(clamp)),
            max: self.max.max(item.centre.min(-clamp)),
        }
    }

    fn aabb(self) -> Aabb {
        Aabb::new(self.min.truncate(), self.max.truncate())
    }
}

/// The bounds of `items`' centres.
pub(super) fn bounds_of(items: &[Item]) -> Aabb {
    items.iter().fold(Grower::EMPTY, |b, it| b.grown(it)).aabb()
}

/// Moves `source` into `target` (of the same length) so that the first
/// `source.len() / 2` items of `target` are those with the smallest keys along
/// `axis` (ties go either way), and returns the bounds of the two halves'
/// centres. `bounds` must hold every item's centre.
pub(super) fn median_partition(
    source: &[Item],
    target: &mut [Item],
    axis: usize,
    bounds: &Aabb,
    scratch: &mut Counts,
) -> (Aabb, Aabb) {
    // One copy per axis: a key read through a run-time axis costs a branch per item.
    match axis {
        0 => median_partition_along::<0>(source, target, bounds, scratch),
        1 => median_partition_along::<1>(source, target, bounds, scratch),
        _ => median_partition_along::<2>(source, target, bounds, scratch),
    }
}

#[inline(always)]
fn key_along<const AXIS: usize>(it: &Item) -> f32 {
    it.centre[AXIS]
}

fn median_partition_along<const AXIS: usize>(
    source: &[Item],
    target: &mut [Item],
    bounds: &Aabb,
    scratch: &mut Counts,
) -> (Aabb, Aabb) {
    debug_assert_eq!(source.len(), target.len());
    let len = source.len();
    let half = len / 2;
    if len < 2 {
        target.copy_from_slice(source);
        return (Aabb::EMPTY, bounds_of(target));
    }
    // The bucket is a non-decreasing function of the key (a rounded product
    // clamped into range): a lower bucket never holds a larger key.
    let low = bounds.min[AXIS];
    let high = bounds.max[AXIS];
    let buckets = (len / 4).clamp(2, MAX_BUCKETS);
    let top = (buckets - 1) as u32;
    let scale = top as f32 / (high - low);
    // A degenerate extent puts every item in bucket 0.
    let scale = if scale.is_finite() { scale } else { 0.0 };
    // Adding 2^23 rounds a float in [0, 2^22) to an integer in its low
    // mantissa bits: a non-decreasing map, cheaper than a saturating cast.
    const ROUNDER: f32 = (1 << 23) as f32;
    let bucket = |it: &Item| {
        let position = (key_along::<AXIS>(it) - low) * scale;
        ((position + ROUNDER).to_bits() - ROUNDER.to_bits()).min(top) as u16
    };
    // Neighbouring items often fall in the same bucket; counting them in four
    // interleaved histograms keeps each increment from waiting for the last.
    // Buckets are kept for the moving pass, except in the largest nodes, where
    // the passes wait on memory and computing a bucket again is free.
    let Counts {
        counts,
        buckets: item_buckets,
    } = scratch;
    let keep = len <= KEEP_BUCKETS;
    item_buckets.clear();
    if keep {
        item_buckets.extend(source.iter().map(bucket));
    }
    counts.clear();
    counts.resize(4 * buckets, 0);
    let (lane0, rest) = counts.split_at_mut(buckets);
    let (lane1, rest) = rest.split_at_mut(buckets);
    let (lane2, lane3) = rest.split_at_mut(buckets);
    let mut count = |b: [u16; 4]| {
        lane0[b[0] as usize] += 1;
        lane1[b[1] as usize] += 1;
        lane2[b[2] as usize] += 1;
        lane3[b[3] as usize] += 1;
    };
    if keep {
        let mut quads = item_buckets.chunks_exact(4);
        for quad in &mut quads {
            count([quad[0], quad[1], quad[2], quad[3]]);
        }
        for &b in quads.remainder() {
            lane0[b as usize] += 1;
        }
    } else {
        let mut quads = source.chunks_exact(4);
        for quad in &mut quads {
            count(std::array::from_fn(|i| bucket(&quad[i])));
        }
        for it in quads.remainder() {
            lane0[bucket(it) as usize] += 1;
        }
    }
    // The median bucket: the one holding the item of rank `half`.
    let (mut median, mut below) = (0, 0);
    let mut equal = 0;
    for i in 0..buckets {
        let count = (lane0[i] + lane1[i] + lane2[i] + lane3[i]) as usize;
        if below + count > half {
            (median, equal) = (i as u16, count);
            break;
        }
        below += count;
    }
    let (mut left, mut right) = if keep {
        scatter(source, target, item_buckets.iter().copied(), median, below, equal)
    } else {
        scatter(source, target, source.iter().map(bucket), median, below, equal)
    };
    let middle = &mut target[below..below + equal];
    let rank = half - below;
    if rank > 0 {
        middle.select_nth_unstable_by(rank, |a, b| key_along::<AXIS>(a).total_cmp(&key_along::<AXIS>(b)));
    }
    let (lower, upper) = middle.split_at(rank);
    left = lower.iter().fold(left, |b, it| b.grown(it));
    right = upper.iter().fold(right, |b, it| b.grown(it));
    (left.aabb(), right.aabb())
}

/// Items below the bucket `median` go first in `target`, those above last,
/// the median bucket's (`equal` of them, after `below` others) in between;
/// returns the bounds of the first and last groups' centres.
fn scatter(
    source: &[Item],
    target: &mut [Item],
    buckets: impl Iterator<Item = u16>,
    median: u16,
    below: usize,
    equal: usize,
) -> (Grower, Grower) {
    // An item's side is as unpredictable as a coin toss, so nothing here
    // branches on it: the side indexes the next free slots and the clamps.
    // Side 0 is left, 1 the median bucket, 2 right.
    const TO_LEFT: [Vec4; 3] = [CLAMPS[1], CLAMPS[0], CLAMPS[0]];
    const TO_RIGHT: [Vec4; 3] = [CLAMPS[0], CLAMPS[0], CLAMPS[1]];
    let mut next = [0usize, below, below + equal];
    let (mut left, mut right) = (Grower::EMPTY, Grower::EMPTY);
    for (it, b) in source.iter().zip(buckets) {
        let side = (b >= median) as usize + (b > median) as usize;
        let slot = next[side];
        target[slot] = *it;
        next[side] = slot + 1;
        left = left.clamped(it, TO_LEFT[side]);
        right = right.clamped(it, TO_RIGHT[side]);
    }
    (left, right)
}

/// Up to this many items, a node is split by [`median_small`].
pub(super) const SMALL_NODE: usize = 16;

/// Like [`median_partition`], for at most [`SMALL_NODE`] items: each item's
/// rank is counted against all others (ties broken by position), and the
/// item is written straight to its rank. Quadratic, but without a branch to
/// mispredict: the keys sit in vector lanes padded to 8 or 16, and each item
/// is compared with all lanes at once, so every rank is ready at the end
/// without a sum across lanes. The result is sorted, so the halves' bounds
/// are plain unions afterwards. Faster than counting each item's rank in a
/// loop over the others (docs/perf-log.md).
pub(super) fn median_small(source: &[Item], target: &mut [Item], axis: usize) -> (Aabb, Aabb) {
    match axis {
        0 => median_small_along::<0>(source, target),
        1 => median_small_along::<1>(source, target),
        _ => median_small_along::<2>(source, target),
    }
}

fn median_small_along<const AXIS: usize>(source: &[Item], target: &mut [Item]) -> (Aabb, Aabb) {
    debug_assert!(source.len() <= SMALL_NODE && source.len() == target.len());
    if source.len() <= SMALL_NODE / 2 {
        ranked::<AXIS, { SMALL_NODE / 8 }>(source, target)
    } else {
        ranked::<AXIS, { SMALL_NODE / 4 }>(source, target)
    }
}

/// [`median_small`] over `4 * V` lanes, which must hold all items.
#[inline(always)]
fn ranked<const AXIS: usize, const V: usize>(source: &[Item], target: &mut [Item]) -> (Aabb, Aabb) {
    let n = source.len();
    debug_assert!(n <= 4 * V);
    // Lane `l` holds item `l`'s key; lanes past the items hold +infinity,
    // which no finite key equals or exceeds.
    let mut keys = [[f32::INFINITY; 4]; V];
    for (l, it) in source.iter().enumerate() {
        keys[l / 4][l % 4] = key_along::<AXIS>(it);
    }
    let keys: [f32x4; V] = keys.map(f32x4::from);
    let lanes: [i32x4; V] = std::array::from_fn(|c| {
        let l = 4 * c as i32;
        i32x4::new([l, l + 1, l + 2, l + 3])
    });
    // Every item's rank at once, lane by lane: item `j` is counted below
    // item `l` when its key is smaller, or equal and `j` comes first.
    let mut ranks = [i32x4::ZERO; V];
    for (j, it) in source.iter().enumerate() {
        let key = f32x4::splat(key_along::<AXIS>(it));
        let position = i32x4::splat(j as i32);
        for ((rank, k), lane) in ranks.iter_mut().zip(&keys).zip(&lanes) {
            let later: f32x4 = bytemuck::cast(lane.simd_gt(position));
            let below = key.simd_lt(*k) | (key.simd_eq(*k) & later);
            *rank -= bytemuck::cast::<f32x4, i32x4>(below);
        }
    }
    let ranks = ranks.map(i32x4::to_array);
    for (it, &rank) in source.iter().zip(ranks.as_flattened()) {
        target[rank as usize] = *it;
    }
    // The result is sorted, so each half's bounds are a plain union.
    let half = n / 2;
    (bounds_of(&target[..half]), bounds_of(&target[half..]))
}

#[cfg(test)]
mod tests {
    use super::CentreItem as Item;
    use super::{Counts, SMALL_NODE, bounds_of, median_partition, median_small};
    use crate::aabb::Aabb;
    use crate::math::Vec3;
    use proptest::prelude::*;

    /// Coordinates with many exact duplicates, both zeros, and magnitudes
    /// from subnormal to near the build's coordinate bound.
    fn coordinate() -> impl Strategy<Value = f32> {
        prop_oneof![
            prop::sample::select(vec![0.0f32, -0.0, 1.0, -1.0, 0.5, 3.0]),
            (-8i32..8).prop_map(|i| i as f32 * 0.25),
            (-1e6f32..1e6),
            (-1e-30f32..1e-30),
            prop::sample::select(vec![f32::MIN_POSITIVE, 1e-40, -1e-40, 1e17, -1e17, 1e18, -1e18]),
        ]
    }

    fn items(max_len: usize) -> impl Strategy<Value = Vec<Item>> {
        prop::collection::vec(
            (
                coordinate(),
                coordinate(),
                coordinate(),
                0.0f32..2.0,
                0.0f32..2.0,
                0.0f32..2.0,
            ),
            0..max_len,
        )
        .prop_map(|corners| {
            corners
                .into_iter()
                .enumerate()
                .map(|(index, (x, y, z, dx, dy, dz))| {
                    let min = Vec3::new(x, y, z);
                    // Zero-size boxes keep duplicate keys exact duplicates.
                    let size = if index % 3 == 0 {
                        Vec3::ZERO
                    } else {
                        Vec3::new(dx, dy, dz)
                    };
                    Item::new(Aabb::new(min, min + size), index as u32)
                })
                .collect()
        })
    }

    /// Checks a median split of `source` into `target` against sorting the keys.
    fn check_split(source: &[Item], target: &[Item], axis: usize, boxes: (Aabb, Aabb)) {
        let half = source.len() / 2;
        let mut indices: Vec<u32> = target.iter().map(Item::index).collect();
        indices.sort_unstable();
        let expected: Vec<u32> = (0..source.len() as u32).collect();
        assert_eq!(indices, expected, "not a permutation");
        let mut keys: Vec<f32> = source.iter().map(|it| it.key(axis)).collect();
        keys.sort_by(f32::total_cmp);
        let mut first: Vec<f32> = target[..half].iter().map(|it| it.key(axis)).collect();
        first.sort_by(f32::total_cmp);
        // Numeric equality: -0.0 and 0.0 are the same key, and may go either way.
        assert!(
            first.iter().zip(&keys[..half]).all(|(a, b)| a == b),
            "first half {first:?} is not the smallest keys {:?}",
            &keys[..half]
        );
        let second_min = target[half..]
            .iter()
            .map(|it| it.key(axis))
            .fold(f32::INFINITY, f32::min);
        assert!(first.last().is_none_or(|&a| a <= second_min));
        // The bounds of each half's centres, from the keys along each axis.
        let expected = |items: &[Item]| {
            let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
            for it in items {
                for a in 0..3 {
                    min[a] = min[a].min(it.key(a));
                    max[a] = max[a].max(it.key(a));
                }
            }
            Aabb::new(Vec3::from(min), Vec3::from(max))
        };
        let same = |a: Aabb, b: Aabb| a.min == b.min && a.max == b.max || a.is_empty() && b.is_empty();
        assert!(same(boxes.0, expected(&target[..half])), "left bounds");
        assert!(same(boxes.1, expected(&target[half..])), "right bounds");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        #[test]
        fn histogram_split_matches_sorting(source in items(2000), axis in 0usize..3) {
            let mut target = vec![Item::default(); source.len()];
            let bounds = bounds_of(&source);
            let boxes = median_partition(&source, &mut target, axis, &bounds, &mut Counts::default());
            check_split(&source, &target, axis, boxes);
        }

        #[test]
        fn rank_split_matches_sorting(source in items(SMALL_NODE + 1), axis in 0usize..3) {
            let mut target = vec![Item::default(); source.len()];
            let boxes = median_small(&source, &mut target, axis);
            check_split(&source, &target, axis, boxes);
        }
    }

    #[test]
    fn large_nodes_compute_buckets_twice_and_split_the_same() {
        let mut rng = crate::sample::Rng::new(3);
        let len = super::KEEP_BUCKETS + 4321;
        let source: Vec<Item> = (0..len as u32)
            .map(|i| {
                // Half the keys from a pool of 50 values, half spread out.
                let x = if i % 2 == 0 {
                    rng.below(50) as f32
                } else {
                    rng.below(1 << 20) as f32 * 1e-3
                };
                Item::new(Aabb::new(Vec3::new(x, 0.0, -x), Vec3::new(x + 1.0, 0.5, -x)), i)
            })
            .collect();
        let bounds = bounds_of(&source);
        for axis in 0..3 {
            let mut target = vec![Item::default(); len];
            let boxes = median_partition(&source, &mut target, axis, &bounds, &mut Counts::default());
            check_split(&source, &target, axis, boxes);
        }
    }

    #[test]
    fn all_equal_keys_and_a_far_outlier() {
        let point = |x: f32, index| Item::new(Aabb::new(Vec3::splat(x), Vec3::splat(x)), index);
        for len in [2usize, 3, 100, 1001] {
            let mut source: Vec<Item> = (0..len as u32).map(|i| point(1.0, i)).collect();
            let bounds = bounds_of(&source);
            let mut target = vec![Item::default(); len];
            let boxes = median_partition(&source, &mut target, 0, &bounds, &mut Counts::default());
            check_split(&source, &target, 0, boxes);
            source[len / 2] = point(1e18, (len / 2) as u32);
            let bounds = bounds_of(&source);
            let boxes = median_partition(&source, &mut target, 0, &bounds, &mut Counts::default());
            check_split(&source, &target, 0, boxes);
        }
    }
}
