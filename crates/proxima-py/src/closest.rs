//! The flat arrays of `Mesh.closest_points` and `Mesh.k_nearest`, made from
//! the library's answers.

use proxima::prelude::*;
use proxima::query::NearestAnswers;

/// What `closest_points` returns, before it becomes numpy arrays.
#[derive(Default)]
pub struct ClosestAnswers {
    /// x, y, z of each closest point.
    pub closest: Vec<f64>,
    /// Each distance.
    pub distance: Vec<f64>,
    /// Each source element.
    pub index: Vec<i64>,
}

/// The arrays of `hits`, in order; a query without an answer (none: every
/// point was checked answerable and the tree is not empty) gets NaN and -1.
pub fn arrays(hits: &[Option<ClosestHit>]) -> ClosestAnswers {
    let n = hits.len();
    let mut out = ClosestAnswers {
        closest: Vec::with_capacity(3 * n),
        distance: Vec::with_capacity(n),
        index: Vec::with_capacity(n),
    };
    for hit in hits {
        match hit {
            Some(hit) => {
                out.closest.extend(hit.point.to_array().map(f64::from));
                out.distance.push(hit.distance as f64);
                out.index.push(hit.source as i64);
            }
            None => {
                out.closest.extend([f64::NAN; 3]);
                out.distance.push(f64::NAN);
                out.index.push(-1);
            }
        }
    }
    out
}

/// The rows of `k_nearest`: `k` distances and indices per point, padded
/// with `inf` and -1 where the mesh has fewer than `k` elements.
pub struct NearestRows {
    k: usize,
    distance: Vec<f64>,
    index: Vec<i64>,
}

impl NearestRows {
    /// Room for `points` rows of `k`.
    pub fn with_capacity(points: usize, k: usize) -> Self {
        Self {
            k,
            distance: Vec::with_capacity(points * k),
            index: Vec::with_capacity(points * k),
        }
    }

    /// Appends the rows of a chunk of answers.
    pub fn extend(&mut self, answers: &NearestAnswers) {
        for i in 0..answers.len() {
            let hits = answers.hits(i);
            self.distance.extend(hits.iter().map(|h| h.distance as f64));
            self.index.extend(hits.iter().map(|h| h.source as i64));
            let missing = self.k - hits.len();
            self.distance.extend(std::iter::repeat_n(f64::INFINITY, missing));
            self.index.extend(std::iter::repeat_n(-1, missing));
        }
    }

    /// Distances and indices, row after row.
    pub fn into_arrays(self) -> (Vec<f64>, Vec<i64>) {
        (self.distance, self.index)
    }
}
