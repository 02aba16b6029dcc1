//! Signed distances at the cell centres of a dense grid, and training
//! samples (points near the surface and uniform in a box, with their signed
//! distances).

use super::field::SignedDistanceField;
use crate::aabb::Aabb;
use crate::budget::{BudgetError, check_fits};
use crate::build::MAX_QUERY_COORDINATE;
use crate::error::SdfError;
use crate::math::Vec3;
use crate::sample::{near_triangles, uniform_in};

/// A dense grid of sample points: the centres of `resolution` cells per
/// axis dividing a box.
///
/// ```
/// use proxima::{Aabb, Vec3};
/// use proxima::sdf::SdfGrid;
/// let grid = SdfGrid::over(&Aabb::new(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)), [4, 2, 2]).unwrap();
/// assert_eq!(grid.cell, Vec3::new(0.5, 0.5, 0.5));
/// assert_eq!(grid.point(0, 0, 0), Vec3::splat(0.25));
/// assert_eq!(grid.point(3, 1, 1), Vec3::new(1.75, 0.75, 0.75));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdfGrid {
    /// The box's smallest corner (the first cell's corner, not its centre).
    pub min: Vec3,
    /// Cell size per axis.
    pub cell: Vec3,
    /// Cells per axis.
    pub resolution: [usize; 3],
}

impl SdfGrid {
    /// The margin around a mesh's bounding box, per side as a fraction of
    /// its size, of the grids and uniform samples of `proxima sdf` and of
    /// Python's `Mesh.sdf_grid` and `Mesh.training_samples` when no cube is
    /// given.
    pub const DEFAULT_MARGIN: f32 = 0.05;

    /// `resolution` cells per axis dividing `bounds`. Fails on a zero
    /// resolution or a box that is empty or not finite.
    pub fn over(bounds: &Aabb, resolution: [usize; 3]) -> Result<Self, SdfError> {
        if resolution.contains(&0) {
            return Err(SdfError::Zero { option: "resolution" });
        }
        let size = bounds.size();
        if bounds.is_empty() || !size.is_finite() || !bounds.min.is_finite() {
            let value = if bounds.is_empty() { -1.0 } else { f32::INFINITY };
            return Err(SdfError::Parameter {
                option: "bounds",
                value,
            });
        }
        let n = Vec3::new(resolution[0] as f32, resolution[1] as f32, resolution[2] as f32);
        Ok(Self {
            min: bounds.min,
            cell: size / n,
            resolution,
        })
    }

    /// The cube of `n` cells per axis over `bounds` grown by `margin` times
    /// its size on every side (the CLI's `--grid N` uses
    /// [`DEFAULT_MARGIN`](Self::DEFAULT_MARGIN)).
    pub fn around(bounds: &Aabb, n: usize, margin: f32) -> Result<Self, SdfError> {
        check_length("margin", margin)?;
        let grow = bounds.size() * margin;
        Self::over(&Aabb::new(bounds.min - grow, bounds.max + grow), [n; 3])
    }

    /// The centre of cell `(i, j, k)`.
    #[inline]
    pub fn point(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.min + self.cell * Vec3::new(i as f32 + 0.5, j as f32 + 0.5, k as f32 + 0.5)
    }

    /// The centre of the first cell.
    pub fn origin(&self) -> Vec3 {
        self.point(0, 0, 0)
    }

    /// Number of cells (saturating).
    pub fn len(&self) -> u64 {
        self.resolution.iter().fold(1u64, |n, &r| n.saturating_mul(r as u64))
    }

    /// `true` for a grid without cells (never, once made by [`over`](Self::over)).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Points near a surface and uniform in a box, with their signed distances.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    /// The points.
    pub points: Vec<Vec3>,
    /// Their signed distances (`points[i]`'s in `signed_distances[i]`).
    pub signed_distances: Vec<f32>,
}

/// Cells of a grid answered by one batch: the points and the batch's answers
/// (about 60 bytes a cell, some 16 MiB) stay bounded whatever the grid's size.
const GRID_BATCH: usize = 1 << 18;

/// What the seed of [`SignedDistanceField::training_samples`]' uniform
/// samples is xor-ed with.
const UNIFORM_STREAM: u64 = 0x5851_f42d_4c95_7f2d;

/// Fails with [`SdfError::Parameter`] unless `value` is finite and not negative.
fn check_length(option: &'static str, value: f32) -> Result<(), SdfError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(SdfError::Parameter { option, value })
    }
}

