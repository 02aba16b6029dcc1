//! The sign certificate (`SignCertificate`): where it decides the side from
//! the closest query, the side must be the exact winding number's. Oracles:
//! a box whose inside is known exactly for points on and within a few ulps
//! of its faces, edges and corners; the winding number by Girard's theorem
//! (`common::winding`); and meshes built to defeat the rule: nested shells,
//! a hollow ball, holes beside the query, a folded open sheet, overlapping
//! spheres, flipped patches, a bow-tie vertex.

use crate::common::winding::{corners, mesh_of, oracle};
use crate::common::{bumpy_sphere, data_dir};
use proxima::prelude::*;
use proxima::sdf::{SdfConfig, SignedDistanceField};
use rayon::prelude::*;

/// The side is the oracle's wherever the exact winding number is farther
/// than this from ½.
const CLEAR: f64 = 0.01;

/// How far a certified winding number may lie from the oracle's (the caps'
/// part comes from a tree of expansions: docs/sdf.md).
const VALUE_TOLERANCE: f64 = 0.04;

fn field(mesh: &Mesh) -> SignedDistanceField {
    SignedDistanceField::new(mesh, &SdfConfig::default()).unwrap()
}

/// What the certificate alone says at `p`: `None` where it leaves the side
/// to the winding number's walk.
fn certified(field: &SignedDistanceField, p: Vec3) -> Option<f32> {
    let closest = field.tree().closest(p)?;
    assert!(
        field.pseudonormals().is_some(),
        "a certified field lends its pseudonormals"
    );
    field
        .certificate()
        .expect("certified by default")
        .winding_number(&closest, p)
}

/// Every point: the field's side is the oracle's where the oracle is clear
/// of ½; where the certificate decides, its value is within
/// [`VALUE_TOLERANCE`] of the oracle. Returns how many the certificate
/// decided.
fn check(mesh: &Mesh, points: &[Vec3], what: &str) -> usize {
    let field = field(mesh);
    let triangles = mesh.triangles().primitives;
    let expected: Vec<f64> = points.par_iter().map(|&p| oracle(&triangles, p)).collect();
    let batch = field.signed_distance_batch(points);
    let mut decided = 0;
    for (k, &p) in points.iter().enumerate() {
        let e = expected[k];
        let s = batch[k].expect("finite point");
        assert_eq!(Some(s), field.signed_distance(p), "{what}: batch = single at {p}");
        if let Some(w) = certified(&field, p) {
            decided += 1;
            assert!(
                (w as f64 - e).abs() < VALUE_TOLERANCE,
                "{what}: certified w({p}) = {w}, oracle {e}"
            );
            assert_eq!(
                s.winding_number,
                Some(w),
                "{what}: the field answers with the certificate"
            );
        }
        if (e - 0.5).abs() > CLEAR && s.distance != 0.0 {
            assert_eq!(
                s.is_inside(),
                e > 0.5,
                "{what}: side at {p}, oracle w = {e}, answer {s:?}"
            );
        }
    }
    decided
}

/// Near-surface and uniform points.
fn points(mesh: &Mesh, n: usize, seed: u64) -> Vec<Vec3> {
    let mut out = proxima::sample::near_surface(mesh, n, 0.01, seed);
    out.extend(proxima::sample::near_surface(mesh, n / 2, 0.1, seed + 7));
    out.extend(proxima::sample::uniform_in_box(mesh, n, seed + 1));
    out
}

/// The box [-1, 1]³, each face a 4 × 4 grid of squares cut into triangles,
/// faces outward.
fn grid_box() -> Mesh {
    let n = 4;
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let point = |i: usize, j: usize| {
                let mut p = [0.0f32; 3];
                p[axis] = side;
                p[u] = -1.0 + 2.0 * i as f32 / n as f32;
                p[v] = -1.0 + 2.0 * j as f32 / n as f32;
                Vec3::from(p)
            };
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
                    // u × v is +axis: counter-clockwise seen from outside on the + side.
                    if side > 0.0 {
                        triangles.push([a, b, c]);
                        triangles.push([a, c, d]);
                    } else {
                        triangles.push([a, c, b]);
                        triangles.push([a, d, c]);
                    }
                }
            }
        }
    }
    mesh_of(&triangles)
}

