//! The peer library parry3d (feature `peers`): its triangle mesh over ours,
//! its distance and first hit for the `compare` binary and the criterion
//! benches, and the parry3d rows of the `bench` binary, on the same
//! triangles and queries, so that every run states its own ratio to the
//! library most Rust users would otherwise reach for.

use crate::report::Record;
use parry3d::query::PointQuery;
use parry3d::shape::TriMesh;
use proxima::{Mesh, Vec3};
use std::time::{Duration, Instant};

/// Queries a peer answers between two looks at its time budget.
const CHUNK: usize = 1024;

/// parry3d's triangle mesh (with its BVH) over the faces of `mesh`.
pub fn parry_trimesh(mesh: &Mesh) -> TriMesh {
    let (vertices, indices) = parry_input(mesh);
    TriMesh::new(vertices, indices).expect("parry3d accepts the mesh")
}

/// The vertices and triangles that [`TriMesh::new`] takes, from the faces of
/// `mesh` (polygons fanned): parry3d's input, made apart so that build
/// timings can leave it out, as they leave out copying ours.
pub fn parry_input(mesh: &Mesh) -> (Vec<parry3d::math::Vector>, Vec<[u32; 3]>) {
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
    (vertices, indices)
}

/// parry3d's distance from `p` to the surface of `trimesh` (not solid).
pub fn parry_distance(trimesh: &TriMesh, p: Vec3) -> f32 {
    let q = parry3d::math::Vector::from_array(p.to_array());
    let projection = trimesh.project_local_point(q, false);
    (projection.point - q).length()
}

/// parry3d's first hit along `ray` (its time of impact), hollow triangles.
pub fn parry_ray(trimesh: &TriMesh, ray: crate::Ray) -> Option<f32> {
    use parry3d::query::RayCast;
    let ray = parry3d::query::Ray::new(
        parry3d::math::Vector::from_array(ray.0.to_array()),
        parry3d::math::Vector::from_array(ray.1.to_array()),
    );
    trimesh.cast_local_ray(&ray, f32::MAX, false)
}

/// `answer(i)` for `i` in `0..count`, in order, on the current pool, a
/// chunk of [`CHUNK`] at a time until `budget` has passed: every chunk once
/// the budget allows, at least the first. A peer's row is bounded so: its
/// work cannot be counted as ours is, and on degenerate input a peer may
/// search far longer per query than on a mesh.
pub fn answer_within<R: Send>(count: usize, budget: Duration, answer: impl Fn(usize) -> R + Sync) -> Vec<R> {
    use rayon::prelude::*;
    let start = Instant::now();
    let mut answers = Vec::with_capacity(count);
    while answers.len() < count && (answers.is_empty() || start.elapsed() < budget) {
        let chunk = answers.len()..(answers.len() + CHUNK).min(count);
        let part: Vec<R> = chunk.into_par_iter().map(&answer).collect();
        answers.extend(part);
    }
    answers
}

/// The note of a peer's row that answered `done` of `count` queries within `budget`.
fn budget_note(done: usize, count: usize, budget: Duration) -> Option<String> {
    (done < count).then(|| {
        format!(
            "parry3d ran on the first {done} of {count} queries only: it used up its time budget of {:.0} s (ten times \
             proxima's slowest row, at least 10 s)",
            budget.as_secs_f64()
        )
    })
}

/// parry3d's build and per-query closest-point time on the mesh's triangles
/// (faces fanned as proxima fans them), answered in input order on the
/// current pool, for at most `budget` ([`answer_within`]). `agree` when
/// every distance is within 1e-5 of the bounding box diagonal of `expected`
/// (parry3d's closest point differs from ours by rounding only), on the
/// queries both answered. `None` when parry3d refuses the mesh.
pub fn parry3d_faces(mesh: &Mesh, points: &[Vec3], expected: &[Option<f32>], budget: Duration) -> Option<Record> {
    use parry3d::math::Vector;
    let (vertices, indices) = parry_input(mesh);
    // The build alone is timed, not the making of its input (nor ours).
    let start = Instant::now();
    let trimesh = parry3d::shape::TriMesh::new(vertices, indices).ok()?;
    let build_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let distances: Vec<f32> = answer_within(points.len(), budget, |i| {
        let q = Vector::from_array(points[i].to_array());
        (trimesh.project_local_point(q, false).point - q).length()
    });
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
        queries: distances.len(),
        seconds,
        agree,
        note: budget_note(distances.len(), points.len(), budget),
    })
}

/// parry3d's build and per-ray first-hit time (`cast_local_ray`, hollow
/// triangles) on the mesh's triangles, in input order on the current pool,
/// for at most `budget` ([`answer_within`]). `agree` when every ray hits or
/// misses as in `expected` (`t`, input index), at a `t` within 1e-5 of the
/// bounding box diagonal, on the rays both cast. `None` when parry3d
/// refuses the mesh.
pub fn parry3d_rays(
    mesh: &Mesh,
    rays: &[(Vec3, Vec3)],
    expected: &[Option<(f32, u32)>],
    budget: Duration,
) -> Option<Record> {
    use parry3d::query::{Ray, RayCast};
    let (vertices, indices) = parry_input(mesh);
    let start = Instant::now();
    let trimesh = parry3d::shape::TriMesh::new(vertices, indices).ok()?;
    let build_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let hits: Vec<Option<f32>> = answer_within(rays.len(), budget, |i| {
        let (o, d) = rays[i];
        let ray = Ray::new(
            parry3d::math::Vector::from_array(o.to_array()),
            parry3d::math::Vector::from_array(d.to_array()),
        );
        trimesh.cast_local_ray(&ray, f32::MAX, false)
    });
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
        queries: hits.len(),
        seconds,
        agree,
        note: budget_note(hits.len(), rays.len(), budget),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A spent budget still answers the first chunk; an ample one answers
    /// every query; both in input order.
    #[test]
    fn peers_answer_in_order_within_their_budget() {
        let count = 3 * CHUNK + 5;
        assert_eq!(
            answer_within(count, Duration::ZERO, |i| i),
            (0..CHUNK).collect::<Vec<_>>()
        );
        assert_eq!(
            answer_within(count, Duration::MAX, |i| i),
            (0..count).collect::<Vec<_>>()
        );
        assert_eq!(answer_within(7, Duration::ZERO, |i| 2 * i), [0, 2, 4, 6, 8, 10, 12]);
        assert!(answer_within(0, Duration::MAX, |i| i).is_empty());
        assert_eq!(budget_note(7, 7, Duration::ZERO), None);
        let note = budget_note(CHUNK, count, Duration::from_secs(12)).unwrap();
        assert!(
            note.starts_with("parry3d ran on the first 1024 of 3077 queries only"),
            "{note}"
        );
    }
}