/// Fails on a zero `count`, and unless `count` items of `bytes_each` fit
/// the memory budget of the environment ([`check_fits`]: the
/// `PROXIMA_MEMORY_BUDGET` of every front end, or the default).
fn check_budget(option: &'static str, count: u64, bytes_each: u64) -> Result<(), SdfError> {
    if count == 0 {
        return Err(SdfError::Zero { option });
    }
    check_fits(option, count, count.into(), bytes_each.into()).map_err(|e| match e {
        BudgetError::TooLarge { budget, .. } => SdfError::MemoryBudget {
            option,
            value: count,
            bytes: u64::try_from(e.bytes()).unwrap_or(u64::MAX),
            budget,
        },
        e => SdfError::Budget(e),
    })
}

impl SignedDistanceField {
    /// The signed distances at the cell centres of `grid`, x fastest (the
    /// value of cell `(i, j, k)` at `i + nx (j + ny k)`), on all cores.
    /// `progress(done, total)` is called on this thread as slabs of cells
    /// finish. Fails before allocating when the values would not fit the
    /// memory budget.
    ///
    /// ```
    /// use proxima::mesh::generate::noisy_icosphere;
    /// use proxima::sdf::{SdfConfig, SdfGrid, SignedDistanceField};
    /// let field = SignedDistanceField::new(&noisy_icosphere(4, 1), &SdfConfig::default()).unwrap();
    /// let grid = SdfGrid::around(&field.bounds(), 8, 0.05).unwrap();
    /// let values = field.sdf_grid(&grid, |_, _| {}).unwrap();
    /// assert_eq!(values.len(), 512);
    /// assert!(values[0] > 0.0); // a corner is outside
    /// assert!(values[4 + 8 * (4 + 8 * 4)] < 0.0); // the middle is inside
    /// ```
    pub fn sdf_grid(&self, grid: &SdfGrid, mut progress: impl FnMut(u64, u64)) -> Result<Vec<f32>, SdfError> {
        check_budget("resolution", grid.len(), 4)?;
        let [nx, ny, nz] = grid.resolution;
        let total = grid.len();
        let mut values = vec![0f32; total as usize];
        // About a hundred progress reports, each a whole number of z slices.
        let slab = (nz / 100).max(1);
        let mut done = 0u64;
        let mut points = Vec::with_capacity(GRID_BATCH.min(values.len()));
        for (s, slab_values) in values.chunks_mut(nx * ny * slab).enumerate() {
            let first = s * nx * ny * slab;
            for (c, out) in slab_values.chunks_mut(GRID_BATCH).enumerate() {
                let start = first + c * GRID_BATCH;
                points.clear();
                points.extend((start..start + out.len()).map(|index| {
                    let (i, row) = (index % nx, index / nx);
                    grid.point(i, row % ny, row / ny)
                }));
                // The batch (Morton order, each radius seeded by the previous
                // answer) is faster than walking the rows one query at a time.
                for (value, answer) in out.iter_mut().zip(self.signed_distance_batch(&points)) {
                    *value = answer.map_or(f32::NAN, |a| a.distance);
                }
            }
            done += slab_values.len() as u64;
            progress(done, total);
        }
        Ok(values)
    }

    /// `n` points uniform on the surface (triangles picked by area) plus a
    /// gaussian offset of standard deviation `sigma` per axis, with their
    /// signed distances. The same seed gives the same points on every
    /// machine. Fails on `n == 0`, a `sigma` negative or not finite, or an
    /// `n` beyond the memory budget.
    pub fn sample_near_surface(&self, n: usize, sigma: f32, seed: u64) -> Result<Samples, SdfError> {
        check_length("sigma", sigma)?;
        // A gaussian of 53-bit uniforms (Box–Muller) stays within 8.6 sigma.
        self.check_reach("sigma", sigma, 9.0 * sigma)?;
        check_budget("count", n as u64, 32)?;
        Ok(self.samples(near_triangles(self.triangles(), n, sigma, seed)))
    }

    /// `n` points uniform in the mesh's box grown by `margin` times its size
    /// on every side, with their signed distances (seeded as
    /// [`sample_near_surface`](Self::sample_near_surface)).
    pub fn sample_uniform(&self, n: usize, margin: f32, seed: u64) -> Result<Samples, SdfError> {
        check_length("margin", margin)?;
        self.check_reach("margin", margin, self.bounds().size().max_element() * margin)?;
        let b = self.bounds();
        let grow = b.size() * margin;
        self.sample_in(&Aabb::new(b.min - grow, b.max + grow), n, seed)
    }