/// `x` moved `k` representable floats up (k > 0) or down.
fn ulps(x: f32, k: i32) -> f32 {
    let mut y = x;
    for _ in 0..k.abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

#[test]
fn closed_meshes_are_certified_whole() {
    for (mesh, what) in [(bumpy_sphere(12, 3), "sphere"), (grid_box(), "box")] {
        let field = field(&mesh);
        let stats = field.certificate().unwrap().stats();
        assert_eq!(stats.certified, stats.triangles, "{what}: {stats:?}");
        assert_eq!(
            (stats.components, stats.boundary_loops, stats.meeting),
            (1, 0, 0),
            "{what}"
        );
        assert_eq!(field.signed_distance(Vec3::ZERO).unwrap().winding_number, Some(1.0));
        assert_eq!(
            field.signed_distance(Vec3::splat(3.0)).unwrap().winding_number,
            Some(0.0)
        );
    }
}

/// Points exactly on the box's faces, edges and corners and 1 to 4096 ulps
/// off them on either side, against the exact answer: inside when every
/// coordinate is strictly inside (-1, 1). The certificate must decide every
/// point farther than its slack (2^-20 of the largest coordinate: 8 ulps
/// above 1, 16 below), and be right wherever it decides; the field must be right
/// everywhere off the surface.
#[test]
fn box_sides_on_and_within_ulps_of_faces_edges_and_corners() {
    let mesh = grid_box();
    let field = field(&mesh);
    let offsets = [0, 1, 2, 3, 7, 8, 9, 12, 16, 64, 4096];
    // On the surface: a face's interior, a grid line, a face edge (two
    // faces), a corner (three faces), a grid vertex.
    let anchors = [
        Vec3::new(1.0, 0.3, -0.55),
        Vec3::new(1.0, 0.5, 0.1),
        Vec3::new(1.0, 1.0, 0.3),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, 0.0, 0.5),
        Vec3::new(0.25, -1.0, -0.75),
    ];
    let (mut decided, mut total) = (0, 0);
    for anchor in anchors {
        // Move every coordinate that sits on ±1 by the same number of ulps,
        // outward (k > 0) or inward.
        for &k in &offsets {
            for outward in [true, false] {
                let step = if outward { k } else { -k };
                let p = Vec3::from(anchor.to_array().map(|c| {
                    if c.abs() == 1.0 {
                        ulps(c, step * c.signum() as i32)
                    } else {
                        c
                    }
                }));
                let inside = p.to_array().iter().all(|c| c.abs() < 1.0);
                let on = p.to_array().iter().any(|c| c.abs() == 1.0) && p.to_array().iter().all(|c| c.abs() <= 1.0);
                let s = field.signed_distance(p).unwrap();
                total += 1;
                if on {
                    assert_eq!(s.distance, 0.0, "{p} is on the surface");
                } else {
                    assert_eq!(
                        s.is_inside(),
                        inside,
                        "{p} ({k} ulps {}): {s:?}",
                        if outward { "out" } else { "in" }
                    );
                }
                let w = certified(&field, p);
                if let Some(w) = w {
                    decided += 1;
                    assert_eq!(w, if inside { 1.0 } else { 0.0 }, "{p}: certified {w}");
                }
                if s.distance.abs() > 1.01 / (1u32 << 20) as f32 {
                    assert!(w.is_some(), "{p}: {k} ulps off the surface is beyond the slack");
                }
                if k == 0 {
                    assert!(w.is_none(), "{p}: on the surface the certificate has no side");
                }
            }
        }
    }
    println!("box: the certificate decided {decided} of {total} points");
}

