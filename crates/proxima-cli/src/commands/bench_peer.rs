//! The peer rows of `proxima bench`: parry3d's closest point (or first
//! ray hit) on the same triangles and queries, so that every run states its own ratio to the
//! library most Rust users would otherwise reach for.

use super::bench::Record;
use proxima::{Mesh, Vec3};

/// parry3d's build and per-query closest-point time on the mesh's triangles
/// (faces fanned as proxima fans them), answered in input order on the
/// current pool. `agree` when every distance is within 1e-5 of the bounding
/// box diagonal of `expected` (parry3d's closest point differs from ours by
/// rounding only). `None` when parry3d refuses the mesh.
#[cfg(feature = "parry3d")]
pub fn parry3d_faces(mesh: &Mesh, points: &[Vec3], expected: &[Option<f32>]) -> Option<Record> {
    use parry3d::math::Vector;
    use parry3d::query::PointQuery;
    use rayon::prelude::*;
    use std::time::Instant;
    let (vertices, indices) = parry3d_input(mesh);
    // The build alone is timed, not the making of its input (nor ours).
    let start = Instant::now();
    let trimesh = parry3d::shape::TriMesh::new(vertices, indices).ok()?;
    let build_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let distances: Vec<f32> = points
        .par_iter()
        .map(|p| {
            let q = Vector::from_array(p.to_array());
            (trimesh.project_local_point(q, false).point - q).length()
        })
        .collect();
    let seconds = start.elapsed().as_secs_f64();
    let tolerance = 1e-5 * mesh.bounds().diagonal();
    let agree = distances
        .iter()
        .zip(expected)
        .all(|(&d, e)| e.is_some_and(|e| (d - e).abs() <= tolerance));
    Some(Record {
        primitives: "faces",
        method: "parry3d",
        build_seconds,
        queries: points.len(),
        seconds,
        agree,
    })
}

/// parry3d's build and per-ray first-hit time (`cast_local_ray`, hollow
/// triangles) on the mesh's triangles, in input order on the current pool.
/// `agree` when every ray hits or misses as in `expected` (`t`, input
/// index), at a `t` within 1e-5 of the bounding box diagonal. `None` when
/// parry3d refuses the mesh.
#[cfg(feature = "parry3d")]
pub fn parry3d_rays(mesh: &Mesh, rays: &[(Vec3, Vec3)], expected: &[Option<(f32, u32)>]) -> Option<Record> {
    use parry3d::query::{Ray, RayCast};
    use rayon::prelude::*;
    use std::time::Instant;
    let (vertices, indices) = parry3d_input(mesh);
    let start = Instant::now();
    let trimesh = parry3d::shape::TriMesh::new(vertices, indices).ok()?;
    let build_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let hits: Vec<Option<f32>> = rays
        .par_iter()
        .map(|(o, d)| {
            let ray = Ray::new(
                parry3d::math::Vector::from_array(o.to_array()),
                parry3d::math::Vector::from_array(d.to_array()),
            );
            trimesh.cast_local_ray(&ray, f32::MAX, false)
        })
        .collect();
    let seconds = start.elapsed().as_secs_f64();
    let tolerance = 1e-5 * mesh.bounds().diagonal();
    let agree = hits.iter().zip(expected).all(|(h, e)| match (h, e) {
        (None, None) => true,
        (Some(t), Some((expected_t, _))) => (t - expected_t).abs() <= tolerance,
        _ => false,
    });
    Some(Record {
        primitives: "faces",
        method: "parry3d",
        build_seconds,
        queries: rays.len(),
        seconds,
        agree,
    })
}

/// parry3d's vertex and index arrays for the mesh's faces, fanned as
/// proxima fans them.
#[cfg(feature = "parry3d")]
fn parry3d_input(mesh: &Mesh) -> (Vec<parry3d::math::Vector>, Vec<[u32; 3]>) {
    let vertices = mesh
        .positions()
        .iter()
        .map(|p| parry3d::math::Vector::from_array(p.to_array()))
        .collect();
    let mut indices = Vec::with_capacity(mesh.triangle_count());
    for face in mesh.faces() {
        for pair in face[1..].windows(2) {
            indices.push([face[0], pair[0], pair[1]]);
        }
    }
    (vertices, indices)
}

/// Without the `parry3d` feature there is no peer row.
#[cfg(not(feature = "parry3d"))]
pub fn parry3d_faces(_: &Mesh, _: &[Vec3], _: &[Option<f32>]) -> Option<Record> {
    None
}

/// Without the `parry3d` feature there is no peer row.
#[cfg(not(feature = "parry3d"))]
pub fn parry3d_rays(_: &Mesh, _: &[(Vec3, Vec3)], _: &[Option<(f32, u32)>]) -> Option<Record> {
    None
}
