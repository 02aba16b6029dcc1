//! What a [`MeshIndex`](super::MeshIndex) refuses.

use crate::BuildError;
use crate::kind::PrimitiveKind;
use crate::mesh::MeshError;

/// A query a mesh cannot answer, or a structure that could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IndexError {
    /// A mesh with no vertices at all: no query has anything to work on.
    #[error("the mesh is empty (0 vertices, 0 faces)")]
    EmptyMesh,
    /// A mesh without primitives of the kind asked for (no faces, so no
    /// edges or polygons either).
    #[error("the mesh has no {kind} to search ({vertices} vertices, {faces} faces)")]
    NoPrimitives {
        /// The kind asked for.
        kind: PrimitiveKind,
        /// The mesh's vertices.
        vertices: usize,
        /// The mesh's faces.
        faces: usize,
    },
    /// New vertex positions that are not one finite position per vertex
    /// ([`MeshIndex::update_vertices`](super::MeshIndex::update_vertices)).
    #[error("{0}")]
    Positions(#[from] MeshError),
    /// A new vertex position beyond the coordinates a tree takes.
    #[error("vertex {vertex} has a coordinate beyond ±{bound:e}, where squared distances overflow f32")]
    PositionTooLarge {
        /// The vertex.
        vertex: usize,
        /// The largest accepted magnitude.
        bound: f32,
    },
    /// A structure's build failed (beyond the tree's limits).
    #[error(transparent)]
    Build(#[from] BuildError),
}
