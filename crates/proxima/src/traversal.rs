//! Grid traversal: the cells a ray passes through, in order (Amanatides & Woo,
//! "A Fast Voxel Traversal Algorithm for Ray Tracing", 1987).
//!
//! [`GridTraversal`] is an [`Iterator`] of [`TraversalStep`]s: each cell
//! `(i, j, k)` with the ray parameters where the ray enters and leaves it.
//! Per step it compares the three parameters of the next boundary crossings,
//! steps the axis (or axes) crossed first, and computes that axis' next
//! crossing — a handful of operations and no allocation.
//!
//! # Which cells are yielded
//!
//! Exactly the cells in which the ray spends a parameter interval of
//! **positive length** within `[t_min, t_max]`, in order, each once:
//!
//! - cells are closed boxes ([`GridLayout::cell_box`]) along every axis the
//!   ray moves along; along an axis where the direction is zero, the ray is
//!   given to the half-open cell `[b(i), b(i+1))`, so a ray lying in a
//!   boundary plane walks the cells *above* it;
//! - a ray through an edge or a corner of cells (two or three boundaries
//!   crossed at the same parameter) steps the crossed axes together: the
//!   cells it only grazes at that single point are not yielded. The same holds
//!   for an origin on a boundary: the walk starts in the cell the ray enters;
//! - the parameter of crossing the boundary `b_a(n)` is
//!   `(b_a(n) − origin_a) · (1 / direction_a)`, computed in `f64`; ties are
//!   decided on these values, so two crossings whose rounded parameters differ
//!   make a cell of tiny positive length, which is yielded;
//! - `t_enter` of each cell is the `t_exit` of the one before; the first
//!   starts at `t_min`, the last ends at `t_max` (or at the step limit). An
//!   empty range (`t_min == t_max`) yields nothing.
//!
//! The walk ends when `t_max` is reached, after `max_steps` cells, with the
//! cell whose exit parameter no longer fits `f32` (yielded with
//! `t_exit = ∞`), or when a cell index would leave `±2^50`
//! ([`MAX_CELL_INDEX`]) — never later: with `t_max = ∞` and no step limit it
//! is merely very long. The parameters are
//! tracked in `f64`, so huge `t` does not stall the walk; they are yielded as
//! `f32`.
//!
//! # Worked example
//!
//! Cell size 0.3, origin (1, 0.2, 0.5), direction (0.3, 0.5, 1) normalized:
//!
//! ```
//! use proxima::traversal::{GridTraversal, TraversalConfig};
//! use proxima::Vec3;
//! let dir = Vec3::new(0.3, 0.5, 1.0).normalize();
//! let walk = GridTraversal::new(Vec3::new(1.0, 0.2, 0.5), dir, &TraversalConfig::cubic(0.3)).unwrap();
//! let steps: Vec<_> = walk.take(4).collect();
//! let cells: Vec<_> = steps.iter().map(|s| s.cell).collect();
//! assert_eq!(cells, [[3, 0, 1], [3, 0, 2], [3, 1, 2], [3, 1, 3]]);
//! // z reaches 0.6 first, at t = 0.1 / 0.8639 = 0.1158, then y reaches 0.3 at
//! // t = 0.1 / 0.4319 = 0.2315.
//! assert!((steps[0].t_exit - 0.1158).abs() < 1e-4);
//! assert!((steps[1].t_exit - 0.2315).abs() < 1e-4);
//! assert_eq!(steps[1].t_enter, steps[0].t_exit);
//! ```

use crate::error::GridError;
use crate::grid::{Cell, GridLayout, MAX_CELL_INDEX, last_true};
use crate::math::Vec3;

/// Where a traversal walks: cell placement, parameter range and step limit.
///
/// ```
/// use proxima::traversal::TraversalConfig;
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

/// The Amanatides–Woo walk of a ray through a grid; see the [module
/// documentation](self) for exactly which cells it yields.
#[derive(Clone, Debug)]
pub struct GridTraversal {
    layout: GridLayout,
    origin: [f64; 3],
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
    /// Errors: a zero or non-finite direction ([`GridError::RayDirection`]), a
    /// non-finite origin ([`GridError::RayOrigin`]), an invalid cell size or
    /// grid origin, a non-finite `t_min` or `t_min > t_max`
    /// ([`GridError::RayRange`]), a start cell beyond the supported indices
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
        if !direction.is_finite() || direction == Vec3::ZERO {
            return Err(GridError::RayDirection);
        }
        if !origin.is_finite() {
            return Err(GridError::RayOrigin);
        }
        if !(t_min.is_finite() && t_min <= t_max) {
            return Err(GridError::RayRange { t_min, t_max });
        }
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
            let index = match walk.step[a] {
                // The last cell entered at or before t0.
                1 => last_true(guess, |i| walk.crossing(a, i) <= t0),
                // Going down, cell i is entered at b(i + 1) and left at b(i).
                -1 => last_true(guess, |i| walk.crossing(a, i) > t0),
                _ => last_true(guess, |i| layout.boundary(a, i) as f64 <= o[a]),
            };
            walk.cell[a] = index.ok_or(GridError::OutOfRange)?;
            if walk.step[a] != 0 {
                walk.t_next[a] = walk.crossing(a, walk.cell[a] + walk.offset[a]);
            }
        }
        Ok(walk)
    }

    /// Parameter where the ray crosses the boundary `b_axis(index)`.
    #[inline]
    fn crossing(&self, axis: usize, index: i64) -> f64 {
        (self.layout.boundary(axis, index) as f64 - self.origin[axis]) * self.inv[axis]
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
        if next.unsigned_abs() > MAX_CELL_INDEX as u64 {
            return false;
        }
        self.cell[a] = next;
        self.t_next[a] = self.crossing(a, next + self.offset[a]);
        true
    }

    /// After a crossing at `self.t`: step every other axis crossed at the same
    /// parameter, and skip cells of zero length (zero-width cells far from
    /// the origin), until the current cell has positive length.
    #[cold]
    fn settle(&mut self) -> bool {
        loop {
            for a in 0..3 {
                if self.t_next[a] <= self.t && !self.advance(a) {
                    return false;
                }
            }
            let [tx, ty, tz] = self.t_next;
            if tx.min(ty).min(tz) > self.t {
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
        // Past f32::MAX the parameters of the cells after this one would all
        // read ∞: the walk ends with the cell it never leaves in f32.
        if t_cross >= self.t_max || self.steps_left == 0 || !out.t_exit.is_finite() {
            self.done = true;
            return Some(out);
        }
        self.t = t_cross;
        // Constant axis indices in each branch keep the state in registers,
        // and a branch (not a select) lets the processor run ahead.
        let ok = if tx == t_cross {
            self.advance(0)
        } else if ty == t_cross {
            self.advance(1)
        } else {
            self.advance(2)
        };
        // Ties (edges, corners) and zero-width cells are rare: one test here.
        let [tx, ty, tz] = self.t_next;
        if !ok || ((tx <= t_cross) | (ty <= t_cross) | (tz <= t_cross) && !self.settle()) {
            self.done = true;
        }
        Some(out)
    }
}
