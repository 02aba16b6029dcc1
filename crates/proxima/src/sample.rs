//! Seeded point sets for tests and benchmarks: the query sets of
//! `BENCHMARKS.md` (`near`: surface samples plus a gaussian offset; `uniform`:
//! uniform in the enlarged bounding box).
//!
//! The generator is SplitMix64: tiny, fast, and the same sequence on every
//! machine, so a seed names a query set.

use crate::aabb::Aabb;
use crate::math::Vec3;
use crate::mesh::Mesh;
use crate::primitive::Triangle;

/// A small seeded pseudo-random generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator whose sequence is fixed by `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit() as f32
    }

    /// Uniform integer in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() as u128 * n as u128) >> 64) as usize
    }

    /// Standard normal (Box–Muller).
    pub fn gaussian(&mut self) -> f64 {
        let u = 1.0 - self.unit();
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }

    /// Uniform in the box.
    pub fn in_box(&mut self, b: &Aabb) -> Vec3 {
        Vec3::new(
            self.range(b.min.x, b.max.x),
            self.range(b.min.y, b.max.y),
            self.range(b.min.z, b.max.z),
        )
    }
}

/// `n` points uniform in the mesh's bounding box enlarged by 10% of its size on
/// every side (the `uniform` query set). The same seed gives the same points
/// on every machine.
///
/// ```
/// use proxima::mesh::generate::noisy_icosphere;
/// use proxima::sample::uniform_in_box;
/// let mesh = noisy_icosphere(4, 1);
/// let points = uniform_in_box(&mesh, 100, 7);
/// assert_eq!(points.len(), 100);
/// assert_eq!(points, uniform_in_box(&mesh, 100, 7));
/// assert_ne!(points, uniform_in_box(&mesh, 100, 8));
/// ```
pub fn uniform_in_box(mesh: &Mesh, n: usize, seed: u64) -> Vec<Vec3> {
    let b = mesh.bounds();
    if b.is_empty() {
        return Vec::new();
    }
    uniform_in(&Aabb::new(b.min - b.size() * 0.1, b.max + b.size() * 0.1), n, seed)
}

/// The `rays` set of BENCHMARKS.md: `n` rays from origins uniform on the
/// sphere of radius 0.75 × the bounding-box diagonal around the box's
/// centre, aimed at points uniform in the box, directions of unit length
/// (none when the box is empty or flat to a point); the same seed gives the
/// same rays on every machine.
///
/// ```
/// use proxima::mesh::generate::noisy_icosphere;
/// use proxima::sample::rays_at_box;
/// let mesh = noisy_icosphere(4, 1);
/// let b = mesh.bounds();
/// let rays = rays_at_box(&b, 100, 7);
/// assert_eq!(rays.len(), 100);
/// for (o, d) in rays {
///     assert!(((o - b.center()).length() / (0.75 * b.diagonal()) - 1.0).abs() < 1e-5);
///     assert!((d.length() - 1.0).abs() < 1e-5);
/// }
/// ```
pub fn rays_at_box(bounds: &Aabb, n: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    if bounds.is_empty() || bounds.diagonal() == 0.0 {
        return Vec::new();
    }
    let mut rng = Rng::new(seed);
    let radius = 0.75 * bounds.diagonal();
    (0..n)
        .map(|_| {
            // A direction uniform on the sphere: a point uniform in the ball, scaled out.
            let unit = loop {
                let d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
                let length = d.length();
                if length > 1e-3 && length <= 1.0 {
                    break d / length;
                }
            };
            let origin = bounds.center() + unit * radius;
            (origin, (rng.in_box(bounds) - origin).normalize())
        })
        .filter(|(_, d)| d.is_finite())
        .collect()
}

/// `n` points uniform in `bounds` (none when it is empty); the same seed
/// gives the same points on every machine.
pub fn uniform_in(bounds: &Aabb, n: usize, seed: u64) -> Vec<Vec3> {
    if bounds.is_empty() {
        return Vec::new();
    }
    let mut rng = Rng::new(seed);
    (0..n).map(|_| rng.in_box(bounds)).collect()
}

/// `n` points uniform on the surface (triangles picked by area) plus a
/// gaussian offset per axis with standard deviation `sigma_fraction` of the
/// bounding-box diagonal (the `near` query set uses 0.01). Empty when the mesh
/// has no area.
pub fn near_surface(mesh: &Mesh, n: usize, sigma_fraction: f32, seed: u64) -> Vec<Vec3> {
    near_triangles(
        &mesh.triangles().primitives,
        n,
        mesh.bounds().diagonal() * sigma_fraction,
        seed,
    )
}

/// `n` points uniform on the triangles (picked by area) plus a gaussian
/// offset per axis of standard deviation `sigma`. Empty when the triangles
/// have no area.
pub fn near_triangles(triangles: &[Triangle], n: usize, sigma: f32, seed: u64) -> Vec<Vec3> {
    let table = AreaTable::new(triangles.iter().map(|t| t.area() as f64));
    let total = table.total();
    if triangles.is_empty() || total <= 0.0 {
        return Vec::new();
    }
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| {
            let target = rng.unit() * total;
            let i = table.pick(target).min(triangles.len() - 1);
            let t = &triangles[i];
            let (mut u, mut v) = (rng.unit() as f32, rng.unit() as f32);
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let on = t.a + (t.b - t.a) * u + (t.c - t.a) * v;
            let offset = Vec3::new(rng.gaussian() as f32, rng.gaussian() as f32, rng.gaussian() as f32);
            on + offset * sigma
        })
        .collect()
}