    /// `n` points uniform in `bounds` (the dataset's cube `[-h, h]³`), with
    /// their signed distances, seeded as
    /// [`sample_near_surface`](Self::sample_near_surface). Fails on an empty
    /// box, one not finite or beyond the coordinates a query accepts, `n == 0`
    /// or an `n` beyond the memory budget.
    ///
    /// ```
    /// use proxima::{Aabb, Vec3};
    /// use proxima::mesh::generate::noisy_icosphere;
    /// use proxima::sdf::{SdfConfig, SignedDistanceField};
    /// let field = SignedDistanceField::new(&noisy_icosphere(4, 1), &SdfConfig::default()).unwrap();
    /// let cube = Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
    /// let samples = field.sample_in(&cube, 100, 7).unwrap();
    /// assert!(samples.points.iter().all(|p| p.abs().max_element() <= 2.0));
    /// assert_eq!(samples.signed_distances.len(), 100);
    /// ```
    pub fn sample_in(&self, bounds: &Aabb, n: usize, seed: u64) -> Result<Samples, SdfError> {
        let extent = bounds.min.abs().max(bounds.max.abs()).max_element();
        if bounds.is_empty() || !extent.is_finite() {
            let value = if bounds.is_empty() { -1.0 } else { f32::INFINITY };
            return Err(SdfError::Parameter {
                option: "bounds",
                value,
            });
        }
        if extent > MAX_QUERY_COORDINATE {
            return Err(SdfError::TooFar {
                option: "bounds",
                value: extent,
                bound: MAX_QUERY_COORDINATE,
            });
        }
        check_budget("count", n as u64, 32)?;
        Ok(self.samples(uniform_in(bounds, n, seed)))
    }

    /// Training samples, the one recipe of `proxima sdf --sample` and
    /// `proxima.dataset`: `near` points near the surface
    /// ([`sample_near_surface`](Self::sample_near_surface) with `sigma`, an
    /// absolute length in the mesh's units, and `seed`), then `uniform`
    /// points uniform in `uniform_box` ([`sample_in`](Self::sample_in), with
    /// a stream of its own derived from `seed`), with their signed
    /// distances. Split a total with
    /// [`training_sample_counts`](crate::sample::training_sample_counts).
    /// The same arguments give the same samples on every machine and thread
    /// count. A count of zero draws nothing of that kind (both zero: no
    /// samples).
    ///
    /// ```
    /// use proxima::{Aabb, Vec3};
    /// use proxima::mesh::generate::noisy_icosphere;
    /// use proxima::sdf::{SdfConfig, SignedDistanceField};
    /// let field = SignedDistanceField::new(&noisy_icosphere(4, 1), &SdfConfig::default()).unwrap();
    /// let cube = Aabb::new(Vec3::splat(-1.5), Vec3::splat(1.5));
    /// let samples = field.training_samples(90, 0.01, 10, &cube, 3).unwrap();
    /// assert_eq!(samples.points.len(), 100);
    /// assert_eq!(samples.points[..90], field.sample_near_surface(90, 0.01, 3).unwrap().points[..]);
    /// ```
    pub fn training_samples(
        &self,
        near: usize,
        sigma: f32,
        uniform: usize,
        uniform_box: &Aabb,
        seed: u64,
    ) -> Result<Samples, SdfError> {
        check_budget("count", (near as u64).saturating_add(uniform as u64), 32)?;
        let mut samples = match near {
            0 => Samples::default(),
            n => self.sample_near_surface(n, sigma, seed)?,
        };
        if uniform > 0 {
            // Another stream than the near samples', so the two sets are not
            // drawn from the same random numbers.
            let more = self.sample_in(uniform_box, uniform, seed ^ UNIFORM_STREAM)?;
            samples.points.extend(more.points);
            samples.signed_distances.extend(more.signed_distances);
        }
        Ok(samples)
    }

    /// Fails when points up to `reach` beyond the mesh's box would lie
    /// beyond the coordinates a query accepts.
    fn check_reach(&self, option: &'static str, value: f32, reach: f32) -> Result<(), SdfError> {
        let b = self.bounds();
        let extent = b.min.abs().max(b.max.abs()).max_element() + reach;
        if extent.is_finite() && extent <= MAX_QUERY_COORDINATE {
            Ok(())
        } else {
            Err(SdfError::TooFar {
                option,
                value,
                bound: MAX_QUERY_COORDINATE,
            })
        }
    }

    fn samples(&self, points: Vec<Vec3>) -> Samples {
        let signed_distances = self
            .signed_distance_batch(&points)
            .into_iter()
            .map(|s| s.map_or(f32::NAN, |s| s.distance))
            .collect();
        Samples {
            points,
            signed_distances,
        }
    }
}
