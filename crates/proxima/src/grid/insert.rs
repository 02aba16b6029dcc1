//! Which cells a primitive overlaps: the classic insertion.
//!
//! As in the classic design: compute the primitive's bounding box, enumerate
//! every cell of the box's cell range ([`GridLayout::cell_range`]), and keep
//! those the primitive really overlaps by the exact closed test
//! ([`BoxOverlap`]; for triangles the prepared [`TriangleBoxTest`], for
//! segments slab clipping, for points containment).
//!
//! One shortcut, exact for any connected primitive (points, segments,
//! triangles): when the bounding box's range is a single cell or a line of
//! cells (at most one axis spans more than one cell), every cell of the range
//! is overlapped — the primitive's projection onto that axis is the whole
//! interval of its box, and on the other axes every point lies in the one
//! cell's slab — so no test is needed. Scan-line insertion
//! (`scanline.rs`) takes the same shortcut, so both methods give the same cells.

use super::layout::GridLayout;
use super::{Cell, CellRange, InsertMethod, scanline};
use crate::aabb::Aabb;
use crate::error::GridError;
use crate::math::Vec3;
use crate::primitive::sat::to64;
use crate::primitive::segment_aabb::segment_overlaps as segment_aabb_overlap;
use crate::primitive::{Bounded, BoxOverlap, LineSegment, Point, Triangle, TriangleBoxTest};

/// What a primitive needs to list the cells it overlaps.
#[derive(Clone, Copy, Debug)]
pub struct InsertParams<'a> {
    /// The cell placement.
    pub layout: &'a GridLayout,
    /// Classic or scan-line (same cells, different speed).
    pub method: InsertMethod,
    /// A primitive whose bounding box spans more cells than this is an error.
    pub max_cells: u64,
    /// When set, only cells inside this range are reported (the others are
    /// neither tested nor visited). The limit still applies to the whole box.
    pub window: Option<CellRange>,
}

impl<'a> InsertParams<'a> {
    /// Classic insertion into `layout`, default per-primitive limit, no window.
    pub fn new(layout: &'a GridLayout) -> Self {
        Self { layout, method: InsertMethod::Classic, max_cells: super::DEFAULT_MAX_CELLS_PER_PRIMITIVE, window: None }
    }
}

/// A primitive that can list the cells of a grid it overlaps.
///
/// Implemented for [`Point`], [`LineSegment`] and [`Triangle`]; any other
/// [`BoxOverlap`] primitive can opt in with an empty `impl` block, which uses
/// the classic insertion with [`BoxOverlap::overlaps_box`] per cell.
pub trait GridInsert: BoxOverlap {
    /// Calls `visit` once for every cell whose closed box the primitive
    /// overlaps (within `params.window` when set), in an unspecified order.
    ///
    /// Errors: [`GridError::NonFinite`] for a non-finite bounding box,
    /// [`GridError::OutOfRange`] for a box beyond the supported cell indices,
    /// [`GridError::PrimitiveTooLarge`] when the box spans more than
    /// `params.max_cells` cells. These report primitive index 0; the grid
    /// build replaces it by the real index.
    ///
    /// ```
    /// use proxima::grid::{GridInsert, GridLayout, InsertParams};
    /// use proxima::{LineSegment, Vec3};
    /// let layout = GridLayout::cubic(1.0).unwrap();
    /// let mut cells = Vec::new();
    /// let seg = LineSegment::new(Vec3::new(0.5, 0.5, 0.5), Vec3::new(2.5, 1.5, 0.5));
    /// seg.visit_cells(&InsertParams::new(&layout), |c| cells.push(c)).unwrap();
    /// cells.sort();
    /// // Through (1.5, 1.0, 0.5): the boundary y = 1 is crossed at x = 1.5.
    /// assert_eq!(cells, [[0, 0, 0], [1, 0, 0], [1, 1, 0], [2, 1, 0]]);
    /// ```
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, visit: F) -> Result<(), GridError> {
        let Some((_, window)) = ranges(&self.bounds(), params)? else { return Ok(()) };
        let mut visit = visit;
        for_each_cell_box(params.layout, &window, |cell, lo, hi| {
            let b = Aabb::new(Vec3::new(lo[0] as f32, lo[1] as f32, lo[2] as f32), Vec3::new(hi[0] as f32, hi[1] as f32, hi[2] as f32));
            if self.overlaps_box(&b) {
                visit(cell);
            }
        });
        Ok(())
    }
}

