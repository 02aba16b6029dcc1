//! What a mesh, or a convex polygon made from its faces, refuses.

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
    /// Per-corner attributes (normals, texture coordinates) that are not one
    /// per face corner.
    #[error("{count} {what} for {corners} face corners; a mesh needs one per corner")]
    CornerCount {
        /// What the attributes are.
        what: &'static str,
        /// How many were given.
        count: usize,
        /// How many corners the faces have.
        corners: usize,
    },
    /// New positions for a mesh's vertices, but not one per vertex.
    #[error("{count} positions for {vertices} vertices; a mesh moves every vertex, in order")]
    VertexCount {
        /// How many positions were given.
        count: usize,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A per-corner attribute with a NaN or infinite component.
    #[error("{what} of face corner {corner}: not finite")]
    NonFiniteCorner {
        /// What the attribute is.
        what: &'static str,
        /// 0-based corner.
        corner: usize,
    },
    /// More elements than 32-bit indices can address.
    #[error("{what}: {count} is more than the 2^32 - 1 that 32-bit indices can address")]
    TooLarge {
        /// What is counted.
        what: &'static str,
        /// How many there are.
        count: usize,
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
