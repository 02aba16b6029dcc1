//! Where the cells are: grid origin, per-axis cell extents, cell boxes and the
//! cell ranges of boxes and points.
//!
//! # Cell boundaries
//!
//! The boundary planes along axis `a` are `b_a(i) = origin_a + i · size_a`,
//! **exactly**: the origin and the extents are `f32` values, and every plane
//! is the real number they give, held in `f64` without rounding
//! ([`GridLayout::boundary`]). Cell `(i, j, k)` is the closed box
//! `[b_x(i), b_x(i+1)] × [b_y(j), b_y(j+1)] × [b_z(k), b_z(k+1)]`; neighbouring
//! cells share their planes, and cell `(0, 0, 0)` starts at the grid origin.
//! Every test of the grid (cell ranges, exact overlap, traversal) compares
//! against these exact planes, so a vertex a fraction of an `f32` step off a
//! plane is on the side it really is, and all tests agree on it — the same
//! answer a user gets from `origin + i * cell_size` in exact (or, for any
//! reasonable grid, `f64`) arithmetic.
//!
//! A plane is a multiple of the lowest bit `2^L` of the origin and the
//! extent, so it is exact in `f64` while `|origin| + |i| · size ≤ 2^(L+53)`.
//! That bounds the cell indices of each axis ([`GridLayout::max_index`]: about
//! `2^29` for an extent that uses all 24 bits of its `f32` mantissa, up to
//! [`MAX_CELL_INDEX`] = `2^50` for round extents); beyond it a query is
//! an error ([`GridError::OutOfRange`]), not a wrap-around or a rounded plane.
//! An origin whose bits reach so far below the extent's that not even cell 0
//! is exact (an origin of `1e-30` with cells of 1) is refused
//! ([`GridError::InexactPlanes`]).

use super::Cell;
use crate::aabb::Aabb;
use crate::error::GridError;
use crate::math::{DVec3, Vec3};

/// The largest cell index magnitude on any axis, whatever the layout (a
/// layout's own limit, [`GridLayout::max_index`], may be lower).
pub const MAX_CELL_INDEX: i64 = 1 << 50;

/// Relative distance to a boundary (in cells, per unit of index) beyond which
/// the rounding of the estimate `(x − origin) / size` (a few units of 2^-53)
/// cannot change the cell of a value: 2^-22, far more than needed.
const FAST_MARGIN: f64 = 1.0 / (1u64 << 22) as f64;

/// The placement of a grid's cells: origin and per-axis extents, validated.
///
/// ```
/// use proxima::grid::GridLayout;
/// use proxima::{Aabb, Vec3};
/// let layout = GridLayout::new(Vec3::ZERO, Vec3::splat(0.5)).unwrap();
/// assert_eq!(layout.cell_of(Vec3::new(0.7, -0.2, 1.0)).unwrap(), [1, -1, 2]);
/// assert_eq!(layout.cell_box([1, -1, 2]), Aabb::new(Vec3::new(0.5, -0.5, 1.0), Vec3::new(1.0, 0.0, 1.5)));
/// // Closed cells: a box ending exactly on a boundary touches the next cell too.
/// let range = layout.cell_range(&Aabb::new(Vec3::splat(0.1), Vec3::splat(0.5))).unwrap();
/// assert_eq!((range.min, range.max), ([0, 0, 0], [1, 1, 1]));
/// assert!(GridLayout::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)).is_err());
///
/// // Planes are exact: 3 · 0.1f32 is not an f32, and the plane is that real number.
/// let tenth = GridLayout::cubic(0.1).unwrap();
/// let plane = 3.0 * (0.1f32 as f64);
/// assert_eq!(tenth.boundary(0, 3), plane);
/// // The f32 values on either side of it fall in the cells on either side.
/// let nearest = plane as f32;
/// let (below, above) = if nearest as f64 > plane { (nearest.next_down(), nearest) } else { (nearest, nearest.next_up()) };
/// assert_eq!(tenth.cell_of(Vec3::new(below, 0.0, 0.0)).unwrap()[0], 2);
/// assert_eq!(tenth.cell_of(Vec3::new(above, 0.0, 0.0)).unwrap()[0], 3);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridLayout {
    origin: Vec3,
    cell_size: Vec3,
    origin64: [f64; 3],
    size64: [f64; 3],
    /// `1 / size` per axis.
    inv64: [f64; 3],
    /// How far (in cells) the rounding of the estimate may move a value near
    /// the origin, with a wide margin: `(|origin| / size + 1) · 2^-22`.
    slack64: [f64; 3],
    /// Per axis, the largest index magnitude `m` for which every plane
    /// `b(i)`, `|i| ≤ m + 1`, is exact in `f64` (at most [`MAX_CELL_INDEX`]).
    max_index: [i64; 3],
}

