//! Statistics of a built grid.

use super::{Cell, HashGrid, Key};
use std::hash::BuildHasher;
use std::mem::size_of;

/// Occupancy and memory of a [`HashGrid`].
///
/// ```
/// use proxima::grid::{GridConfig, HashGrid};
/// use proxima::{Mesh, Vec3};
/// let mesh = Mesh::from_triangles(vec![Vec3::splat(0.1), Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.9, 0.1)], &[[0, 1, 2]]).unwrap();
/// let grid: HashGrid<_> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(1.0)).unwrap();
/// let stats = grid.stats();
/// assert_eq!((stats.primitives, stats.occupied_cells, stats.entries), (1, 1, 1));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridStats {
    /// Number of primitives.
    pub primitives: usize,
    /// Number of occupied cells.
    pub occupied_cells: usize,
    /// Number of cell–primitive pairs.
    pub entries: usize,
    /// Most primitives in one cell (0 for an empty grid).
    pub max_per_cell: usize,
    /// Mean number of primitives per occupied cell (0 for an empty grid).
    pub mean_per_cell: f64,
    /// Approximate heap memory of the grid, primitives included.
    pub memory_bytes: usize,
}

impl<T, S: BuildHasher> HashGrid<T, S> {
    /// Occupancy and memory figures.
    pub fn stats(&self) -> GridStats {
        let occupied = self.cells.len();
        let max_per_cell = self
            .starts
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0);
        let mean_per_cell = if occupied == 0 {
            0.0
        } else {
            self.entries.len() as f64 / occupied as f64
        };
        // SwissTable: one (key, value) slot plus one control byte per bucket.
        let map = self.slots.capacity() * (size_of::<(Key, u32)>() + 1);
        let memory_bytes = map
            + self.cells.capacity() * size_of::<Cell>()
            + self.starts.capacity() * 4
            + self.entries.capacity() * 4
            + self.leaves.memory_bytes();
        GridStats {
            primitives: self.leaves.len(),
            occupied_cells: occupied,
            entries: self.entries.len(),
            max_per_cell,
            mean_per_cell,
            memory_bytes,
        }
    }
}