/// Two closed outward spheres, one inside the other: w = 1 between them
/// and 2 inside the inner one. A point between them nearest the inner
/// sphere is in front of it and still inside: each component carries its
/// own integer. Turned inward, the inner sphere makes a hollow ball: its
/// cavity is outside (w = 0).
#[test]
fn nested_shells_and_a_hollow_ball() {
    let outer = bumpy_sphere(10, 1);
    let inner: Vec<[Vec3; 3]> = corners(&bumpy_sphere(6, 2))
        .iter()
        .map(|t| t.map(|v| v * 0.5))
        .collect();
    for hollow in [false, true] {
        let mut all = corners(&outer);
        all.extend(
            inner
                .iter()
                .map(|&[a, b, c]| if hollow { [a, c, b] } else { [a, b, c] }),
        );
        let mesh = mesh_of(&all);
        let what = if hollow { "hollow ball" } else { "nested shells" };
        let f = field(&mesh);
        let stats = f.certificate().unwrap().stats();
        assert_eq!(
            (stats.certified, stats.components),
            (stats.triangles, 2),
            "{what}: {stats:?}"
        );
        // Between the shells, just outside the inner one.
        let between = Vec3::new(0.56, 0.0, 0.0);
        assert_eq!(certified(&f, between), Some(1.0), "{what}");
        let centre = certified(&f, Vec3::ZERO);
        assert_eq!(centre, Some(if hollow { 0.0 } else { 2.0 }), "{what}");
        assert_eq!(f.signed_distance(Vec3::ZERO).unwrap().is_inside(), !hollow);
        let decided = check(&mesh, &points(&mesh, 300, 3), what);
        assert!(decided > 500, "{what}: the certificate decided {decided}");
    }
}

/// A sphere with a hole (the faces above z = 0.7 removed): the rim is
/// capped, queries beside the hole and in its mouth (w far from 0 and 1)
/// see the caps' winding number; where the cap lies between a query and
/// its closest point, the field walks the whole winding number.
#[test]
fn holes_beside_the_query() {
    let sphere = bumpy_sphere(10, 5);
    let holed: Vec<[Vec3; 3]> = corners(&sphere)
        .into_iter()
        .filter(|t| t.iter().map(|v| v.z).sum::<f32>() / 3.0 < 0.7)
        .collect();
    let mesh = mesh_of(&holed);
    let f = field(&mesh);
    let stats = f.certificate().unwrap().stats();
    assert_eq!(stats.boundary_loops, 1, "{stats:?}");
    assert!(stats.certified > stats.triangles * 9 / 10, "{stats:?}");
    let mut probes = points(&mesh, 300, 11);
    for i in 0..=40 {
        let t = i as f32 / 40.0;
        probes.push(Vec3::new(0.0, 0.0, 0.3 + 0.9 * t)); // up through the mouth
        probes.push(Vec3::new(0.6 * t, 0.0, 0.75)); // across the rim
    }
    let decided = check(&mesh, &probes, "holed sphere");
    assert!(decided > 300, "decided {decided}");
}

/// An open sheet folded into a V, and a sheet in a closed box: the caps of
/// a folded rim cross the sheet, those triangles are left to the walk.
#[test]
fn folded_sheet() {
    let n = 12;
    let mut triangles = Vec::new();
    let point = |i: usize, j: usize| {
        let x = -1.0 + 2.0 * i as f32 / n as f32;
        Vec3::new(x, -1.0 + 2.0 * j as f32 / n as f32, 0.8 * x.abs())
    };
    for i in 0..n {
        for j in 0..n {
            triangles.push([point(i, j), point(i + 1, j), point(i + 1, j + 1)]);
            triangles.push([point(i, j), point(i + 1, j + 1), point(i, j + 1)]);
        }
    }
    let mesh = mesh_of(&triangles);
    let decided = check(&mesh, &points(&mesh, 300, 21), "folded sheet");
    println!("folded sheet: decided {decided}");
}

/// Two overlapping spheres: the triangles crossing the other sphere are
/// not certified; the pseudonormal's wrong crescents stay right.
#[test]
fn overlapping_spheres_leave_the_crossing_to_the_walk() {
    let a = corners(&bumpy_sphere(10, 1));
    let mut all = a.clone();
    all.extend(a.iter().map(|t| t.map(|v| v + Vec3::new(0.5, 0.0, 0.0))));
    let mesh = mesh_of(&all);
    let f = field(&mesh);
    let stats = f.certificate().unwrap().stats();
    assert!(stats.meeting > 0 && stats.certified < stats.triangles, "{stats:?}");
    // Inside the first sphere, nearest the second's buried surface: w = 1.
    let p = Vec3::new(-0.6, 0.0, 0.0);
    assert!(f.signed_distance(p).unwrap().is_inside());
    check(&mesh, &points(&mesh, 300, 4), "overlapping spheres");
}

