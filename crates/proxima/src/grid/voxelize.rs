//! Surface voxelization: the cells of an `N × N × N` grid that a triangle soup
//! touches.
//!
//! The grid covers a given box (usually the mesh's bounding box): cubic cells
//! of side `longest side / N`, grid origin at the box minimum (rounded down
//! by less than `2^-23` cell in the rare case where the minimum's bits reach
//! far below the cell's, so that every cell plane stays exact), and only cells
//! with indices in `[0, N)` on each axis — a vertex on the box maximum touches
//! cell `N`'s closed box but does not open it. A cell is occupied when some
//! triangle shares at least one point with its closed box (the conservative
//! count: touching counts), decided by the same insertion as the hash grid.
//!
//! Storage is a dense bitset (x fastest, then y, each z slice padded to whole
//! 64-bit words) when `N³` bits fit [`VoxelConfig::dense_limit_bits`]
//! (2^30 bits = 128 MiB, i.e. 1024³, by default) and the memory budget,
//! otherwise a sorted list of occupied cells gathered through a hash set.
//! Before anything is allocated, the cells of the triangles' cell ranges
//! (clipped to the grid) are counted: an upper bound on the work, checked
//! against [`VoxelConfig::max_cell_tests`].
//!
//! In parallel, the z slices are cut into chunks (a few per thread), the
//! triangles are bucketed by the chunks their z extent may reach, and each
//! chunk is filled by one task with the insertion restricted to its slices:
//! no atomics, no shared writes, the same cells as sequentially.

use super::insert::InsertParams;
use super::{Cell, CellRange, FastHash, GridInsert, GridLayout, InsertMethod, Key};
use crate::aabb::Aabb;
use crate::budget::VOXEL_BYTES_PER_SPARSE_CELL;
use crate::error::GridError;
use crate::math::{DVec3, Vec3};
use crate::primitive::{Bounded, Triangle};
use rayon::prelude::*;
use std::collections::HashSet;
use std::sync::atomic::{AtomicU64, Ordering};

/// Default of [`VoxelConfig::dense_limit_bits`]: 2^30 bits (128 MiB, 1024³ cells).
pub const DEFAULT_DENSE_LIMIT_BITS: u64 = 1 << 30;

/// Parameters of [`voxelize`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelConfig {
    /// Cells along the longest side of the box (at least 1).
    pub resolution: u32,
    /// A dense bitset is used when `resolution³` is at most this many bits.
    pub dense_limit_bits: u64,
    /// Sparse storage: more occupied cells than this is an error.
    pub max_occupied: u64,
    /// How triangles find their cells (same cells either way).
    pub insert: InsertMethod,
    /// Use the rayon thread pool.
    pub parallel: bool,
    /// The triangles' cell ranges, clipped to the grid, may hold at most this
    /// many cells in all (an upper bound on the cells tested; checked before
    /// anything is allocated).
    pub max_cell_tests: u64,
    /// Bytes the storage may take: a dense bitset that would not fit is not
    /// used, and sparse storage stops with [`GridError::MemoryBudget`] before
    /// it passes the budget (at the measured bytes per cell, [`crate::budget`]).
    pub memory_budget: u64,
}

impl VoxelConfig {
    /// `resolution` cells along the longest side, scan-line insertion, in
    /// parallel, default limits and memory budget ([`crate::budget`]).
    pub fn new(resolution: u32) -> Self {
        Self {
            resolution,
            dense_limit_bits: DEFAULT_DENSE_LIMIT_BITS,
            max_occupied: super::DEFAULT_MAX_ENTRIES,
            insert: InsertMethod::Scanline,
            parallel: true,
            max_cell_tests: crate::budget::DEFAULT_MAX_CELL_TESTS,
            memory_budget: crate::budget::default_memory_budget(),
        }
    }
}

/// The occupied cells of a voxelization.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelGrid {
    resolution: u32,
    layout: GridLayout,
    storage: Storage,
    occupied: u64,
}

