//! How far apart two point clouds are: Chamfer and Hausdorff distances.

use super::PointCloud;
use crate::query::NearestQuery;

/// The distances from every point of one cloud to the other cloud.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Directed {
    /// Mean of the distances.
    pub mean: f64,
    /// Mean of the squared distances.
    pub mean_squared: f64,
    /// Sum of the distances.
    pub sum: f64,
    /// Sum of the squared distances.
    pub sum_squared: f64,
    /// The largest distance: the one-sided Hausdorff distance.
    pub max: f64,
    /// The point (of the cloud measured from) at that largest distance,
    /// the lowest index among ties.
    pub argmax: u32,
}

/// Both directions between clouds `a` and `b`.
///
/// Conventions, to compare with other libraries: pytorch3d's
/// `chamfer_distance` (default reductions) is
/// `forward.mean_squared + backward.mean_squared`; point-cloud-utils'
/// `chamfer_distance` is `forward.mean + backward.mean`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chamfer {
    /// From each point of `a` to the nearest of `b`.
    pub forward: Directed,
    /// From each point of `b` to the nearest of `a`.
    pub backward: Directed,
}

impl Chamfer {
    /// The symmetric Hausdorff distance: the larger one-sided one.
    pub fn hausdorff(&self) -> f64 {
        self.forward.max.max(self.backward.max)
    }
}

/// The Chamfer distances between clouds `a` and `b`, both directions, on
/// all cores (each point's nearest neighbour in the other cloud, chosen by
/// `f32` squared distance, ties by index; its distance and the sums in
/// `f64`).
///
/// ```
/// use proxima::points::{PointCloud, chamfer};
/// use proxima::Vec3;
/// let a = PointCloud::new(&[Vec3::ZERO, Vec3::X]).unwrap();
/// let b = PointCloud::new(&[Vec3::new(0.0, 2.0, 0.0)]).unwrap();
/// let c = chamfer(&a, &b);
/// assert_eq!(c.backward.mean, 2.0);
/// assert_eq!(c.forward.sum_squared, 4.0 + 5.0);
/// assert_eq!((c.forward.max, c.forward.argmax), (5f64.sqrt(), 1));
/// ```
pub fn chamfer(a: &PointCloud, b: &PointCloud) -> Chamfer {
    Chamfer {
        forward: directed(a, b),
        backward: directed(b, a),
    }
}

/// The symmetric Hausdorff distance between clouds `a` and `b`: the
/// largest distance from a point of either to the other cloud.
pub fn hausdorff(a: &PointCloud, b: &PointCloud) -> f64 {
    chamfer(a, b).hausdorff()
}

/// From each point of `from` to its nearest point of `to`.
fn directed(from: &PointCloud, to: &PointCloud) -> Directed {
    let hits = to.tree().closest_batch(from.points());
    let mut out = Directed {
        mean: 0.0,
        mean_squared: 0.0,
        sum: 0.0,
        sum_squared: 0.0,
        max: f64::NEG_INFINITY,
        argmax: 0,
    };
    for (i, (hit, p)) in hits.iter().zip(from.points()).enumerate() {
        // Every point of a cloud is finite and within the query bound, and
        // the other cloud is not empty: each has an answer. Its distance is
        // measured again in f64 from the f32 coordinates, so that squares
        // and sums carry no f32 rounding.
        let d = hit
            .as_ref()
            .map_or(f64::INFINITY, |h| (h.point.as_dvec3() - p.as_dvec3()).length());
        out.sum += d;
        out.sum_squared += d * d;
        if d > out.max {
            out.max = d;
            out.argmax = i as u32;
        }
    }
    let n = hits.len() as f64;
    out.mean = out.sum / n;
    out.mean_squared = out.sum_squared / n;
    out
}
