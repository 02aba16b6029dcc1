//! Grid traversal: the cells a ray passes through, in order (Amanatides & Woo,
//! "A Fast Voxel Traversal Algorithm for Ray Tracing", 1987). The walk of
//! [`GridTraversal`] (exactly which cells, with which parameters) is
//! documented on the type; [`HashGrid::first_hit`](super::HashGrid::first_hit)
//! walks the occupied cells with it.

use super::{Cell, GridLayout, last_true};
use crate::error::GridError;
use crate::exact::{Exact, common_scale, integer};
use crate::math::Vec3;
use num_bigint::BigInt;
use std::cmp::Ordering;

/// Relative distance within which two rounded crossing parameters may be in
/// either exact order: each carries at most three roundings (the difference,
/// the reciprocal, the product), 3 u of its size; 8 u covers both.
const CROSSING_SLACK: f64 = 4.0 * f64::EPSILON;

/// Where a traversal walks: cell placement, parameter range and step limit.
///
/// ```
/// use proxima::grid::TraversalConfig;
/// use proxima::Vec3;
/// let config = TraversalConfig { t_max: 10.0, max_steps: 1000, ..TraversalConfig::cubic(0.5) };
/// assert_eq!(config.grid_origin, Vec3::ZERO);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraversalConfig {
    /// Cell extents along x, y and z.
    pub cell_size: Vec3,
    /// Minimum corner of cell `(0, 0, 0)`.
    pub grid_origin: Vec3,
    /// Start of the walk (finite).
    pub t_min: f32,
    /// End of the walk (may be infinite).
    pub t_max: f32,
    /// At most this many cells are yielded.
    pub max_steps: u64,
}

impl TraversalConfig {
    /// Cells of extents `cell_size`, grid origin at the world origin, `t` from
    /// 0 to infinity, no step limit.
    pub fn new(cell_size: Vec3) -> Self {
        Self {
            cell_size,
            grid_origin: Vec3::ZERO,
            t_min: 0.0,
            t_max: f32::INFINITY,
            max_steps: u64::MAX,
        }
    }

    /// Cubic cells of side `size` (see [`TraversalConfig::new`]).
    pub fn cubic(size: f32) -> Self {
        Self::new(Vec3::splat(size))
    }
}

/// One cell of a walk, with the parameters where the ray enters and leaves it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraversalStep {
    /// The cell.
    pub cell: Cell,
    /// Ray parameter where the ray enters the cell (or `t_min`).
    pub t_enter: f32,
    /// Ray parameter where the ray leaves the cell (or `t_max`).
    pub t_exit: f32,
}

