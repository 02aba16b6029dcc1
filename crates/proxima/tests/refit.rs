//! Meshes that move: after `update_vertices`, every structure of a mesh
//! index answers as a fresh index over the moved mesh does, and brute force
//! (the ray hits, closest primitives, k-nearest, signed distances and
//! sides, normals), whatever the policy, after small motions, swirls that
//! wreck the trees' shape, faces collapsed to points, and a hundred updates
//! in a row. Bad positions change nothing.

use crate::common;

use proxima::index::{IndexConfig, IndexError, MeshIndex, RefitPolicy};
use proxima::prelude::*;
use proxima::sample::Rng;
use proxima::sdf::{Sign, winding_number_exact};
use proxima::{BuildError, MeshError, RayTree};

/// Every structure an index can build, built.
fn build_everything(index: &MeshIndex) {
    for kind in PrimitiveKind::ALL {
        index.closest(kind, &[Vec3::ZERO]).unwrap();
    }
    index.field(Sign::WindingNumber).unwrap();
    index.field(Sign::Pseudonormal).unwrap();
    index.ray_tree().unwrap();
    index.oriented_bounds().unwrap();
    index.vertex_normals();
}

/// Queries on and near the moved mesh's features: the `common` set (on
/// vertices, edge midpoints, near the surface, far) and each vertex
/// nudged by an ulp or two on either side along each axis.
fn queries(mesh: &Mesh, seed: u64) -> Vec<Vec3> {
    let mut out = common::queries(mesh, 150, seed);
    let mut rng = Rng::new(seed);
    for _ in 0..40 {
        let v = mesh.positions()[rng.below(mesh.vertex_count())];
        let axis = rng.below(3);
        for steps in [-2i32, -1, 1, 2] {
            let mut p = v;
            for _ in 0..steps.abs() {
                p[axis] = if steps < 0 {
                    p[axis].next_down()
                } else {
                    p[axis].next_up()
                };
            }
            out.push(p);
        }
    }
    out
}

/// Rays through the moved mesh's vertices and edge midpoints (where
/// neighbouring triangles meet) and at random.
fn rays(mesh: &Mesh, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut rng = Rng::new(seed);
    let b = mesh.bounds();
    let mut out = proxima::sample::rays_at_box(&b, 200, seed);
    let edges = mesh.edge_indices();
    for k in 0..200 {
        let target = if k % 2 == 0 {
            mesh.positions()[rng.below(mesh.vertex_count())]
        } else {
            let [a, c] = edges[rng.below(edges.len())];
            (mesh.positions()[a as usize] + mesh.positions()[c as usize]) * 0.5
        };
        let dir = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::Z);
        out.push((target - dir * b.diagonal(), dir));
    }
    out
}

/// The moved index answers as a fresh index over its mesh, and closest
/// faces and ray hits equal brute force.
fn assert_as_fresh(index: &MeshIndex, what: &str, seed: u64) {
    let mesh = index.mesh();
    let fresh = MeshIndex::new(mesh.clone());
    let points = queries(mesh, seed);
    for kind in PrimitiveKind::ALL {
        assert_eq!(
            index.closest(kind, &points),
            fresh.closest(kind, &points),
            "{what}: {kind}"
        );
        assert_eq!(
            index.k_nearest(kind, &points[..60], 5),
            fresh.k_nearest(kind, &points[..60], 5),
            "{what}: {kind} k-nearest"
        );
    }
    // Brute force over the faces' triangles.
    let triangles = mesh.triangles();
    let hits = index.closest(PrimitiveKind::Faces, &points).unwrap();
    for (p, hit) in points.iter().zip(&hits) {
        let best = triangles
            .primitives
            .iter()
            .map(|t| (t.closest_point((*p).into()) - Vec3A::from(*p)).length_squared())
            .fold(f32::INFINITY, f32::min);
        assert_eq!(hit.unwrap().distance, best.sqrt(), "{what}: closest at {p}");
    }
    let rays = rays(mesh, seed);
    let tree = index.ray_tree().unwrap();
    let fresh_tree = fresh.ray_tree().unwrap();
    let (first, any) = (
        tree.first_hit_batch(&rays, 0.0, f32::INFINITY),
        tree.any_hit_batch(&rays, 0.0, f32::INFINITY),
    );
    assert_eq!(
        first,
        fresh_tree.first_hit_batch(&rays, 0.0, f32::INFINITY),
        "{what}: rays"
    );
    assert_eq!(
        any,
        fresh_tree.any_hit_batch(&rays, 0.0, f32::INFINITY),
        "{what}: any hit"
    );
    let linear = proxima::LinearSearch::new(triangles.clone());
    for (k, &(o, d)) in rays.iter().enumerate().step_by(7) {
        assert_eq!(
            first[k],
            linear.first_hit(o, d, 0.0, f32::INFINITY),
            "{what}: ray {k} by brute force"
        );
    }
    // Signed distances: the pseudonormal field's are the fresh one's; the
    // winding field's distances too, and its side the exact sum's wherever
    // that is clear of ½, off the surface (within a few ulps of a triangle,
    // the f32 solid angle cannot tell the sides apart, fresh build or not).
    let (moved, new) = (
        index.field(Sign::Pseudonormal).unwrap(),
        fresh.field(Sign::Pseudonormal).unwrap(),
    );
    let winding = index.field(Sign::WindingNumber).unwrap();
    for p in &points {
        let a = moved.signed_distance(*p).map(|s| (s.distance.to_bits(), s.closest));
        assert_eq!(
            a,
            new.signed_distance(*p).map(|s| (s.distance.to_bits(), s.closest)),
            "{what}: {p}"
        );
        let Some(w) = winding.signed_distance(*p) else { continue };
        assert_eq!(
            Some(w.closest),
            a.map(|a| a.1),
            "{what}: winding field's closest at {p}"
        );
        let exact = winding_number_exact(&triangles.primitives, *p);
        if (exact - 0.5).abs() > 0.01 && w.closest.distance > 1e-5 * mesh.bounds().diagonal() {
            assert_eq!(w.is_inside(), exact > 0.5, "{what}: side at {p} (w = {exact})");
        }
    }
    assert_eq!(index.vertex_normals(), fresh.vertex_normals(), "{what}: normals");
}

