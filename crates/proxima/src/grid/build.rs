//! Building a [`HashGrid`]: count, then fill.
//!
//! 1. Each primitive lists its cells ([`GridInsert::visit_cells`]); each cell
//!    gets a slot on first sight (one hash lookup per cell–primitive pair),
//!    the slot's count grows, and the slot is appended to one flat array.
//! 2. Prefix sums of the counts give each slot its range of the shared
//!    entry array.
//! 3. The flat array is replayed, writing each primitive index into its
//!    slot's next free place — primitives inside a cell end up in input order.
//!
//! Memory: 4 bytes per pair for the replay array, 4 per pair of entries, and
//! per occupied cell a map entry, its key and its start.
//!
//! Before step 1, when the primitives' cell ranges could hold more than the
//! memory budget, the cells are first only counted ([`count_within_budget`]):
//! the entries exactly and the occupied cells by a distinct-count sample, with
//! nothing stored, so that a grid beyond the budget is refused at the cost of
//! counting up to the budget, not of filling it.

use super::{Cell, CellRange, GridConfig, GridInsert, HashGrid, InsertMethod, InsertParams, Key};
use crate::budget::{GRID_BYTES_PER_CELL, GRID_BYTES_PER_ENTRY};
use crate::error::GridError;
use crate::primitive::PrimitiveSet;
use crate::query::Leaves;
use std::collections::{HashMap, HashSet};
use std::hash::BuildHasher;

impl<T: GridInsert, S: BuildHasher + Default> HashGrid<T, S> {
    /// Builds the grid over `set` (primitives and their mesh sources).
    ///
    /// Errors: invalid cell size or origin; a non-finite primitive; a
    /// primitive spanning more than `config.max_cells_per_primitive` cells;
    /// cell ranges holding more than `config.max_cell_tests` cells in all
    /// ([`GridError::CellTests`], before anything is allocated); more than
    /// `config.max_entries` cell–primitive pairs; more memory than
    /// `config.memory_budget` ([`GridError::MemoryBudget`]); more than
    /// 2^32 − 1 primitives; `sources` of the wrong length.
    pub fn build(set: PrimitiveSet<T>, config: &GridConfig) -> Result<Self, GridError> {
        let layout = config.layout()?;
        let PrimitiveSet { primitives, sources } = set;
        if primitives.len() != sources.len() {
            return Err(GridError::SourceCount {
                primitives: primitives.len(),
                sources: sources.len(),
            });
        }
        if primitives.len() >= u32::MAX as usize {
            return Err(GridError::TooManyPrimitives {
                count: primitives.len(),
            });
        }
        let max_entries = config.max_entries.min(u32::MAX as u64 - 1) as usize;
        let params = InsertParams {
            layout: &layout,
            method: config.insert,
            max_cells: config.max_cells_per_primitive,
            window: None,
        };
        // The budget, before anything is allocated: the cell ranges bound
        // both the cells tested and the entries.
        let total_work = work_estimate(&primitives, &params)?;
        if total_work > config.max_cell_tests as u128 {
            return Err(GridError::CellTests {
                cells: total_work,
                limit: config.max_cell_tests,
            });
        }
        // Every cell of every range an entry and an occupied cell: the most
        // the grid can need. Beyond the budget, count before storing.
        let most = total_work * (GRID_BYTES_PER_ENTRY + GRID_BYTES_PER_CELL) as u128;
        if most > config.memory_budget as u128 {
            count_within_budget(&primitives, &params, total_work, config)?;
        }
        let mut over_budget = false;
        let mut work_done = 0u128;
        let bytes = |entries: usize, cells: usize| {
            entries as u128 * GRID_BYTES_PER_ENTRY as u128 + cells as u128 * GRID_BYTES_PER_CELL as u128
        };

        // 1. Count.
        let mut slots: HashMap<Key, u32, S> = HashMap::default();
        let mut cells: Vec<Cell> = Vec::new();
        let mut counts: Vec<u32> = Vec::new();
        let mut pair_slots: Vec<u32> = Vec::with_capacity(primitives.len() * 2);
        let mut ends: Vec<u32> = Vec::with_capacity(primitives.len());
        for (index, p) in primitives.iter().enumerate() {
            // Past the budget nothing more is stored; the rest of this
            // primitive's cells are only counted, for the estimate.
            let mut skipped = 0usize;
            p.visit_cells(&params, |cell| {
                if over_budget {
                    skipped += 1;
                    return;
                }
                let slot = *slots.entry(Key(cell)).or_insert_with(|| {
                    cells.push(cell);
                    counts.push(0);
                    (cells.len() - 1) as u32
                });
                counts[slot as usize] += 1;
                pair_slots.push(slot);
                over_budget |= bytes(pair_slots.len(), cells.len()) > config.memory_budget as u128;
            })
            .map_err(|e| with_index(e, index))?;
            if over_budget {
                // The whole, estimated from the share of the work done (this
                // primitive's cells all counted), at the bytes per entry so far.
                work_done += range_count(p, &params);
                let held = pair_slots.len() as u128;
                let entries = ((held + skipped as u128).saturating_mul(total_work) / work_done.max(1)).max(held);
                let per_entry = bytes(pair_slots.len(), cells.len()).div_ceil(held.max(1));
                return Err(GridError::MemoryBudget {
                    what: "cell entries",
                    count: entries,
                    bytes: entries.saturating_mul(per_entry),
                    budget: config.memory_budget,
                });
            }
            work_done += range_count(p, &params);
            if pair_slots.len() > max_entries {
                return Err(GridError::TooManyCells {
                    limit: config.max_entries,
                });
            }
            ends.push(pair_slots.len() as u32);
        }

        // 2. Prefix sums.
        let mut starts = Vec::with_capacity(counts.len() + 1);
        let mut total = 0u32;
        starts.push(0);
        for &c in &counts {
            total += c;
            starts.push(total);
        }

        // 3. Fill (counts becomes the write cursor).
        let mut cursor: Vec<u32> = starts[..counts.len()].to_vec();
        drop(counts);
        let mut entries = vec![0u32; pair_slots.len()];
        let mut begin = 0usize;
        for (p, &end) in ends.iter().enumerate() {
            for &slot in &pair_slots[begin..end as usize] {
                let at = &mut cursor[slot as usize];
                entries[*at as usize] = p as u32;
                *at += 1;
            }
            begin = end as usize;
        }

        let count = primitives.len();
        let bounds = cells
            .iter()
            .map(|&c| CellRange { min: c, max: c })
            .reduce(|a, b| a.merge(&b));
        Ok(Self {
            layout,
            // Slots in input order: a slot is its primitive's index.
            leaves: Leaves::new(primitives, (0..count as u32).collect(), sources),
            slots,
            cells,
            starts,
            entries,
            bounds,
        })
    }
}

