//! Answers of many neighbour queries, flat.

/// The neighbours of many queries in compressed rows (CSR), so that a
/// million queries do not allocate a million vectors: query `i`'s
/// neighbours are `indices[offsets[i]..offsets[i + 1]]`, at
/// `distances[...]`, nearest first (ties by index).
///
/// ```
/// use proxima::points::PointCloud;
/// use proxima::Vec3;
/// let cloud = PointCloud::new(&[Vec3::ZERO, Vec3::X, Vec3::new(3.0, 0.0, 0.0)]).unwrap();
/// let found = cloud.within_batch(&[Vec3::ZERO, Vec3::new(3.0, 0.5, 0.0)], 1.0, None).unwrap();
/// assert_eq!(found.offsets, [0, 2, 3]);
/// assert_eq!(found.indices, [0, 1, 2]);
/// assert_eq!(found.of(1).0, [2]);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Neighbours {
    /// `queries + 1` offsets into `indices` and `distances`.
    pub offsets: Vec<usize>,
    /// The neighbours' indices in the cloud.
    pub indices: Vec<u32>,
    /// Their distances to the query.
    pub distances: Vec<f32>,
}

impl Neighbours {
    /// How many queries.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// `true` when there is no query.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Query `i`'s neighbours: their indices and distances.
    pub fn of(&self, i: usize) -> (&[u32], &[f32]) {
        let range = self.offsets[i]..self.offsets[i + 1];
        (&self.indices[range.clone()], &self.distances[range])
    }
}

/// The `k` nearest points of many queries, `k` per query in one flat array
/// each (row `i` is `[i * k, (i + 1) * k)`), nearest first, padded with
/// `u32::MAX` and infinity where the cloud has fewer than `k` points (the
/// layout of scipy's `cKDTree.query`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KNearest {
    /// Neighbours per query.
    pub k: usize,
    /// `queries × k` indices into the cloud.
    pub indices: Vec<u32>,
    /// Their distances.
    pub distances: Vec<f32>,
}
