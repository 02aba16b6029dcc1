//! Scan-line insertion: the cells of a segment or triangle without testing
//! every cell of its bounding box.
//!
//! The primitive (a convex polygon of two or three vertices, in `f64`) is
//! clipped to each slab of cells along one axis (Sutherland–Hodgman), then each
//! slab's piece is cut by each row along a second axis: the piece left in a
//! row is convex, so the cells of that row it overlaps are exactly those whose
//! extent along the third axis meets the piece's extent, which is read off
//! the slab piece's vertices inside the row and its edges' crossings with the
//! row's two lines (no polygon is built per row). Slabs and rows are clipped *widened* by a margin
//! `ε` (a `1e-7` fraction of the coordinates' magnitude, far above the `f64`
//! rounding of the clipping and of the exact test), so the candidates provably
//! include every cell the exact test accepts; each candidate is then tested
//! with the same exact test as the classic insertion. Hence both insertions
//! give exactly the same cells, and the scan-line tests about as many cells as
//! the primitive really overlaps instead of its whole box range.
//!
//! The axes are chosen per primitive: slabs along the axis of fewest cells,
//! the innermost run along the axis of most cells, which minimizes the number
//! of clipped rows. Small boxes (at most [`SMALL_RANGE`] cells) are handled
//! classically: clipping would cost more than the tests it saves.

use super::cells::{CellTest, classic_cells};
use super::layout::GridLayout;
use super::{Cell, CellRange};

/// Bounding-box ranges of at most this many cells are tested cell by cell.
pub(crate) const SMALL_RANGE: u128 = 27;

/// Relative clipping margin.
const MARGIN: f64 = 1e-7;

/// Vertices a clipped segment or triangle can have (see [`Poly`]).
const SMALL_CAPACITY: usize = 8;

/// Vertices a clipped convex polygon can have (see [`Poly`]).
const POLYGON_CAPACITY: usize = crate::primitive::polygon::MAX_POLYGON_VERTICES + 4;

/// A convex polygon of at most `N` vertices: clipping by four planes adds at
/// most four, to a segment (2) or a triangle (3), which fit in 8 as before;
/// convex polygons of up to
/// [`MAX_POLYGON_VERTICES`](crate::primitive::polygon::MAX_POLYGON_VERTICES) (8)
/// use 12, so that segments and triangles keep the smaller copies.
#[derive(Clone, Copy)]
struct Poly<const N: usize> {
    v: [[f64; 3]; N],
    n: usize,
}

impl<const N: usize> Poly<N> {
    #[inline]
    fn from(vertices: &[[f64; 3]]) -> Self {
        let mut p = Poly {
            v: [[0.0; 3]; N],
            n: vertices.len(),
        };
        p.v[..vertices.len()].copy_from_slice(vertices);
        p
    }

    #[inline]
    fn push(&mut self, x: [f64; 3]) {
        // Cannot overflow for convex input (see the type's doc); stay safe anyway.
        if self.n < self.v.len() {
            self.v[self.n] = x;
            self.n += 1;
        }
    }

    /// The range of the vertices along `axis`.
    #[inline]
    fn extent(&self, axis: usize) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for v in &self.v[..self.n] {
            lo = lo.min(v[axis]);
            hi = hi.max(v[axis]);
        }
        (lo, hi)
    }

    /// Sutherland–Hodgman against the closed half-space `sign · (x_axis − plane) ≤ 0`.
    #[inline]
    fn clip_half(&self, axis: usize, plane: f64, sign: f64) -> Poly<N> {
        let mut out = Poly { v: [[0.0; 3]; N], n: 0 };
        if self.n == 0 {
            return out;
        }
        let mut prev = self.v[self.n - 1];
        let mut dp = sign * (prev[axis] - plane);
        for &cur in &self.v[..self.n] {
            let dc = sign * (cur[axis] - plane);
            if (dp <= 0.0) != (dc <= 0.0) {
                let t = (plane - prev[axis]) / (cur[axis] - prev[axis]);
                let mut x = [0.0; 3];
                for k in 0..3 {
                    x[k] = prev[k] + t * (cur[k] - prev[k]);
                }
                x[axis] = plane;
                out.push(x);
            }
            if dc <= 0.0 {
                out.push(cur);
            }
            prev = cur;
            dp = dc;
        }
        out
    }

    /// The extent along `q` of the part with `lo ≤ x_r ≤ hi`, without
    /// building that part: the vertices inside the strip and the crossings
    /// of the edges with its two lines (`None` when the strip misses it).
    #[inline]
    fn strip_extent(&self, r: usize, lo: f64, hi: f64, q: usize) -> Option<(f64, f64)> {
        let mut min = f64::INFINITY;
        let mut max = f64::NEG_INFINITY;
        let v = &self.v[..self.n];
        for (k, a) in v.iter().enumerate() {
            if lo <= a[r] && a[r] <= hi {
                min = min.min(a[q]);
                max = max.max(a[q]);
            }
            let b = &v[(k + 1) % v.len()];
            for plane in [lo, hi] {
                if (a[r] < plane && plane < b[r]) || (b[r] < plane && plane < a[r]) {
                    let x = a[q] + (plane - a[r]) / (b[r] - a[r]) * (b[q] - a[q]);
                    min = min.min(x);
                    max = max.max(x);
                }
            }
        }
        (min <= max).then_some((min, max))
    }

    /// The part with `lo ≤ x_axis ≤ hi`.
    #[inline]
    fn clip(&self, axis: usize, lo: f64, hi: f64) -> Poly<N> {
        let (min, max) = self.extent(axis);
        if min > hi || max < lo {
            return Poly { v: [[0.0; 3]; N], n: 0 };
        }
        let mut p = *self;
        if min < lo {
            p = p.clip_half(axis, lo, -1.0);
        }
        if max > hi {
            p = p.clip_half(axis, hi, 1.0);
        }
        p
    }
}