#[derive(Clone, Debug, PartialEq)]
enum Storage {
    /// Bit `(k · words_per_slice · 64) + j · N + i`.
    Dense { words: Vec<u64>, words_per_slice: usize },
    /// Sorted by (k, j, i).
    Sparse(Vec<Cell>),
}

/// The grid origin for `n` cells of side `cell` from `min`: `min` itself,
/// unless its bits reach so far below the cell's that the planes of `n`
/// cells would not be exact (a minimum of `1e-9` beside cells of `0.01`):
/// then `min` rounded down to a multiple of the cell's lowest bit, a move of
/// less than `2^-23` cell (see [`GridLayout`]'s exact planes).
fn grid_origin(min: Vec3, cell: f32, n: u32) -> Vec3 {
    let Some((_, low)) = crate::exact::parts(cell as f64) else {
        return min;
    };
    let step = 2f64.powi(low);
    Vec3::from_array(std::array::from_fn(|a| {
        if super::layout::exact_index_limit(min[a], cell) > n as i64 {
            min[a]
        } else {
            // A multiple of `step` no larger in magnitude than |min| + step:
            // an f32 when rounding down is needed at all (|min| < cell).
            ((min[a] as f64 / step).floor() * step) as f32
        }
    }))
}

/// Voxelizes `triangles` over `bounds` (see the module documentation).
///
/// Errors: resolution 0 ([`GridError::Resolution`]); a box that is empty, not
/// finite or of zero size, so that no cell size follows from it
/// ([`GridError::DegenerateBounds`]); a non-finite triangle; cell
/// ranges holding more than `config.max_cell_tests` cells
/// ([`GridError::CellTests`], before anything is allocated); more occupied
/// cells than `config.max_occupied` in sparse storage; sparse storage beyond
/// `config.memory_budget` ([`GridError::MemoryBudget`]).
///
/// ```
/// use proxima::grid::{VoxelConfig, voxelize};
/// use proxima::{Aabb, Triangle, Vec3};
/// // A square in the plane z = 0 made of two triangles, voxelized at 4³.
/// let (a, b, c, d) = (Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0), Vec3::new(4.0, 4.0, 0.0), Vec3::new(0.0, 4.0, 0.0));
/// let tris = [Triangle::new(a, b, c), Triangle::new(a, c, d)];
/// let bounds = Aabb::new(Vec3::ZERO, Vec3::new(4.0, 4.0, 4.0));
/// let vox = voxelize(&tris, &bounds, &VoxelConfig::new(4)).unwrap();
/// // Only the 16 cells of the bottom layer: z = 0 touches no cell k = -1 inside [0, 4).
/// assert_eq!(vox.occupied(), 16);
/// assert!(vox.contains([3, 3, 0]) && !vox.contains([0, 0, 1]));
/// ```
pub fn voxelize(triangles: &[Triangle], bounds: &Aabb, config: &VoxelConfig) -> Result<VoxelGrid, GridError> {
    let n = config.resolution;
    if n == 0 {
        return Err(GridError::Resolution);
    }
    let side = bounds.size().max_element();
    let mut cell = side / n as f32;
    // A point-like (or empty) box has no extent to divide: say so, rather than
    // blaming a cell size the caller never gave.
    if !(cell > 0.0 && cell.is_finite()) {
        return Err(GridError::DegenerateBounds);
    }
    // Rounded to f32 (the side, then the quotient), the cell may be a little
    // short: the grid would end before the box and the cells clipped away
    // would miss the triangles there. Each step moves the end by about one
    // ulp of the side, so this takes a step or two.
    let reaches = |origin: Vec3, cell: f32| {
        let end = origin.as_dvec3() + DVec3::splat(cell as f64 * n as f64);
        end.cmpge(bounds.max.as_dvec3()).all()
    };
    let mut origin = grid_origin(bounds.min, cell, n);
    while !reaches(origin, cell) && cell.is_finite() {
        cell = cell.next_up();
        origin = grid_origin(bounds.min, cell, n);
    }
    let layout = GridLayout::new(origin, Vec3::splat(cell))?;
    // The budget, before anything is allocated (`N³` overflows `u64` from
    // N = 2^22 on: counted in `u128`).
    let n128 = n as u128;
    let whole = CellRange {
        min: [0; 3],
        max: [n as i64 - 1; 3],
    };
    let mut work = 0u128;
    for tri in triangles {
        if let Ok(range) = layout.cell_range(&tri.bounds()) {
            work += range.intersection(&whole).count();
        }
    }
    if work > config.max_cell_tests as u128 {
        return Err(GridError::CellTests {
            cells: work,
            limit: config.max_cell_tests,
        });
    }
    let dense_bytes = (n128 * n128).div_ceil(64) * 8 * n128;
    let dense = n128 * n128 * n128 <= config.dense_limit_bits as u128 && dense_bytes <= config.memory_budget as u128;
    let budget_cells = config.memory_budget / VOXEL_BYTES_PER_SPARSE_CELL;
    let nn = n as usize * n as usize;
    let slices = n as usize;

    // Chunks of z slices, and the triangles each may concern.
    let chunks = if config.parallel {
        (rayon::current_num_threads() * 4).clamp(1, slices)
    } else {
        1
    };
    let per_chunk = slices.div_ceil(chunks);
    let chunks = slices.div_ceil(per_chunk);
    let buckets: Vec<Vec<u32>> = if chunks == 1 {
        Vec::new()
    } else {
        let mut buckets = vec![Vec::with_capacity(triangles.len() / chunks + 16); chunks];
        let (z0, dz) = (layout.origin().z, cell);
        for (t, tri) in triangles.iter().enumerate() {
            let (lo, hi) = (tri.a.z.min(tri.b.z).min(tri.c.z), tri.a.z.max(tri.b.z).max(tri.c.z));
            // A generous estimate: the exact window test inside each chunk decides.
            // Truncation instead of floor (no libm call): off by one at most
            // for negative values, which the margin of one slice covers.
            let k0 = (((lo - z0) / dz) as i64 - 1).clamp(0, slices as i64 - 1) as usize;
            let k1 = (((hi - z0) / dz) as i64 + 1).clamp(0, slices as i64 - 1) as usize;
            for bucket in &mut buckets[k0 / per_chunk..=k1 / per_chunk] {
                bucket.push(t as u32);
            }
        }
        buckets
    };
    let chunk_tris = |c: usize| -> Box<dyn Iterator<Item = (usize, &Triangle)> + Send + '_> {
        if chunks == 1 {
            Box::new(triangles.iter().enumerate())
        } else {
            Box::new(buckets[c].iter().map(|&t| (t as usize, &triangles[t as usize])))
        }
    };
    let params = |c: usize| InsertParams {
        layout: &layout,
        method: config.insert,
        max_cells: u64::MAX,
        window: Some(CellRange {
            min: [0, 0, (c * per_chunk) as i64],
            max: [
                n as i64 - 1,
                n as i64 - 1,
                (((c + 1) * per_chunk).min(slices) - 1) as i64,
            ],
        }),
    };
    let indexed = |e: GridError, index: usize| match e {
        GridError::NonFinite { .. } => GridError::NonFinite { index },
        other => other,
    };

    let (storage, occupied) = if dense {
        let words_per_slice = nn.div_ceil(64);
        let mut words = vec![0u64; words_per_slice * slices];
        let fill = |c: usize, out: &mut [u64]| -> Result<(), GridError> {
            let p = params(c);
            let k0 = (c * per_chunk) as i64;
            for (index, tri) in chunk_tris(c) {
                tri.visit_cells(&p, |cell| {
                    let bit = (cell[2] - k0) as usize * words_per_slice * 64
                        + cell[1] as usize * n as usize
                        + cell[0] as usize;
                    out[bit >> 6] |= 1u64 << (bit & 63);
                })
                .map_err(|e| indexed(e, index))?;
            }
            Ok(())
        };
        let chunk_words = words_per_slice * per_chunk;
        if chunks == 1 {
            fill(0, &mut words)?;
        } else {
            words
                .par_chunks_mut(chunk_words)
                .enumerate()
                .try_for_each(|(c, out)| fill(c, out))?;
        }
        let occupied = words.iter().map(|w| w.count_ones() as u64).sum();
        (Storage::Dense { words, words_per_slice }, occupied)
    } else {
        let limit = config.max_occupied;
        // Cells held by all chunks (each adds its own after every triangle):
        // the storage stops at the budget, never past it.
        let stored = AtomicU64::new(0);
        let cell_limit = limit.min(budget_cells);
        // Cells of the triangles' ranges done so far, by all chunks.
        let done = AtomicU64::new(0);
        let over = |held: u64| {
            if limit <= budget_cells {
                GridError::TooManyCells { limit }
            } else {
                // The whole, estimated from the share of the work done
                // (`held` counts the last triangle's cells in full).
                let done = done.load(Ordering::Relaxed).max(1) as u128;
                let count = (held as u128 * work / done).max(held as u128);
                GridError::MemoryBudget {
                    what: "occupied cells",
                    count,
                    bytes: count * VOXEL_BYTES_PER_SPARSE_CELL as u128,
                    budget: config.memory_budget,
                }
            }
        };
        let collect = |c: usize| -> Result<Vec<Cell>, GridError> {
            let p = params(c);
            let mut set: HashSet<Key, FastHash> = HashSet::default();
            // Cells of this chunk already added to `stored`: the others
            // see them within 1024 new cells, so all chunks together never
            // pass the limit by more than 1024 cells per thread.
            let mut reported = 0u64;
            let mut total = 0u64;
            for (index, tri) in chunk_tris(c) {
                let mut report = |held: u64, reported: &mut u64| {
                    total = stored.fetch_add(held - *reported, Ordering::Relaxed) + (held - *reported);
                    *reported = held;
                    total > cell_limit
                };
                let mut full = false;
                // Every cell of the triangle is counted, stored or not, for the estimate.
                let (before, mut visits) = (set.len() as u64, 0u64);
                tri.visit_cells(&p, |cell| {
                    visits += 1;
                    if !full && set.insert(Key(cell)) && set.len() as u64 - reported >= 1024 {
                        full = report(set.len() as u64, &mut reported);
                    }
                })
                .map_err(|e| indexed(e, index))?;
                if let (Ok(range), Some(window)) = (layout.cell_range(&tri.bounds()), p.window) {
                    done.fetch_add(range.intersection(&window).count() as u64, Ordering::Relaxed);
                }
                full |= report(set.len() as u64, &mut reported);
                if full {
                    return Err(over(total - (set.len() as u64 - before) + visits));
                }
            }
            let mut cells: Vec<Cell> = set.into_iter().map(|k| k.0).collect();
            cells.sort_unstable_by_key(|c| [c[2], c[1], c[0]]);
            Ok(cells)
        };
        let parts: Vec<Vec<Cell>> = if chunks == 1 {
            vec![collect(0)?]
        } else {
            (0..chunks).into_par_iter().map(collect).collect::<Result<_, _>>()?
        };
        let total: usize = parts.iter().map(Vec::len).sum();
        if total as u64 > cell_limit {
            return Err(over(total as u64));
        }
        let cells = parts.concat();
        (Storage::Sparse(cells), total as u64)
    };
    Ok(VoxelGrid {
        resolution: n,
        layout,
        storage,
        occupied,
    })
}

