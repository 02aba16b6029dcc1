//! The grid's answer to [`RayQuery`]: its walk over the cells a ray crosses.
//!
//! The ray is prepared, range-checked and moved near the occupied cells by
//! the query layer, as for every structure ([`RayQuery`]); the grid supplies
//! the walk. The walk is clipped to the box of the occupied cells (slightly
//! widened, so rounding never loses the first cell), then the cells are
//! visited by a [`GridTraversal`]. Every primitive of a visited cell goes to
//! the query's visitor, which keeps the hit of smallest `t` (ties to the
//! lowest index) with the watertight test ([`WatertightRay`]); the walk stops
//! as soon as the best hit so far lies before the exit of the current cell
//! (by a rounding slack, so that an equal-`t` hit in the next cell is still
//! seen): every triangle meeting the ray earlier meets it inside a cell
//! already visited, and is stored there. A triangle spanning several cells
//! may be tested more than once (no mailbox: the query stays read-only and
//! allocation-free).

use super::{Cell, CellRange, GridTraversal, HashGrid};
use crate::aabb::Aabb;
use crate::error::{GridError, RayError};
use crate::math::Vec3;
use crate::primitive::{RayIntersect, WatertightRay};
use crate::query::{Counter, Leaves, QueryStats, RayHit, RayQuery, RayVisitor, SpatialIndex, first_hit_by};
use std::hash::BuildHasher;

impl<T: RayIntersect, S: BuildHasher> HashGrid<T, S> {
    /// The first primitive hit by `origin + t · direction` with `t` in
    /// `[t_min, t_max]` (`None` when there is none). Of several triangles hit
    /// at the same `t`, the one of smallest index is returned: the answer of
    /// [`RayQuery::first_hit`], which this is, with the grid's errors:
    /// [`GridError::Ray`] for a ray that cannot be cast, and
    /// [`GridError::OutOfRange`] for a walk beyond the grid's cell indices or
    /// an origin too far from the occupied cells
    /// ([`RayError::OriginTooFar`] for the trees).
    ///
    /// ```
    /// use proxima::grid::{GridConfig, HashGrid};
    /// use proxima::{GridError, Mesh, RayError, Vec3};
    /// let mesh = Mesh::from_triangles(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.0, 0.0, 3.0), Vec3::new(0.0, 1.0, 3.0)],
    ///     &[[3, 4, 5], [0, 1, 2]],
    /// )
    /// .unwrap();
    /// let grid: HashGrid<_> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(0.25)).unwrap();
    /// let hit = grid.first_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap();
    /// assert_eq!((hit.source, hit.t), (1, 1.0));
    /// assert!(grid.first_hit(Vec3::new(0.9, 0.9, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().is_none());
    /// assert_eq!(grid.first_hit(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0), Err(GridError::Ray(RayError::Direction)));
    /// ```
    pub fn first_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<Option<RayHit>, GridError> {
        self.first_hit_counted(origin, direction, t_min, t_max, &mut ())
    }