/// Visits the cells of `window` that `test` accepts, generating candidates by
/// clipping the convex polygon `vertices` (2 to 8 vertices) slab by slab and row by
/// row. `full` is the polygon's whole bounding-box range, `window` the part of
/// it to report.
pub(crate) fn scan(
    layout: &GridLayout,
    full: &CellRange,
    window: &CellRange,
    vertices: &[[f64; 3]],
    test: &impl CellTest,
    visit: impl FnMut(Cell),
) {
    if vertices.len() <= 3 {
        scan_with::<SMALL_CAPACITY>(layout, full, window, vertices, test, visit);
    } else {
        scan_with::<POLYGON_CAPACITY>(layout, full, window, vertices, test, visit);
    }
}

/// [`scan`] with pieces of capacity `N`.
fn scan_with<const N: usize>(
    layout: &GridLayout,
    full: &CellRange,
    window: &CellRange,
    vertices: &[[f64; 3]],
    test: &impl CellTest,
    mut visit: impl FnMut(Cell),
) {
    if full.count() <= SMALL_RANGE {
        classic_cells(layout, window, test, visit);
        return;
    }
    // Slab axis s: fewest cells; inner axis q: most cells; row axis r: the other.
    let mut axes = [0usize, 1, 2];
    axes.sort_by_key(|&a| window.extent(a));
    let [s, r, q] = axes;

    let mut scale = layout
        .origin()
        .abs()
        .max_element()
        .max(layout.cell_size().max_element()) as f64;
    for v in vertices {
        scale = scale.max(v[0].abs()).max(v[1].abs()).max(v[2].abs());
    }
    let eps = scale * MARGIN;

    let poly = Poly::<N>::from(vertices);
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    let mut cell = [0i64; 3];
    for ks in window.min[s]..=window.max[s] {
        let (s0, s1) = (layout.boundary(s, ks), layout.boundary(s, ks + 1));
        let slab = poly.clip(s, s0 - eps, s1 + eps);
        if slab.n == 0 {
            continue;
        }
        let (rmin, rmax) = slab.extent(r);
        let j0 = layout
            .first_touching(r, rmin - eps)
            .unwrap_or(window.min[r])
            .max(window.min[r]);
        let j1 = layout
            .last_at_or_below(r, rmax + eps)
            .unwrap_or(window.max[r])
            .min(window.max[r]);
        (lo[s], hi[s], cell[s]) = (s0, s1, ks);
        for jr in j0..=j1 {
            let (r0, r1) = (layout.boundary(r, jr), layout.boundary(r, jr + 1));
            let Some((qmin, qmax)) = slab.strip_extent(r, r0 - eps, r1 + eps, q) else {
                continue;
            };
            let i0 = layout
                .first_touching(q, qmin - eps)
                .unwrap_or(window.min[q])
                .max(window.min[q]);
            let i1 = layout
                .last_at_or_below(q, qmax + eps)
                .unwrap_or(window.max[q])
                .min(window.max[q]);
            (lo[r], hi[r], cell[r]) = (r0, r1, jr);
            if i0 > i1 || !test.run(q, lo, hi) {
                continue;
            }
            let mut q0 = layout.boundary(q, i0);
            for iq in i0..=i1 {
                let q1 = layout.boundary(q, iq + 1);
                (lo[q], hi[q], cell[q]) = (q0, q1, iq);
                if test.cell(q, lo, hi) {
                    visit(cell);
                }
                q0 = q1;
            }
        }
    }
}