impl VoxelGrid {
    /// Cells along each axis.
    pub fn resolution(&self) -> u32 {
        self.resolution
    }

    /// The cell placement (origin at the box minimum, cubic cells).
    pub fn layout(&self) -> &GridLayout {
        &self.layout
    }

    /// Side of the cubic cells.
    pub fn cell_size(&self) -> f32 {
        self.layout.cell_size().x
    }

    /// Minimum corner of cell `(0, 0, 0)`.
    pub fn origin(&self) -> Vec3 {
        self.layout.origin()
    }

    /// Number of occupied cells.
    pub fn occupied(&self) -> u64 {
        self.occupied
    }

    /// `true` when the cells are stored as a dense bitset.
    pub fn is_dense(&self) -> bool {
        matches!(self.storage, Storage::Dense { .. })
    }

    /// `true` when `cell` is occupied (cells outside `[0, N)³` never are).
    pub fn contains(&self, cell: Cell) -> bool {
        let n = self.resolution as i64;
        if cell.iter().any(|&c| c < 0 || c >= n) {
            return false;
        }
        match &self.storage {
            Storage::Dense { words, words_per_slice } => {
                let bit = cell[2] as usize * words_per_slice * 64 + (cell[1] * n + cell[0]) as usize;
                words[bit >> 6] >> (bit & 63) & 1 == 1
            }
            Storage::Sparse(cells) => cells
                .binary_search_by_key(&[cell[2], cell[1], cell[0]], |c| [c[2], c[1], c[0]])
                .is_ok(),
        }
    }