/// The running sums of weights (triangles' areas) and where each of
/// equal parts of their total starts: [`pick`](Self::pick) finds the item
/// a uniform number falls on in a few steps within one part, instead of a
/// search over every sum (which on a large mesh misses the cache at most of
/// its steps).
struct AreaTable {
    cumulative: Vec<f64>,
    /// `starts[k]`: the first item whose sum exceeds `k · step` (the count of
    /// sums at most that), for `k` in `0..parts`.
    starts: Vec<u32>,
    step: f64,
}

/// Items per part of an [`AreaTable`], on average.
const ITEMS_PER_PART: usize = 8;

impl AreaTable {
    fn new(weights: impl Iterator<Item = f64>) -> Self {
        let mut total = 0f64;
        let cumulative: Vec<f64> = weights
            .map(|w| {
                total += w;
                total
            })
            .collect();
        let parts = (cumulative.len() / ITEMS_PER_PART).max(1);
        let step = total / parts as f64;
        let mut starts = Vec::with_capacity(parts);
        let mut at = 0;
        for k in 0..parts {
            let bound = k as f64 * step;
            while at < cumulative.len() && cumulative[at] <= bound {
                at += 1;
            }
            starts.push(at as u32);
        }
        Self {
            cumulative,
            starts,
            step,
        }
    }

    fn total(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// `cumulative.partition_point(|&c| c <= target)`, exactly: the search
    /// runs between the starts of the part that holds `target` and the next
    /// (the count is monotone in the bound, so it lies between theirs).
    fn pick(&self, target: f64) -> usize {
        let parts = self.starts.len();
        // The part `k` with `k · step <= target < (k + 1) · step`, the
        // estimate corrected where it rounded across a bound.
        let mut k = ((target / self.step) as usize).min(parts - 1);
        while k > 0 && k as f64 * self.step > target {
            k -= 1;
        }
        while k + 1 < parts && (k + 1) as f64 * self.step <= target {
            k += 1;
        }
        let lo = self.starts[k] as usize;
        let hi = self.starts.get(k + 1).map_or(self.cumulative.len(), |&s| s as usize);
        lo + self.cumulative[lo..hi].partition_point(|&c| c <= target)
    }
}

/// How many of `total` training samples are drawn near the surface and how
/// many uniform in a box, when `uniform_fraction` of them are uniform:
/// `(near, uniform)`, `uniform` the nearest whole number to
/// `total × uniform_fraction` (computed in `f64`; halves round down, so
/// that 0.5 gives the near samples the odd one). A fraction outside
/// `[0, 1]` (or NaN) counts as the nearest end.
///
/// ```
/// use proxima::sample::training_sample_counts;
/// assert_eq!(training_sample_counts(101, 0.5), (51, 50));
/// assert_eq!(training_sample_counts(20_000, 0.1), (18_000, 2_000));
/// assert_eq!(training_sample_counts(10, 0.0), (10, 0));
/// assert_eq!(training_sample_counts(10, 1.0), (0, 10));
/// ```
pub fn training_sample_counts(total: usize, uniform_fraction: f64) -> (usize, usize) {
    let fraction = if uniform_fraction.is_nan() {
        0.0
    } else {
        uniform_fraction.clamp(0.0, 1.0)
    };
    let uniform = ((total as f64 * fraction - 0.5).ceil().max(0.0) as usize).min(total);
    (total - uniform, uniform)
}

/// `n` small random triangles (edges up to 0.1) in the cube [-1, 1]³: the
/// soup the crate's unit tests build trees over.
#[cfg(test)]
pub(crate) fn small_triangles(n: usize, seed: u64) -> Vec<crate::Triangle> {
    let mut rng = Rng::new(seed);
    let mut v = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
    (0..n)
        .map(|_| {
            let a = v();
            crate::Triangle::new(a, a + v() * 0.05, a + v() * 0.05)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table picks what a search over every running sum picks: on
    /// random weights, zero weights (equal sums), one weight, and targets
    /// exactly on sums and on the parts' bounds and an ulp on either side.
    #[test]
    fn area_table_picks_as_a_search_over_every_sum() {
        let mut rng = Rng::new(5);
        for case in 0..40 {
            let n = [1, 2, 7, 8, 9, 100, 1000][case % 7] + case;
            let weights: Vec<f64> = (0..n)
                .map(|i| match (case + i) % 5 {
                    0 => 0.0,
                    1 => rng.unit() * 1e-6,
                    _ => rng.unit(),
                })
                .collect();
            let table = AreaTable::new(weights.iter().copied());
            let total = table.total();
            let mut targets: Vec<f64> = (0..200).map(|_| rng.unit() * total).collect();
            let ulps = |x: f64| {
                [
                    x,
                    f64::from_bits(x.to_bits().saturating_sub(1)),
                    f64::from_bits(x.to_bits() + 1),
                ]
            };
            for &c in &table.cumulative {
                targets.extend(ulps(c));
            }
            for k in 0..table.starts.len() {
                targets.extend(ulps(k as f64 * table.step));
            }
            targets.push(0.0);
            for target in targets.into_iter().filter(|t| (0.0..total).contains(t)) {
                let expected = table.cumulative.partition_point(|&c| c <= target);
                assert_eq!(
                    table.pick(target),
                    expected,
                    "case {case}: target {target:e} of {total:e}"
                );
            }
        }
    }
}
