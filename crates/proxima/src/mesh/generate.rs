//! Synthetic meshes for tests and benchmarks.

use super::Mesh;
use crate::math::Vec3;
use crate::sample::Rng;
use std::collections::HashMap;

/// A closed geodesic sphere with smooth random bumps: each of the 20
/// icosahedron faces is cut into `frequency²` triangles, vertices are pushed
/// onto the unit sphere and then displaced radially by a sum of a few smooth
/// waves chosen by `seed`. `frequency = 224` gives 1,003,520 triangles (the
/// `ico1m` mesh of BENCHMARKS.md). The mesh is watertight: vertices on shared
/// icosahedron edges are computed identically from both sides and welded.
///
/// ```
/// let mesh = proxima::mesh::generate::noisy_icosphere(4, 1);
/// assert_eq!(mesh.face_count(), 20 * 4 * 4);
/// assert_eq!(mesh.edge_indices().len(), 3 * mesh.face_count() / 2); // closed: every edge shared by two faces
/// ```
pub fn noisy_icosphere(frequency: u32, seed: u64) -> Mesh {
    let frequency = frequency.max(1);
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let corners: [[f64; 3]; 12] = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    const FACES: [[usize; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut rng = Rng::new(seed);
    let waves: Vec<(Vec3, f32, f32, f32)> = (0..6)
        .map(|_| {
            let dir = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X);
            (
                dir,
                rng.range(2.0, 9.0),
                rng.range(0.0, std::f32::consts::TAU),
                rng.range(0.01, 0.04),
            )
        })
        .collect();
    let f = frequency as u64;
    // A lattice point of a face is identified by its integer weights on the
    // icosahedron corners; keyed by (corner, weight) pairs sorted by corner, the
    // same point reached from two faces has the same key and the same position.
    let mut index: HashMap<[(usize, u64); 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut vertex = |weights: [(usize, u64); 3]| -> u32 {
        // Zero weights say nothing about the point: blank their corner.
        let mut key = weights.map(|(c, w)| if w == 0 { (usize::MAX, 0) } else { (c, w) });
        key.sort_unstable();
        *index.entry(key).or_insert_with(|| {
            let mut p = [0f64; 3];
            for &(c, w) in key.iter().filter(|(c, _)| *c != usize::MAX) {
                for (axis, value) in p.iter_mut().enumerate() {
                    *value += corners[c][axis] * w as f64;
                }
            }
            let dir = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32).normalize();
            let bump: f32 = waves
                .iter()
                .map(|&(d, freq, phase, amp)| amp * (freq * dir.dot(d) + phase).sin())
                .sum();
            positions.push(dir * (1.0 + bump));
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(20 * (f * f) as usize);
    for [a, b, c] in FACES {
        let at = |i: u64, j: u64| [(a, f - i - j), (b, i), (c, j)];
        for i in 0..f {
            for j in 0..f - i {
                let v0 = vertex(at(i, j));
                let v1 = vertex(at(i + 1, j));
                let v2 = vertex(at(i, j + 1));
                triangles.push([v0, v1, v2]);
                if i + j + 1 < f {
                    let v3 = vertex(at(i + 1, j + 1));
                    triangles.push([v1, v3, v2]);
                }
            }
        }
    }
    Mesh::from_triangles(positions, &triangles).expect("generated indices are in range and positions finite")
}
