//! Typed errors, one enum per boundary: mesh construction, file loading and
//! structure building.

use std::fmt;
use std::path::PathBuf;

/// A byte count for a message (`1.5 GiB (1610612736 bytes)`).
fn human(bytes: &u128) -> String {
    let short = crate::budget::human_bytes(*bytes);
    if short.ends_with(" bytes") {
        short
    } else {
        format!("{short} ({bytes} bytes)")
    }
}

fn human64(bytes: &u64) -> String {
    human(&u128::from(*bytes))
}

/// A budget for a message, with the variable that sets it
/// (`2.0 GiB (2147483648 bytes; PROXIMA_MEMORY_BUDGET sets it)`).
fn budget_set_by_env(budget: &u64) -> String {
    let short = crate::budget::human_bytes(u128::from(*budget));
    if short.ends_with(" bytes") {
        format!("{short} (PROXIMA_MEMORY_BUDGET sets it)")
    } else {
        format!("{short} ({budget} bytes; PROXIMA_MEMORY_BUDGET sets it)")
    }
}

/// A mesh whose data breaks an invariant.
///
/// ```
/// use proxima::{Mesh, MeshError, Vec3};
/// let e = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 3]]).unwrap_err();
/// assert_eq!(e, MeshError::IndexOutOfRange { face: 0, vertex: 3, vertex_count: 3 });
/// assert_eq!(e.to_string(), "face 0 refers to vertex 3, but the mesh has 3 vertices");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {index} has a non-finite coordinate")]
    NonFiniteVertex {
        /// 0-based vertex index.
        index: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the mesh has {vertex_count} vertices")]
    IndexOutOfRange {
        /// 0-based face index.
        face: usize,
        /// The offending 0-based vertex index.
        vertex: u64,
        /// Number of vertices in the mesh.
        vertex_count: usize,
    },
    /// A face has fewer than three vertices.
    #[error("face {face} has {len} vertices; a face needs at least 3")]
    FaceTooSmall {
        /// 0-based face index.
        face: usize,
        /// Its number of vertices.
        len: usize,
    },
    /// Face offsets that do not start at 0, decrease, or miss the end of the indices.
    #[error("face offsets must start at 0, never decrease, and end at the number of indices")]
    BadOffsets,
    /// More elements than 32-bit indices can address.
    #[error("{what}: {count} is more than the 2^32 - 1 that 32-bit indices can address")]
    TooLarge {
        /// What is counted.
        what: &'static str,
        /// How many there are.
        count: usize,
    },
}

/// Why a file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadErrorKind {
    /// Reading the file failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The extension names no format we read.
    #[error("unknown mesh format (expected .obj, .ply, .stl, .off or .glb, optionally .gz)")]
    UnknownFormat,
    /// The content does not follow the format.
    #[error("{0}")]
    Syntax(String),
    /// The file ends before the data it announces.
    #[error("unexpected end of file: {0}")]
    Truncated(String),
    /// The file announces sizes that cannot be real (checked before allocating).
    #[error("implausible size: {0}")]
    Implausible(String),
    /// The data parses but does not make a valid mesh.
    #[error("{0}")]
    Mesh(#[from] MeshError),
    /// A compressed file expands beyond the configured limit
    /// ([`LoadOptions::max_decompressed_bytes`](crate::io::LoadOptions)).
    #[error("decompressed data exceeds the limit of {limit} bytes")]
    DecompressedTooLarge {
        /// The limit, in bytes.
        limit: u64,
    },
    /// An uncompressed input holds more bytes than the configured limit
    /// ([`LoadOptions::max_input_bytes`](crate::io::LoadOptions)); reading stops there.
    #[error("the input exceeds the limit of {limit} bytes")]
    InputTooLarge {
        /// The limit, in bytes.
        limit: u64,
    },
    /// A line of a text format longer than the limit
    /// ([`LoadOptions::max_line_bytes`](crate::io::LoadOptions)), such as an
    /// endless stream without line ends; reading stops there.
    #[error("line longer than {limit} bytes (is this a text file?)")]
    LineTooLong {
        /// The limit, in bytes.
        limit: usize,
    },
    /// A NUL byte where a text format (OBJ, OFF, a PLY header or ascii data, a
    /// points file) is expected: binary data, not text.
    #[error("a NUL byte: binary data where text is expected")]
    NotText,
    /// Text that is not valid UTF-8 where UTF-8 is required (points files).
    #[error("invalid UTF-8")]
    InvalidUtf8,
    /// What the file holds (counted while it is read, or from its header or
    /// its glTF scene before anything is expanded) would pass the memory
    /// budget ([`LoadOptions::memory_budget`](crate::io::LoadOptions)) once
    /// loaded, at the bytes per vertex and per triangle of
    /// [`crate::budget`]; reading stops there.
    #[error(
        "{what} need about {}, more than the memory budget of {}",
        human(.bytes), budget_set_by_env(.budget)
    )]
    MemoryBudget {
        /// What was counted, for the message (`at least 20000000 vertices
        /// and 0 triangles, with their trees and the 160000000 bytes read,`).
        what: String,
        /// Bytes counted so far (a lower bound of the whole when reading
        /// stopped early).
        bytes: u128,
        /// The budget, in bytes.
        budget: u64,
    },
}

