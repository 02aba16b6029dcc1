//! Exact overlap tests (triangle/box SAT, segment/box slab clipping,
//! point/box) against an independent method: Sutherland–Hodgman clipping of
//! the primitive by the six closed half-spaces of the box. The clipped
//! polygon is non-empty (possibly a point or a segment) exactly when the
//! primitive meets the closed box. The oracle runs in `f64` for random float
//! input, and in exact rational arithmetic for small-integer input, where
//! touching and degenerate configurations are frequent and must come out
//! exactly.

use crate::common;

use crate::common::oracle::{Num, Q, clip_by_box};
use proptest::prelude::*;
use proxima::primitive::sat::{Interval, Project, project_points, separated_along};
use proxima::primitive::{TriangleBoxTest, WatertightRay};
use proxima::{Aabb, BoxOverlap, LineSegment, Point, Triangle, Vec3};

// ---------------------------------------------------------------- oracle ---

/// `true` when the convex polygon (1, 2 or 3 points) meets the closed box.
fn clip_oracle<N: Num>(points: &[Vec3], b: &Aabb) -> bool {
    clip_by_box::<N>(points, b)
}

fn tri_points(t: &Triangle) -> [Vec3; 3] {
    t.vertices()
}

// ------------------------------------------------------------ strategies ---

fn small_int() -> impl Strategy<Value = f32> {
    (-4i32..=4).prop_map(|v| v as f32)
}

