//! Queries between two placed meshes and within one, against brute force
//! over every pair of triangles placed by the same `RigidPose::apply`: the
//! exact intersection test decides the yes/no oracles, the triangle-pair
//! distance the distance oracles (both tested on their own, against exact
//! rationals, in the library's unit tests). What these tests check is that
//! the walk of two trees skips no pair that brute force counts.

use crate::common::{bumpy_sphere, data_dir, random_soup};
use proxima::pair::{
    self, PairError, RigidPose, intersecting_pairs, intersects, pairs_within, self_intersections, triangle_distance,
    triangles_intersect,
};
use proxima::sample::Rng;
use proxima::{DVec3, Mesh, MeshIndex, Vec3};

/// Every triangle of `mesh` placed by `pose`, its face, and its box.
fn placed(mesh: &Mesh, pose: &RigidPose) -> Vec<([DVec3; 3], u32, DVec3, DVec3)> {
    let set = mesh.triangles();
    set.primitives
        .iter()
        .zip(&set.sources)
        .map(|(t, &face)| {
            let c = [pose.apply(t.a), pose.apply(t.b), pose.apply(t.c)];
            (c, face, c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]))
        })
        .collect()
}

fn box_gap2(lo_a: DVec3, hi_a: DVec3, lo_b: DVec3, hi_b: DVec3) -> f64 {
    (lo_a - hi_b).max(lo_b - hi_a).max(DVec3::ZERO).length_squared()
}