/// An inclusive box of cell indices: every cell `c` with `min ≤ c ≤ max` per axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CellRange {
    /// Smallest index on each axis.
    pub min: Cell,
    /// Largest index on each axis (inclusive).
    pub max: Cell,
}

impl CellRange {
    /// Number of cells along `axis` (0 when the range is empty).
    #[inline]
    pub fn extent(&self, axis: usize) -> u64 {
        if self.max[axis] < self.min[axis] {
            0
        } else {
            (self.max[axis] - self.min[axis]) as u64 + 1
        }
    }

    /// Number of cells (0 when empty).
    #[inline]
    pub fn count(&self) -> u128 {
        (0..3).map(|a| self.extent(a) as u128).product()
    }

    /// `true` when the range holds no cell.
    #[inline]
    pub fn is_empty(&self) -> bool {
        (0..3).any(|a| self.max[a] < self.min[a])
    }

    /// `true` when `cell` is in the range.
    #[inline]
    pub fn contains(&self, cell: Cell) -> bool {
        (0..3).all(|a| self.min[a] <= cell[a] && cell[a] <= self.max[a])
    }

    /// The cells in both ranges (possibly empty).
    #[inline]
    pub fn intersection(&self, other: &CellRange) -> CellRange {
        CellRange {
            min: std::array::from_fn(|a| self.min[a].max(other.min[a])),
            max: std::array::from_fn(|a| self.max[a].min(other.max[a])),
        }
    }

    /// The smallest range holding both.
    #[inline]
    pub fn merge(&self, other: &CellRange) -> CellRange {
        CellRange {
            min: std::array::from_fn(|a| self.min[a].min(other.min[a])),
            max: std::array::from_fn(|a| self.max[a].max(other.max[a])),
        }
    }

    /// `true` when at most one axis holds more than one cell: the range is a
    /// single cell or a line of cells. A connected primitive whose bounding
    /// box has such a range overlaps every cell of it.
    #[inline]
    pub fn is_line(&self) -> bool {
        (0..3).filter(|&a| self.extent(a) > 1).count() <= 1
    }

    /// The cells in x-fastest order (x, then y, then z).
    pub fn iter(&self) -> impl Iterator<Item = Cell> + '_ {
        let r = *self;
        (r.min[2]..=r.max[2])
            .flat_map(move |k| (r.min[1]..=r.max[1]).flat_map(move |j| (r.min[0]..=r.max[0]).map(move |i| [i, j, k])))
    }
}

impl GridLayout {
    /// Cells of extents `cell_size` with cell `(0, 0, 0)` starting at `origin`.
    /// Fails on a non-finite origin, on a zero, negative or non-finite extent,
    /// and on an origin whose planes cannot be exact even next to it
    /// ([`GridError::InexactPlanes`], see the module documentation).
    pub fn new(origin: Vec3, cell_size: Vec3) -> Result<Self, GridError> {
        if !(cell_size.is_finite() && cell_size.cmpgt(Vec3::ZERO).all()) {
            return Err(GridError::CellSize {
                x: cell_size.x,
                y: cell_size.y,
                z: cell_size.z,
            });
        }
        if !origin.is_finite() {
            return Err(GridError::GridOrigin);
        }
        let to64 = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let max_index: [i64; 3] = std::array::from_fn(|a| exact_index_limit(origin[a], cell_size[a]));
        if let Some(axis) = (0..3).find(|&a| max_index[a] < 1) {
            return Err(GridError::InexactPlanes {
                axis: b"xyz"[axis] as char,
                origin: origin[axis],
                size: cell_size[axis],
            });
        }
        Ok(Self {
            origin,
            cell_size,
            origin64: to64(origin),
            size64: to64(cell_size),
            inv64: to64(cell_size).map(|s| 1.0 / s),
            slack64: std::array::from_fn(|a| (origin[a].abs() as f64 / cell_size[a] as f64 + 1.0) * FAST_MARGIN),
            max_index,
        })
    }

