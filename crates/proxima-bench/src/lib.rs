//! Shared pieces of the benchmarks: mesh choice and the parry3d baseline.

use parry3d::query::PointQuery;
use parry3d::shape::TriMesh;
use proxima::{Mesh, Vec3};
use std::path::PathBuf;

/// The shared data folder beside the checkout, if present.
pub fn data_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data"));
    dir.is_dir().then_some(dir)
}

/// A mesh by name: `ico1m` (the seeded 1,003,520-triangle bumpy icosphere),
/// `ico100k` (101,120 triangles), or a file path (absolute, or relative to the
/// shared data folder).
pub fn load_named(name: &str) -> Result<Mesh, String> {
    match name {
        "ico1m" => Ok(proxima::mesh::generate::noisy_icosphere(224, 1)),
        "ico100k" => Ok(proxima::mesh::generate::noisy_icosphere(71, 1)),
        _ => {
            let path = PathBuf::from(name);
            let path = if path.exists() {
                path
            } else {
                data_dir().map(|d| d.join(name)).unwrap_or(path)
            };
            proxima::io::load(&path).map_err(|e| e.to_string())
        }
    }
}

/// parry3d's triangle mesh (with its BVH) over the faces of `mesh`.
pub fn parry_trimesh(mesh: &Mesh) -> TriMesh {
    let vertices: Vec<parry3d::math::Vector> = mesh
        .positions()
        .iter()
        .map(|p| parry3d::math::Vector::from_array(p.to_array()))
        .collect();
    let mut indices = Vec::with_capacity(mesh.triangle_count());
    for face in mesh.faces() {
        for w in face[1..].windows(2) {
            indices.push([face[0], w[0], w[1]]);
        }
    }
    TriMesh::new(vertices, indices).expect("parry3d accepts the mesh")
}

/// parry3d's distance from `p` to the surface of `trimesh` (not solid).
pub fn parry_distance(trimesh: &TriMesh, p: Vec3) -> f32 {
    let q = parry3d::math::Vector::from_array(p.to_array());
    let projection = trimesh.project_local_point(q, false);
    (projection.point - q).length()
}
