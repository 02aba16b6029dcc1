//! Build parameters.

use crate::error::BuildError;

/// The deepest tree the build produces. Traversals use a fixed stack of this
/// many entries, so no query allocates and none can overflow.
pub const MAX_DEPTH: u32 = 60;

/// The largest coordinate magnitude a tree accepts: 2^60 (about 1.15e18).
///
/// Distances are compared squared, in `f32`. Between points whose coordinates
/// are at most 2^60 (2^62 for the query) in magnitude, a squared distance is
/// below 3 · 2^126 and stays finite; beyond that it can overflow to infinity,
/// and every candidate would tie at `∞`. A build over larger coordinates fails
/// with [`BuildError::CoordinateTooLarge`] instead of answering nonsense
/// (rescale such data first).
pub const MAX_COORDINATE: f32 = (1u64 << 60) as f32;

/// The largest coordinate magnitude of a query point: 2^62 (about 4.6e18).
///
/// Between such a point and any primitive within [`MAX_COORDINATE`], squared
/// distances stay finite (see there). Farther out every candidate would tie at
/// `∞` and the answer would be primitive 0 at an infinite distance, so the
/// queries of the trees and of [`LinearSearch`](crate::LinearSearch) answer
/// such a point as they answer a NaN one: `None`, or no hits.
/// [`check_query_point`](crate::check_query_point) says why, for callers that report it.
pub const MAX_QUERY_COORDINATE: f32 = (1u64 << 62) as f32;

/// How a node's primitives are divided between its two children.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SplitMethod {
    /// The classic split: order the primitives by their centroid along the
    /// axis where the node's centroids spread most, and cut them into two
    /// equal halves.
    #[default]
    Median,
    /// Binned surface area heuristic: centroids are sorted into 16 bins along
    /// each axis, and the cut between bins with the least
    /// `area(left) * count(left) + area(right) * count(right)` is taken. Tighter
    /// boxes than the median split, for a somewhat slower build. Falls back to
    /// the median split when all centroids coincide.
    BinnedSah,
}

/// Build parameters of an [`AabbTree`](crate::AabbTree).
///
/// ```
/// use proxima::BuildConfig;
/// let config = BuildConfig { max_depth: 20, ..BuildConfig::default() };
/// assert!(config.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildConfig {
    /// Nodes at this depth (the root has depth 0) become leaves whatever their
    /// size. At most [`MAX_DEPTH`].
    pub max_depth: u32,
    /// A node with at most this many primitives becomes a leaf (the classic
    /// design's `min_size`). At least 1.
    pub min_size: u32,
    /// How nodes are split.
    pub split: SplitMethod,
}

impl Default for BuildConfig {
    /// Median split, leaves of up to 4 primitives, no practical depth limit.
    fn default() -> Self {
        Self {
            max_depth: MAX_DEPTH,
            min_size: 4,
            split: SplitMethod::Median,
        }
    }
}

impl BuildConfig {
    /// The classic median split with leaves of up to 4 primitives: the fastest
    /// build. The default.
    pub fn fast_build() -> Self {
        Self::default()
    }

    /// Binned SAH with leaves of up to 4 primitives: fewer nodes and
    /// primitives visited per closest-point query than [`fast_build`](Self::fast_build),
    /// for a slower build (figures in docs/perf-log.md). For trees that answer many queries.
    pub fn fast_queries() -> Self {
        Self {
            split: SplitMethod::BinnedSah,
            ..Self::default()
        }
    }

    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), BuildError> {
        if self.max_depth == 0 || self.max_depth > MAX_DEPTH {
            return Err(BuildError::MaxDepth {
                got: self.max_depth,
                max: MAX_DEPTH,
            });
        }
        if self.min_size == 0 {
            return Err(BuildError::MinSize);
        }
        Ok(())
    }
}
