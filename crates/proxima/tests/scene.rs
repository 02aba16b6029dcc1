//! Scenes of rigid instances against brute force over every instance's
//! triangles: closest points in `f64` (the query carried into each mesh's
//! frame exactly, distances kept by a rigid pose), first hits by a
//! ray-triangle test in `f64` on the placed triangles, and the union's side
//! by the exact winding sums. A moved instance answers as a scene built
//! with the new pose, a deformed mesh as a scene built over the moved
//! vertices; bad input is refused and changes nothing.

use crate::common;

use crate::common::oracle::{segment_distance, triangle_distance};
use proxima::index::MeshIndex;
use proxima::pair::RigidPose;
use proxima::prelude::*;
use proxima::sample::Rng;
use proxima::scene::{Scene, SceneError};
use proxima::sdf::{Sign, winding_number_exact};
use proxima::{DVec3, RayError};
use std::sync::Arc;

/// Triangles of the soup, the one open mesh of the scenes.
const SOUP: usize = 80;

fn random_pose(rng: &mut Rng, spread: f32) -> RigidPose {
    let q = [rng.gaussian(), rng.gaussian(), rng.gaussian(), rng.gaussian()];
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let t = [0, 1, 2].map(|_| rng.range(-spread, spread) as f64);
    RigidPose::from_quaternion(q.map(|x| x / n), t).unwrap()
}

/// Three meshes (two closed spheres of different sizes, an open soup),
/// placed `count` times at random, overlapping here and there.
fn scene(count: usize, seed: u64) -> (Scene, Vec<Arc<MeshIndex>>) {
    scene_of(count, seed, common::random_soup(SOUP, 3))
}

/// `count` instances of two spheres and `third`.
fn scene_of(count: usize, seed: u64, third: Mesh) -> (Scene, Vec<Arc<MeshIndex>>) {
    let meshes = vec![
        Arc::new(MeshIndex::new(common::bumpy_sphere(6, 1))),
        Arc::new(MeshIndex::new(common::bumpy_sphere(3, 2))),
        Arc::new(MeshIndex::new(third)),
    ];
    let mut rng = Rng::new(seed);
    let instances = (0..count)
        .map(|k| (meshes[k % 3].clone(), random_pose(&mut rng, 4.0)))
        .collect();
    (Scene::new(instances).unwrap(), meshes)
}

/// The distance from world `p` to every triangle of every instance, in
/// `f64`: `p` carried into the mesh's frame exactly (no rounding to f32).
fn brute_distances(scene: &Scene, p: Vec3) -> Vec<(f64, u32, u32)> {
    let mut out = Vec::new();
    for (i, instance) in scene.instances().iter().enumerate() {
        let local = instance.pose().inverse().apply(p);
        for (k, t) in instance.mesh().mesh().triangles().primitives.iter().enumerate() {
            out.push((triangle_distance(t, local.to_array()), i as u32, k as u32));
        }
    }
    out
}

/// The first hit of a world ray on the placed triangles, in `f64`
/// (Möller–Trumbore, edges closed with a margin of 1e-9 in the barycentric
/// coordinates, so that a ray through a vertex is not lost to the rounding
/// of `u + v`), with its instance and triangle.
fn brute_first_hit(scene: &Scene, o: Vec3, d: Vec3) -> Option<(f64, u32, u32)> {
    let (o, d) = (o.as_dvec3(), d.as_dvec3());
    let mut best: Option<(f64, u32, u32)> = None;
    for (i, instance) in scene.instances().iter().enumerate() {
        for (k, t) in instance.mesh().mesh().triangles().primitives.iter().enumerate() {
            let [a, b, c] = [t.a, t.b, t.c].map(|v| instance.pose().apply(v));
            let (e1, e2) = (b - a, c - a);
            let h = d.cross(e2);
            let det = e1.dot(h);
            if det.abs() < 1e-300 {
                continue;
            }
            let s = o - a;
            let u = s.dot(h) / det;
            let q = s.cross(e1);
            let v = d.dot(q) / det;
            let tt = e2.dot(q) / det;
            if u >= -1e-9 && v >= -1e-9 && u + v <= 1.0 + 1e-9 && tt >= 0.0 && best.is_none_or(|b| tt < b.0) {
                best = Some((tt, i as u32, k as u32));
            }
        }
    }
    best
}