/// A load failure, with the file and (for text formats) the 1-based line.
#[derive(Debug, thiserror::Error)]
pub struct LoadError {
    /// The file being read.
    pub path: PathBuf,
    /// 1-based line number, when the format is text and the place is known.
    pub line: Option<usize>,
    /// What went wrong.
    #[source]
    pub kind: LoadErrorKind,
}

impl LoadError {
    /// An error at `line` (if known) of `path`.
    pub fn new(path: impl Into<PathBuf>, line: Option<usize>, kind: impl Into<LoadErrorKind>) -> Self {
        Self {
            path: path.into(),
            line,
            kind: kind.into(),
        }
    }
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.path.display(), line, self.kind),
            None => write!(f, "{}: {}", self.path.display(), self.kind),
        }
    }
}

/// A query point the trees cannot answer for.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QueryError {
    /// A coordinate is NaN or infinite.
    #[error("query point has a non-finite coordinate")]
    NonFinite,
    /// A coordinate beyond the bound
    /// ([`MAX_QUERY_COORDINATE`](crate::build::MAX_QUERY_COORDINATE)) where
    /// squared distances overflow `f32`.
    #[error("query point has a coordinate beyond ±{bound:e}, where squared distances overflow f32")]
    CoordinateTooLarge {
        /// The largest accepted magnitude.
        bound: f32,
    },
}

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
}

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

/// A ray that cannot be cast: the ray queries of the trees return it instead
/// of answering.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RayError {
    /// A ray origin with a NaN or infinite coordinate.
    #[error("ray origin must be finite")]
    Origin,
    /// A ray direction that is zero, or has a NaN or infinite component.
    #[error("ray direction must be finite and non-zero")]
    Direction,
    /// A ray origin so far from the structure's bounds (more than 2^30 times
    /// the larger of their diagonal and their largest coordinate) that even
    /// `f64` cannot place the ray near them finely enough to tell their front
    /// from their back. Bounds of a single point (primitives of no area,
    /// which no ray hits) never give it.
    #[error(
        "ray origin lies too far from the mesh (more than 2^30 times the larger of its size and its coordinates) for \
         its hits to be told apart"
    )]
    OriginTooFar,
    /// A ray parameter range that is NaN, starts at an infinity, or has `t_min > t_max`.
    #[error("ray range [{t_min}, {t_max}] is not a valid interval")]
    Range {
        /// Start of the range.
        t_min: f32,
        /// End of the range.
        t_max: f32,
    },
}

/// Why a list of vertices is not accepted as a
/// [`ConvexPolygon`](crate::primitive::ConvexPolygon) (see the module
/// documentation of `primitive::polygon` for the criteria).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolygonError {
    /// Fewer than 3 vertices, or more than the capacity.
    #[error("a convex polygon has 3 to {max} vertices, got {count}")]
    VertexCount {
        /// Number of vertices given.
        count: usize,
        /// The largest number accepted.
        max: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("polygon vertex {index} has a non-finite coordinate")]
    NonFinite {
        /// 0-based vertex index in the polygon.
        index: usize,
    },
    /// The vertices span no area: the normal vanishes or is not finite.
    #[error("the polygon has no area (its normal vanishes)")]
    Degenerate,
    /// The vertices lie farther from one plane than the tolerance allows.
    #[error(
        "the polygon is not planar: its vertices span {thickness} along the normal, more than the allowed {allowed}"
    )]
    NotPlanar {
        /// Extent of the vertices along the unit normal.
        thickness: f64,
        /// The largest accepted extent (relative tolerance times the bounding box diagonal).
        allowed: f64,
    },
    /// The boundary does not turn strictly left at some vertex (seen along the
    /// normal), or winds around more than once.
    #[error("the polygon is not strictly convex at vertex {index}")]
    NotConvex {
        /// 0-based vertex index in the polygon.
        index: usize,
    },
}

