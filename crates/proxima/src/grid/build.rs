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

use super::{Cell, CellRange, GridConfig, GridInsert, HashGrid, InsertParams, Key};
use crate::budget::{GRID_BYTES_PER_CELL, GRID_BYTES_PER_ENTRY};
use crate::error::GridError;
use crate::primitive::PrimitiveSet;
use std::collections::HashMap;
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

        let bounds = cells
            .iter()
            .map(|&c| CellRange { min: c, max: c })
            .reduce(|a, b| a.merge(&b));
        Ok(Self {
            layout,
            primitives,
            sources,
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
