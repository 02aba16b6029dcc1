//! Polygon meshes and the primitives extracted from them.

mod error;
mod extract;
pub mod generate;
mod polygons;

pub use error::{MeshError, PolygonError};
pub use polygons::PolygonExtraction;

use crate::aabb::Aabb;
use crate::math::Vec3;

/// A polygon mesh: vertex positions and faces of three or more vertices.
///
/// Faces are stored compactly (all indices in one array, with an offset per
/// face). The invariants — every index is in range, every face has at least
/// three vertices, every coordinate is finite — are checked by the
/// constructors, so the fields are private.
///
/// ```
/// use proxima::{Mesh, Vec3};
/// let mesh = Mesh::from_faces(
///     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE],
///     &[vec![0, 1, 3, 2]],
/// )
/// .unwrap();
/// assert_eq!(mesh.face_count(), 1);
/// assert_eq!(mesh.triangles().len(), 2); // the quad, fan-triangulated
/// assert_eq!(mesh.edges().len(), 4);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    positions: Vec<Vec3>,
    /// Face `f` uses `indices[offsets[f]..offsets[f + 1]]`; `offsets[0] == 0`.
    offsets: Vec<u32>,
    indices: Vec<u32>,
    /// Optional per face corner (parallel to `indices`), from the file.
    corners: CornerAttributes,
}

/// What a file may give each face corner: shading normals and texture
/// coordinates, kept per corner so that seams and hard edges survive.
#[derive(Clone, Debug, Default, PartialEq)]
struct CornerAttributes {
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<[f32; 2]>>,
}

/// The empty mesh: no vertices, no faces.
impl Default for Mesh {
    fn default() -> Self {
        Self {
            positions: Vec::new(),
            offsets: vec![0],
            indices: Vec::new(),
            corners: CornerAttributes::default(),
        }
    }
}

