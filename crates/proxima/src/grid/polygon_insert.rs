//! Which cells a convex polygon overlaps.
//!
//! A 3-vertex polygon is inserted exactly as its [`Triangle`] (same shortcuts,
//! same cells). A larger one: the cells of its bounding box range, kept by the
//! prepared separating axis test ([`PolygonBoxTest`]), split into the part
//! shared by a run of cells and the per-cell part as for triangles; a range
//! that is a single line of cells is taken whole (exact for any connected
//! primitive, see `insert.rs`). Scan-line insertion clips the polygon slab by
//! slab like a triangle when its vertices are coplanar in `f64`, where the test
//! is exact; for a polygon that is planar only within tolerance the test is
//! conservative (it may accept a cell the polygon only comes very close to),
//! so scan-line candidates might miss such a cell, and these polygons take the
//! classic enumeration instead. Both methods therefore give the same cells.

use super::cells::{CellTest, classic_cells, for_each_cell};
use super::insert::ranges;
use super::{Cell, GridInsert, InsertMethod, InsertParams, scanline};
use crate::error::GridError;
use crate::primitive::polygon::MAX_POLYGON_VERTICES;
use crate::primitive::sat::to64;
use crate::primitive::{Bounded, ConvexPolygon, PolygonBoxTest};

impl CellTest for PolygonBoxTest {
    #[inline(always)]
    fn run(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        self.overlaps_run_axes(q, lo, hi)
    }
    #[inline(always)]
    fn cell(&self, q: usize, lo: [f64; 3], hi: [f64; 3]) -> bool {
        self.overlaps_cell_axes(q, lo, hi)
    }
}

impl GridInsert for ConvexPolygon {
    #[inline]
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, visit: F) -> Result<(), GridError> {
        if let Some(tri) = self.as_triangle() {
            return tri.visit_cells(params, visit);
        }
        let Some((full, window)) = ranges(&self.bounds(), params)? else {
            return Ok(());
        };
        if full.is_line() {
            for_each_cell(&window, visit);
            return Ok(());
        }
        let test = PolygonBoxTest::new(self).for_boxes_within(super::insert::range_magnitude(params.layout, &full));
        match params.method {
            InsertMethod::Scanline if test.is_planar() => {
                let mut v = [[0.0; 3]; MAX_POLYGON_VERTICES];
                for (slot, p) in v.iter_mut().zip(self.vertices()) {
                    *slot = to64(*p);
                }
                scanline::scan(params.layout, &full, &window, &v[..self.len()], &test, visit);
            }
            _ => classic_cells(params.layout, &window, &test, visit),
        }
        Ok(())
    }
}
