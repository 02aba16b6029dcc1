//! The spatial hash grid: a hash map from integer cell `(i, j, k)` to the
//! primitives that overlap the cell, storing only occupied cells.
//!
//! One file per operation: cell placement in `layout.rs`, the hash functions
//! in `hasher.rs`, the cells of a range (plain or through an exact cell test)
//! in `cells.rs`, the classic insertion (box range, then exact test per cell)
//! in `insert.rs` (for convex polygons in `polygon_insert.rs`), the scan-line insertion in `scanline.rs`, the build in
//! `build.rs`, the cells a ray crosses ([`GridTraversal`]) in `traversal.rs`, the
//! first-hit ray query (the walk of [`RayQuery`](crate::query::RayQuery)) in
//! `ray.rs`, dense/sparse surface voxelization in `voxelize.rs` and statistics
//! in `stats.rs`.
//!
//! # Conventions
//!
//! - Cell `(0, 0, 0)` starts at the grid origin (the world origin by default);
//!   indices are `i64` of any sign. Cell boundaries are defined once, in
//!   [`GridLayout`].
//! - Cells and primitives are **closed**: a primitive that only touches a cell
//!   (a vertex on its face, an edge along its edge, a face in its face plane)
//!   is stored in that cell. So a primitive lying on a boundary plane is in the
//!   cells on both sides, and a vertex exactly on a cell corner is in all eight
//!   cells around it.
//! - Contents are stored compactly: one shared array of primitive indices,
//!   one range of it per occupied cell (filled count-then-fill), and a hash
//!   map from cell to range. Inside a cell, primitives are in input order.
//!
//! ```
//! use proxima::grid::{GridConfig, HashGrid};
//! use proxima::{Mesh, Vec3};
//! let mesh = Mesh::from_triangles(
//!     vec![Vec3::new(0.25, 0.25, 1.0), Vec3::new(1.75, 0.25, 1.0), Vec3::new(0.25, 1.75, 1.0)],
//!     &[[0, 1, 2]],
//! )
//! .unwrap();
//! let grid: HashGrid<_> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(1.0)).unwrap();
//! // The triangle lies in the plane z = 1, shared by the cells k = 0 and k = 1;
//! // its hypotenuse x + y = 2 passes exactly through the corner (1, 1) of the
//! // cells (1, 1, k), which it therefore touches.
//! assert_eq!(grid.occupied_count(), 8);
//! assert_eq!(grid.cell(&[1, 1, 0]), &[0]);
//! assert!(grid.cell(&[2, 0, 0]).is_empty());
//! ```

mod build;
mod cells;
mod error;
mod hasher;
mod insert;
mod layout;
mod polygon_insert;
mod ray;
mod scanline;
mod stats;
mod traversal;
mod voxelize;

pub use error::GridError;
pub use hasher::{ClassicHash, ClassicHasher, FastHash, FastHasher};
pub use insert::{GridInsert, InsertParams};
pub(crate) use layout::last_true;
pub use layout::{CellRange, GridLayout, MAX_CELL_INDEX};
pub use stats::GridStats;
pub use traversal::{GridTraversal, TraversalConfig, TraversalStep};
pub use voxelize::{VoxelConfig, VoxelGrid, voxelize};

use crate::math::Vec3;
use crate::query::Leaves;
use std::collections::HashMap;
use std::hash::{BuildHasher, Hash, Hasher};

/// Integer cell coordinates `(i, j, k)`.
pub type Cell = [i64; 3];

/// Default of [`GridConfig::max_cells_per_primitive`]: 2^27 cells.
pub const DEFAULT_MAX_CELLS_PER_PRIMITIVE: u64 = 1 << 27;
/// Default of [`GridConfig::max_entries`]: 2^28 cell–primitive pairs. The
/// memory budget ([`GridConfig::memory_budget`]) usually binds first: a build
/// holds about [`GRID_BYTES_PER_ENTRY`](crate::budget::GRID_BYTES_PER_ENTRY)
/// bytes per pair plus [`GRID_BYTES_PER_CELL`](crate::budget::GRID_BYTES_PER_CELL)
/// per occupied cell at its peak.
pub const DEFAULT_MAX_ENTRIES: u64 = 1 << 28;

/// How a primitive finds the cells it overlaps. Both give exactly the same
/// cells; they differ in speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum InsertMethod {
    /// The classic design: every cell of the primitive's bounding box is tested
    /// exactly, and kept when the primitive really overlaps it.
    #[default]
    Classic,
    /// Scan-line: the primitive is clipped slab by slab and row by row, and only
    /// the cells of each row that the clipped piece spans are tested (with the
    /// same exact test). Faster when triangles span many cells.
    Scanline,
}

