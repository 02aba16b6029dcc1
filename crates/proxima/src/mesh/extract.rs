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

    /// Triangle `triangle` of [`triangles`](Self::triangles), whose source
    /// is face `face`, read from the positions as they are now: what a
    /// refit gathers without extracting the whole set again.
    ///
    /// # Panics
    /// When `face` is not a face, or `triangle` not one of its fan.
    #[inline]
    pub(crate) fn fan_triangle(&self, triangle: u32, face: u32) -> Triangle {
        let p = |corner: usize| self.positions[self.indices[corner] as usize];
        // Where every face is a triangle, face f starts at 3f: one random
        // read fewer per triangle than through the offsets.
        if self.indices.len() == 3 * self.face_count() {
            let start = 3 * face as usize;
            return Triangle::new(p(start), p(start + 1), p(start + 2));
        }
        let start = self.offsets[face as usize] as usize;
        // The fan's `k`-th triangle is (v0, v(k + 1), v(k + 2)).
        let k = triangle as usize + 2 * face as usize - start;
        Triangle::new(p(start), p(start + k + 1), p(start + k + 2))
    }
}

#[cfg(test)]
mod tests {
    use crate::math::Vec3;
    use crate::mesh::Mesh;

    /// Every fan triangle read alone is the one the whole extraction gives,
    /// in a mesh of faces of three to six corners and in one of triangles
    /// only (whose faces are found without the offsets).
    #[test]
    fn fan_triangles_read_alone_are_those_extracted() {
        let positions: Vec<Vec3> = (0..12)
            .map(|i| Vec3::new(i as f32, (i * i % 7) as f32, (i % 3) as f32))
            .collect();
        let faces = [
            vec![0, 1, 2],
            vec![3, 4, 5, 6],
            vec![7, 8, 9, 10, 11],
            vec![0, 2, 4, 6, 8, 10],
            vec![1, 3, 5],
        ];
        let mixed = Mesh::from_faces(positions.clone(), &faces).unwrap();
        let triangles = Mesh::from_triangles(positions, &[[0, 1, 2], [3, 4, 5], [9, 10, 11], [2, 6, 10]]).unwrap();
        for mesh in [mixed, triangles] {
            let set = mesh.triangles();
            assert!(set.primitives.len() >= 4);
            for (i, (t, &face)) in set.primitives.iter().zip(&set.sources).enumerate() {
                assert_eq!(mesh.fan_triangle(i as u32, face), *t, "triangle {i}");
            }
        }
    }
}