/// Brute force: the face pairs that meet (exact test on every pair whose
/// boxes touch; disjoint boxes of exact coordinates cannot meet).
fn brute_meeting(a: &Mesh, pa: &RigidPose, b: &Mesh, pb: &RigidPose) -> Vec<[u32; 2]> {
    let (ta, tb) = (placed(a, pa), placed(b, pb));
    let mut out = Vec::new();
    for (ca, fa, la, ha) in &ta {
        for (cb, fb, lb, hb) in &tb {
            if box_gap2(*la, *ha, *lb, *hb) == 0.0 && triangles_intersect(ca, cb) {
                out.push([*fa, *fb]);
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Brute force: the smallest triangle-pair distance, over every pair.
fn brute_distance(a: &Mesh, pa: &RigidPose, b: &Mesh, pb: &RigidPose) -> f64 {
    let (ta, tb) = (placed(a, pa), placed(b, pb));
    let mut best = f64::INFINITY;
    for (ca, _, la, ha) in &ta {
        for (cb, _, lb, hb) in &tb {
            // A pair whose boxes lie farther apart than the best cannot be
            // nearer (slack for the rounding of both computations).
            if box_gap2(*la, *ha, *lb, *hb) <= best * best * (1.0 + 1e-9) {
                best = best.min(triangle_distance(ca, cb).distance);
            }
        }
    }
    best
}

/// Brute force: the face pairs within `d`.
fn brute_within(a: &Mesh, pa: &RigidPose, b: &Mesh, pb: &RigidPose, d: f64) -> Vec<[u32; 2]> {
    let (ta, tb) = (placed(a, pa), placed(b, pb));
    let mut out = Vec::new();
    for (ca, fa, la, ha) in &ta {
        for (cb, fb, lb, hb) in &tb {
            if box_gap2(*la, *ha, *lb, *hb) <= d * d * (1.0 + 1e-9) && triangle_distance(ca, cb).distance <= d {
                out.push([*fa, *fb]);
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Brute force: the face pairs of one mesh that meet beyond what they share.
fn brute_self(mesh: &Mesh) -> Vec<[u32; 2]> {
    let t = placed(mesh, &RigidPose::IDENTITY);
    let corners = mesh.triangle_vertex_indices();
    let mut out = Vec::new();
    for i in 0..t.len() {
        for j in i + 1..t.len() {
            let ((ci, fi, li, hi), (cj, fj, lj, hj)) = (&t[i], &t[j]);
            if fi == fj || box_gap2(*li, *hi, *lj, *hj) > 0.0 {
                continue;
            }
            let shares = corners[i].iter().any(|v| corners[j].contains(v));
            let meet = if shares {
                pair::triangle_intersection::neighbours_intersect(ci, corners[i], cj, corners[j])
            } else {
                triangles_intersect(ci, cj)
            };
            if meet {
                out.push([*fi.min(fj), *fi.max(fj)]);
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// A seeded rigid pose: a random rotation, a translation within `reach`.
fn random_pose(rng: &mut Rng, reach: f64) -> RigidPose {
    let q: [f64; 4] = std::array::from_fn(|_| f64::from(rng.range(-1.0, 1.0)));
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-3);
    let t: [f64; 3] = std::array::from_fn(|_| f64::from(rng.range(-1.0, 1.0)) * reach);
    RigidPose::from_quaternion(q.map(|v| v / n), t).unwrap()
}

fn scaled(mesh: &Mesh, s: f32) -> Mesh {
    let p = mesh.positions().iter().map(|&v| v * s).collect();
    let faces: Vec<Vec<u32>> = mesh.faces().map(|f| f.to_vec()).collect();
    Mesh::from_faces(p, &faces).unwrap()
}

/// Checks every query between `a` at `pa` and `b` at `pb` against brute force.
fn check_pair(a: &Mesh, pa: &RigidPose, b: &Mesh, pb: &RigidPose, margin: f64) {
    let (ia, ib) = (MeshIndex::new(a.clone()), MeshIndex::new(b.clone()));
    let meeting = brute_meeting(a, pa, b, pb);
    assert_eq!(intersecting_pairs(&ia, pa, &ib, pb).unwrap(), meeting);
    assert_eq!(intersects(&ia, pa, &ib, pb).unwrap(), !meeting.is_empty());
    let d = pair::distance(&ia, pa, &ib, pb).unwrap();
    let expected = brute_distance(a, pa, b, pb);
    assert_eq!(d.distance, expected, "distance");
    assert_eq!(d.distance == 0.0, !meeting.is_empty());
    // The witnesses: on their faces' triangles, as far apart as said.
    let ta = placed(a, pa)[d.triangle_a as usize];
    let tb = placed(b, pb)[d.triangle_b as usize];
    assert_eq!((ta.1, tb.1), (d.face_a, d.face_b));
    let at = |c: [DVec3; 3], w: [f64; 3]| c[0] * w[0] + c[1] * w[1] + c[2] * w[2];
    let scale = 1e-9 * (1.0 + ta.3.abs().max_element() + tb.3.abs().max_element());
    assert!((at(ta.0, d.barycentric_a) - d.point_a).length() <= scale);
    assert!((at(tb.0, d.barycentric_b) - d.point_b).length() <= scale);
    assert!(((d.point_a - d.point_b).length() - d.distance).abs() <= scale);
    assert_eq!(triangle_distance(&ta.0, &tb.0).distance, d.distance);
    // Clearance checks on both sides of the answer.
    if expected > 0.0 {
        assert_eq!(pair::distance_below(&ia, pa, &ib, pb, expected).unwrap(), None);
        assert_eq!(
            pair::distance_below(&ia, pa, &ib, pb, expected * 1.5)
                .unwrap()
                .map(|x| x.distance),
            Some(expected)
        );
    }
    assert_eq!(
        pairs_within(&ia, pa, &ib, pb, margin).unwrap(),
        brute_within(a, pa, b, pb, margin)
    );
}

#[test]
fn random_soups_at_every_scale_match_brute_force() {
    let mut rng = Rng::new(36);
    for (case, scale) in [1e-3f32, 1.0, 1e3].into_iter().enumerate() {
        for round in 0..4 {
            let a = scaled(&random_soup(150, 100 * case as u64 + round), scale);
            let b = scaled(&random_soup(120, 1000 + 100 * case as u64 + round), scale);
            let reach = f64::from(scale) * if round < 2 { 0.3 } else { 2.0 };
            let (pa, pb) = (random_pose(&mut rng, reach), random_pose(&mut rng, reach));
            check_pair(&a, &pa, &b, &pb, 0.02 * f64::from(scale));
            check_pair(&a, &RigidPose::IDENTITY, &b, &pb, 0.02 * f64::from(scale));
        }
    }
}

#[test]
fn closed_meshes_moved_against_each_other_match_brute_force() {
    let a = bumpy_sphere(6, 1);
    let b = bumpy_sphere(5, 2);
    let mut rng = Rng::new(7);
    for _ in 0..6 {
        let pose = random_pose(&mut rng, 2.5);
        check_pair(&a, &RigidPose::IDENTITY, &b, &pose, 0.05);
    }
}

/// An axis-aligned box of 12 triangles, corners at dyadic coordinates.
fn cube(lo: f32, hi: f32) -> Mesh {
    let p: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new([lo, hi][i & 1], [lo, hi][(i >> 1) & 1], [lo, hi][(i >> 2) & 1]))
        .collect();
    let faces = [
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    Mesh::from_triangles(p, &faces).unwrap()
}

#[test]
fn touching_exactly_and_apart_by_one_ulp() {
    let a = cube(-0.5, 0.75);
    let (ia, ib) = (MeshIndex::new(a.clone()), MeshIndex::new(a.clone()));
    let width = 1.25f64;
    for (shift, meet) in [(width, true), (width.next_down(), true), (width.next_up(), false)] {
        for axis in 0..3 {
            let mut t = DVec3::ZERO;
            t[axis] = shift;
            let pose = RigidPose::translation_only(t).unwrap();
            assert_eq!(
                intersects(&ia, &RigidPose::IDENTITY, &ib, &pose).unwrap(),
                meet,
                "shift {shift:e} axis {axis}"
            );
            assert_eq!(!brute_meeting(&a, &RigidPose::IDENTITY, &a, &pose).is_empty(), meet);
            check_pair(&a, &RigidPose::IDENTITY, &a, &pose, 1e-3);
        }
    }
    // Rotated a quarter turn about z through its centre: the same box, so
    // every face meets its copy (coplanar overlaps, shared edges).
    let q = std::f64::consts::FRAC_1_SQRT_2;
    let centre = 0.125;
    let turn = RigidPose::from_quaternion([0.0, 0.0, q, q], [2.0 * centre, 0.0, 0.0]).unwrap();
    check_pair(&a, &RigidPose::IDENTITY, &a, &turn, 1e-3);
}

#[test]
fn a_mesh_inside_another_does_not_meet_it() {
    let outer = bumpy_sphere(4, 3);
    let inner = scaled(&bumpy_sphere(3, 4), 0.3);
    let (io, ii) = (MeshIndex::new(outer.clone()), MeshIndex::new(inner.clone()));
    assert!(!intersects(&io, &RigidPose::IDENTITY, &ii, &RigidPose::IDENTITY).unwrap());
    let d = pair::distance(&io, &RigidPose::IDENTITY, &ii, &RigidPose::IDENTITY).unwrap();
    assert!(d.distance > 0.3, "{}", d.distance);
    assert_eq!(
        d.distance,
        brute_distance(&outer, &RigidPose::IDENTITY, &inner, &RigidPose::IDENTITY)
    );
}

#[test]
fn batches_answer_as_one_pose_at_a_time_in_order() {
    let (a, b) = (bumpy_sphere(4, 5), bumpy_sphere(3, 6));
    let (ia, ib) = (MeshIndex::new(a), MeshIndex::new(b));
    let mut rng = Rng::new(11);
    let poses: Vec<RigidPose> = (0..40).map(|_| random_pose(&mut rng, 3.0)).collect();
    let distances = pair::distance_batch(&ia, &ib, &poses).unwrap();
    let hits = pair::intersects_batch(&ia, &ib, &poses).unwrap();
    for (i, pose) in poses.iter().enumerate() {
        assert_eq!(
            distances[i],
            pair::distance(&ia, &RigidPose::IDENTITY, &ib, pose).unwrap()
        );
        assert_eq!(hits[i], intersects(&ia, &RigidPose::IDENTITY, &ib, pose).unwrap());
    }
    assert!(hits.iter().any(|&h| h) && hits.iter().any(|&h| !h), "{hits:?}");
    // Clearance over the batch: exactly the poses nearer than the bound.
    let bound = 0.3;
    let below = pair::distance_below_batch(&ia, &ib, &poses, bound).unwrap();
    for (i, pose) in poses.iter().enumerate() {
        assert_eq!(
            below[i],
            pair::distance_below(&ia, &RigidPose::IDENTITY, &ib, pose, bound).unwrap()
        );
        assert_eq!(below[i].is_some(), distances[i].distance < bound);
    }
    assert!(below.iter().any(Option::is_some) && below.iter().any(Option::is_none));
}

#[test]
fn self_intersections_match_brute_force() {
    // Closed and embedded: none.
    let sphere = bumpy_sphere(6, 8);
    assert_eq!(
        self_intersections(&MeshIndex::new(sphere.clone())).unwrap(),
        brute_self(&sphere)
    );
    assert!(brute_self(&sphere).is_empty());
    // Two overlapping spheres in one mesh: the crossing faces.
    let (s1, s2) = (bumpy_sphere(5, 9), bumpy_sphere(5, 10));
    let mut p: Vec<Vec3> = s1.positions().to_vec();
    let base = p.len() as u32;
    p.extend(s2.positions().iter().map(|&v| v + Vec3::new(0.7, 0.1, 0.0)));
    let mut faces: Vec<Vec<u32>> = s1.faces().map(|f| f.to_vec()).collect();
    faces.extend(s2.faces().map(|f| f.iter().map(|&i| i + base).collect()));
    let union = Mesh::from_faces(p, &faces).unwrap();
    let found = self_intersections(&MeshIndex::new(union.clone())).unwrap();
    assert!(!found.is_empty());
    assert_eq!(found, brute_self(&union));
    // Random soups (degenerate triangles included).
    for seed in 0..4 {
        let soup = random_soup(300, 50 + seed);
        assert_eq!(
            self_intersections(&MeshIndex::new(soup.clone())).unwrap(),
            brute_self(&soup)
        );
    }
}

#[test]
fn folded_neighbours_are_reported_and_hinged_ones_are_not() {
    // A strip of two triangles sharing the edge 0-1, at a dihedral angle:
    // they meet only along the shared edge, so no pair.
    let hinge = Mesh::from_triangles(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.5, 0.0, 1.0)],
        &[[0, 1, 2], [1, 0, 3]],
    )
    .unwrap();
    assert!(self_intersections(&MeshIndex::new(hinge.clone())).unwrap().is_empty());
    assert_eq!(brute_self(&hinge), Vec::<[u32; 2]>::new());
    // Folded flat onto each other (the second apex on the first's side): reported.
    let folded = Mesh::from_triangles(
        vec![Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1.0, 0.0), Vec3::new(0.25, 0.5, 0.0)],
        &[[0, 1, 2], [1, 0, 3]],
    )
    .unwrap();
    assert_eq!(self_intersections(&MeshIndex::new(folded)).unwrap(), [[0, 1]]);
    // A fan around vertex 0 whose second face crosses the first beyond it.
    let crossing = Mesh::from_triangles(
        vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
        ],
        &[[0, 1, 2], [0, 3, 4]],
    )
    .unwrap();
    assert_eq!(self_intersections(&MeshIndex::new(crossing.clone())).unwrap(), [[0, 1]]);
    assert_eq!(brute_self(&crossing), [[0, 1]]);
}

/// A fan of `k` triangles around vertex 0 (closed, or open when `open`),
/// built to probe the fan certificate of `self_intersections`: ring points
/// at the given angles and heights, the apex nudged by a few ulps.
fn fan_mesh(angles: &[f32], heights: &[f32], apex: Vec3, open: bool, fin: Option<[Vec3; 2]>) -> Mesh {
    let k = angles.len() as u32;
    let mut p = vec![apex];
    p.extend(
        angles
            .iter()
            .zip(heights)
            .map(|(&a, &h)| Vec3::new(a.cos(), a.sin(), h)),
    );
    let mut tris: Vec<[u32; 3]> = (0..k).map(|i| [0, 1 + i, 1 + (i + 1) % k]).collect();
    if open {
        tris.pop();
    }
    if let Some([x, y]) = fin {
        p.extend([x, y]);
        tris.push([0, k + 1, k + 2]);
    }
    Mesh::from_triangles(p, &tris).unwrap()
}

#[test]
fn fans_flat_folded_and_within_ulps_of_flat_match_brute_force() {
    // Every face pair of these fans shares the apex: the certificate alone
    // settles them, or the exact neighbour test does. Brute force runs the
    // neighbour test on all of them.
    let mut rng = Rng::new(41);
    let ulps = |x: f32, n: i32| {
        let mut x = x;
        for _ in 0..n.unsigned_abs() {
            x = if n > 0 { x.next_up() } else { x.next_down() };
        }
        x
    };
    let (mut with_pairs, mut without) = (0, 0);
    for case in 0..600 {
        let k = 3 + rng.below(8);
        let step = std::f32::consts::TAU / k as f32;
        let angles: Vec<f32> = (0..k)
            .map(|i| match case % 4 {
                // Going around twice (k odd: a star), or once.
                0 if k % 2 == 1 => 2.0 * step * i as f32,
                // One ring point pulled back past its neighbour: a fold.
                1 if i == 1 => -0.2 * step,
                _ => step * (i as f32 + rng.range(-0.3, 0.3)),
            })
            .collect();
        let heights: Vec<f32> = (0..k)
            .map(|_| match (case / 4) % 3 {
                // Flat, within a few ulps of flat, or bumpy.
                0 => 0.0,
                1 => ulps(0.0, rng.below(7) as i32 - 3) * (rng.below(3) as f32),
                _ => rng.range(-0.5, 0.5),
            })
            .collect();
        let mut nudge = |x: f32| ulps(x, rng.below(5) as i32 - 2);
        let apex = if case % 5 == 0 {
            Vec3::ZERO
        } else {
            Vec3::new(nudge(0.0), nudge(0.0), nudge(0.0))
        };
        let open = case % 7 == 3;
        let fin = (case % 11 == 5).then(|| [Vec3::new(0.3, 0.3, -1.0), Vec3::new(0.3, 0.3, 1.0)]);
        let mut mesh = fan_mesh(&angles, &heights, apex, open, fin);
        if case % 13 == 6 {
            // Ring point 2 halfway to ring point 1 from the apex at 0, exactly:
            // triangle (0, 1, 2) is a segment, and the faces on either side
            // of it, which share only the apex, touch along it.
            let mut p = mesh.positions().to_vec();
            p[0] = Vec3::ZERO;
            p[2] = p[1] * 0.5;
            let faces: Vec<Vec<u32>> = mesh.faces().map(|f| f.to_vec()).collect();
            mesh = Mesh::from_faces(p, &faces).unwrap();
        }
        let expected = brute_self(&mesh);
        assert_eq!(
            self_intersections(&MeshIndex::new(mesh)).unwrap(),
            expected,
            "case {case}"
        );
        if expected.is_empty() {
            without += 1
        } else {
            with_pairs += 1
        }
    }
    // Both outcomes are well represented.
    assert!(
        with_pairs > 100 && without > 100,
        "{with_pairs} with pairs, {without} without"
    );
}

#[test]
fn shared_meshes_self_intersections_match_brute_force() {
    let Some(dir) = data_dir() else { return };
    for name in ["fandisk.obj", "bunny-npm.obj", "spot_quadrangulated.obj", "teapot.obj"] {
        let path = dir.join(name);
        let mesh = proxima::io::load(&path).unwrap();
        let found = self_intersections(&MeshIndex::new(mesh.clone())).unwrap();
        println!("{name}: {} self-intersecting face pairs", found.len());
        assert_eq!(found, brute_self(&mesh), "{name}");
    }
}

#[test]
fn shared_mesh_against_a_moved_copy_matches_brute_force() {
    let Some(dir) = data_dir() else { return };
    let mesh = proxima::io::load(dir.join("fandisk.obj")).unwrap();
    let size = f64::from(mesh.bounds().diagonal());
    let mut rng = Rng::new(12);
    for reach in [0.05, 0.3] {
        let pose = random_pose(&mut rng, reach * size);
        let moved = RigidPose::from_rows({
            let mut rows = pose.to_rows();
            // Same rotation, about the mesh's centre.
            let c = DVec3::from(mesh.bounds().center());
            let t = c - pose.rotation() * c + pose.translation() * 0.1;
            for (row, value) in rows.iter_mut().zip(t.to_array()) {
                row[3] = value;
            }
            rows
        })
        .unwrap();
        check_pair(&mesh, &RigidPose::IDENTITY, &mesh, &moved, 1e-3 * size);
    }
}

/// Brute force: the smallest triangle-pair distance and the lowest
/// `(triangle_a, triangle_b)` that reaches it (the library's tie rule).
fn brute_nearest(a: &Mesh, pa: &RigidPose, b: &Mesh, pb: &RigidPose) -> (f64, u32, u32) {
    let (ta, tb) = (placed(a, pa), placed(b, pb));
    let mut best = (f64::INFINITY, u32::MAX, u32::MAX);
    for (i, (ca, ..)) in ta.iter().enumerate() {
        for (j, (cb, ..)) in tb.iter().enumerate() {
            let d = triangle_distance(ca, cb).distance;
            if d < best.0 {
                best = (d, i as u32, j as u32);
            }
        }
    }
    best
}

/// A rotation scaled by `1 + stretch`: still a pose (within the rotation
/// tolerance), no longer orthonormal, so lengths in its frame differ from
/// lengths in the world.
fn stretched(pose: &RigidPose, stretch: f64) -> RigidPose {
    RigidPose::new(pose.rotation() * (1.0 + stretch), pose.translation()).unwrap()
}

/// Poses where the walk's bounds along the line of the best pair and along
/// the oriented boxes' normals decide nearly everything: curved surfaces far
/// apart (many pairs within a hair of the answer), parallel faces (exact
/// ties, broken by the lowest triangle pair), and rotations that are
/// orthonormal only within the tolerance. Every answer is brute force's,
/// pair for pair.
#[test]
fn far_curved_and_tied_poses_match_brute_force_pair_for_pair() {
    let sphere = bumpy_sphere(5, 3);
    let smooth = proxima::mesh::generate::noisy_icosphere(6, 0);
    let boxy = cube(-0.5, 0.75);
    let mut rng = Rng::new(40);
    let mut cases: Vec<(&Mesh, RigidPose, &Mesh, RigidPose)> = Vec::new();
    for round in 0..6 {
        let far = 3.0 + f64::from(round);
        let direction = DVec3::new(
            rng.range(-1.0, 1.0).into(),
            rng.range(-1.0, 1.0).into(),
            rng.range(-1.0, 1.0).into(),
        )
        .normalize();
        let turn = random_pose(&mut rng, 0.0);
        let moved = RigidPose::new(turn.rotation(), direction * far).unwrap();
        cases.push((&sphere, random_pose(&mut rng, 0.5), &smooth, moved));
        cases.push((&smooth, RigidPose::IDENTITY, &smooth, moved));
        cases.push((
            &sphere,
            stretched(&random_pose(&mut rng, 0.5), 4e-7),
            &sphere,
            stretched(&moved, -3e-7),
        ));
    }
    // Parallel faces a dyadic distance apart, and diagonal offsets.
    for t in [[3.0, 0.0, 0.0], [0.0, -2.5, 0.0], [2.0, 2.0, 0.0], [1.5, 2.0, 2.5]] {
        let pose = RigidPose::translation_only(DVec3::from_array(t)).unwrap();
        cases.push((&boxy, RigidPose::IDENTITY, &boxy, pose));
        cases.push((&boxy, RigidPose::IDENTITY, &smooth, pose));
        for stretch in [-4.5e-7, 4.5e-7] {
            cases.push((
                &boxy,
                stretched(&RigidPose::IDENTITY, stretch),
                &boxy,
                stretched(&pose, -stretch),
            ));
        }
    }
    for (case, (a, pa, b, pb)) in cases.into_iter().enumerate() {
        let (ia, ib) = (MeshIndex::new(a.clone()), MeshIndex::new(b.clone()));
        let d = pair::distance(&ia, &pa, &ib, &pb).unwrap();
        let (expected, ta, tb) = brute_nearest(a, &pa, b, &pb);
        assert_eq!(
            (d.distance, d.triangle_a, d.triangle_b),
            (expected, ta, tb),
            "case {case}"
        );
        assert_eq!(
            pair::distance_below(&ia, &pa, &ib, &pb, expected).unwrap(),
            None,
            "case {case}"
        );
        let below = pair::distance_below(&ia, &pa, &ib, &pb, expected.next_up()).unwrap();
        assert_eq!(
            below.map(|x| (x.triangle_a, x.triangle_b)),
            Some((ta, tb)),
            "case {case}"
        );
    }
}

#[test]
fn bad_input_is_refused_with_the_argument_named() {
    let empty = MeshIndex::new(Mesh::from_compact(vec![Vec3::ZERO], vec![0], vec![]).unwrap());
    let one = MeshIndex::new(cube(0.0, 1.0));
    let id = RigidPose::IDENTITY;
    let e = pair::distance(&one, &id, &empty, &id).unwrap_err();
    assert!(matches!(e, PairError::Mesh { mesh: "b", .. }), "{e}");
    assert!(e.to_string().starts_with("mesh b: "), "{e}");
    let e = self_intersections(&empty).unwrap_err();
    assert!(matches!(e, PairError::Mesh { mesh: "mesh", .. }), "{e}");
    let far = RigidPose::translation_only(DVec3::new(0.0, 2e38, 0.0)).unwrap();
    let e = intersects(&one, &id, &one, &far).unwrap_err();
    assert!(e.to_string().starts_with("pose_b: "), "{e}");
    let e = pair::distance_batch(&one, &one, &[id, id, far]).unwrap_err();
    assert!(e.to_string().starts_with("poses[2]: "), "{e}");
    for bad in [-1.0, f64::NAN] {
        let e = pairs_within(&one, &id, &one, &id, bad).unwrap_err();
        assert!(matches!(e, PairError::BadDistance { option: "d", .. }), "{e}");
        let e = pair::distance_below(&one, &id, &one, &id, bad).unwrap_err();
        assert!(e.to_string().starts_with("d_max must be at least 0"), "{e}");
    }
}

/// A pair list stops at what the memory budget holds (`d = ∞` pairs every
/// face with every face), with the budget error naming the argument. Runs
/// itself again in a child process with `PROXIMA_MEMORY_BUDGET` set:
/// setting it here would race the other tests of this process.
#[test]
fn pair_lists_stop_at_the_memory_budget() {
    const CHILD: &str = "PROXIMA_TEST_PAIR_BUDGET_CHILD";
    const NAME: &str = "pair_lists_stop_at_the_memory_budget";
    if std::env::var_os(CHILD).is_some() {
        // 4 KiB hold 512 face pairs of 8 bytes: 12 x 12 = 144 fit, 642 x 642 do not.
        let small = MeshIndex::new(cube(0.0, 1.0));
        let id = RigidPose::IDENTITY;
        assert_eq!(
            pairs_within(&small, &id, &small, &id, f64::INFINITY).unwrap().len(),
            144
        );
        let big = MeshIndex::new(bumpy_sphere(8, 1));
        let Err(e) = pairs_within(&big, &id, &big, &id, f64::INFINITY) else {
            panic!("1280 x 1280 face pairs fit 4 KiB");
        };
        assert!(matches!(e, PairError::Budget(_)), "{e}");
        assert!(e.to_string().starts_with("d inf: needs about"), "{e}");
        return;
    }
    let out = crate::common::rerun_with_budget(module_path!(), NAME, CHILD, "4K");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("1 passed"),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
