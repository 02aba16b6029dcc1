//! Extraction of point, segment and triangle primitives from a mesh.

use super::Mesh;
use crate::primitive::{LineSegment, Point, PrimitiveSet, Triangle};

impl Mesh {
    /// Every vertex as a point; the source of each is its vertex index.
    ///
    /// ```
    /// use proxima::{Mesh, Vec3};
    /// let quad = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]).unwrap();
    /// assert_eq!(quad.vertices().len(), 4);
    /// assert_eq!(quad.edges().len(), 4); // each undirected edge once
    /// assert_eq!(quad.triangles().sources, [0, 0]); // the fan of face 0
    /// ```
    pub fn vertices(&self) -> PrimitiveSet<Point> {
        PrimitiveSet::from_primitives(self.positions.iter().map(|&p| Point(p)).collect())
    }

    /// The unique undirected edges as vertex-index pairs `[low, high]`, numbered
    /// in the order they first appear when walking each face's boundary
    /// (v0→v1, v1→v2, …, vn→v0) in face order. Zero-length edges between two
    /// distinct vertex indices at the same position are kept; an edge from a
    /// vertex to itself (a repeated index in a face) is skipped.
    pub fn edge_indices(&self) -> Vec<[u32; 2]> {
        // Sort-based deduplication: (key, first position) sorted by key, keep the
        // first occurrence, then restore appearance order. No hashing, and the
        // memory is two flat arrays.
        let mut keyed: Vec<(u64, u32)> = Vec::with_capacity(self.indices.len());
        let mut position = 0u32;
        for face in self.faces() {
            for (i, &v) in face.iter().enumerate() {
                let w = face[(i + 1) % face.len()];
                if v != w {
                    let (lo, hi) = if v < w { (v, w) } else { (w, v) };
                    keyed.push(((lo as u64) << 32 | hi as u64, position));
                }
                position += 1;
            }
        }
        keyed.sort_unstable();
        keyed.dedup_by_key(|e| e.0);
        keyed.sort_unstable_by_key(|e| e.1);
        keyed
            .into_iter()
            .map(|(key, _)| [(key >> 32) as u32, key as u32])
            .collect()
    }

    /// The unique undirected edges as segments; the source of each is its edge
    /// index in [`Mesh::edge_indices`] order.
    pub fn edges(&self) -> PrimitiveSet<LineSegment> {
        let p = &self.positions;
        PrimitiveSet::from_primitives(
            self.edge_indices()
                .into_iter()
                .map(|[a, b]| LineSegment::new(p[a as usize], p[b as usize]))
                .collect(),
        )
    }

    /// The vertex indices of each triangle of [`Mesh::triangles`], in the
    /// same order: face `f`'s fan `(v0, vi, vi+1)`. Two triangles are
    /// neighbours when they share an index (self-intersection tests).
    ///
    /// ```
    /// use proxima::{Mesh, Vec3};
    /// let quad = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]).unwrap();
    /// assert_eq!(quad.triangle_vertex_indices(), [[0, 1, 2], [0, 2, 3]]);
    /// ```
    pub fn triangle_vertex_indices(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(self.triangle_count());
        for face in self.faces() {
            for w in face[1..].windows(2) {
                out.push([face[0], w[0], w[1]]);
            }
        }
        out
    }

    /// The faces fan-triangulated (v0, vi, vi+1); the source of each triangle is
    /// the index of its face.
    pub fn triangles(&self) -> PrimitiveSet<Triangle> {
        let p = &self.positions;
        let mut set = PrimitiveSet {
            primitives: Vec::with_capacity(self.triangle_count()),
            sources: Vec::with_capacity(self.triangle_count()),
        };
        for (f, face) in self.faces().enumerate() {
            let v0 = p[face[0] as usize];
            for w in face[1..].windows(2) {
                set.primitives
                    .push(Triangle::new(v0, p[w[0] as usize], p[w[1] as usize]));
                set.sources.push(f as u32);
            }
        }
        set
    }
}