#[test]
fn closest_points_equal_brute_force() {
    let (scene, _) = scene(30, 5);
    let b = scene.bounds();
    let mut points = proxima::sample::uniform_in(&b, 300, 7);
    // Near and on placed vertices.
    let mut rng = Rng::new(8);
    for k in 0..100 {
        let instance = &scene.instances()[k % scene.len()];
        let v = instance.mesh().mesh().positions()[rng.below(instance.mesh().mesh().vertex_count())];
        let offset =
            Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.01 * (k % 2) as f32;
        points.push(instance.pose().apply(v).as_vec3() + offset);
    }
    let batch = scene.closest_batch(&points);
    for (p, hit) in points.iter().zip(&batch) {
        let hit = hit.unwrap();
        assert_eq!(Some(hit), scene.closest(*p));
        let all = brute_distances(&scene, *p);
        let best = all.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
        let tolerance = 1e-5 * (1.0 + p.abs().max_element() as f64);
        assert!(
            (hit.distance as f64 - best).abs() <= tolerance,
            "{p}: {} vs {best}",
            hit.distance
        );
        // The reported triangle is at that distance, and the point on it.
        let reported = all.iter().find(|x| (x.1, x.2) == (hit.instance, hit.triangle)).unwrap();
        assert!(
            (reported.0 - best).abs() <= tolerance,
            "{p}: reported {reported:?}, best {best}"
        );
        assert!(((hit.point - p.as_dvec3()).length() - best).abs() <= tolerance);
        let face = scene.instances()[hit.instance as usize]
            .mesh()
            .mesh()
            .triangles()
            .sources[hit.triangle as usize];
        assert_eq!(hit.face, face);
    }
}

#[test]
fn first_hits_equal_brute_force() {
    let (scene, _) = scene(24, 9);
    let b = scene.bounds();
    let mut rays = proxima::sample::rays_at_box(&b, 400, 10);
    // Rays aimed at placed vertices (where triangles of one instance meet).
    let mut rng = Rng::new(11);
    for k in 0..100 {
        let instance = &scene.instances()[k % scene.len()];
        let v = instance
            .pose()
            .apply(instance.mesh().mesh().positions()[rng.below(instance.mesh().mesh().vertex_count())])
            .as_vec3();
        let d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X);
        rays.push((v - d * 20.0, d));
    }
    let batch = scene.first_hit_batch(&rays, 0.0, f32::INFINITY);
    let any = scene.any_hit_batch(&rays, 0.0, f32::INFINITY);
    let (mut hits, mut checked, mut grazing) = (0, 0, 0);
    for (k, &(o, d)) in rays.iter().enumerate() {
        let hit = batch[k].unwrap();
        assert_eq!(hit, scene.first_hit(o, d, 0.0, f32::INFINITY).unwrap());
        assert_eq!(any[k].unwrap(), hit.is_some());
        let brute = brute_first_hit(&scene, o, d);
        let length = d.length() as f64;
        match (hit, brute) {
            (Some(h), Some((t, i, tri))) => {
                hits += 1;
                let tolerance = 1e-5 * (1.0 + o.abs().max_element() as f64) / length;
                // Later than the exact first hit only where that one is on
                // a triangle's boundary; earlier only where the ray grazes
                // the reported triangle, within rounding.
                if h.t as f64 > t + tolerance {
                    assert_on_boundary(&scene, (t, i, tri), o, d, k);
                    grazing += 1;
                    continue;
                }
                if (h.t as f64 - t).abs() > tolerance {
                    assert_grazes(&scene, &h, o, d, tolerance, k);
                    grazing += 1;
                    continue;
                }
                if (h.instance, h.triangle) != (i, tri) {
                    // Only where two triangles are hit at the same t (shared edges,
                    // touching instances).
                    let second = brute_first_hit_of(&scene, o, d, h.instance, h.triangle);
                    assert!(
                        (second - t).abs() <= tolerance,
                        "ray {k}: {:?} vs {:?}",
                        (h.instance, h.triangle),
                        (i, tri)
                    );
                }
                checked += 1;
            }
            (None, None) => {}
            // A ray grazing an edge may hit in one arithmetic and not the other.
            (Some(h), None) => {
                hits += 1;
                let tolerance = 1e-5 * (1.0 + o.abs().max_element() as f64) / length;
                assert_grazes(&scene, &h, o, d, tolerance, k);
                grazing += 1;
            }
            (None, Some(b)) => {
                assert_on_boundary(&scene, b, o, d, k);
                grazing += 1;
            }
        }
    }
    assert!(
        hits > 150 && checked + grazing >= hits && grazing < 30,
        "{hits} hits, {grazing} grazing"
    );
}