    /// [`first_hit`](Self::first_hit), also counting the cells visited
    /// (`nodes_visited`) and the primitives tested.
    pub fn first_hit_with_stats(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<(Option<RayHit>, QueryStats), GridError> {
        let mut stats = QueryStats::default();
        let hit = self.first_hit_counted(origin, direction, t_min, t_max, &mut stats)?;
        Ok((hit, stats))
    }

    fn first_hit_counted<C: Counter>(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
        counter: &mut C,
    ) -> Result<Option<RayHit>, GridError> {
        first_hit_by(
            self,
            origin,
            direction,
            t_min,
            t_max,
            counter,
            |ray, t_min, first, counter| self.walk_cells(ray, direction, t_min, first, counter),
        )
        .map_err(|e| match e {
            // Farther than f64 can place the ray finely: the grid has always
            // called that a walk out of its range.
            GridError::Ray(RayError::OriginTooFar) => GridError::OutOfRange,
            e => e,
        })
    }

    /// Hands `visitor` the primitives of the occupied cells that `ray` (made
    /// from `direction`, prepared by the query layer) crosses from `t_min`,
    /// in order, until the visitor's best hit lies before the current cell's
    /// exit or it ends the query. [`GridError::OutOfRange`] when the walk
    /// cannot start within the layout's cell range.
    fn walk_cells<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) -> Result<(), GridError> {
        let Some((world, margin, bounds)) = self.occupied_box() else {
            return Ok(());
        };
        let layout = &self.layout;
        let origin = ray.origin();
        // Clipped in f64: a ray whose direction is long compared with the
        // cells (a fuzzed one started 3e15 away, with t = 1 at the hit)
        // crosses the whole grid within one f32 ulp of t.
        let Some((t0, t1)) = ray_interval_f64(&world, origin, direction, t_min as f64, visitor.t_hi() as f64) else {
            return Ok(());
        };
        if !t1.is_finite() {
            return Ok(());
        }
        // A hit's computed t can come out a little before the cell exit at
        // which its triangle starts (rounding of order ε · |vertex − origin|),
        // and a triangle in the next cell can tie with it: stop only once the
        // best hit lies before the exit by more than that.
        let reach = (world.min - origin).abs().max((world.max - origin).abs()).max_element();
        let slack = 32.0 * f32::EPSILON * reach / direction.abs().max_element();
        // The walk also starts a margin before t_min: a triangle hit right at
        // the origin may lie, by a rounding, in the cell behind an origin on
        // a cell boundary (the hit test itself still starts at t_min).
        let back = margin as f64 / direction.abs().max_element() as f64;
        // Cells outside the occupied box are empty: the walk crosses only the
        // box's cells and one more on each side (more than the f64 rounding
        // of the clipping at any index the layout allows), not the margin's,
        // which are billions where cells are small beside the coordinates.
        let spare = |cell: Cell, by: i64| -> Cell {
            std::array::from_fn(|a| (cell[a] + by).clamp(-layout.max_index(a), layout.max_index(a)))
        };
        let (lo, _) = layout.cell_bounds(spare(bounds.min, -1));
        let (_, hi) = layout.cell_bounds(spare(bounds.max, 1));
        let Some((w0, w1)) = ray_interval_f64(&Aabb::enclosing(lo, hi), origin, direction, t0 - back, t1) else {
            return Ok(());
        };
        let walk = GridTraversal::in_layout_f64(layout, origin, direction, w0, w1)?;
        let primitives = self.leaves.primitives();
        for step in walk {
            counter.nodes(1);
            let cell = self.cell(&step.cell);
            counter.primitives(cell.len() as u64);
            for &p in cell {
                // Slots are input indices (the grid keeps its primitives in
                // input order).
                if visitor.visit(p as usize, &primitives[p as usize], ray, t_min) {
                    return Ok(());
                }
            }
            // Stop once the best hit lies before the exit of this cell by more
            // than the rounding slack and an ulp (the exit is rounded to f32; a
            // fuzzed ray with 1e17 coordinates met two triangles at their
            // shared vertex, on a cell boundary): a tie beyond is still seen.
            // Before a hit, `t_hi` is the end of the range, where the walk ends.
            let best = visitor.t_hi();
            if best < step.t_exit - slack && best.next_up() < step.t_exit {
                break;
            }
        }
        Ok(())
    }
}

impl<T, S: BuildHasher> HashGrid<T, S> {
    /// The box of the occupied cells, rounded outward to `f32` and widened by
    /// a margin (returned too), with the occupied cell range; `None` when no
    /// cell is occupied. It holds every primitive.
    fn occupied_box(&self) -> Option<(Aabb, f32, CellRange)> {
        let bounds = self.bounds?;
        let layout = &self.layout;
        let Aabb { min: lo, max: hi } = layout.cell_box(bounds.min).merge(&layout.cell_box(bounds.max));
        let margin = 1e-5 * (lo.abs().max(hi.abs()).max_element() + layout.cell_size().max_element());
        Some((Aabb::new(lo, hi).inflate(margin), margin, bounds))
    }
}

/// The grid's primitives in input order, and the box of its occupied cells
/// (widened a little; [`Aabb::EMPTY`] when none is occupied), which holds
/// them all. (The inherent [`HashGrid::bounds`] is the occupied cell range.)
impl<T, S: BuildHasher> SpatialIndex<T> for HashGrid<T, S> {
    #[inline]
    fn leaves(&self) -> &Leaves<T> {
        &self.leaves
    }

    fn bounds(&self) -> Aabb {
        self.occupied_box().map_or(Aabb::EMPTY, |(world, ..)| world)
    }
}

/// Rays through the grid: the walk over its occupied cells. Every query of
/// [`RayQuery`] (`first_hit`, `any_hit`, batches) answers as on the trees;
/// the inherent [`HashGrid::first_hit`] is the same query with the grid's
/// errors ([`GridError`]).
impl<T: RayIntersect, S: BuildHasher> RayQuery<T> for HashGrid<T, S> {
    fn ray_walk<V: RayVisitor<T>, C: Counter>(
        &self,
        ray: &WatertightRay,
        direction: Vec3,
        t_min: f32,
        visitor: &mut V,
        counter: &mut C,
    ) {
        // A walk that cannot start within the layout's cell range, which
        // `HashGrid::first_hit` reports as `OutOfRange`, has no error among
        // the ray's: through the trait it visits nothing.
        let _ = self.walk_cells(ray, direction, t_min, visitor, counter);
    }
}

/// The parameter interval of `origin + t · direction` inside `b` within
/// `[t_min, t_max]`, in `f64` (slab test); `None` when it misses.
fn ray_interval_f64(b: &Aabb, origin: Vec3, direction: Vec3, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (t_min, t_max);
    for axis in 0..3 {
        let (o, d) = (origin[axis] as f64, direction[axis] as f64);
        let (lo, hi) = (b.min[axis] as f64, b.max[axis] as f64);
        if d == 0.0 {
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let (near, far) = ((lo - o) / d, (hi - o) / d);
        let (near, far) = if near <= far { (near, far) } else { (far, near) };
        t0 = t0.max(near);
        t1 = t1.min(far);
        if t0 > t1 {
            return None;
        }
    }
    Some((t0, t1))
}