    /// Calls `f` for every occupied cell, x fastest, then y, then z.
    pub fn for_each_cell(&self, mut f: impl FnMut(Cell)) {
        let n = self.resolution as usize;
        match &self.storage {
            Storage::Dense { words, words_per_slice } => {
                for (k, slice) in words.chunks(*words_per_slice).enumerate() {
                    for (w, &word) in slice.iter().enumerate() {
                        let mut bits = word;
                        while bits != 0 {
                            let pos = w * 64 + bits.trailing_zeros() as usize;
                            f([(pos % n) as i64, (pos / n) as i64, k as i64]);
                            bits &= bits - 1;
                        }
                    }
                }
            }
            Storage::Sparse(cells) => cells.iter().copied().for_each(f),
        }
    }

    /// The occupied cells, x fastest, then y, then z, without a copy.
    ///
    /// ```
    /// use proxima::grid::{VoxelConfig, voxelize};
    /// use proxima::{Aabb, Triangle, Vec3};
    /// let tri = Triangle::new(Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0));
    /// let vox = voxelize(&[tri], &Aabb::new(Vec3::ZERO, Vec3::splat(2.0)), &VoxelConfig::new(2)).unwrap();
    /// assert_eq!(vox.iter().collect::<Vec<_>>(), vox.cells());
    /// assert_eq!(vox.iter().count() as u64, vox.occupied());
    /// ```
    pub fn iter(&self) -> Box<dyn Iterator<Item = Cell> + '_> {
        let n = self.resolution as usize;
        match &self.storage {
            Storage::Dense { words, words_per_slice } => {
                Box::new(words.chunks(*words_per_slice).enumerate().flat_map(move |(k, slice)| {
                    slice.iter().enumerate().flat_map(move |(w, &word)| {
                        let mut bits = word;
                        std::iter::from_fn(move || {
                            (bits != 0).then(|| {
                                let pos = w * 64 + bits.trailing_zeros() as usize;
                                bits &= bits - 1;
                                [(pos % n) as i64, (pos / n) as i64, k as i64]
                            })
                        })
                    })
                }))
            }
            Storage::Sparse(cells) => Box::new(cells.iter().copied()),
        }
    }

    /// The occupied cells, x fastest, then y, then z.
    pub fn cells(&self) -> Vec<Cell> {
        let mut out = Vec::with_capacity(self.occupied as usize);
        self.for_each_cell(|c| out.push(c));
        out
    }
}
