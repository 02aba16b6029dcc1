//! Which cells a primitive overlaps: the classic insertion.
//!
//! As in the classic design: compute the primitive's bounding box, enumerate
//! every cell of the box's cell range ([`GridLayout::cell_range`]), and keep
//! those the primitive really overlaps by the exact closed test
//! ([`BoxOverlap`]; for triangles and convex polygons the prepared
//! [`ConvexBoxTest`] (`visit_convex_cells`), for
//! segments slab clipping, for points containment).
//!
//! One shortcut, exact for any connected primitive (points, segments,
//! triangles): when the bounding box's range is a single cell or a line of
//! cells (at most one axis spans more than one cell), every cell of the range
//! is overlapped — the primitive's projection onto that axis is the whole
//! interval of its box, and on the other axes every point lies in the one
//! cell's slab — so no test is needed. And when one axis spans a single cell,
//! a triangle is tested in 2D (three axes instead of ten, see `FlatTest`). Scan-line insertion
//! (`scanline.rs`) takes the same shortcut, so both methods give the same cells.

use super::cells::{CellTest, classic_cells, for_each_cell, for_each_cell_box};
use super::layout::GridLayout;
use super::{Cell, CellRange, InsertMethod, scanline};
use crate::aabb::Aabb;
use crate::error::GridError;
use crate::math::DVec3;
use crate::primitive::exact_sat::{self, box_magnitude, shape_bounds};
use crate::primitive::sat::to64;
use crate::primitive::segment_aabb::segment_overlaps as segment_aabb_overlap;
use crate::primitive::{Bounded, BoxOverlap, ConvexBoxTest, LineSegment, Point, Triangle};

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
        Self {
            layout,
            method: InsertMethod::Classic,
            max_cells: super::DEFAULT_MAX_CELLS_PER_PRIMITIVE,
            window: None,
        }
    }
}

/// A primitive that can list the cells of a grid it overlaps.
///
/// Implemented for [`Point`], [`LineSegment`], [`Triangle`] and
/// [`ConvexPolygon`](crate::ConvexPolygon) (in `polygon_insert.rs`); any other
/// [`BoxOverlap`] primitive can opt in with an empty `impl` block, which uses
/// the classic insertion with [`BoxOverlap::overlaps_bounds`] per cell.
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
        let Some((_, window)) = ranges(&self.bounds(), params)? else {
            return Ok(());
        };
        let mut visit = visit;
        for_each_cell_box(params.layout, &window, |cell, lo, hi| {
            if self.overlaps_bounds(DVec3::from_array(lo), DVec3::from_array(hi)) {
                visit(cell);
            }
        });
        Ok(())
    }
}

/// The primitive's full cell range and the part of it inside the window, after
/// the checks; `None` when the window leaves nothing.
#[inline(always)]
pub(crate) fn ranges(bounds: &Aabb, params: &InsertParams<'_>) -> Result<Option<(CellRange, CellRange)>, GridError> {
    if !bounds.is_finite() {
        return Err(GridError::NonFinite { index: 0 });
    }
    let full = params.layout.cell_range(bounds)?;
    let count = full.count();
    if count > params.max_cells as u128 {
        return Err(GridError::PrimitiveTooLarge {
            index: 0,
            cells: count,
            limit: params.max_cells,
        });
    }
    let window = match params.window {
        Some(w) => full.intersection(&w),
        None => full,
    };
    Ok((!window.is_empty()).then_some((full, window)))
}

/// The largest magnitude of any cell bound in `range`: boundaries grow with
/// their index, so the outer ones bound them all (the rounding bounds of the
/// exact tests are prepared once per primitive from it).
#[inline]
pub(crate) fn range_magnitude(layout: &GridLayout, range: &CellRange) -> f64 {
    (0..3)
        .map(|a| {
            let (lo, hi) = (layout.boundary(a, range.min[a]), layout.boundary(a, range.max[a] + 1));
            lo.abs().max(hi.abs())
        })
        .fold(0.0, f64::max)
}

// Inlined into the cell loops: the hot path is a few multiply-adds per axis,
// and a call per cell costs more than the test (measured, see docs/perf-log.md).
impl<const N: usize> CellTest for ConvexBoxTest<N> {
    #[inline(always)]
    fn run(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        self.overlaps_run_axes(q, lo, hi)
    }
    #[inline(always)]
    fn cell(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        self.overlaps_cell_axes(q, lo, hi)
    }
}