/// A view-projection matrix or camera that bounds no usable view volume.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrustumError {
    /// A matrix entry or camera parameter is NaN or infinite.
    #[error("the view-projection matrix has a non-finite entry")]
    NonFinite,
    /// The matrix cannot be inverted (its rows are linearly dependent).
    #[error("the view-projection matrix is singular")]
    Singular,
    /// A Gribb–Hartmann plane has a zero normal: it bounds nothing.
    #[error("the {plane} plane of the view-projection matrix has a zero normal")]
    ZeroNormal {
        /// Which plane (`left`, `right`, `bottom`, `top`, `near` or `far`).
        plane: &'static str,
    },
    /// Some corner of the clip cube maps to infinity or behind the eye, so the
    /// set the matrix keeps is unbounded or empty.
    #[error("the view-projection matrix bounds no finite volume (a clip-cube corner maps to w <= 0)")]
    NoVolume,
    /// A vertical field of view outside (0, 180) degrees.
    #[error("field of view must be between 0 and 180 degrees (exclusive), got {degrees}")]
    FieldOfView {
        /// The requested angle.
        degrees: f32,
    },
    /// An aspect ratio that is not finite and positive.
    #[error("aspect ratio must be finite and positive, got {aspect}")]
    Aspect {
        /// The requested ratio.
        aspect: f32,
    },
    /// A near distance that is not finite and positive.
    #[error("near distance must be finite and positive, got {near}")]
    Near {
        /// The requested distance.
        near: f32,
    },
    /// A far distance that is not finite or not beyond the near distance.
    #[error("far distance must be finite and greater than near ({near}), got {far}")]
    Far {
        /// The near distance.
        near: f32,
        /// The requested far distance.
        far: f32,
    },
    /// A camera with a non-finite vector, the eye on its target, or `up`
    /// zero or parallel to the view direction.
    #[error("look-at camera needs finite vectors, eye != target, and up not parallel to the view direction")]
    View,
    /// A look-at camera whose view-projection matrix (computed in `f64`) has
    /// a value beyond `f32`.
    #[error("the camera's {what} is {}, beyond f32", short(*value))]
    Overflow {
        /// Which value: the eye's distance along a view axis, a scale or
        /// offset of the projection, or an entry of the product.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A look-at camera whose projection alone (the camera moved to the
    /// origin) gives a view-projection matrix that bounds no frustum in
    /// `f32`: a `far / near` beyond `f32`'s depth resolution (about 2^24:
    /// the far plane rounds onto the near one), or an extreme field of view
    /// or distance scale.
    #[error(
        "the projection of near = {}, far = {} (far / near = {}), a field of view of {fov_y_degrees} degrees and \
         aspect {aspect} is beyond an f32 view-projection matrix: {error}",
        short(*near as f64), short(*far as f64), short(*far as f64 / *near as f64)
    )]
    Projection {
        /// The near distance.
        near: f32,
        /// The far distance.
        far: f32,
        /// The vertical field of view.
        fov_y_degrees: f32,
        /// The aspect ratio.
        aspect: f32,
        /// What the projection's matrix failed.
        error: Box<FrustumError>,
    },
    /// A look-at camera whose projection holds at the origin, but whose eye
    /// lies so far from the origin, compared with `near`, that its `f32`
    /// view-projection matrix no longer bounds the frustum (the translation
    /// swamps the near and far planes).
    #[error(
        "the eye lies {} from the origin, too far for an f32 view-projection matrix with near = {} and far = {}: \
         {error}",
        short(*distance), short(*near as f64), short(*far as f64)
    )]
    EyeTooFar {
        /// The eye's distance from the origin.
        distance: f64,
        /// The near distance.
        near: f32,
        /// The far distance.
        far: f32,
        /// What the camera's matrix failed.
        error: Box<FrustumError>,
    },
}

/// `x` as a message shows it: `f32`'s shortest digits (`1e31`, not
/// `9.999999848243207e30`), in exponent form outside `[1e-4, 1e7)`; seven
/// digits beyond `f32`.
fn short(x: f64) -> String {
    let rounded = x as f32;
    if !rounded.is_finite() {
        format!("{x:.6e}")
    } else if rounded == 0.0 || (1e-4..1e7).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// Why a signed distance field, or a grid or sample of one, cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SdfError {
    /// The mesh has no face, so neither a distance nor a side.
    #[error("the mesh has no faces: a signed distance needs triangles")]
    NoFaces,
    /// The tree could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A count or resolution of zero.
    #[error("{option} must be at least 1")]
    Zero {
        /// The option.
        option: &'static str,
    },
    /// The output would not fit the memory budget
    /// ([`check_fits`](crate::budget::check_fits): `PROXIMA_MEMORY_BUDGET` or the default).
    #[error("{option} = {value} needs {bytes} bytes, more than the memory budget of {budget} bytes")]
    MemoryBudget {
        /// The option that sizes the output.
        option: &'static str,
        /// Its value.
        value: u64,
        /// Bytes it needs.
        bytes: u64,
        /// The budget.
        budget: u64,
    },
    /// The memory budget of the environment cannot be read
    /// ([`BudgetError::Environment`](crate::budget::BudgetError)).
    #[error(transparent)]
    Budget(#[from] crate::budget::BudgetError),
    /// A spread or margin so large that samples would lie beyond the
    /// coordinates a query accepts
    /// ([`MAX_QUERY_COORDINATE`](crate::build::MAX_QUERY_COORDINATE)).
    #[error("{option} = {value} puts samples beyond ±{bound:e}, where squared distances overflow f32")]
    TooFar {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f32,
        /// The largest coordinate a query accepts.
        bound: f32,
    },
    /// A length (a sample spread or margin, a grid's bounds) that is negative or not finite.
    #[error("{option} must be finite and not negative, got {value}")]
    Parameter {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f32,
    },
}
