//! First triangle hit along a ray, walking the grid's cells in ray order.
//!
//! The ray is first clipped to the box of the occupied cells (slightly
//! widened, so rounding never loses the first cell), then the cells are
//! visited by a [`GridTraversal`]. Every triangle of a visited cell is tested
//! with the watertight test ([`WatertightRay`]); the walk stops as soon as the
//! best hit so far lies before the exit of the current cell (by a rounding
//! slack, so that an equal-`t` hit in the next cell is still seen): every
//! triangle meeting the ray earlier meets it inside a cell already visited,
//! and is stored there. A triangle spanning several cells may be tested more
//! than once (no mailbox: the query stays read-only and allocation-free).

use super::{Cell, GridTraversal, HashGrid};
use crate::aabb::Aabb;
use crate::error::GridError;
use crate::math::Vec3;
use crate::primitive::{RayIntersect, TriangleHit, WatertightRay};
use crate::query::{Counter, FarRay, QueryStats, RayHit};
use std::hash::BuildHasher;

impl<T: RayIntersect, S: BuildHasher> HashGrid<T, S> {
    /// The first primitive hit by `origin + t · direction` with `t` in
    /// `[t_min, t_max]` (`None` when there is none). Of several triangles hit
    /// at the same `t`, the one of smallest index is returned: the answer of
    /// the trees' [`RayQuery::first_hit`](crate::query::RayQuery::first_hit).
    /// Errors as theirs, as [`GridError`]s, and
    /// [`GridError::OutOfRange`] for a walk beyond the grid's cell indices.
    ///
    /// ```
    /// use proxima::grid::{GridConfig, HashGrid};
    /// use proxima::{Mesh, Vec3};
    /// let mesh = Mesh::from_triangles(
    ///     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.0, 0.0, 3.0), Vec3::new(0.0, 1.0, 3.0)],
    ///     &[[3, 4, 5], [0, 1, 2]],
    /// )
    /// .unwrap();
    /// let grid: HashGrid<_> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(0.25)).unwrap();
    /// let hit = grid.first_hit(Vec3::new(0.2, 0.2, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap();
    /// assert_eq!((hit.source, hit.t), (1, 1.0));
    /// assert!(grid.first_hit(Vec3::new(0.9, 0.9, -1.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().is_none());
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
        crate::ray::Ray::with_range(origin, direction, t_min, t_max)?;
        let ray = WatertightRay::new(origin, direction).ok_or(GridError::RayDirection)?;
        let Some(bounds) = self.bounds else { return Ok(None) };
        let layout = &self.layout;
        // The occupied cells' box, rounded outward to f32.
        let Aabb { min: lo, max: hi } = layout.cell_box(bounds.min).merge(&layout.cell_box(bounds.max));
        let margin = 1e-5 * (lo.abs().max(hi.abs()).max_element() + layout.cell_size().max_element());
        let world = Aabb::new(lo, hi).inflate(margin);
        // A far origin is moved close in f64 (see `FarRay`): in f32 the hit
        // tests could not tell the near face from the far one.
        // Farther than f64 can place it finely: out of range, as documented.
        let far = FarRay::new(origin, direction, t_min, t_max, world.min, world.max).ok_or(GridError::OutOfRange)?;
        let (origin, t_min, t_max) = (far.origin, far.t_min, far.t_max);
        let ray = if far.shift == 0.0 {
            ray
        } else {
            WatertightRay::new(origin, direction).ok_or(GridError::RayDirection)?
        };
        // Clipped in f64: a ray whose direction is long compared with the
        // cells (a fuzzed one started 3e15 away, with t = 1 at the hit)
        // crosses the whole grid within one f32 ulp of t.
        let Some((t0, t1)) = ray_interval_f64(&world, origin, direction, t_min as f64, t_max as f64) else {
            return Ok(None);
        };
        if !t1.is_finite() {
            return Ok(None);
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
            return Ok(None);
        };
        let walk = GridTraversal::in_layout_f64(layout, origin, direction, w0, w1)?;
        // (primitive, hit) of smallest t so far, ties to the lowest index.
        let mut best: Option<(u32, TriangleHit)> = None;
        for step in walk {
            counter.nodes(1);
            let t_best = best.map_or(t_max, |(_, b)| b.t);
            let cell = self.cell(&step.cell);
            counter.primitives(cell.len() as u64);
            for &p in cell {
                if let Some(hit) = self.primitives[p as usize].intersect_ray(&ray, t_min, t_best)
                    && best.is_none_or(|(q, b)| hit.t < b.t || (hit.t == b.t && p < q))
                {
                    best = Some((p, hit));
                }
            }
            // Stop once the best hit lies before the exit of this cell by more
            // than the rounding slack and an ulp (the exit is rounded to f32; a
            // fuzzed ray with 1e17 coordinates met two triangles at their
            // shared vertex, on a cell boundary): a tie beyond is still seen.
            if best.is_some_and(|(_, b)| b.t < step.t_exit - slack && b.t.next_up() < step.t_exit) {
                break;
            }
        }
        Ok(best.map(|(p, hit)| RayHit {
            primitive: p,
            source: self.sources[p as usize],
            t: far.original_t(hit.t),
            point: self.primitives[p as usize].hit_point(&hit),
            u: hit.u,
            v: hit.v,
        }))
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