/// The one insertion routine of triangles (`N = 3`) and convex polygons (at
/// most `N` vertices `v` in boundary order, bounding box `bounds`): the cells
/// of the bounding box's range kept by the prepared separating axis test
/// ([`ConvexBoxTest`]), split into the part shared by a run of cells and the
/// per-cell part.
///
/// A range that is a line of cells is taken whole (exact for any connected
/// primitive, see the module documentation). A triangle within one slab of
/// cells, or lying in a plane of constant coordinate (as every triangle of a
/// voxel mesh does), is a 2D problem ([`FlatTest`]): in the plane case every
/// cell of the range touches that plane, and the normal and the other edge
/// axes, parallel to it, decide nothing the range has not (and would all need
/// the exact fallback). Scan-line insertion clips the shape slab by slab when
/// the test is exact — always for a triangle, for a polygon when its vertices
/// are coplanar in `f64`; for a polygon that is planar only within tolerance
/// the test is conservative (it may accept a cell the polygon only comes very
/// close to), so scan-line candidates might miss such a cell, and these
/// polygons take the classic enumeration instead. Both methods therefore give
/// the same cells.
#[inline(always)]
pub(crate) fn visit_convex_cells<const N: usize, F: FnMut(Cell)>(
    bounds: &Aabb,
    v: &[[f64; 3]],
    params: &InsertParams<'_>,
    visit: F,
) -> Result<(), GridError> {
    let Some((full, window)) = ranges(bounds, params)? else {
        return Ok(());
    };
    if full.is_line() {
        for_each_cell(&window, visit);
        return Ok(());
    }
    let magnitude = range_magnitude(params.layout, &full);
    if N == 3
        && let Ok(tri) = <&[[f64; 3]; 3]>::try_from(v)
        && let Some(s) = (0..3).find(|&a| full.extent(a) == 1 || (tri[0][a] == tri[1][a] && tri[1][a] == tri[2][a]))
    {
        let test = FlatTest::new(tri, s, magnitude);
        match params.method {
            InsertMethod::Classic => classic_cells(params.layout, &window, &test, visit),
            InsertMethod::Scanline => scanline::scan(params.layout, &full, &window, v, &test, visit),
        }
        return Ok(());
    }
    // Cells of the range overlap the shape's box: the box normals cannot
    // separate, only the other axes are tested.
    let test = ConvexBoxTest::<N>::from_vertices(v).for_boxes_within(magnitude);
    match params.method {
        InsertMethod::Scanline if N == 3 || test.is_planar() => {
            scanline::scan(params.layout, &full, &window, v, &test, visit)
        }
        _ => classic_cells(params.layout, &window, &test, visit),
    }
    Ok(())
}

/// A triangle whose bounding box lies within one slab of cells along `s`, or
/// in a plane `x_s = constant`. Every cell of its range holds the triangle's
/// whole extent along `s`, so
/// the triangle meets the cell exactly when their projections along `s` meet:
/// a 2D test of a triangle against a rectangle, whose separating axes are the
/// rectangle's two normals (already passed by the range) and the triangle's
/// three edge normals — in 3D, `edge_i × unit_s`. Three axes instead of ten.
pub(crate) struct FlatTest {
    s: usize,
    first: [f64; 3],
    second: [f64; 3],
    min: [f64; 3],
    max: [f64; 3],
    /// The rounding bound of the three axes and the vertices, for the exact
    /// fallback (as in [`ConvexBoxTest`]).
    bound: f64,
    box_magnitude: f64,
    vertices: [[f64; 3]; 3],
}

impl FlatTest {
    /// The test for cells whose bounds are at most `box_magnitude` in absolute value.
    fn new(v: &[[f64; 3]; 3], s: usize, box_magnitude: f64) -> Self {
        let (s1, s2) = ((s + 1) % 3, (s + 2) % 3);
        let mut t = FlatTest {
            s,
            first: [0.0; 3],
            second: [0.0; 3],
            min: [0.0; 3],
            max: [0.0; 3],
            bound: 0.0,
            box_magnitude,
            vertices: *v,
        };
        let min = |a: f64, b: f64| if a < b { a } else { b };
        let max = |a: f64, b: f64| if a > b { a } else { b };
        let magnitude = v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        t.bound = shape_bounds(magnitude, box_magnitude, 3).0;
        for i in 0..3 {
            let (p, q) = (v[i], v[(i + 1) % 3]);
            // (q − p) × unit_s: components (q − p)[s2] at s1, −(q − p)[s1] at s2.
            let (a1, a2) = (q[s2] - p[s2], -(q[s1] - p[s1]));
            let proj = v.map(|x| x[s1] * a1 + x[s2] * a2);
            (t.first[i], t.second[i]) = (a1, a2);
            (t.min[i], t.max[i]) = if a1 == 0.0 || a2 == 0.0 {
                // Parallel to a rectangle side: decided by the range (see ConvexBoxTest).
                (f64::NEG_INFINITY, f64::INFINITY)
            } else {
                (min(min(proj[0], proj[1]), proj[2]), max(max(proj[0], proj[1]), proj[2]))
            };
        }
        t
    }
}

impl CellTest for FlatTest {
    #[inline(always)]
    fn cell(&self, _q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        let (c, h) = (
            std::array::from_fn(|k| (lo[k] + hi[k]) * 0.5),
            std::array::from_fn(|k| (hi[k] - lo[k]) * 0.5),
        );
        debug_assert!(
            box_magnitude(&lo, &hi) <= self.box_magnitude,
            "bounds prepared for smaller cells"
        );
        (0..3).all(|i| {
            !exact_sat::edge_axis_gap_separates(
                self.s,
                (self.first[i], self.second[i]),
                (self.min[i], self.max[i]),
                self.bound,
                (&c, &h),
                (&lo, &hi),
                &self.vertices,
                i,
            )
        })
    }
}

/// Slab clipping of the segment `a`–`b`.
pub(crate) struct SegmentTest {
    a: [f64; 3],
    b: [f64; 3],
}

impl CellTest for SegmentTest {
    #[inline]
    fn cell(&self, _q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        segment_aabb_overlap(self.a, self.b, lo, hi)
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
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, visit: F) -> Result<(), GridError> {
        let Some((full, window)) = ranges(&self.bounds(), params)? else {
            return Ok(());
        };
        if full.is_line() {
            for_each_cell(&window, visit);
            return Ok(());
        }
        let test = SegmentTest {
            a: to64(self.a),
            b: to64(self.b),
        };
        match params.method {
            InsertMethod::Classic => classic_cells(params.layout, &window, &test, visit),
            InsertMethod::Scanline => scanline::scan(params.layout, &full, &window, &[test.a, test.b], &test, visit),
        }
        Ok(())
    }
}

impl GridInsert for Triangle {
    #[inline]
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, visit: F) -> Result<(), GridError> {
        visit_convex_cells::<3, F>(
            &self.bounds(),
            &[to64(self.a), to64(self.b), to64(self.c)],
            params,
            visit,
        )
    }
}