/// The Amanatides–Woo walk of a ray through a grid.
///
/// [`GridTraversal`] is an [`Iterator`] of [`TraversalStep`]s: each cell
/// `(i, j, k)` with the ray parameters where the ray enters and leaves it.
/// Per step it compares the three parameters of the next boundary crossings,
/// steps the axis (or axes) crossed first, and computes that axis' next
/// crossing — a handful of operations and no allocation.
///
/// # Which cells are yielded
///
/// Exactly the cells in which the ray spends a parameter interval of
/// **positive length** within `[t_min, t_max]`, in order, each once:
///
/// - cells are closed boxes ([`GridLayout::cell_box`]) along every axis the
///   ray moves along; along an axis where the direction is zero, the ray is
///   given to the half-open cell `[b(i), b(i+1))`, so a ray lying in a
///   boundary plane walks the cells *above* it;
/// - a ray through an edge or a corner of cells (two or three boundaries
///   crossed at the same parameter) steps the crossed axes together: the
///   cells it only grazes at that single point are not yielded. The same holds
///   for an origin on a boundary: the walk starts in the cell the ray enters;
/// - which cells, and in which order, is decided exactly: the crossing
///   parameters `(b_a(n) − origin_a) / direction_a` are compared in `f64`
///   when they are clearly apart and in integer arithmetic otherwise (every
///   `f32` is a dyadic rational), so a ray through an edge or a corner of
///   cells steps its axes together even when the rounded parameters differ,
///   and two crossings that differ by less than a rounding step still make a
///   cell of positive length. The reported parameters are the rounded values
///   `(b_a(n) − origin_a) · (1 / direction_a)`, in `f64`;
/// - `t_enter` of each cell is the `t_exit` of the one before; the first
///   starts at `t_min`, the last ends at `t_max` (or at the step limit). An
///   empty range (`t_min == t_max`) yields nothing.
///
/// The walk ends when `t_max` is reached, after `max_steps` cells, with the
/// cell whose exit parameter no longer fits `f32` (yielded with
/// `t_exit = ∞`), or when a cell index would leave the layout's range
/// ([`GridLayout::max_index`], at most `±2^50`) — never later: with `t_max = ∞` and no step limit it
/// is merely very long. The parameters are
/// tracked in `f64`, so huge `t` does not stall the walk; they are yielded as
/// `f32`.
///
/// # Worked example
///
/// Cell size 0.3, origin (1, 0.2, 0.5), direction (0.3, 0.5, 1) normalized:
///
/// ```
/// use proxima::grid::{GridTraversal, TraversalConfig};
/// use proxima::Vec3;
/// let dir = Vec3::new(0.3, 0.5, 1.0).normalize();
/// let walk = GridTraversal::new(Vec3::new(1.0, 0.2, 0.5), dir, &TraversalConfig::cubic(0.3)).unwrap();
/// let steps: Vec<_> = walk.take(4).collect();
/// let cells: Vec<_> = steps.iter().map(|s| s.cell).collect();
/// assert_eq!(cells, [[3, 0, 1], [3, 0, 2], [3, 1, 2], [3, 1, 3]]);
/// // z reaches 0.6 first, at t = 0.1 / 0.8639 = 0.1158, then y reaches 0.3 at
/// // t = 0.1 / 0.4319 = 0.2315.
/// assert!((steps[0].t_exit - 0.1158).abs() < 1e-4);
/// assert!((steps[1].t_exit - 0.2315).abs() < 1e-4);
/// assert_eq!(steps[1].t_enter, steps[0].t_exit);
/// ```
#[derive(Clone, Debug)]
pub struct GridTraversal {
    layout: GridLayout,
    origin: [f64; 3],
    /// The direction, for exact comparisons of crossings.
    direction: [f64; 3],
    /// `1 / direction` per axis (infinite for a zero component).
    inv: [f64; 3],
    cell: Cell,
    /// +1, −1 or 0 per axis.
    step: [i64; 3],
    /// 1 when stepping up (the next boundary is `b(i + 1)`), else 0.
    offset: [i64; 3],
    /// Parameter of the next boundary crossing per axis (∞ for a zero direction).
    t_next: [f64; 3],
    /// Entry parameter of the current cell.
    t: f64,
    t_max: f64,
    steps_left: u64,
    done: bool,
}

impl GridTraversal {
    /// The walk of `origin + t · direction` through the grid of `config`.
    ///
    /// Errors: a ray or range that [`Ray::with_range`](crate::Ray::with_range)
    /// refuses (a non-finite origin, a zero or non-finite direction, a
    /// non-finite `t_min` or `t_min > t_max`: [`GridError::Ray`]), an invalid
    /// cell size or grid origin, a start cell beyond the supported indices
    /// ([`GridError::OutOfRange`]).
    pub fn new(origin: Vec3, direction: Vec3, config: &TraversalConfig) -> Result<Self, GridError> {
        let layout = GridLayout::new(config.grid_origin, config.cell_size)?;
        let mut walk = Self::in_layout(&layout, origin, direction, config.t_min, config.t_max)?;
        walk.steps_left = config.max_steps;
        walk.done |= config.max_steps == 0;
        Ok(walk)
    }

