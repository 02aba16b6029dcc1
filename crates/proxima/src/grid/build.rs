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
use crate::error::GridError;
use crate::primitive::PrimitiveSet;
use std::collections::HashMap;
use std::hash::BuildHasher;

impl<T: GridInsert, S: BuildHasher + Default> HashGrid<T, S> {
    /// Builds the grid over `set` (primitives and their mesh sources).
    ///
    /// Errors: invalid cell size or origin; a non-finite primitive; a
    /// primitive spanning more than `config.max_cells_per_primitive` cells;
    /// more than `config.max_entries` cell–primitive pairs; more than 2^32 − 1
    /// primitives; `sources` of the wrong length.
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

        // 1. Count.
        let mut slots: HashMap<Key, u32, S> = HashMap::default();
        let mut cells: Vec<Cell> = Vec::new();
        let mut counts: Vec<u32> = Vec::new();
        let mut pair_slots: Vec<u32> = Vec::with_capacity(primitives.len() * 2);
        let mut ends: Vec<u32> = Vec::with_capacity(primitives.len());
        for (index, p) in primitives.iter().enumerate() {
            p.visit_cells(&params, |cell| {
                let slot = *slots.entry(Key(cell)).or_insert_with(|| {
                    cells.push(cell);
                    counts.push(0);
                    (cells.len() - 1) as u32
                });
                counts[slot as usize] += 1;
                pair_slots.push(slot);
            })
            .map_err(|e| with_index(e, index))?;
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

/// The error with the primitive index filled in.
fn with_index(e: GridError, index: usize) -> GridError {
    match e {
        GridError::NonFinite { .. } => GridError::NonFinite { index },
        GridError::OutOfRange => GridError::PrimitiveOutOfRange { index },
        GridError::PrimitiveTooLarge { cells, limit, .. } => GridError::PrimitiveTooLarge { index, cells, limit },
        other => other,
    }
}
