//! The Hausdorff distance between two meshes' surfaces against brute force
//! over every triangle, with the independent `f64` point–triangle distance
//! of `common::oracle`.
//!
//! Brute force samples the surface measured from on a barycentric grid of
//! step `1/n`. `d(., B)` is 1-Lipschitz and every point of a triangle is
//! within its longest edge over `n` of a sample, so the true value lies in
//! `[sampled, sampled + spacing]`. The library's bounds must bracket it,
//! meet within the tolerance, and its lower bound must be realized by the
//! points it returns.

use crate::common::oracle::{D3, d3, triangle_distance};
use crate::common::{bumpy_sphere, data_dir, random_soup};
use proxima::pair::{DirectedHausdorff, PairError, directed_hausdorff, hausdorff};
use proxima::sample::Rng;
use proxima::{Mesh, MeshIndex, Triangle, Vec3};

/// Brute force: `d(p, B)` over every triangle of `b`.
fn distance_to(b: &[Triangle], p: D3) -> f64 {
    b.iter().map(|t| triangle_distance(t, p)).fold(f64::INFINITY, f64::min)
}

/// The largest sampled `d(., B)` over `a`'s triangles on a barycentric grid
/// of step `1/n`, and the spacing that bounds the error.
fn sampled(a: &Mesh, b: &[Triangle], n: usize) -> (f64, f64) {
    let (mut best, mut spacing) = (0.0f64, 0.0f64);
    for t in &a.triangles().primitives {
        let (p, q, r) = (t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3());
        let longest = (q - p).length().max((r - q).length()).max((p - r).length());
        spacing = spacing.max(longest / n as f64);
        for i in 0..=n {
            for j in 0..=n - i {
                let x = p + (q - p) * (i as f64 / n as f64) + (r - p) * (j as f64 / n as f64);
                best = best.max(distance_to(b, x.to_array()));
            }
        }
    }
    (best, spacing)
}

/// Everything a directed answer promises, against brute force.
fn check(h: &DirectedHausdorff, a: &Mesh, b: &Mesh, tolerance: f64, n: usize, what: &str) {
    let tb = b.triangles().primitives;
    let scale = 1e-9 * f64::from(a.bounds().diagonal().max(b.bounds().diagonal())).max(1e-30);
    assert_eq!(h.unsettled, 0, "{what}: {h:?}");
    assert!(h.lower <= h.upper && h.upper - h.lower <= tolerance, "{what}: {h:?}");
    // The lower bound is the distance of its point, which lies on its face.
    let on_face = a.triangles();
    let face_distance = on_face
        .primitives
        .iter()
        .zip(&on_face.sources)
        .filter(|&(_, &f)| f == h.face)
        .map(|(t, _)| triangle_distance(t, h.point.to_array()))
        .fold(f64::INFINITY, f64::min);
    assert!(face_distance <= scale, "{what}: point off its face by {face_distance}");
    let measured = distance_to(&tb, h.point.to_array());
    assert!(
        (measured - h.lower).abs() <= scale,
        "{what}: lower {} but its point is {measured}",
        h.lower
    );
    assert!((h.closest.distance(h.point) - h.lower).abs() <= scale, "{what}: {h:?}");
    // The bracket.
    let (value, spacing) = sampled(a, &tb, n);
    assert!(
        h.upper >= value - scale,
        "{what}: upper {} below a sampled {value}",
        h.upper
    );
    assert!(
        h.lower <= value + spacing + scale,
        "{what}: lower {} above {value} + {spacing}",
        h.lower
    );
}

fn index(mesh: &Mesh) -> MeshIndex {
    MeshIndex::new(mesh.clone())
}

#[test]
fn random_soups_are_bracketed() {
    for seed in 0..6 {
        let (a, b) = (random_soup(40, 10 + seed), random_soup(40, 20 + seed));
        let tolerance = 1e-3 * f64::from(a.bounds().diagonal());
        let h = hausdorff(&index(&a), &index(&b), tolerance).unwrap();
        check(&h.forward, &a, &b, tolerance, 16, &format!("soup {seed} forward"));
        check(&h.backward, &b, &a, tolerance, 16, &format!("soup {seed} backward"));
        assert_eq!(h.lower(), h.forward.lower.max(h.backward.lower));
    }
}

/// Two closed bumpy spheres of different resolutions: the usual case of a
/// reconstruction against its reference, where the farthest points lie
/// inside faces.
#[test]
fn spheres_of_two_resolutions_are_bracketed() {
    let (a, b) = (bumpy_sphere(3, 1), bumpy_sphere(5, 2));
    for tolerance in [1e-2, 1e-4] {
        let h = hausdorff(&index(&a), &index(&b), tolerance).unwrap();
        check(&h.forward, &a, &b, tolerance, 12, "coarse to fine");
        check(&h.backward, &b, &a, tolerance, 8, "fine to coarse");
    }
}

/// A mesh against itself is 0 apart exactly; a flat square against its copy
/// lifted by `d` is exactly `d` apart everywhere.
#[test]
fn exact_cases() {
    let a = bumpy_sphere(4, 3);
    let h = hausdorff(&index(&a), &index(&a), 1e-3).unwrap();
    assert_eq!((h.lower(), h.upper()), (0.0, 0.0));
    let square = |z: f32| {
        let p = vec![
            Vec3::new(0.0, 0.0, z),
            Vec3::new(3.0, 0.0, z),
            Vec3::new(3.0, 2.0, z),
            Vec3::new(0.0, 2.0, z),
        ];
        Mesh::from_faces(p, &[vec![0, 1, 2, 3]]).unwrap()
    };
    let h = hausdorff(&index(&square(0.0)), &index(&square(0.75)), 1e-6).unwrap();
    assert_eq!((h.forward.lower, h.backward.lower), (0.75, 0.75));
    assert!(h.upper() >= 0.75 && h.upper() <= 0.75 + 1e-6);
}