    /// The walk of `origin + t · direction`, `t ∈ [t_min, t_max]`, through the
    /// cells of `layout` (no step limit); errors as [`GridTraversal::new`].
    pub fn in_layout(
        layout: &GridLayout,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Result<Self, GridError> {
        crate::ray::Ray::with_range(origin, direction, t_min, t_max)?;
        Self::in_layout_f64(layout, origin, direction, t_min as f64, t_max as f64)
    }

    /// [`GridTraversal::in_layout`] over an `f64` parameter range, for callers
    /// that clip the ray in `f64` (a long ray's `f32` parameters cannot tell
    /// its cells apart). The ray and range must already be valid.
    pub(crate) fn in_layout_f64(
        layout: &GridLayout,
        origin: Vec3,
        direction: Vec3,
        t_min: f64,
        t_max: f64,
    ) -> Result<Self, GridError> {
        let o = [origin.x as f64, origin.y as f64, origin.z as f64];
        let d = [direction.x as f64, direction.y as f64, direction.z as f64];
        let t0 = t_min;
        let mut walk = Self {
            layout: *layout,
            origin: o,
            direction: d,
            inv: d.map(|x| 1.0 / x),
            cell: [0; 3],
            step: d.map(|x| {
                if x > 0.0 {
                    1
                } else if x < 0.0 {
                    -1
                } else {
                    0
                }
            }),
            offset: d.map(|x| (x > 0.0) as i64),
            t_next: [f64::INFINITY; 3],
            t: t0,
            t_max,
            steps_left: u64::MAX,
            done: t_min == t_max,
        };
        for a in 0..3 {
            let start = o[a] + t0 * d[a];
            let guess = ((start - layout.origin()[a] as f64) / layout.cell_size()[a] as f64).floor();
            let max = layout.max_index(a);
            let index = match walk.step[a] {
                // The last cell entered at or before t0.
                1 => last_true(guess, max, |i| walk.compare_with(a, i, t0) != Ordering::Greater),
                // Going down, cell i is entered at b(i + 1) and left at b(i).
                -1 => last_true(guess, max, |i| walk.compare_with(a, i, t0) == Ordering::Greater),
                _ => last_true(guess, max, |i| layout.boundary(a, i) <= o[a]),
            };
            walk.cell[a] = index.ok_or(GridError::OutOfRange)?;
            if walk.step[a] != 0 {
                walk.t_next[a] = walk.crossing(a, walk.cell[a] + walk.offset[a]);
            }
        }
        Ok(walk)
    }

    /// Parameter where the ray crosses the boundary `b_axis(index)`, rounded.
    #[inline]
    fn crossing(&self, axis: usize, index: i64) -> f64 {
        (self.layout.boundary(axis, index) - self.origin[axis]) * self.inv[axis]
    }

    /// The exact crossing parameter of `b_axis(index)` compared with `t`:
    /// rounded when they are clearly apart, in integers otherwise.
    fn compare_with(&self, axis: usize, index: i64, t: f64) -> Ordering {
        let c = self.crossing(axis, index);
        let slack = CROSSING_SLACK * c.abs().max(t.abs());
        if c < t - slack {
            Ordering::Less
        } else if c > t + slack {
            Ordering::Greater
        } else {
            exact_crossing_vs(
                self.layout.boundary(axis, index),
                self.origin[axis],
                self.direction[axis],
                t,
            )
        }
    }

    /// The exact order of the crossings of `b_a(n)` and `b_b(m)` (both axes moving).
    fn compare_crossings(&self, a: usize, n: i64, b: usize, m: i64) -> Ordering {
        exact_crossings(
            [self.layout.boundary(a, n), self.origin[a], self.direction[a]],
            [self.layout.boundary(b, m), self.origin[b], self.direction[b]],
        )
    }

    /// The grid the walk goes through.
    pub fn layout(&self) -> &GridLayout {
        &self.layout
    }
}

impl GridTraversal {
    /// Steps axis `a` to its next cell; `false` when the index would leave
    /// the supported range.
    #[inline(always)]
    fn advance(&mut self, a: usize) -> bool {
        let next = self.cell[a] + self.step[a];
        if next.abs() > self.layout.max_index(a) {
            return false;
        }
        self.cell[a] = next;
        self.t_next[a] = self.crossing(a, next + self.offset[a]);
        true
    }

    /// The boundary index of axis `a`'s next crossing.
    #[inline(always)]
    fn next_boundary(&self, a: usize) -> i64 {
        self.cell[a] + self.offset[a]
    }

    /// Among the axes whose rounded next crossing is at most `limit`, the
    /// one crossed first, decided exactly (the lowest axis among exact ties).
    #[cold]
    fn first_exactly(&self, limit: f64) -> usize {
        let mut first = usize::MAX;
        for a in (0..3).filter(|&a| self.step[a] != 0 && self.t_next[a] <= limit) {
            if first == usize::MAX
                || self.compare_crossings(a, self.next_boundary(a), first, self.next_boundary(first)) == Ordering::Less
            {
                first = a;
            }
        }
        first
    }

    /// After the crossing of `b_m(n)` at rounded parameter `t`: steps every
    /// axis whose next crossing is exactly at or before it — the crossing
    /// axis and the other axes of an edge or corner — until
    /// the current cell has positive length. `false` when an index would
    /// leave the supported range.
    #[cold]
    fn settle_exactly(&mut self, m: usize, n: i64, t: f64) -> bool {
        let limit = t + CROSSING_SLACK * t.abs();
        loop {
            let mut stepped = false;
            for a in 0..3 {
                while self.step[a] != 0
                    && self.t_next[a] <= limit
                    && self.compare_crossings(a, self.next_boundary(a), m, n) != Ordering::Greater
                {
                    if !self.advance(a) {
                        return false;
                    }
                    stepped = true;
                }
            }
            if !stepped {
                return true;
            }
        }
    }
}

impl Iterator for GridTraversal {
    type Item = TraversalStep;