/// The deformations: a little noise, a swirl about the vertical axis that
/// turns the top half a turn against the bottom (boxes then overlap
/// everywhere), and faces collapsed to single points.
fn deform(mesh: &Mesh, how: &str, step: u64) -> Vec<Vec3> {
    let mut rng = Rng::new(step);
    let b = mesh.bounds();
    let scale = b.diagonal();
    let mut out: Vec<Vec3> = mesh.positions().to_vec();
    match how {
        "noise" => {
            for p in &mut out {
                *p += Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.01 * scale;
            }
        }
        "swirl" => {
            for p in &mut out {
                let t = (p.z - b.min.z) / (b.max.z - b.min.z).max(1e-6);
                let (s, c) = (std::f32::consts::TAU * t).sin_cos();
                let q = *p - b.center();
                *p = b.center() + Vec3::new(c * q.x - s * q.y, s * q.x + c * q.y, q.z);
            }
        }
        "collapse" => {
            // A third of the vertices onto the first vertex of their face's
            // neighbour: zero-area faces, edges of length 0.
            let target = out[0];
            for (k, p) in out.iter_mut().enumerate() {
                if k % 3 == 0 {
                    *p = target;
                }
            }
        }
        _ => unreachable!(),
    }
    out
}

#[test]
fn every_structure_equals_a_fresh_build_after_a_deformation() {
    let meshes = [
        ("sphere", common::bumpy_sphere(10, 3)),
        ("soup", common::random_soup(600, 4)),
    ];
    for (name, mesh) in meshes {
        for how in ["noise", "swirl", "collapse"] {
            for policy in [RefitPolicy::Refit, RefitPolicy::default(), RefitPolicy::Rebuild] {
                let config = IndexConfig {
                    refit: policy,
                    ..Default::default()
                };
                let mut index = MeshIndex::with_config(mesh.clone(), config);
                build_everything(&index);
                let positions = deform(&mesh, how, 7);
                let updated = index.update_vertices(&positions).unwrap();
                assert_eq!(index.mesh().positions(), &positions[..]);
                let names: Vec<&str> = updated.iter().map(|u| u.structure).collect();
                assert_eq!(names, index.built(), "{name} {how}: every structure built is updated");
                for u in &updated {
                    let tree = ["vertices", "edges", "faces", "polygons", "rays"].contains(&u.structure);
                    match policy {
                        RefitPolicy::Rebuild => assert!(u.rebuilt || !tree),
                        RefitPolicy::Refit if u.structure != "polygons" => assert!(!u.rebuilt, "{u:?}"),
                        _ => {}
                    }
                }
                assert_as_fresh(&index, &format!("{name} {how} {policy:?}"), 11);
            }
        }
    }
}