/// A sphere with a patch of faces turned over, and two tetrahedra sharing
/// one vertex (two fans at it): the certificate leaves both to the walk
/// around them and the sides stay the oracle's.
#[test]
fn flipped_patches_and_bow_ties() {
    let mut faces = corners(&bumpy_sphere(8, 6));
    for t in faces.iter_mut().filter(|t| t[0].x > 0.6) {
        *t = [t[0], t[2], t[1]];
    }
    let mesh = mesh_of(&faces);
    let stats = field(&mesh).certificate().unwrap().stats();
    assert!(stats.certified < stats.triangles, "{stats:?}");
    check(&mesh, &points(&mesh, 300, 5), "flipped patch");

    let tetrahedron = |s: f32| {
        let [a, b, c, d] = [
            Vec3::ZERO,
            Vec3::new(s, 0.0, 0.0),
            Vec3::new(0.0, s, 0.0),
            Vec3::new(0.0, 0.0, s),
        ];
        [[a, c, b], [a, b, d], [a, d, c], [b, c, d]]
    };
    let mut both = tetrahedron(1.0).to_vec();
    both.extend(tetrahedron(-1.0).map(|[a, b, c]| [a, c, b]));
    let mesh = mesh_of(&both);
    let f = field(&mesh);
    assert_eq!(certified(&f, Vec3::splat(0.001)), None, "beside the bow-tie vertex");
    let mut probes = points(&mesh, 200, 6);
    probes.extend((1..=20).flat_map(|i| {
        let t = i as f32 * 0.01;
        [Vec3::splat(t), Vec3::splat(-t), Vec3::new(t, -t, t)]
    }));
    check(&mesh, &probes, "bow tie");
}

/// The shared meshes with holes, seams and crossings: the certificate's
/// values are the oracle's and its sides right, at points near the surface.
#[test]
fn shared_meshes_follow_the_oracle() {
    let Some(dir) = data_dir() else { return };
    for (name, n) in [
        ("teapot.obj", 300),
        ("blade.off", 300),
        ("stanford-bunny.obj", 150),
        ("dragon_vrip_res2.ply", 60),
    ] {
        let path = dir.join(name);
        if !path.exists() {
            println!("skipped {name}: not in {}", dir.display());
            continue;
        }
        let mesh = proxima::io::load(&path).unwrap();
        let stats = field(&mesh).certificate().unwrap().stats();
        println!("{name}: {stats:?}");
        assert!(stats.certified > stats.triangles / 2, "{name}: {stats:?}");
        let decided = check(&mesh, &points(&mesh, n, 31), name);
        assert!(decided > n, "{name}: decided {decided}");
    }
}