/// Parameters of a [`HashGrid`] build.
///
/// ```
/// use proxima::grid::{GridConfig, InsertMethod};
/// use proxima::Vec3;
/// let config = GridConfig {
///     origin: Vec3::new(-1.0, -1.0, -1.0),
///     insert: InsertMethod::Scanline,
///     ..GridConfig::new(Vec3::new(0.5, 0.5, 2.0))
/// };
/// assert!(config.layout().is_ok());
/// assert!(GridConfig::cubic(0.0).layout().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridConfig {
    /// Cell extents along x, y and z (finite and positive).
    pub cell_size: Vec3,
    /// Minimum corner of cell `(0, 0, 0)`.
    pub origin: Vec3,
    /// How cells are found for each primitive.
    pub insert: InsertMethod,
    /// A primitive whose bounding box spans more cells than this is an error.
    pub max_cells_per_primitive: u64,
    /// More cell–primitive pairs than this in the whole grid is an error
    /// (at most `u32::MAX`).
    pub max_entries: u64,
    /// The primitives' cell ranges may hold at most this many cells in all
    /// (an upper bound on the cells tested; checked before the build).
    pub max_cell_tests: u64,
    /// Bytes the build may hold, counted at the measured bytes per entry and
    /// per occupied cell ([`crate::budget`]); the build stops with
    /// [`GridError::MemoryBudget`] before passing it.
    pub memory_budget: u64,
}

impl GridConfig {
    /// Cells of extents `cell_size`, grid origin at the world origin, classic
    /// insertion, default limits and memory budget ([`crate::budget`]).
    pub fn new(cell_size: Vec3) -> Self {
        Self {
            cell_size,
            origin: Vec3::ZERO,
            insert: InsertMethod::Classic,
            max_cells_per_primitive: DEFAULT_MAX_CELLS_PER_PRIMITIVE,
            max_entries: DEFAULT_MAX_ENTRIES,
            max_cell_tests: crate::budget::DEFAULT_MAX_CELL_TESTS,
            memory_budget: crate::budget::default_memory_budget(),
        }
    }

    /// Cubic cells of side `size` (see [`GridConfig::new`]).
    pub fn cubic(size: f32) -> Self {
        Self::new(Vec3::splat(size))
    }

    /// The validated cell placement.
    pub fn layout(&self) -> Result<GridLayout, GridError> {
        GridLayout::new(self.origin, self.cell_size)
    }
}

/// The hash map key of a cell: hashes its three indices with `write_i64`, in
/// order, which is what [`ClassicHash`] and [`FastHash`] expect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Key(Cell);

impl Hash for Key {
    #[inline]
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_i64(self.0[0]);
        state.write_i64(self.0[1]);
        state.write_i64(self.0[2]);
    }
}

/// A spatial hash grid over primitives of type `T`, with cell keys hashed by `S`.
///
/// Build it with [`HashGrid::build`]; ask [`cell`](HashGrid::cell) for the
/// primitives of a cell, walk the [`occupied`](HashGrid::occupied) cells, or
/// (for triangles) cast a ray with [`first_hit`](HashGrid::first_hit) or any
/// query of [`RayQuery`](crate::query::RayQuery).
#[derive(Clone, Debug)]
pub struct HashGrid<T, S = ClassicHash> {
    layout: GridLayout,
    /// The primitives in input order (slot = index), with their sources:
    /// what the ray queries of [`RayQuery`](crate::query::RayQuery) answer from.
    leaves: Leaves<T>,
    /// Cell → slot.
    slots: HashMap<Key, u32, S>,
    /// Slot → cell, in order of first insertion.
    cells: Vec<Cell>,
    /// Slot `s` holds `entries[starts[s]..starts[s + 1]]`.
    starts: Vec<u32>,
    /// Primitive indices, grouped by slot.
    entries: Vec<u32>,
    /// The smallest cell range holding every occupied cell.
    bounds: Option<CellRange>,
}

impl<T, S: BuildHasher> HashGrid<T, S> {
    /// The cell placement.
    #[inline]
    pub fn layout(&self) -> &GridLayout {
        &self.layout
    }

    /// The primitives, in input order.
    #[inline]
    pub fn primitives(&self) -> &[T] {
        self.leaves.primitives()
    }

    /// `sources()[p]`: the mesh element primitive `p` came from.
    #[inline]
    pub fn sources(&self) -> &[u32] {
        self.leaves.sources()
    }

    /// Number of primitives.
    #[inline]
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// `true` when the grid holds no primitive.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }

    /// Number of occupied cells.
    #[inline]
    pub fn occupied_count(&self) -> usize {
        self.cells.len()
    }

    /// Number of cell–primitive pairs.
    #[inline]
    pub fn entry_count(&self) -> usize {
        self.entries.len()
    }

    /// The smallest cell range holding every occupied cell (`None` when empty).
    #[inline]
    pub fn bounds(&self) -> Option<CellRange> {
        self.bounds
    }

    /// The primitives (indices into [`primitives`](HashGrid::primitives)) that
    /// overlap `cell`, in increasing order; empty for an unoccupied cell.
    #[inline]
    pub fn cell(&self, cell: &Cell) -> &[u32] {
        match self.slots.get(&Key(*cell)) {
            Some(&slot) => self.slot(slot as usize),
            None => &[],
        }
    }

    /// The contents of slot `s`.
    #[inline]
    fn slot(&self, s: usize) -> &[u32] {
        &self.entries[self.starts[s] as usize..self.starts[s + 1] as usize]
    }

    /// The occupied cells with their primitives, in order of first insertion.
    pub fn occupied(&self) -> impl ExactSizeIterator<Item = (Cell, &[u32])> + '_ {
        self.cells.iter().enumerate().map(|(s, &c)| (c, self.slot(s)))
    }

    /// The primitives of the half-open cell holding `p` (see [`GridLayout::cell_of`]).
    pub fn at_point(&self, p: Vec3) -> Result<&[u32], GridError> {
        Ok(self.cell(&self.layout.cell_of(p)?))
    }
}