/// A hit that exact arithmetic does not find first: the ray passes within
/// `tolerance` of the reported triangle (placed in `f64`) at the reported
/// point, which lies on the ray at `t`: the query's rounding into the
/// mesh's frame moved the ray by that much.
fn assert_grazes(scene: &Scene, h: &proxima::scene::SceneRayHit, o: Vec3, d: Vec3, tolerance: f64, k: usize) {
    let instance = &scene.instances()[h.instance as usize];
    let t = instance.mesh().mesh().triangles().primitives[h.triangle as usize];
    let local = instance.pose().inverse().apply_f64(h.point);
    assert!(
        triangle_distance(&t, local.to_array()) <= tolerance,
        "ray {k}: the hit point is off its triangle"
    );
    let on_ray = o.as_dvec3() + d.as_dvec3() * h.t as f64;
    assert!(
        (on_ray - h.point).length() <= tolerance * 10.0,
        "ray {k}: the hit point is off the ray"
    );
}

/// An exact hit `(t, instance, triangle)` that lies on the triangle's
/// boundary within rounding: a ray through a vertex or an edge, which the
/// query's rounding into the mesh's frame may move off it.
fn assert_on_boundary(scene: &Scene, (t, i, tri): (f64, u32, u32), o: Vec3, d: Vec3, k: usize) {
    let instance = &scene.instances()[i as usize];
    let triangle = instance.mesh().mesh().triangles().primitives[tri as usize];
    let at = instance
        .pose()
        .inverse()
        .apply_f64(o.as_dvec3() + d.as_dvec3() * t)
        .to_array();
    let [a, b, c] = [triangle.a, triangle.b, triangle.c].map(common::oracle::d3);
    let edge = segment_distance(a, b, at)
        .min(segment_distance(b, c, at))
        .min(segment_distance(c, a, at));
    let tolerance = 1e-5 * (1.0 + o.abs().max_element() as f64);
    assert!(
        edge <= tolerance,
        "ray {k}: brute force hits {:?} {edge} from its edges",
        (t, i, tri)
    );
}

/// The `t` at which the ray hits one given placed triangle, in `f64`.
fn brute_first_hit_of(scene: &Scene, o: Vec3, d: Vec3, instance: u32, triangle: u32) -> f64 {
    let inst = &scene.instances()[instance as usize];
    let t = inst.mesh().mesh().triangles().primitives[triangle as usize];
    let [a, b, c] = [t.a, t.b, t.c].map(|v| inst.pose().apply(v));
    let (o, d) = (o.as_dvec3(), d.as_dvec3());
    let n = (b - a).cross(c - a);
    (a - o).dot(n) / d.dot(n)
}