/// Vertices moved by one to three ulps: the distance is a few ulps, and the
/// bounds still bracket brute force at the finest tolerance allowed.
#[test]
fn nudged_by_ulps() {
    let a = bumpy_sphere(3, 4);
    let mut rng = Rng::new(5);
    let moved: Vec<Vec3> = a
        .positions()
        .iter()
        .map(|p| {
            let nudge = |x: f32, k: i32| {
                let step = |x: f32| if k > 0 { x.next_up() } else { x.next_down() };
                (0..k.abs()).fold(x, |x, _| step(x))
            };
            let k = rng.below(7) as i32 - 3;
            Vec3::new(nudge(p.x, k), nudge(p.y, -k), p.z)
        })
        .collect();
    let mut b = a.clone();
    b.set_positions(&moved).unwrap();
    let tolerance = 1e-7 * f64::from(a.bounds().diagonal()) * 1.01;
    let h = hausdorff(&index(&a), &index(&b), tolerance).unwrap();
    check(&h.forward, &a, &b, tolerance, 6, "nudged forward");
    check(&h.backward, &b, &a, tolerance, 6, "nudged backward");
    assert!(h.lower() > 0.0);
}

/// Triangles collapsed to points and segments on either side.
#[test]
fn degenerate_triangles() {
    let a = Mesh::from_triangles(
        vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(5.0, 5.0, 5.0),
        ],
        &[[0, 1, 2], [3, 3, 3], [0, 3, 3]],
    )
    .unwrap();
    let b = Mesh::from_triangles(
        vec![
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(4.0, 4.0, 4.0),
        ],
        &[[0, 0, 0], [1, 2, 2], [0, 1, 1]],
    )
    .unwrap();
    let h = hausdorff(&index(&a), &index(&b), 1e-4).unwrap();
    check(&h.forward, &a, &b, 1e-4, 40, "collapsed forward");
    check(&h.backward, &b, &a, 1e-4, 40, "collapsed backward");
}

/// The two triangulations of spot (one fans its non-planar quads the other
/// way) differ by up to about 1% of its size. Brute force over every
/// vertex and random surface points: the lower bound is at least every
/// vertex's distance, the upper at least every sample's.
#[test]
fn spot_triangulations() {
    let Some(dir) = data_dir() else {
        eprintln!("skipped: ../shared/data not found");
        return;
    };
    let (a, b) = match (
        proxima::io::load(dir.join("spot_triangulated.obj")),
        proxima::io::load(dir.join("spot_quadrangulated.obj")),
    ) {
        (Ok(a), Ok(b)) => (a, b),
        _ => {
            eprintln!("skipped: spot meshes not found");
            return;
        }
    };
    let tolerance = 1e-4 * f64::from(a.bounds().diagonal());
    let h = hausdorff(&index(&a), &index(&b), tolerance).unwrap();
    for (d, from, to) in [(&h.forward, &a, &b), (&h.backward, &b, &a)] {
        assert_eq!(d.unsettled, 0);
        assert!(d.upper - d.lower <= tolerance);
        let tb = to.triangles().primitives;
        let vertices = from.positions().iter().map(|&v| distance_to(&tb, d3(v)));
        let worst_vertex = vertices.fold(0.0f64, f64::max);
        assert!(d.lower >= worst_vertex - 1e-12, "{} < {worst_vertex}", d.lower);
        let mut rng = Rng::new(7);
        let ta = from.triangles().primitives;
        for _ in 0..1500 {
            let t = &ta[rng.below(ta.len())];
            let (mut u, mut v) = (rng.unit(), rng.unit());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let p = t.a.as_dvec3() + (t.b.as_dvec3() - t.a.as_dvec3()) * u + (t.c.as_dvec3() - t.a.as_dvec3()) * v;
            let x = distance_to(&tb, p.to_array());
            assert!(x <= d.upper + 1e-12, "a sample at {x} beyond upper {}", d.upper);
        }
        // Measured by the farthest vertex, the usual shortcut, the distance
        // is short of the true one by more than the tolerance here.
        assert!(d.lower > worst_vertex, "{} against {worst_vertex}", d.lower);
    }
}

#[test]
fn bad_input_is_refused() {
    let a = bumpy_sphere(2, 1);
    let diagonal = f64::from(a.bounds().diagonal());
    for bad in [0.0, -1.0, f64::NAN, f64::NEG_INFINITY, 0.5e-7 * diagonal] {
        let e = hausdorff(&index(&a), &index(&a), bad).unwrap_err();
        assert!(matches!(e, PairError::BadTolerance { .. }), "{bad}: {e}");
        assert!(e.to_string().starts_with("tolerance = "), "{e}");
    }
    let empty = MeshIndex::new(Mesh::from_triangles(vec![Vec3::ZERO], &[]).unwrap());
    let e = directed_hausdorff(&empty, &index(&a), 1.0).unwrap_err();
    assert!(matches!(e, PairError::Mesh { mesh: "a", .. }), "{e}");
    let e = directed_hausdorff(&index(&a), &empty, 1.0).unwrap_err();
    assert!(matches!(e, PairError::Mesh { mesh: "b", .. }), "{e}");
    // The lowest tolerance allowed is accepted.
    assert!(hausdorff(&index(&a), &index(&a), 1.01e-7 * diagonal).is_ok());
}