/// A hundred updates in a row, refit each time (never rebuilt), stay
/// equal to a fresh build; the surface-area cost grows with a random walk
/// and the policy's rebuild brings it back to 1.
#[test]
fn a_hundred_refits_in_a_row_stay_exact() {
    let mesh = common::bumpy_sphere(5, 9);
    let config = IndexConfig {
        refit: RefitPolicy::Refit,
        ..Default::default()
    };
    let mut index = MeshIndex::with_config(mesh.clone(), config);
    build_everything(&index);
    let mut rng = Rng::new(12);
    let mut positions = mesh.positions().to_vec();
    let mut last_ratio = 1.0;
    for step in 0..100 {
        for p in &mut positions {
            *p += Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.02;
        }
        let updated = index.update_vertices(&positions).unwrap();
        assert!(updated.iter().all(|u| !u.rebuilt));
        last_ratio = updated.iter().find(|u| u.structure == "faces").unwrap().cost_ratio;
        if step % 10 == 9 {
            assert_as_fresh(&index, &format!("step {step}"), step);
        }
    }
    // Vertices wander about 0.1 (a twentieth of the diameter) from where the tree was built.
    assert!(last_ratio > 1.05, "{last_ratio}");
}

/// The default policy rebuilds a wrecked tree and refits a slightly moved
/// one; `Refit` keeps the wrecked shape (its cost ratio says so), and its
/// answers are still exact.
#[test]
fn the_policy_rebuilds_past_its_ratio() {
    let mesh = common::bumpy_sphere(12, 5);
    let faces =
        |updated: &[proxima::index::Updated], name: &str| updated.iter().find(|u| u.structure == name).unwrap().clone();
    let mut index = MeshIndex::new(mesh.clone());
    build_everything(&index);
    let small = index.update_vertices(&deform(&mesh, "noise", 1)).unwrap();
    for name in ["faces", "rays", "vertices"] {
        let u = faces(&small, name);
        assert!(!u.rebuilt && u.cost_ratio < 1.2, "{u:?}");
    }
    let wrecked = index.update_vertices(&deform(&mesh, "swirl", 1)).unwrap();
    for name in ["faces", "rays", "edges"] {
        let u = faces(&wrecked, name);
        assert!(u.rebuilt && u.cost_ratio > RefitPolicy::DEFAULT_RATIO, "{u:?}");
    }
    // The cost at build is the rebuilt tree's from now on: moving back by a
    // swirl again is measured against it.
    let mut refit_only = MeshIndex::with_config(
        mesh.clone(),
        IndexConfig {
            refit: RefitPolicy::Refit,
            ..Default::default()
        },
    );
    build_everything(&refit_only);
    let kept = refit_only.update_vertices(&deform(&mesh, "swirl", 1)).unwrap();
    let u = faces(&kept, "faces");
    assert!(!u.rebuilt && u.cost_ratio > 2.0, "{u:?}");
    assert_as_fresh(&refit_only, "kept swirl", 3);
}

/// Polygons that stop being planar are split by the extraction: another
/// set of primitives, which the polygons' tree is rebuilt for, under any
/// policy.
#[test]
fn polygons_that_bend_are_rebuilt() {
    let n = 12;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(Vec3::new(i as f32, j as f32, 0.0));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let faces: Vec<Vec<u32>> = (0..n)
        .flat_map(|j| (0..n).map(move |i| vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]))
        .collect();
    let mesh = Mesh::from_faces(positions.clone(), &faces).unwrap();
    let config = IndexConfig {
        refit: RefitPolicy::Refit,
        ..Default::default()
    };
    let mut index = MeshIndex::with_config(mesh, config);
    build_everything(&index);
    // Every other vertex lifted: no quad is planar any more.
    let bent: Vec<Vec3> = positions
        .iter()
        .enumerate()
        .map(|(k, p)| *p + Vec3::Z * (k % 2) as f32 * 0.7)
        .collect();
    let updated = index.update_vertices(&bent).unwrap();
    let polygons = updated.iter().find(|u| u.structure == "polygons").unwrap();
    assert!(polygons.rebuilt && polygons.cost_ratio.is_nan(), "{polygons:?}");
    assert!(!updated.iter().find(|u| u.structure == "faces").unwrap().rebuilt);
    assert_as_fresh(&index, "bent quads", 5);
}