/// Inside any instance is inside the scene, by each instance's own sign:
/// on closed meshes (two spheres and a cube-ish third), both signs agree
/// with the exact winding sums wherever those are clear of ½.
#[test]
fn the_sign_is_the_unions() {
    let (scene, _) = scene_of(18, 12, common::bumpy_sphere(2, 9));
    let points = proxima::sample::uniform_in(&scene.bounds(), 600, 13);
    let (mut inside, mut outside) = (0, 0);
    for sign in [Sign::WindingNumber, Sign::Pseudonormal] {
        let batch = scene.signed_distance_batch(&points, sign);
        for (p, s) in points.iter().zip(&batch) {
            let s = s.unwrap();
            assert_eq!(s.closest, scene.closest(*p).unwrap());
            let mut clear = true;
            let mut expected = false;
            for instance in scene.instances() {
                let local = instance.pose().inverse().apply(*p).as_vec3();
                let w = winding_number_exact(&instance.mesh().mesh().triangles().primitives, local);
                clear &= (w - 0.5).abs() > 0.01;
                expected |= w > 0.5;
            }
            if clear && s.closest.distance > 1e-4 {
                assert_eq!(s.distance < 0.0, expected, "{p} {sign:?}");
                assert_eq!(scene.contains(*p, sign), expected);
                if expected { inside += 1 } else { outside += 1 }
            }
        }
    }
    assert!(inside > 20 && outside > 200, "{inside} inside, {outside} outside");
}

#[test]
fn a_moved_instance_answers_as_a_new_scene() {
    let (mut scene, meshes) = scene(40, 14);
    let mut rng = Rng::new(15);
    for step in 0..60 {
        let i = rng.below(scene.len());
        // Far away now and then, so that the top level is worn and rebuilt.
        let pose = random_pose(&mut rng, if step % 7 == 0 { 40.0 } else { 4.0 });
        scene.set_pose(i, pose).unwrap();
    }
    let poses: Vec<_> = scene
        .instances()
        .iter()
        .enumerate()
        .map(|(k, i)| (meshes[k % 3].clone(), *i.pose()))
        .collect();
    let fresh = Scene::new(poses).unwrap();
    assert_answers_as(&scene, &fresh, 16);
    // The same mesh placed many times built its trees once, shared.
    assert!(Arc::ptr_eq(scene.instances()[0].mesh(), scene.instances()[3].mesh()));
    assert!(meshes[0].built().contains(&"faces") && meshes[0].built().contains(&"rays"));
}

