//! Which cells a convex polygon overlaps.
//!
//! A 3-vertex polygon is inserted exactly as its [`Triangle`](crate::Triangle)
//! (same shortcuts, same cells); a larger one by the same routine as triangles
//! (`visit_convex_cells` in `insert.rs`) with the polygon's separating axis
//! test ([`PolygonBoxTest`](crate::primitive::PolygonBoxTest)).

use super::insert::visit_convex_cells;
use super::{Cell, GridInsert, InsertParams};
use crate::error::GridError;
use crate::primitive::polygon::MAX_POLYGON_VERTICES;
use crate::primitive::sat::to64;
use crate::primitive::{Bounded, ConvexPolygon};

impl GridInsert for ConvexPolygon {
    #[inline]
    fn visit_cells<F: FnMut(Cell)>(&self, params: &InsertParams<'_>, visit: F) -> Result<(), GridError> {
        if let Some(tri) = self.as_triangle() {
            return tri.visit_cells(params, visit);
        }
        let mut v = [[0.0; 3]; MAX_POLYGON_VERTICES];
        for (slot, p) in v.iter_mut().zip(self.vertices()) {
            *slot = to64(*p);
        }
        visit_convex_cells::<MAX_POLYGON_VERTICES, F>(&self.bounds(), &v[..self.len()], params, visit)
    }
}