impl Mesh {
    /// A mesh from positions and faces stored compactly: face `f` is
    /// `indices[offsets[f]..offsets[f + 1]]`, and `offsets` starts with 0 and has
    /// one more entry than there are faces. Fails on an index out of range, a face
    /// of fewer than three vertices, or a non-finite coordinate.
    pub fn from_compact(positions: Vec<Vec3>, offsets: Vec<u32>, indices: Vec<u32>) -> Result<Self, MeshError> {
        if positions.len() > u32::MAX as usize {
            return Err(MeshError::TooLarge {
                what: "vertices",
                count: positions.len(),
            });
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFiniteVertex { index });
        }
        let offsets = if offsets.is_empty() { vec![0] } else { offsets };
        let consistent = offsets[0] == 0
            && offsets.windows(2).all(|w| w[0] <= w[1])
            && offsets.last().is_some_and(|&end| end as usize == indices.len());
        if !consistent {
            return Err(MeshError::BadOffsets);
        }
        for face in 0..offsets.len() - 1 {
            let (begin, end) = (offsets[face] as usize, offsets[face + 1] as usize);
            if end - begin < 3 {
                return Err(MeshError::FaceTooSmall { face, len: end - begin });
            }
            if let Some(&vertex) = indices[begin..end].iter().find(|&&v| v as usize >= positions.len()) {
                return Err(MeshError::IndexOutOfRange {
                    face,
                    vertex: vertex as u64,
                    vertex_count: positions.len(),
                });
            }
        }
        Ok(Self {
            positions,
            offsets,
            indices,
            corners: CornerAttributes::default(),
        })
    }

    /// The mesh with a shading normal per face corner (`normals[k]` for the
    /// corner `k` of the faces' concatenated index lists, as
    /// [`face_offset`](Self::face_offset) numbers them). Fails unless there
    /// is one per corner, each finite. They need not be unit length.
    pub fn with_corner_normals(mut self, normals: Vec<Vec3>) -> Result<Self, MeshError> {
        self.check_corners("normals", normals.len(), normals.iter().position(|n| !n.is_finite()))?;
        self.corners.normals = Some(normals);
        Ok(self)
    }

    /// The mesh with texture coordinates per face corner (numbered as for
    /// [`with_corner_normals`](Self::with_corner_normals)). Fails unless
    /// there is one per corner, each finite.
    pub fn with_corner_uvs(mut self, uvs: Vec<[f32; 2]>) -> Result<Self, MeshError> {
        let bad = uvs.iter().position(|uv| !uv.iter().all(|c| c.is_finite()));
        self.check_corners("texture coordinates", uvs.len(), bad)?;
        self.corners.uvs = Some(uvs);
        Ok(self)
    }

    fn check_corners(&self, what: &'static str, count: usize, non_finite: Option<usize>) -> Result<(), MeshError> {
        if count != self.indices.len() {
            return Err(MeshError::CornerCount {
                what,
                count,
                corners: self.indices.len(),
            });
        }
        match non_finite {
            Some(corner) => Err(MeshError::NonFiniteCorner { what, corner }),
            None => Ok(()),
        }
    }

    /// The shading normals per face corner, when the mesh has them.
    pub fn corner_normals(&self) -> Option<&[Vec3]> {
        self.corners.normals.as_deref()
    }

    /// The texture coordinates per face corner, when the mesh has them.
    pub fn corner_uvs(&self) -> Option<&[[f32; 2]]> {
        self.corners.uvs.as_deref()
    }

    /// The number of face corners (the faces' vertex counts summed).
    pub fn corner_count(&self) -> usize {
        self.indices.len()
    }

    /// The first corner of face `f`: its corners are `face_offset(f)..`
    /// `face_offset(f + 1)`, in the order of [`face`](Self::face).
    ///
    /// # Panics
    /// When `f` is above [`Mesh::face_count`].
    pub fn face_offset(&self, f: usize) -> usize {
        self.offsets[f] as usize
    }

    /// A mesh from positions and one index list per face.
    pub fn from_faces(positions: Vec<Vec3>, faces: &[Vec<u32>]) -> Result<Self, MeshError> {
        let mut offsets = Vec::with_capacity(faces.len() + 1);
        offsets.push(0u32);
        let mut indices = Vec::new();
        for face in faces {
            indices.extend_from_slice(face);
            let end = u32::try_from(indices.len()).map_err(|_| MeshError::TooLarge {
                what: "face indices",
                count: indices.len(),
            })?;
            offsets.push(end);
        }
        Self::from_compact(positions, offsets, indices)
    }

    /// A triangle mesh.
    pub fn from_triangles(positions: Vec<Vec3>, triangles: &[[u32; 3]]) -> Result<Self, MeshError> {
        let count = triangles.len().checked_mul(3).filter(|&n| n <= u32::MAX as usize);
        let count = count.ok_or(MeshError::TooLarge {
            what: "face indices",
            count: triangles.len(),
        })?;
        let offsets = (0..=triangles.len()).map(|f| (f * 3) as u32).collect();
        let mut indices = Vec::with_capacity(count);
        indices.extend(triangles.iter().flatten());
        Self::from_compact(positions, offsets, indices)
    }

    /// Moves the vertices to `positions`, one per vertex in the same
    /// order, the faces unchanged (a deforming mesh's new frame). The
    /// file's corner normals, if any, are dropped: they described the
    /// surface as it was (texture coordinates stay). Fails, changing
    /// nothing, unless there are as many positions as vertices, each
    /// finite.
    ///
    /// ```
    /// use proxima::{Mesh, MeshError, Vec3};
    /// let mut mesh = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    /// mesh.set_positions(&[Vec3::Z, Vec3::X, Vec3::Y]).unwrap();
    /// assert_eq!(mesh.positions()[0], Vec3::Z);
    /// assert_eq!(mesh.set_positions(&[Vec3::Z]), Err(MeshError::VertexCount { count: 1, vertices: 3 }));
    /// ```
    pub fn set_positions(&mut self, positions: &[Vec3]) -> Result<(), MeshError> {
        if positions.len() != self.positions.len() {
            return Err(MeshError::VertexCount {
                count: positions.len(),
                vertices: self.positions.len(),
            });
        }
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFiniteVertex { index });
        }
        self.positions.copy_from_slice(positions);
        self.corners.normals = None;
        Ok(())
    }

    /// Vertex positions, in file order (including vertices no face uses).
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces (polygons of any size).
    pub fn face_count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The vertex indices of face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.indices[self.offsets[f] as usize..self.offsets[f + 1] as usize]
    }

    /// The faces in file order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        self.offsets
            .windows(2)
            .map(|w| &self.indices[w[0] as usize..w[1] as usize])
    }

    /// Number of triangles after fan triangulation (a face of n vertices gives n - 2).
    pub fn triangle_count(&self) -> usize {
        self.indices.len() - 2 * self.face_count()
    }

    /// The index in [`Mesh::triangles`] of face `f`'s first fan triangle (its
    /// `n - 2` triangles follow in order).
    ///
    /// # Panics
    /// When `f` is not below [`Mesh::face_count`].
    pub fn first_triangle(&self, f: usize) -> usize {
        self.offsets[f] as usize - 2 * f
    }

    /// Number of faces with more than three vertices.
    pub fn polygon_count(&self) -> usize {
        self.faces().filter(|f| f.len() > 3).count()
    }

    /// `true` when the mesh has no vertices.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The bounding box of all vertices (empty for an empty mesh).
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }
}
