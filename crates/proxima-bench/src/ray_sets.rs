//! The ray sets of the ray benchmark binaries (`compare --rays`,
//! `rays_peers`): rays from outside and near the surface, and rays aimed
//! exactly at edges and vertices.

use proxima::{Mesh, Vec3};

/// A ray as `(origin, direction)`.
pub type Ray = (Vec3, Vec3);

/// The ray sets of the ray benchmarks: `outside`, from outside the bounding
/// sphere (1 to 3 radii from the center) aimed at random points of the box,
/// mostly hits; `inside`, from near the surface (Gaussian offsets of 1% of
/// the diagonal) in random directions.
pub fn ray_sets(mesh: &Mesh, n: usize, seed: u64) -> Vec<(&'static str, Vec<Ray>)> {
    let b = mesh.bounds();
    let radius = 0.5 * b.diagonal();
    let mut rng = proxima::sample::Rng::new(seed);
    let unit = |rng: &mut proxima::sample::Rng| loop {
        let d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let len = d.length();
        if len > 1e-3 && len <= 1.0 {
            break d / len;
        }
    };
    let outside = (0..n)
        .map(|_| {
            let o = b.center() + unit(&mut rng) * radius * rng.range(1.0, 3.0);
            (o, (rng.in_box(&b) - o).normalize())
        })
        .collect();
    let inside = proxima::sample::near_surface(mesh, n, 0.01, seed + 1)
        .into_iter()
        .map(|o| (o, unit(&mut rng)))
        .collect();
    vec![("outside", outside), ("inside", inside)]
}

/// Rays aimed exactly at edge midpoints (even `k`) and vertices (odd `k`),
/// each from the side that every incident triangle faces, from 0.01 to 2
/// bbox diagonals away. Only edges shared by exactly two triangles, and
/// vertices all of whose edges are, with no degenerate or back-facing
/// incident triangle, are aimed at: such a ray crosses the surface there, so
/// a watertight test must report a hit (on that surface or before it).
pub fn aimed_rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<Ray> {
    let p = mesh.positions();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(mesh.triangle_count());
    for face in mesh.faces() {
        for w in face[1..].windows(2) {
            tris.push([face[0], w[0], w[1]]);
        }
    }
    let normal = |t: &[u32; 3]| {
        let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    };
    // Undirected edges with their triangles, by sorting (no hashing).
    let mut edge_list: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * tris.len());
    for (f, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edge_list.push((a.min(b), a.max(b), f as u32));
        }
    }
    edge_list.sort_unstable();
    let mut open_vertex = vec![false; p.len()];
    let mut edges: Vec<(u32, u32, [u32; 2])> = Vec::new();
    for run in edge_list.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        if run.len() == 2 {
            edges.push((run[0].0, run[0].1, [run[0].2, run[1].2]));
        } else {
            open_vertex[run[0].0 as usize] = true;
            open_vertex[run[0].1 as usize] = true;
        }
    }
    let mut vertex_faces: Vec<Vec<u32>> = vec![Vec::new(); p.len()];
    for (f, t) in tris.iter().enumerate() {
        for &v in t {
            vertex_faces[v as usize].push(f as u32);
        }
    }
    let reach = mesh.bounds().diagonal();
    let mut rng = proxima::sample::Rng::new(seed);
    let mut out = Vec::with_capacity(n);
    let mut attempts = 0;
    while out.len() < n && attempts < 20 * n + 100 && !edges.is_empty() {
        attempts += 1;
        let (target, faces): (Vec3, &[u32]) = if out.len() % 2 == 0 {
            let (a, b, f) = &edges[rng.below(edges.len())];
            ((p[*a as usize] + p[*b as usize]) * 0.5, f)
        } else {
            let v = rng.below(p.len());
            if open_vertex[v] || vertex_faces[v].is_empty() {
                continue;
            }
            (p[v], &vertex_faces[v])
        };
        let normals: Vec<Vec3> = faces.iter().map(|&f| normal(&tris[f as usize])).collect();
        let axis = normals.iter().sum::<Vec3>().normalize_or_zero();
        let jitter = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let side = (axis + jitter).normalize_or_zero();
        if axis == Vec3::ZERO || normals.iter().any(|n| n.dot(side) < 0.02) {
            continue;
        }
        let o = target + side * reach * rng.range(0.01, 2.0);
        out.push((o, target - o));
    }
    out
}