    #[inline]
    fn next(&mut self) -> Option<TraversalStep> {
        if self.done {
            return None;
        }
        let [tx, ty, tz] = self.t_next;
        let t_cross = tx.min(ty).min(tz);
        let out = TraversalStep {
            cell: self.cell,
            t_enter: self.t as f32,
            t_exit: t_cross.min(self.t_max) as f32,
        };
        self.steps_left -= 1;
        // Crossings within `slack` of each other may be in either order or
        // tied: those (rays through edges and corners) are decided exactly.
        let limit = t_cross + CROSSING_SLACK * t_cross.abs();
        let near = (tx <= limit) as u32 + (ty <= limit) as u32 + (tz <= limit) as u32;
        // Constant axis indices in each branch keep the state in registers,
        // and a branch (not a select) lets the processor run ahead.
        let m = if near > 1 {
            self.first_exactly(limit)
        } else if tx == t_cross {
            0
        } else if ty == t_cross {
            1
        } else {
            2
        };
        let n = self.next_boundary(m);
        let near_end = self.t_max.is_finite()
            && (t_cross - self.t_max).abs() <= CROSSING_SLACK * t_cross.abs().max(self.t_max.abs());
        let ends = if near_end {
            self.compare_with(m, n, self.t_max) != Ordering::Less
        } else {
            t_cross >= self.t_max
        };
        // Past f32::MAX the parameters of the cells after this one would all
        // read ∞: the walk ends with the cell it never leaves in f32.
        if ends || self.steps_left == 0 || !out.t_exit.is_finite() {
            self.done = true;
            return Some(out);
        }
        self.t = t_cross;
        let ok = if near > 1 {
            self.settle_exactly(m, n, t_cross)
        } else {
            let ok = match m {
                0 => self.advance(0),
                1 => self.advance(1),
                _ => self.advance(2),
            };
            // A zero-width or tiny next cell is rare: one test here.
            let [tx, ty, tz] = self.t_next;
            ok && ((tx > limit) & (ty > limit) & (tz > limit) || self.settle_exactly(m, n, t_cross))
        };
        if !ok {
            self.done = true;
        }
        Some(out)
    }
}

/// The exact order of `(plane − origin) / direction` and `t` (direction ≠ 0).
#[cold]
#[inline(never)]
fn exact_crossing_vs(plane: f64, origin: f64, direction: f64, t: f64) -> Ordering {
    // 1 joins the inputs so that the scale of the product t · direction can
    // be matched: distance · 1 against t · direction, both of degree two.
    let (low, bits) = common_scale(&[plane, origin, direction, t, 1.0]);
    // Products of two inputs or differences: 2 · bits + 2 at most.
    if bits <= 61 {
        crossing_vs_in::<i128>(plane, origin, direction, t, low)
    } else {
        crossing_vs_in::<BigInt>(plane, origin, direction, t, low)
    }
}

fn crossing_vs_in<T: Exact>(plane: f64, origin: f64, direction: f64, t: f64, low: i32) -> Ordering {
    let distance: T = (integer::<T>(plane, low) - integer(origin, low)) * integer(1.0, low);
    let reach: T = integer::<T>(t, low) * integer(direction, low);
    // distance / direction against t: multiply by direction, flip if negative.
    let order = distance.cmp(&reach);
    if direction > 0.0 { order } else { order.reverse() }
}

/// The exact order of two crossing parameters, each `[plane, origin, direction]`
/// with a non-zero direction.
#[cold]
#[inline(never)]
fn exact_crossings(a: [f64; 3], b: [f64; 3]) -> Ordering {
    let (low, bits) = common_scale(&[a[0], a[1], a[2], b[0], b[1], b[2]]);
    if bits <= 61 {
        crossings_in::<i128>(a, b, low)
    } else {
        crossings_in::<BigInt>(a, b, low)
    }
}

fn crossings_in<T: Exact>(a: [f64; 3], b: [f64; 3], low: i32) -> Ordering {
    // (pa − oa) / da against (pb − ob) / db: cross-multiply by da · db, and
    // flip the order when that product is negative.
    let left = (integer::<T>(a[0], low) - integer(a[1], low)) * integer(b[2], low);
    let right = (integer::<T>(b[0], low) - integer(b[1], low)) * integer(a[2], low);
    let order = left.cmp(&right);
    if (a[2] > 0.0) == (b[2] > 0.0) {
        order
    } else {
        order.reverse()
    }
}