/// The primitive's full cell range and the part of it inside the window, after
/// the checks; `None` when the window leaves nothing.
#[inline]
pub(crate) fn ranges(bounds: &Aabb, params: &InsertParams<'_>) -> Result<Option<(CellRange, CellRange)>, GridError> {
    if !bounds.is_finite() {
        return Err(GridError::NonFinite { index: 0 });
    }
    let full = params.layout.cell_range(bounds)?;
    let count = full.count();
    if count > params.max_cells as u128 {
        return Err(GridError::PrimitiveTooLarge { index: 0, cells: count, limit: params.max_cells });
    }
    let window = match params.window {
        Some(w) => full.intersection(&w),
        None => full,
    };
    Ok((!window.is_empty()).then_some((full, window)))
}

/// Calls `f(cell, lo, hi)` for every cell of `range` with its closed box (as
/// `f64`, exact), x fastest; each boundary is computed once per row.
#[inline]
pub(crate) fn for_each_cell_box(layout: &GridLayout, range: &CellRange, mut f: impl FnMut(Cell, [f64; 3], [f64; 3])) {
    for k in range.min[2]..=range.max[2] {
        let (z0, z1) = (layout.boundary64(2, k), layout.boundary64(2, k + 1));
        for j in range.min[1]..=range.max[1] {
            let (y0, y1) = (layout.boundary64(1, j), layout.boundary64(1, j + 1));
            let mut x0 = layout.boundary64(0, range.min[0]);
            for i in range.min[0]..=range.max[0] {
                let x1 = layout.boundary64(0, i + 1);
                f([i, j, k], [x0, y0, z0], [x1, y1, z1]);
                x0 = x1;
            }
        }
    }
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

impl GridInsert for Point {
    /// A point overlaps every cell of its (degenerate) box's range: one cell,
    /// or two, four or eight when it lies on boundary planes.
    #[inline]
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, visit: F) -> Result<(), GridError> {
        if let Some((_, window)) = ranges(&self.bounds(), params)? {
            for_each_cell(&window, visit);
        }
        Ok(())
    }
}

impl GridInsert for LineSegment {
    #[inline]
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, mut visit: F) -> Result<(), GridError> {
        let Some((full, window)) = ranges(&self.bounds(), params)? else { return Ok(()) };
        if full.is_line() {
            for_each_cell(&window, visit);
            return Ok(());
        }
        let (a, b) = (to64(self.a), to64(self.b));
        let test = |lo: [f64; 3], hi: [f64; 3]| segment_aabb_overlap(a, b, lo, hi);
        match params.method {
            InsertMethod::Classic => for_each_cell_box(params.layout, &window, |c, lo, hi| {
                if test(lo, hi) {
                    visit(c)
                }
            }),
            InsertMethod::Scanline => scanline::scan(params.layout, &full, &window, &[a, b], test, visit),
        }
        Ok(())
    }
}

impl GridInsert for Triangle {
    #[inline]
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, mut visit: F) -> Result<(), GridError> {
        let Some((full, window)) = ranges(&self.bounds(), params)? else { return Ok(()) };
        if full.is_line() {
            for_each_cell(&window, visit);
            return Ok(());
        }
        let prepared = TriangleBoxTest::new(self);
        // Cells of the range overlap the triangle's box: the box normals
        // cannot separate, only the ten other axes are tested.
        let test = |lo: [f64; 3], hi: [f64; 3]| prepared.overlaps_axes(lo, hi);
        match params.method {
            InsertMethod::Classic => for_each_cell_box(params.layout, &window, |c, lo, hi| {
                if test(lo, hi) {
                    visit(c)
                }
            }),
            InsertMethod::Scanline => {
                let v = [to64(self.a), to64(self.b), to64(self.c)];
                scanline::scan(params.layout, &full, &window, &v, test, visit)
            }
        }
        Ok(())
    }
}