/// A mesh index made with `certify_sign: false` walks every winding number;
/// its sides are the certified index's, and after a move that makes the
/// mesh cross itself both still follow the oracle: first with the
/// certificate deferred (none until the signed distances asked of the
/// index number half the triangles), then with it made again.
#[test]
fn indexes_with_and_without_the_certificate_agree_after_a_move() {
    use proxima::{IndexConfig, MeshIndex};
    let mesh = bumpy_sphere(8, 9);
    let plain = IndexConfig {
        certify_sign: false,
        ..IndexConfig::default()
    };
    let mut with = MeshIndex::new(mesh.clone());
    let mut without = MeshIndex::with_config(mesh.clone(), plain);
    // Fold the top of the sphere down through the bottom.
    let moved: Vec<Vec3> = mesh
        .positions()
        .iter()
        .map(|&p| if p.z > 0.3 { Vec3::new(p.x, p.y, -p.z + 0.2) } else { p })
        .collect();
    let triangles_before = mesh.triangles().primitives;
    for round in 0..3 {
        if round == 1 {
            with.update_vertices(&moved).unwrap();
            without.update_vertices(&moved).unwrap();
        }
        let a = with.field(Sign::WindingNumber).unwrap();
        let b = without.field(Sign::WindingNumber).unwrap();
        assert_eq!(a.certificate().is_some(), round != 1, "round {round}");
        assert!(b.certificate().is_none());
        let triangles = if round == 0 {
            triangles_before.clone()
        } else {
            with.mesh().triangles().primitives
        };
        let probes = points(with.mesh(), 150, 40 + round);
        let (sa, sb) = (a.signed_distance_batch(&probes), b.signed_distance_batch(&probes));
        for (k, &p) in probes.iter().enumerate() {
            let e = oracle(&triangles, p);
            let (x, y) = (sa[k].unwrap(), sb[k].unwrap());
            assert_eq!(x.closest, y.closest);
            if (e - 0.5).abs() > CLEAR && x.distance != 0.0 {
                assert_eq!(x.is_inside(), e > 0.5, "round {round}: {p}, oracle {e}");
                assert_eq!(y.is_inside(), e > 0.5, "round {round}: {p}, oracle {e}");
            }
        }
        if round == 1 {
            // Short of what pays for the certificate, then past it.
            let due = with.mesh().triangle_count() / 2;
            assert!(probes.len() < due, "{} probes, {due} due", probes.len());
            let field = with.field(Sign::WindingNumber).unwrap();
            assert!(field.certificate().is_none());
            field.signed_distance_batch(&points(with.mesh(), due / 2, 50));
            assert!(
                field.certificate().is_none(),
                "made by the index's next call, not during a batch"
            );
            assert!(without.field(Sign::WindingNumber).unwrap().certificate().is_none());
        }
    }
    let stats = with.field(Sign::WindingNumber).unwrap().certificate().unwrap().stats();
    assert!(stats.meeting > 0, "the folded sphere crosses itself: {stats:?}");
}

/// A field made for fewer signed distances than pay for the certificate
/// (`MeshIndex::field_for`) answers without one, the same sides as the
/// oracle and the same answers as a certified field's, and makes it once
/// its walked signed distances reach half the triangles; one made for more
/// has it from the start.
#[test]
fn a_field_made_for_few_queries_certifies_once_they_pay() {
    use proxima::sdf::certificate_pays;
    use proxima::{IndexConfig, MeshIndex};
    let mesh = bumpy_sphere(8, 11);
    let triangles = mesh.triangles().primitives;
    let due = mesh.triangle_count() / 2;
    assert!(certificate_pays(due, mesh.triangle_count()) && !certificate_pays(due - 1, mesh.triangle_count()));
    let eager = MeshIndex::new(mesh.clone());
    let certified = eager.field(Sign::WindingNumber).unwrap();
    assert!(certified.certificate().is_some());
    let few = MeshIndex::new(mesh.clone());
    let field = few.field_for(Sign::WindingNumber, due - 1).unwrap();
    assert!(field.certificate().is_none());
    let probes = points(&mesh, 200, 61);
    let (got, expected) = (
        field.signed_distance_batch(&probes),
        certified.signed_distance_batch(&probes),
    );
    for (k, &p) in probes.iter().enumerate() {
        let (x, y) = (got[k].unwrap(), expected[k].unwrap());
        assert_eq!(x.closest, y.closest);
        let e = oracle(&triangles, p);
        if (e - 0.5).abs() > CLEAR && x.distance != 0.0 {
            assert_eq!(x.is_inside(), e > 0.5, "{p}, oracle {e}");
            assert_eq!(x.distance, y.distance, "{p}");
        }
    }
    // 200 walked so far: the rest of the due count, then the index's next call makes it.
    field.signed_distance_batch(&points(&mesh, due - 200, 62));
    assert!(field.certificate().is_none());
    let field = few.field(Sign::WindingNumber).unwrap();
    assert!(field.certificate().is_some());
    // Made for as many as pay: certified at once; without the option: never.
    let many = MeshIndex::new(mesh.clone());
    assert!(
        many.field_for(Sign::WindingNumber, due)
            .unwrap()
            .certificate()
            .is_some()
    );
    let off = IndexConfig {
        certify_sign: false,
        ..IndexConfig::default()
    };
    let never = MeshIndex::with_config(mesh, off);
    assert!(never.field_for(Sign::WindingNumber, 0).unwrap().certificate().is_none());
}
