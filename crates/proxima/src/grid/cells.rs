//! The cells of a range: plain enumeration, and enumeration filtered by an
//! exact cell test split into a per-run and a per-cell part.
//!
//! Shared by the classic insertion (`insert.rs`, `polygon_insert.rs`) and the
//! scan-line insertion (`scanline.rs`), which falls back to the classic
//! enumeration for small ranges; both import from here, neither from the other.

use super::layout::GridLayout;
use super::{Cell, CellRange};

/// An exact cell test split in two, so that the part that does not depend on
/// a run's inner axis `q` is evaluated once per run of cells along `q`.
/// Both parts see the same `f64` cell bounds, so a cell is accepted exactly
/// when the unsplit test would accept it, whatever the axis and order.
pub(crate) trait CellTest {
    /// `false` when no cell of the run along `q` can overlap (`lo`, `hi` hold
    /// the run's bounds on the other two axes).
    #[inline]
    fn run(&self, _q: usize, _lo: [f64; 3], _hi: [f64; 3]) -> bool {
        true
    }
    /// The rest of the test for one cell of a run that passed [`CellTest::run`].
    fn cell(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool;
}

/// Every cell of `range`, x fastest.
#[inline]
pub(crate) fn for_each_cell(range: &CellRange, mut f: impl FnMut(Cell)) {
    for k in range.min[2]..=range.max[2] {
        for j in range.min[1]..=range.max[1] {
            for i in range.min[0]..=range.max[0] {
                f([i, j, k]);
            }
        }
    }
}

/// Calls `f(cell, lo, hi)` for every cell of `range` with its closed box (as
/// `f64`, exact), x fastest; each boundary is computed once per row.
#[inline]
pub(crate) fn for_each_cell_box(layout: &GridLayout, range: &CellRange, mut f: impl FnMut(Cell, [f64; 3], [f64; 3])) {
    for k in range.min[2]..=range.max[2] {
        let (z0, z1) = (layout.boundary(2, k), layout.boundary(2, k + 1));
        for j in range.min[1]..=range.max[1] {
            let (y0, y1) = (layout.boundary(1, j), layout.boundary(1, j + 1));
            let mut x0 = layout.boundary(0, range.min[0]);
            for i in range.min[0]..=range.max[0] {
                let x1 = layout.boundary(0, i + 1);
                f([i, j, k], [x0, y0, z0], [x1, y1, z1]);
                x0 = x1;
            }
        }
    }
}

/// The cells of `range` that `test` accepts, x fastest (runs along x).
#[inline]
pub(crate) fn classic_cells(layout: &GridLayout, range: &CellRange, test: &impl CellTest, mut visit: impl FnMut(Cell)) {
    for k in range.min[2]..=range.max[2] {
        let (z0, z1) = (layout.boundary(2, k), layout.boundary(2, k + 1));
        for j in range.min[1]..=range.max[1] {
            let (y0, y1) = (layout.boundary(1, j), layout.boundary(1, j + 1));
            if !test.run(0, [0.0, y0, z0], [0.0, y1, z1]) {
                continue;
            }
            let mut x0 = layout.boundary(0, range.min[0]);
            for i in range.min[0]..=range.max[0] {
                let x1 = layout.boundary(0, i + 1);
                if test.cell(0, [x0, y0, z0], [x1, y1, z1]) {
                    visit([i, j, k]);
                }
                x0 = x1;
            }
        }
    }
}
