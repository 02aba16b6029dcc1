//! What a tree build refuses (the binary, wide, sphere and ray trees, and
//! the linear search's primitive checks).

/// Impossible parameters for building a structure.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// `max_depth` outside the supported range.
    #[error("max_depth must be between 1 and {max}, got {got}")]
    MaxDepth {
        /// The requested depth.
        got: u32,
        /// The largest supported depth.
        max: u32,
    },
    /// `min_size` (largest leaf that is not split further) is zero.
    #[error("min_size must be at least 1")]
    MinSize,
    /// A primitive has a non-finite bounding box.
    #[error("primitive {index} has a non-finite coordinate")]
    NonFinite {
        /// Index of the primitive in the input.
        index: usize,
    },
    /// A primitive has a coordinate beyond the bound
    /// ([`MAX_COORDINATE`](crate::build::MAX_COORDINATE)) where squared distances
    /// would overflow `f32`.
    #[error("primitive {index} has a coordinate beyond ±{bound:e}, where squared distances overflow f32")]
    CoordinateTooLarge {
        /// Index of the primitive in the input.
        index: usize,
        /// The largest accepted magnitude.
        bound: f32,
    },
    /// More primitives than 32-bit indices can address.
    #[error("{count} primitives is more than 32-bit indices can address")]
    TooMany {
        /// Number of primitives.
        count: usize,
    },
    /// `sources` and primitives have different lengths.
    #[error("{primitives} primitives but {sources} source indices")]
    SourceCount {
        /// Number of primitives.
        primitives: usize,
        /// Number of source indices.
        sources: usize,
    },
    /// A refit was given primitives that are not the tree's, moved: another
    /// count, or a slot's primitive from another source (the mesh's faces,
    /// or its planar polygons, changed).
    #[error("the tree holds {tree} primitives, but the refit was given {primitives}{}", .slot.map_or(String::new(), |s| format!(", slot {s} from another source")))]
    RefitMismatch {
        /// Primitives given.
        primitives: usize,
        /// Primitives in the tree.
        tree: usize,
        /// The first slot whose primitive came from another source.
        slot: Option<usize>,
    },
}