fn int_point() -> impl Strategy<Value = Vec3> {
    (small_int(), small_int(), small_int()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Boxes with integer corners, including zero-width ones.
fn int_box() -> impl Strategy<Value = Aabb> {
    (int_point(), (0i32..=3, 0i32..=3, 0i32..=3))
        .prop_map(|(min, (dx, dy, dz))| Aabb::new(min, min + Vec3::new(dx as f32, dy as f32, dz as f32)))
}

/// Integer triangles: general, collinear, with repeated vertices, or points.
fn int_triangle() -> impl Strategy<Value = Triangle> {
    (int_point(), int_point(), int_point(), 0u8..6, -2i32..=3).prop_map(|(a, b, c, kind, k)| match kind {
        0 => Triangle::new(a, b, a + (b - a) * k as f32), // collinear (or repeated)
        1 => Triangle::new(a, a, c),                      // repeated vertex
        2 => Triangle::new(a, a, a),                      // a point
        _ => Triangle::new(a, b, c),
    })
}

fn float_point() -> impl Strategy<Value = Vec3> {
    (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn float_box() -> impl Strategy<Value = Aabb> {
    (float_point(), (0.0f32..1.5, 0.0f32..1.5, 0.0f32..1.5))
        .prop_map(|(min, (dx, dy, dz))| Aabb::new(min, min + Vec3::new(dx, dy, dz)))
}

fn float_triangle() -> impl Strategy<Value = Triangle> {
    (float_point(), float_point(), float_point(), 0u8..8, 0.0f32..2.0).prop_map(|(a, b, c, kind, s)| match kind {
        0 => Triangle::new(a, b, a + (b - a) * s), // nearly collinear (rounded)
        1 => Triangle::new(a, b, b),
        // Small triangles: most overlaps are decided near the box.
        2 | 3 => Triangle::new(a, a + (b - a) * 0.1, a + (c - a) * 0.1),
        _ => Triangle::new(a, b, c),
    })
}

// ----------------------------------------------------------------- tests ---

proptest! {
    #![proptest_config(ProptestConfig { cases: 6000, ..ProptestConfig::default() })]

    /// Small-integer input: exact oracle, exact agreement (touching, degenerate).
    #[test]
    fn triangle_box_matches_exact_clipping(tri in int_triangle(), b in int_box()) {
        let expected = clip_oracle::<Q>(&tri_points(&tri), &b);
        prop_assert_eq!(tri.overlaps_box(&b), expected, "{:?} {:?}", tri, b);
        prop_assert_eq!(TriangleBoxTest::new(&tri).overlaps(&b), expected);
    }

    /// Random float input: f64 oracle.
    #[test]
    fn triangle_box_matches_f64_clipping(tri in float_triangle(), b in float_box()) {
        prop_assert_eq!(tri.overlaps_box(&b), clip_oracle::<f64>(&tri_points(&tri), &b), "{:?} {:?}", tri, b);
    }

    #[test]
    fn segment_box_matches_exact_clipping(a in int_point(), c in int_point(), b in int_box()) {
        let seg = LineSegment::new(a, c);
        prop_assert_eq!(seg.overlaps_box(&b), clip_oracle::<Q>(&[a, c], &b), "{:?} {:?}", seg, b);
    }

    #[test]
    fn segment_box_matches_f64_clipping(a in float_point(), c in float_point(), b in float_box()) {
        let seg = LineSegment::new(a, a + (c - a) * 0.3);
        prop_assert_eq!(seg.overlaps_box(&b), clip_oracle::<f64>(&[seg.a, seg.b], &b));
    }

    #[test]
    fn point_box_matches_clipping(p in int_point(), b in int_box()) {
        prop_assert_eq!(Point(p).overlaps_box(&b), clip_oracle::<Q>(&[p], &b));
    }

    /// A degenerate triangle overlaps exactly what its edges overlap.
    #[test]
    fn degenerate_triangle_is_its_segment(a in int_point(), c in int_point(), k in -2i32..=3, b in int_box()) {
        let tri = Triangle::new(a, c, a + (c - a) * k as f32);
        let far = [tri.a, tri.b, tri.c].into_iter().fold((tri.a, tri.a), |(lo, hi), p| {
            // the two extreme points along the line
            let d = c - a;
            (if p.dot(d) < lo.dot(d) { p } else { lo }, if p.dot(d) > hi.dot(d) { p } else { hi })
        });
        prop_assert_eq!(tri.overlaps_box(&b), LineSegment::new(far.0, far.1).overlaps_box(&b));
    }

    /// The projection API: every point of the shape projects inside its
    /// interval, and a separating axis really separates.
    #[test]
    fn projection_intervals_are_shadows(tri in float_triangle(), b in float_box(), axis in float_point(), u in 0.0f32..1.0, v in 0.0f32..1.0) {
        let ti = tri.project(axis);
        let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
        let p = tri.a + (tri.b - tri.a) * u + (tri.c - tri.a) * v;
        let pp = Point(p).project(axis).min;
        let slack = 1e-5 * (1.0 + axis.length() as f64 * 4.0);
        prop_assert!(ti.min - slack <= pp && pp <= ti.max + slack);
        let bi = b.project(axis);
        prop_assert_eq!(bi, project_points(&b.corners(), axis));
        if separated_along(&tri, &b, axis) {
            prop_assert!(!clip_oracle::<f64>(&tri_points(&tri), &b));
        }
    }
}

#[test]
fn interval_rules() {
    let a = Interval::new(0.0, 1.0);
    assert!(a.overlaps(&Interval::new(1.0, 2.0)), "touching intervals overlap");
    assert!(a.separated_from(&Interval::new(1.0 + 1e-12, 2.0)));
    assert_eq!(Interval::from_values([3.0, -1.0, 2.0]), Interval::new(-1.0, 3.0));
    // A zero axis never separates.
    let tri = Triangle::new(Vec3::splat(5.0), Vec3::splat(6.0), Vec3::new(5.0, 6.0, 5.0));
    assert!(!separated_along(&tri, &Aabb::new(Vec3::ZERO, Vec3::ONE), Vec3::ZERO));
}

/// Hand-made cases: faces, edges and corners of the box, axis-aligned and
/// degenerate triangles.
#[test]
fn touching_and_degenerate_cases() {
    let unit = Aabb::new(Vec3::ZERO, Vec3::ONE);
    let v = Vec3::new;
    let cases: &[(&str, Triangle, bool)] = &[
        (
            "in the top face plane",
            Triangle::new(v(0.2, 0.2, 1.0), v(0.8, 0.2, 1.0), v(0.2, 0.8, 1.0)),
            true,
        ),
        (
            "in the top face plane, outside",
            Triangle::new(v(1.2, 0.2, 1.0), v(1.8, 0.2, 1.0), v(1.2, 0.8, 1.0)),
            false,
        ),
        (
            "covering the top face",
            Triangle::new(v(-5.0, -5.0, 1.0), v(10.0, -5.0, 1.0), v(-5.0, 10.0, 1.0)),
            true,
        ),
        (
            "just above the top face",
            Triangle::new(v(-5.0, -5.0, 1.0001), v(10.0, -5.0, 1.0001), v(-5.0, 10.0, 1.0001)),
            false,
        ),
        (
            "in the plane x = 1 beside the box",
            Triangle::new(v(1.0, 1.5, 0.0), v(1.0, 3.0, 0.0), v(1.0, 1.5, 1.0)),
            false,
        ),
        (
            "edge along the box edge x=1,y=1",
            Triangle::new(v(1.0, 1.0, -1.0), v(1.0, 1.0, 2.0), v(2.0, 2.0, 0.5)),
            true,
        ),
        (
            "vertex on the corner",
            Triangle::new(v(1.0, 1.0, 1.0), v(2.0, 1.0, 1.0), v(1.0, 2.0, 2.0)),
            true,
        ),
        (
            "edge through the corner",
            Triangle::new(v(2.0, 0.0, 1.0), v(0.0, 2.0, 1.0), v(3.0, 3.0, 3.0)),
            true,
        ),
        (
            "edge passing by the corner",
            Triangle::new(v(2.0, 0.1, 1.0), v(0.1, 2.0, 1.0), v(3.0, 3.0, 3.0)),
            false,
        ),
        (
            "plane through the corner only",
            Triangle::new(v(3.0, 0.0, 0.0), v(0.0, 3.0, 0.0), v(0.0, 0.0, 3.0)),
            true,
        ),
        (
            "plane beyond the corner",
            Triangle::new(v(3.1, 0.0, 0.0), v(0.0, 3.1, 0.0), v(0.0, 0.0, 3.1)),
            false,
        ),
        (
            "zero-area: collinear, crossing",
            Triangle::new(v(-1.0, 0.5, 0.5), v(0.0, 0.5, 0.5), v(2.0, 0.5, 0.5)),
            true,
        ),
        (
            "zero-area: collinear, beside",
            Triangle::new(v(-1.0, 1.5, 0.5), v(0.0, 1.5, 0.5), v(2.0, 1.5, 0.5)),
            false,
        ),
        (
            "zero-area: repeated vertex, touching",
            Triangle::new(v(1.0, 1.0, 0.5), v(1.0, 1.0, 0.5), v(2.0, 2.0, 0.5)),
            true,
        ),
        (
            "a point inside",
            Triangle::new(v(0.5, 0.5, 0.5), v(0.5, 0.5, 0.5), v(0.5, 0.5, 0.5)),
            true,
        ),
        (
            "a point outside",
            Triangle::new(v(1.5, 0.5, 0.5), v(1.5, 0.5, 0.5), v(1.5, 0.5, 0.5)),
            false,
        ),
        (
            "collinear diagonal missing the corner",
            Triangle::new(v(1.1, 0.0, 0.0), v(2.0, -0.9, 0.0), v(3.0, -1.9, 0.0)),
            false,
        ),
        (
            "the box inside the triangle's plane slab",
            Triangle::new(v(-9.0, -9.0, 0.5), v(9.0, -9.0, 0.5), v(0.0, 9.0, 0.5)),
            true,
        ),
    ];
    for (name, tri, expected) in cases {
        assert_eq!(tri.overlaps_box(&unit), *expected, "{name}");
        assert_eq!(
            clip_oracle::<f64>(&tri.vertices(), &unit),
            *expected,
            "oracle disagrees on {name}"
        );
    }
    // Zero-width boxes (a face of a cell, a point).
    let face = Aabb::new(v(0.0, 0.0, 1.0), v(1.0, 1.0, 1.0));
    assert!(Triangle::new(v(0.5, 0.5, 0.0), v(0.5, 0.5, 2.0), v(0.6, 0.5, 1.0)).overlaps_box(&face));
    let point = Aabb::new(v(1.0, 1.0, 1.0), v(1.0, 1.0, 1.0));
    assert!(Triangle::new(v(0.0, 0.0, 0.0), v(2.0, 2.0, 2.0), v(2.0, 0.0, 0.0)).overlaps_box(&point));
}

/// Real triangles (every 7th of every shared mesh) against boxes around
/// them: SAT agrees with f64 clipping.
#[test]
fn real_triangles_match_clipping() {
    let mut rng = proxima::sample::Rng::new(7);
    let mut checked = 0;
    for path in common::shared_meshes().iter().take(6) {
        let mesh = proxima::io::load(path).unwrap();
        let tris = mesh.triangles().primitives;
        let scale = mesh.bounds().diagonal() / 200.0;
        for tri in tris.iter().step_by(7) {
            let c = tri.center();
            for _ in 0..3 {
                let min = c + Vec3::new(rng.range(-2.0, 1.0), rng.range(-2.0, 1.0), rng.range(-2.0, 1.0)) * scale;
                let b = Aabb::new(
                    min,
                    min + Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0)) * scale,
                );
                assert_eq!(
                    tri.overlaps_box(&b),
                    clip_oracle::<f64>(&tri.vertices(), &b),
                    "{tri:?} {b:?}"
                );
                checked += 1;
            }
        }
    }
    println!("{checked} real triangle/box pairs checked");
}

// ------------------------------------------------------------- ray/tri ---

/// Möller–Trumbore in f64: the independent oracle for the watertight test.
fn moller_trumbore(o: Vec3, d: Vec3, t: &Triangle) -> Option<(f64, f64, f64)> {
    let f = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let (o, d, a, b, c) = (f(o), f(d), f(t.a), f(t.b), f(t.c));
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let cross = |p: [f64; 3], q: [f64; 3]| {
        [
            p[1] * q[2] - p[2] * q[1],
            p[2] * q[0] - p[0] * q[2],
            p[0] * q[1] - p[1] * q[0],
        ]
    };
    let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let (e1, e2) = (sub(b, a), sub(c, a));
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = sub(o, a);
    let u = dot(s, p) / det;
    let q = cross(s, e1);
    let v = dot(d, q) / det;
    let t = dot(e2, q) / det;
    Some((t, u, v))
}

#[test]
fn watertight_ray_matches_moller_trumbore() {
    let mut rng = proxima::sample::Rng::new(11);
    let mut hits = 0;
    for _ in 0..200_000 {
        let p = |rng: &mut proxima::sample::Rng| {
            Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
        };
        let tri = Triangle::new(p(&mut rng), p(&mut rng), p(&mut rng));
        let o = p(&mut rng) * 3.0;
        // Aimed at a point of the triangle's plane near it, so about half hit.
        let (u, v) = (rng.range(-0.3, 1.0), rng.range(-0.3, 1.0));
        let d = (tri.a + (tri.b - tri.a) * u + (tri.c - tri.a) * v - o).normalize_or(Vec3::X);
        let ray = WatertightRay::new(o, d).unwrap();
        let got = ray.intersect(&tri, 0.0, f32::INFINITY);
        // Grazing rays are ill-conditioned for f32; the tolerances below hold
        // when the ray meets the plane at more than ~6 degrees.
        let grazing = tri.scaled_normal().normalize_or_zero().dot(d).abs() < 0.1;
        match moller_trumbore(o, d, &tri) {
            Some(_) if grazing => {}
            Some((t, u, v)) => {
                let margin = u.min(v).min(1.0 - u - v);
                if margin > 1e-4 && t > 1e-4 {
                    let hit = got.unwrap_or_else(|| panic!("missed {tri:?} from {o:?} along {d:?}"));
                    assert!((hit.t as f64 - t).abs() < 1e-4 * (1.0 + t), "t {} vs {t}", hit.t);
                    assert!((hit.u as f64 - u).abs() < 1e-3 && (hit.v as f64 - v).abs() < 1e-3);
                    hits += 1;
                } else if margin < -1e-4 || t < -1e-4 {
                    assert!(got.is_none(), "false hit {tri:?} from {o:?} along {d:?}: {got:?}");
                }
            }
            None => assert!(got.is_none()),
        }
    }
    assert!(hits > 30_000, "only {hits} hits exercised");
}

/// Rays from the centre of a closed star-shaped mesh, aimed exactly at
/// vertices and edge midpoints, never slip through.
#[test]
fn watertight_rays_do_not_slip_through_shared_edges() {
    let mesh = proxima::mesh::generate::noisy_icosphere(12, 3);
    let tris = mesh.triangles().primitives;
    let positions = mesh.positions();
    let edges = mesh.edge_indices();
    let mut targets: Vec<Vec3> = positions.to_vec();
    targets.extend(
        edges
            .iter()
            .map(|&[a, b]| (positions[a as usize] + positions[b as usize]) * 0.5),
    );
    for origin in [Vec3::ZERO, Vec3::new(0.01, -0.02, 0.03)] {
        for &target in &targets {
            let ray = WatertightRay::new(origin, target - origin).unwrap();
            assert!(
                tris.iter().any(|t| ray.intersect(t, 0.0, f32::INFINITY).is_some()),
                "ray towards {target:?} slipped through"
            );
        }
    }
}