/// `positions` moved: by noise of `noise` everywhere, and swirled about
/// the y axis by an angle growing with height (wrecking a refit tree).
fn deformed(positions: &[Vec3], noise: f32, swirl: f32, rng: &mut Rng) -> Vec<Vec3> {
    positions
        .iter()
        .map(|&p| {
            let (s, c) = (p.y * swirl).sin_cos();
            let turned = Vec3::new(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
            turned + Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * noise
        })
        .collect()
}

/// A scene of the same instances built anew: each instance's mesh as it
/// is now, in an index of its own.
fn rebuilt(scene: &Scene) -> Scene {
    Scene::new(
        scene
            .instances()
            .iter()
            .map(|i| (Arc::new(MeshIndex::new(i.mesh().mesh().clone())), *i.pose()))
            .collect(),
    )
    .unwrap()
}

/// Every query of `scene` equals `fresh`'s, and the closest points brute
/// force's.
fn assert_answers_as(scene: &Scene, fresh: &Scene, seed: u64) {
    let points = proxima::sample::uniform_in(&fresh.bounds(), 150, seed);
    let rays = proxima::sample::rays_at_box(&fresh.bounds(), 150, seed + 1);
    // (The world boxes may differ: they are made from the top of each
    // mesh's tree, refit or built anew.)
    assert_eq!(scene.closest_batch(&points), fresh.closest_batch(&points));
    assert_eq!(
        scene.first_hit_batch(&rays, 0.0, f32::INFINITY),
        fresh.first_hit_batch(&rays, 0.0, f32::INFINITY)
    );
    assert_eq!(
        scene.signed_distance_batch(&points, Sign::WindingNumber),
        fresh.signed_distance_batch(&points, Sign::WindingNumber)
    );
    for p in &points[..30] {
        let best = brute_distances(scene, *p)
            .iter()
            .map(|x| x.0)
            .fold(f64::INFINITY, f64::min);
        let hit = scene.closest(*p).unwrap();
        assert!((hit.distance as f64 - best).abs() <= 1e-5 * (1.0 + p.abs().max_element() as f64));
    }
}

/// A mesh deformed inside a scene moves every instance of it, and the
/// scene answers as one built anew over the moved vertices: first on a
/// copy of the scene's own while the caller still holds the mesh (which
/// stays as it was), then, once the scene holds the only references, by
/// refitting the mesh's structures in place, 30 times over, with swirls
/// that wear the trees and collapses of the noise to nothing.
#[test]
fn a_deformed_mesh_answers_as_a_new_scene() {
    let (mut scene, meshes) = scene(12, 21);
    let mut rng = Rng::new(22);
    let points = proxima::sample::uniform_in(&scene.bounds(), 50, 23);
    scene.closest_batch(&points); // the structures built
    let rest = meshes[0].mesh().positions().to_vec();
    let report = scene.update_vertices(3, &deformed(&rest, 0.02, 0.3, &mut rng)).unwrap();
    assert!(report.is_empty(), "a copy has nothing built to update: {report:?}");
    assert_eq!(
        meshes[0].mesh().positions(),
        &rest[..],
        "the caller's mesh is untouched"
    );
    assert!(!Arc::ptr_eq(scene.instances()[0].mesh(), &meshes[0]));
    assert!(Arc::ptr_eq(scene.instances()[0].mesh(), scene.instances()[3].mesh()));
    assert_answers_as(&scene, &rebuilt(&scene), 24);
    drop(meshes);
    for step in 0..30 {
        let i = rng.below(scene.len());
        let at = scene.instances()[i].mesh().mesh().positions().to_vec();
        let (noise, swirl) = match step % 3 {
            0 => (0.0, 0.0),
            1 => (0.01, 0.0),
            _ => (0.005, 0.8),
        };
        let report = scene
            .update_vertices(i, &deformed(&at, noise, swirl, &mut rng))
            .unwrap();
        // Unshared now: the structures built are refit or rebuilt in place.
        assert!(report.iter().any(|u| u.structure == "faces"), "{report:?}");
        if step % 6 == 5 {
            assert_answers_as(&scene, &rebuilt(&scene), 25 + step as u64);
        }
    }
}

/// A deformation that cannot be taken changes nothing: the answers, the
/// meshes and their sharing stay as they were.
#[test]
fn a_refused_deformation_changes_nothing() {
    let (mut scene, meshes) = scene(6, 31);
    let points = proxima::sample::uniform_in(&scene.bounds(), 100, 32);
    let before = scene.closest_batch(&points);
    let n = meshes[1].mesh().vertex_count();
    let mut far = meshes[1].mesh().positions().to_vec();
    far[0] = Vec3::new(1e30, 0.0, 0.0);
    let mut nan = meshes[1].mesh().positions().to_vec();
    nan[n - 1] = Vec3::NAN;
    for (index, positions) in [
        (1, vec![Vec3::ZERO; n - 1]),
        (1, nan),
        (1, far),
        (6, meshes[1].mesh().positions().to_vec()),
    ] {
        let e = scene.update_vertices(index, &positions).unwrap_err();
        match index {
            6 => assert_eq!(e, SceneError::InstanceOutOfRange { index: 6, count: 6 }),
            _ => assert!(
                matches!(e, SceneError::Mesh { instance: 1, .. } | SceneError::Placement(_)),
                "{e}"
            ),
        }
        assert_eq!(scene.closest_batch(&points), before);
        assert!(Arc::ptr_eq(scene.instances()[1].mesh(), &meshes[1]));
        assert!(Arc::ptr_eq(scene.instances()[4].mesh(), &meshes[1]));
    }
}

#[test]
fn bad_input_is_refused_and_changes_nothing() {
    let points_only = Arc::new(MeshIndex::new(
        Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[]).unwrap(),
    ));
    let sphere = Arc::new(MeshIndex::new(common::bumpy_sphere(3, 1)));
    let identity = RigidPose::IDENTITY;
    let e = Scene::new(vec![(sphere.clone(), identity), (points_only, identity)])
        .err()
        .unwrap();
    assert!(matches!(e, SceneError::Mesh { instance: 1, .. }), "{e}");
    assert!(e.to_string().starts_with("instance 1: the mesh has no faces"), "{e}");
    let mut scene = Scene::new(vec![(sphere.clone(), identity)]).unwrap();
    let p = Vec3::new(0.3, 2.0, 0.1);
    let before = scene.closest(p);
    assert_eq!(
        scene.set_pose(1, identity),
        Err(SceneError::InstanceOutOfRange { index: 1, count: 1 })
    );
    let far = RigidPose::translation_only(DVec3::new(3e18, 0.0, 0.0)).unwrap();
    assert!(matches!(scene.set_pose(0, far), Err(SceneError::Placement(_))));
    assert_eq!(scene.closest(p), before);
    // Mirrors are not rigid poses.
    let mirror = [
        [-1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    assert!(RigidPose::from_rows(mirror).is_err());
    // Queries that are not ones.
    assert_eq!(scene.closest(Vec3::NAN), None);
    assert!(matches!(
        scene.first_hit(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0),
        Err(RayError::Direction)
    ));
    assert!(scene.first_hit(Vec3::NAN, Vec3::X, 0.0, 1.0).is_err());
    // An empty scene answers nothing.
    let empty = Scene::new(Vec::new()).unwrap();
    assert_eq!(empty.closest(p), None);
    assert_eq!(empty.first_hit(p, Vec3::X, 0.0, f32::INFINITY), Ok(None));
    assert!(!empty.contains(p, Sign::WindingNumber));
}

/// The `k` nearest faces equal brute force's: each face at its distance
/// (faces of these meshes are single triangles), the distances the `k`
/// smallest, nearest first; fewer than `k` where the scene has fewer.
#[test]
fn k_nearest_faces_equal_brute_force() {
    let (scene, _) = scene(12, 18);
    let points = proxima::sample::uniform_in(&scene.bounds(), 120, 19);
    for k in [1, 7, 40] {
        let batch = scene.k_nearest_batch(&points, k);
        for (p, hits) in points.iter().zip(&batch) {
            assert_eq!(hits, &scene.k_nearest(*p, k));
            let mut all = brute_distances(&scene, *p);
            all.sort_by(|a, b| a.0.total_cmp(&b.0));
            assert_eq!(hits.len(), k);
            let tolerance = 1e-5 * (1.0 + p.abs().max_element() as f64);
            for (j, hit) in hits.iter().enumerate() {
                assert!((hit.distance as f64 - all[j].0).abs() <= tolerance, "{p} k={k} #{j}");
                let own = all.iter().find(|x| (x.1, x.2) == (hit.instance, hit.triangle)).unwrap();
                assert!((own.0 - hit.distance as f64).abs() <= tolerance);
                if j > 0 {
                    assert!(hits[j - 1].distance <= hit.distance);
                }
            }
        }
    }
    let few = Scene::new(vec![(
        Arc::new(MeshIndex::new(common::bumpy_sphere(1, 1))),
        RigidPose::IDENTITY,
    )])
    .unwrap();
    assert_eq!(few.k_nearest(Vec3::ZERO, 1000).len(), 20);
    assert!(few.k_nearest(Vec3::ZERO, 0).is_empty() && few.k_nearest(Vec3::NAN, 3).is_empty());
}