/// The sum of the cell counts of the primitives' cell ranges, with the
/// per-primitive checks of the insertion made in the same order (so the same
/// error comes first): a non-finite box, a box out of range, a box over the
/// limit.
pub(super) fn work_estimate<T: GridInsert>(primitives: &[T], params: &InsertParams<'_>) -> Result<u128, GridError> {
    let mut total = 0u128;
    for (index, p) in primitives.iter().enumerate() {
        let bounds = p.bounds();
        if !bounds.is_finite() {
            return Err(GridError::NonFinite { index });
        }
        let range = params.layout.cell_range(&bounds).map_err(|e| with_index(e, index))?;
        let cells = range.count();
        if cells > params.max_cells as u128 {
            return Err(GridError::PrimitiveTooLarge {
                index,
                cells,
                limit: params.max_cells,
            });
        }
        total += cells;
    }
    Ok(total)
}

/// Sampled cells held at most by [`DistinctSample`]: its estimate is off by
/// about 1/sqrt(4096), 1.6% (one standard deviation), once it samples.
const SAMPLE_CELLS: usize = 1 << 13;

/// How much less than its estimate of the occupied cells
/// [`count_within_budget`] assumes when it refuses: six standard deviations
/// of the sample's error, so that a grid within the budget is not refused
/// (and the build's own exact count stays the last word).
const SAMPLE_MARGIN: f64 = 0.9;

