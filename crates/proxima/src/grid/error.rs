//! What a hash grid, a voxelization or a grid traversal refuses.

use crate::error::{human, human64};
use crate::ray::RayError;

/// Impossible parameters for a hash grid, a voxelization or a grid traversal.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// A cell extent is zero, negative, NaN or infinite.
    #[error("cell size must be finite and positive on every axis, got {x}, {y}, {z}")]
    CellSize {
        /// Extent along x.
        x: f32,
        /// Extent along y.
        y: f32,
        /// Extent along z.
        z: f32,
    },
    /// The grid origin has a NaN or infinite coordinate.
    #[error("grid origin must be finite")]
    GridOrigin,
    /// A voxelization resolution of 0.
    #[error("resolution must be at least 1")]
    Resolution,
    /// A cell size derived from a bounding box that has no extent (all the
    /// vertices at one point), or is empty or not finite: there is nothing to
    /// size cells by.
    #[error(
        "the bounding box is degenerate (a single point, empty, or wider than f32 can divide): no cell size can be derived from it"
    )]
    DegenerateBounds,
    /// A ray that cannot be cast, for the reasons every ray query has
    /// ([`Ray::with_range`](crate::Ray::with_range)): a non-finite origin, a
    /// zero or non-finite direction, an invalid range. (An origin too far
    /// from a grid's occupied cells is [`OutOfRange`](GridError::OutOfRange).)
    #[error(transparent)]
    Ray(#[from] RayError),
    /// A primitive with a NaN or infinite coordinate.
    #[error("primitive {index} has a non-finite coordinate")]
    NonFinite {
        /// Index of the primitive in the input.
        index: usize,
    },
    /// A point whose cell index does not fit the layout's range: beyond
    /// [`GridLayout::max_index`](crate::grid::GridLayout::max_index), where
    /// cell planes stop being exact in `f64` (at most 2^50).
    #[error("a coordinate lies too far from the grid origin for the cell size (cell index out of range)")]
    OutOfRange,
    /// A grid origin whose lowest bits lie so far below the cell size's that
    /// the planes `origin + i · size` next to it need more than `f64`'s 53
    /// bits: not even cell 0 could be placed exactly.
    #[error(
        "grid origin {origin:e} along {axis} has bits far below those of the cell size {size:e}: its cell planes cannot be exact (round the origin to a multiple of the cell size)"
    )]
    InexactPlanes {
        /// The axis, `x`, `y` or `z`.
        axis: char,
        /// The origin's coordinate along it.
        origin: f32,
        /// The cell size along it.
        size: f32,
    },
    /// A primitive whose cell indices do not fit the supported range
    /// ([`OutOfRange`](GridError::OutOfRange) met while building a grid).
    #[error("primitive {index} lies too far from the grid origin for the cell size (cell index out of range)")]
    PrimitiveOutOfRange {
        /// Index of the primitive in the input.
        index: usize,
    },
    /// A primitive whose bounding box spans more cells than the limit.
    #[error("primitive {index} spans {cells} cells, more than the limit of {limit}")]
    PrimitiveTooLarge {
        /// Index of the primitive in the input.
        index: usize,
        /// Number of cells its bounding box spans.
        cells: u128,
        /// The configured limit.
        limit: u64,
    },
    /// More cell entries (cell–primitive pairs, or cells of a dense grid) than the limit.
    #[error("the grid needs more than {limit} cell entries; use larger cells or raise the limit")]
    TooManyCells {
        /// The configured limit.
        limit: u64,
    },
    /// The cells of the primitives' bounding boxes (an upper bound on the
    /// cells a grid build or a voxelization tests) are more than the limit:
    /// refused before anything is allocated, so that no option can ask for
    /// hours of work.
    #[error(
        "the primitives' cell ranges hold {cells} cells to test, more than the limit of {limit} (use larger cells or a lower resolution)"
    )]
    CellTests {
        /// The sum, over the primitives, of the cells of their cell ranges.
        cells: u128,
        /// The configured limit (`max_cell_tests`).
        limit: u64,
    },
    /// The storage would need more memory than the budget (`memory_budget`).
    /// Known sizes (a dense bitset) are refused before they are allocated;
    /// sizes that depend on the answer are counted as they grow, and the
    /// build stops at the budget, estimating the whole from the part done.
    #[error(
        "needs about {} for about {count} {what}, more than the memory budget of {} (use larger cells or a lower resolution, or raise the budget)",
        human(.bytes), human64(.budget)
    )]
    MemoryBudget {
        /// What is counted: `cell entries`, `occupied cells` or `voxels`.
        what: &'static str,
        /// How many of them the whole structure would need (estimated).
        count: u128,
        /// Bytes the whole structure would need (estimated).
        bytes: u128,
        /// The budget, in bytes.
        budget: u64,
    },
    /// More primitives than 32-bit indices can address.
    #[error("{count} primitives is more than 32-bit indices can address")]
    TooManyPrimitives {
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
}