    /// Cubic cells of side `size`, grid origin at the world origin.
    pub fn cubic(size: f32) -> Result<Self, GridError> {
        Self::new(Vec3::ZERO, Vec3::splat(size))
    }

    /// The grid origin (the minimum corner of cell `(0, 0, 0)`).
    #[inline]
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The cell extents along x, y and z.
    #[inline]
    pub fn cell_size(&self) -> Vec3 {
        self.cell_size
    }

    /// The largest cell index magnitude along `axis` whose planes are exact:
    /// queries reaching beyond it are [`GridError::OutOfRange`].
    #[inline]
    pub fn max_index(&self, axis: usize) -> i64 {
        self.max_index[axis]
    }

    /// The boundary plane `b_axis(index) = origin + index · size`: the lower
    /// side of the cells of that index. Exact for `|index| ≤ max_index + 1`
    /// (every index a query of the layout reaches).
    #[inline(always)]
    pub fn boundary(&self, axis: usize, index: i64) -> f64 {
        self.origin64[axis] + index as f64 * self.size64[axis]
    }

    /// The closed box of `cell`, exactly: its minimum and maximum corners.
    #[inline]
    pub fn cell_bounds(&self, cell: Cell) -> (DVec3, DVec3) {
        let corner = |offset: i64| {
            DVec3::new(
                self.boundary(0, cell[0] + offset),
                self.boundary(1, cell[1] + offset),
                self.boundary(2, cell[2] + offset),
            )
        };
        (corner(0), corner(1))
    }

    /// The closed box of `cell` in `f32`, rounded outward where a plane is
    /// not an `f32`: it holds the cell ([`GridLayout::cell_bounds`] is the
    /// cell itself). For drawing and for coarse tests.
    #[inline]
    pub fn cell_box(&self, cell: Cell) -> Aabb {
        let (lo, hi) = self.cell_bounds(cell);
        Aabb::enclosing(lo, hi)
    }

    /// The cell holding `p` when cells are taken half-open, `[b(i), b(i+1))` on
    /// each axis: every point belongs to exactly one such cell.
    pub fn cell_of(&self, p: Vec3) -> Result<Cell, GridError> {
        let mut cell = [0; 3];
        for (axis, c) in cell.iter_mut().enumerate() {
            *c = self.last_at_or_below(axis, p[axis] as f64)?;
        }
        Ok(cell)
    }

    /// Every cell whose closed box overlaps the closed box `b` (touching counts).
    #[inline(always)]
    pub fn cell_range(&self, b: &Aabb) -> Result<CellRange, GridError> {
        if !b.is_finite() || b.is_empty() {
            return Err(GridError::OutOfRange);
        }
        let mut range = CellRange {
            min: [0; 3],
            max: [0; 3],
        };
        for axis in 0..3 {
            range.min[axis] = self.first_touching(axis, b.min[axis] as f64)?;
            range.max[axis] = self.last_at_or_below(axis, b.max[axis] as f64)?;
        }
        Ok(range)
    }

    /// The largest `i` with `b(i) ≤ x`: the last cell along `axis` whose closed
    /// extent touches `x` (and the half-open cell holding `x`).
    #[inline(always)]
    pub(crate) fn last_at_or_below(&self, axis: usize, x: f64) -> Result<i64, GridError> {
        let (guess, safe) = self.estimate(axis, x);
        if safe {
            Ok(guess)
        } else {
            self.last_at_or_below_slow(axis, x, guess)
        }
    }

    #[cold]
    #[inline(never)]
    fn last_at_or_below_slow(&self, axis: usize, x: f64, guess: i64) -> Result<i64, GridError> {
        last_true(guess as f64, self.max_index[axis], |i| self.boundary(axis, i) <= x).ok_or(GridError::OutOfRange)
    }