/// Positions of the wrong count, not finite or too large are refused with
/// the error that names them, and the index is as it was: the same mesh,
/// the same structures, the same answers.
#[test]
fn bad_positions_change_nothing() {
    let mesh = common::bumpy_sphere(4, 2);
    let mut index = MeshIndex::new(mesh.clone());
    build_everything(&index);
    let points = queries(&mesh, 3);
    let before = index.closest(PrimitiveKind::Faces, &points).unwrap();
    let built = index.built();
    let n = mesh.vertex_count();
    let mut cases: Vec<(Vec<Vec3>, IndexError)> = vec![
        (
            vec![Vec3::ZERO; n - 1],
            MeshError::VertexCount {
                count: n - 1,
                vertices: n,
            }
            .into(),
        ),
        (Vec::new(), MeshError::VertexCount { count: 0, vertices: n }.into()),
    ];
    for (k, bad) in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY].into_iter().enumerate() {
        let mut positions = mesh.positions().to_vec();
        positions[5 + k][k] = bad;
        cases.push((positions, MeshError::NonFiniteVertex { index: 5 + k }.into()));
    }
    let mut huge = mesh.positions().to_vec();
    huge[7].y = -2e18;
    cases.push((
        huge,
        IndexError::PositionTooLarge {
            vertex: 7,
            bound: proxima::build::MAX_COORDINATE,
        },
    ));
    for (positions, expected) in cases {
        let error = index.update_vertices(&positions).unwrap_err();
        assert_eq!(error, expected);
        assert!(error.to_string().contains("vert"), "{error}");
        assert_eq!(index.mesh().positions(), mesh.positions());
        assert_eq!(index.built(), built);
        assert_eq!(index.closest(PrimitiveKind::Faces, &points).unwrap(), before);
    }
}

/// The trees refuse a set that is not theirs, moved, and stay as they were.
#[test]
fn trees_refuse_another_set() {
    let mesh = common::bumpy_sphere(4, 6);
    let other = common::bumpy_sphere(5, 6);
    let mut wide = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    let mut rays = RayTree::build(&mesh).unwrap();
    let mut aabb = AabbTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    let p = Vec3::new(0.1, 0.7, 0.2);
    let before = (wide.closest(p), aabb.closest(p));
    let count = BuildError::RefitMismatch {
        primitives: other.triangle_count(),
        tree: mesh.triangle_count(),
        slot: None,
    };
    assert_eq!(wide.refit(&other.triangles()), Err(count.clone()));
    assert_eq!(aabb.refit(&other.triangles()), Err(count.clone()));
    assert_eq!(rays.refit(&other.triangles()), Err(count));
    // The same count, sources shuffled.
    let mut shuffled = mesh.triangles();
    shuffled.sources.swap(3, 40);
    assert!(matches!(
        wide.refit(&shuffled),
        Err(BuildError::RefitMismatch { slot: Some(_), .. })
    ));
    let mut nan = mesh.triangles();
    nan.primitives[9].b.x = f32::NAN;
    assert_eq!(wide.refit(&nan), Err(BuildError::NonFinite { index: 9 }));
    assert_eq!(rays.refit(&nan), Err(BuildError::NonFinite { index: 9 }));
    assert_eq!((wide.closest(p), aabb.closest(p)), before);
}

/// Wide trees without AVX2's merged leaves, and trees of points and
/// segments, refit to the fresh build's answers; the binary tree under a
/// refit wide tree keeps its invariants.
#[test]
fn every_layout_refits() {
    let mesh = common::bumpy_sphere(8, 8);
    let mut moved = mesh.clone();
    moved.set_positions(&deform(&mesh, "swirl", 2)).unwrap();
    let tree = AabbTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    let mut portable = WideTree::from_tree_portable(tree);
    portable.refit(&moved.triangles()).unwrap();
    portable.tree().validate().unwrap();
    let fresh = WideTree::build_set(moved.triangles(), &Default::default()).unwrap();
    let points = queries(&moved, 4);
    assert_eq!(portable.closest_batch(&points), fresh.closest_batch(&points));
    let mut vertices = WideTree::build_set(mesh.vertices(), &Default::default()).unwrap();
    vertices.refit(&moved.vertices()).unwrap();
    let fresh = WideTree::build_set(moved.vertices(), &Default::default()).unwrap();
    assert_eq!(vertices.closest_batch(&points), fresh.closest_batch(&points));
    assert_eq!(vertices.k_nearest_batch(&points, 7), fresh.k_nearest_batch(&points, 7));
}

/// The shared meshes, waved as the viewer's demo waves the bunny: every
/// structure answers as a fresh build.
#[test]
fn shared_meshes_refit_exactly() {
    for path in common::shared_meshes().into_iter().take(4) {
        let mesh = proxima::io::load(&path).unwrap();
        if mesh.triangle_count() > 200_000 {
            continue;
        }
        let b = mesh.bounds();
        let wave: Vec<Vec3> = mesh
            .positions()
            .iter()
            .map(|p| *p + Vec3::Y * 0.05 * b.diagonal() * (6.0 * (p.x - b.min.x) / b.diagonal()).sin())
            .collect();
        let mut index = MeshIndex::new(mesh);
        build_everything(&index);
        index.update_vertices(&wave).unwrap();
        assert_as_fresh(&index, &path.display().to_string(), 21);
    }
}