/// Counts the entries (exactly) and the occupied cells (by a distinct-count
/// sample) of the grid the build would make, visiting the same cells with
/// nothing stored, and fails with [`GridError::MemoryBudget`] as soon as
/// those counted so far need more than the budget, at the bytes the build
/// counts ([`GRID_BYTES_PER_ENTRY`], [`GRID_BYTES_PER_CELL`]). The count and
/// the bytes reported estimate the whole from the share of the work done, as
/// the build's do. Stops counting (and leaves the rest to the build) once the
/// entries pass `config.max_entries`.
fn count_within_budget<T: GridInsert>(
    primitives: &[T],
    params: &InsertParams<'_>,
    total_work: u128,
    config: &GridConfig,
) -> Result<(), GridError> {
    // The scan-line insertion finds the same cells as the classic one with fewer tests.
    let params = InsertParams {
        method: InsertMethod::Scanline,
        ..*params
    };
    let mut entries = 0u64;
    let mut cells = DistinctSample::default();
    let mut work_done = 0u128;
    for (index, p) in primitives.iter().enumerate() {
        p.visit_cells(&params, |cell| {
            entries += 1;
            cells.insert(cell);
        })
        .map_err(|e| with_index(e, index))?;
        work_done += range_count(p, &params);
        let need =
            |cells: f64| entries as u128 * GRID_BYTES_PER_ENTRY as u128 + (cells * GRID_BYTES_PER_CELL as f64) as u128;
        let (estimate, low) = cells.estimate();
        if need(low) > config.memory_budget as u128 {
            let count = (entries as u128 * total_work / work_done.max(1)).max(entries as u128);
            let per_entry = need(estimate).div_ceil(entries.max(1) as u128);
            return Err(GridError::MemoryBudget {
                what: "cell entries",
                count,
                bytes: count.saturating_mul(per_entry),
                budget: config.memory_budget,
            });
        }
        if entries > config.max_entries {
            break;
        }
    }
    Ok(())
}

/// A count of distinct cells in bounded memory (distinct sampling): a cell is
/// kept when its hash lies in the lowest `2^-level` of the hash range, and
/// the level rises (halving what is kept) whenever more than
/// [`SAMPLE_CELLS`] are kept; the kept cells times `2^level` estimate the
/// distinct cells seen, exactly while the level is 0.
#[derive(Default)]
struct DistinctSample {
    level: u32,
    kept: HashSet<u64>,
}

impl DistinctSample {
    fn insert(&mut self, cell: Cell) {
        let hash = cell_hash(cell);
        if hash > u64::MAX >> self.level {
            return;
        }
        self.kept.insert(hash);
        if self.kept.len() > SAMPLE_CELLS {
            self.level += 1;
            let threshold = u64::MAX >> self.level;
            self.kept.retain(|&h| h <= threshold);
        }
    }

    /// The estimate of the distinct cells seen, and a low estimate (less the
    /// margin once sampling).
    fn estimate(&self) -> (f64, f64) {
        let estimate = self.kept.len() as f64 * (1u64 << self.level) as f64;
        let low = if self.level == 0 {
            estimate
        } else {
            estimate * SAMPLE_MARGIN
        };
        (estimate, low)
    }
}

/// A 64-bit hash of a cell whose bits are all well mixed (SplitMix64's
/// finalizer over each index in turn), as distinct sampling requires.
fn cell_hash(cell: Cell) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    cell.iter().fold(0, |h, &i| mix(h ^ i as u64))
}

/// The cells of `p`'s cell range (0 when it has none).
fn range_count<T: GridInsert>(p: &T, params: &InsertParams<'_>) -> u128 {
    params.layout.cell_range(&p.bounds()).map_or(0, |r| r.count())
}

/// The error with the primitive index filled in.
fn with_index(e: GridError, index: usize) -> GridError {
    match e {
        GridError::NonFinite { .. } => GridError::NonFinite { index },
        GridError::OutOfRange => GridError::PrimitiveOutOfRange { index },
        GridError::PrimitiveTooLarge { cells, limit, .. } => GridError::PrimitiveTooLarge { index, cells, limit },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distinct_sample_counts_within_its_margin() {
        // Exact while it holds every cell; then within a few of its 1.6%
        // standard deviations, whatever the repeats and the cells' layout.
        let mut sample = DistinctSample::default();
        for i in 0..SAMPLE_CELLS as i64 {
            sample.insert([i, -i, 7]);
            sample.insert([i, -i, 7]);
        }
        assert_eq!(sample.estimate(), (SAMPLE_CELLS as f64, SAMPLE_CELLS as f64));
        for (n, layout) in [(100_000i64, 0), (1_000_000, 1), (3_000_000, 2)] {
            let mut sample = DistinctSample::default();
            for i in 0..n {
                let cell = match layout {
                    0 => [i, 0, 0],
                    1 => [i % 1000, i / 1000, 0],
                    _ => [i % 100, (i / 100) % 100, i / 10_000],
                };
                sample.insert(cell);
                sample.insert(cell);
            }
            let (estimate, low) = sample.estimate();
            let error = (estimate - n as f64).abs() / n as f64;
            assert!(error < 0.05, "{n} cells estimated as {estimate}");
            assert!(low < n as f64 && low == estimate * SAMPLE_MARGIN);
            assert!(sample.kept.len() <= SAMPLE_CELLS);
        }
    }
}