    /// `floor((x − origin) / size)` and whether `x` is so far from both
    /// boundaries of that cell that their `f32` rounding cannot matter: then
    /// the cell strictly contains `x` and is the answer of both searches.
    #[inline(always)]
    fn estimate(&self, axis: usize, x: f64) -> (i64, bool) {
        let t = (x - self.origin64[axis]) * self.inv64[axis];
        let max = self.max_index[axis];
        if t.is_nan() || t.abs() >= max as f64 {
            return (if t > 0.0 { max } else { -max }, false);
        }
        let i = t as i64;
        let i = if (i as f64) > t { i - 1 } else { i };
        let frac = t - i as f64;
        let margin = self.slack64[axis] + t.abs() * FAST_MARGIN;
        (i, frac > margin && frac < 1.0 - margin)
    }

    /// The smallest `i` with `b(i + 1) ≥ x`: the first cell along `axis` whose
    /// closed extent touches `x`.
    #[inline(always)]
    pub(crate) fn first_touching(&self, axis: usize, x: f64) -> Result<i64, GridError> {
        let (guess, safe) = self.estimate(axis, x);
        if safe {
            Ok(guess)
        } else {
            self.first_touching_slow(axis, x, guess)
        }
    }

    #[cold]
    #[inline(never)]
    fn first_touching_slow(&self, axis: usize, x: f64, guess: i64) -> Result<i64, GridError> {
        last_true(guess as f64 - 1.0, self.max_index[axis], |i| {
            self.boundary(axis, i + 1) < x
        })
        .map(|i| i + 1)
        .ok_or(GridError::OutOfRange)
    }
}

/// The largest `i` in `[-max, max]` for which `pred` holds, for a `pred`
/// that is true up to some index and false after it; `None` when it holds
/// nowhere or at `max` (out of range). Galloping search from `guess`: two
/// evaluations when the guess is right.
#[inline]
pub(crate) fn last_true(guess: f64, max: i64, pred: impl Fn(i64) -> bool) -> Option<i64> {
    let max_f = max as f64;
    if guess.is_nan() {
        return None;
    }
    let g = guess.clamp(-max_f, max_f) as i64;
    let (mut lo, mut hi);
    if pred(g) {
        lo = g;
        let mut step = 1;
        loop {
            if lo == max {
                return None;
            }
            let next = (lo + step).min(max);
            if !pred(next) {
                hi = next;
                break;
            }
            lo = next;
            step *= 2;
        }
    } else {
        hi = g;
        let mut step = 1;
        loop {
            if hi == -max {
                return None;
            }
            let next = (hi - step).max(-max);
            if pred(next) {
                lo = next;
                break;
            }
            hi = next;
            step *= 2;
        }
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if pred(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(lo)
}

/// The exponent of the lowest set bit of a finite non-zero `x`.
fn lowest_bit(x: f64) -> i32 {
    let (_, exponent) = crate::exact::parts(x).expect("non-zero");
    exponent
}

/// The largest `m ≤ MAX_CELL_INDEX` such that `origin + i · size` is exact in
/// `f64` for every `|i| ≤ m + 1`; below 1 when even the first planes are not.
///
/// Every plane is a multiple of `2^L`, `L` the lowest bit of `origin` and
/// `size`, so it is exact when its magnitude is at most `2^(L+53)`; so is
/// `i · size`, a multiple of `2^L` no larger in magnitude than
/// `|origin| + |i| · size`. Hence `m + 1 ≤ (2^(L+53) − |origin|) / size`,
/// taken with a margin for the rounding of that quotient.
pub(crate) fn exact_index_limit(origin: f32, size: f32) -> i64 {
    let (origin, size) = (origin as f64, size as f64);
    let low = if origin == 0.0 {
        lowest_bit(size)
    } else {
        lowest_bit(origin).min(lowest_bit(size))
    };
    let room = (2f64.powi(low + 53) - origin.abs()) / size;
    if room < 3.0 {
        return 0;
    }
    // Rounded down and one more off for the quotient's rounding.
    ((room * (1.0 - f64::EPSILON)).floor() as i64 - 2).min(MAX_CELL_INDEX)
}
