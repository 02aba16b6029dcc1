//! Closest points on primitives against an independent f64 oracle (plane
//! projection plus edges, instead of the Voronoi-region walk under test) and
//! against dense sampling of the primitive.

use proptest::prelude::*;
use proxima::{Aabb, Bounded, ClosestPoint, LineSegment, Point, Triangle, Vec3, Vec3A};

use crate::common::oracle::{d3, dist, segment_distance, triangle_distance};

fn coord() -> impl Strategy<Value = f32> {
    prop_oneof![-10.0f32..10.0, Just(0.0f32), Just(1.0f32), -1.0f32..1.0]
}
fn vec3() -> impl Strategy<Value = Vec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}
/// Triangles including degenerate ones: repeated vertices, collinear vertices.
fn triangle() -> impl Strategy<Value = Triangle> {
    (vec3(), vec3(), vec3(), 0u8..6, -2.0f32..3.0).prop_map(|(a, b, c, kind, s)| match kind {
        0 => Triangle::new(a, a, c),
        1 => Triangle::new(a, b, a + (b - a) * s),
        2 => Triangle::new(a, a, a),
        _ => Triangle::new(a, b, c),
    })
}

fn tolerance(points: &[Vec3], p: Vec3) -> f64 {
    let scale = points
        .iter()
        .chain([&p])
        .map(|v| v.abs().max_element())
        .fold(1.0f32, f32::max);
    scale as f64 * 2e-5
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    #[test]
    fn triangle_closest_point_is_exact(t in triangle(), p in vec3()) {
        let q = t.closest_point(Vec3A::from(p));
        let tol = tolerance(&t.vertices(), p);
        let expected = triangle_distance(&t, d3(p));
        let got = dist(d3(q.into()), d3(p));
        prop_assert!((got - expected).abs() <= tol, "distance {got} vs oracle {expected}");
        // The answer lies on the triangle.
        prop_assert!(triangle_distance(&t, d3(q.into())) <= tol);
        prop_assert!(t.bounds().inflate(tol as f32).contains_point(q.into()));
        // No sampled point of the triangle is closer.
        for i in 0..=8 {
            for j in 0..=8 - i {
                let s = t.a + (t.b - t.a) * (i as f32 / 8.0) + (t.c - t.a) * (j as f32 / 8.0);
                prop_assert!(got <= dist(d3(s), d3(p)) + tol);
            }
        }
    }

    #[test]
    fn segment_closest_point_is_exact(a in vec3(), b in vec3(), zero in any::<bool>(), p in vec3()) {
        let s = LineSegment::new(a, if zero { a } else { b });
        let q: Vec3 = s.closest_point(Vec3A::from(p)).into();
        let tol = tolerance(&[s.a, s.b], p);
        prop_assert!((dist(d3(q), d3(p)) - segment_distance(d3(s.a), d3(s.b), d3(p))).abs() <= tol);
        prop_assert!(segment_distance(d3(s.a), d3(s.b), d3(q)) <= tol);
        for i in 0..=16 {
            let sample = s.a + (s.b - s.a) * (i as f32 / 16.0);
            prop_assert!(dist(d3(q), d3(p)) <= dist(d3(sample), d3(p)) + tol);
        }
    }

    #[test]
    fn point_closest_point_is_itself(a in vec3(), p in vec3()) {
        prop_assert_eq!(Vec3::from(Point(a).closest_point(Vec3A::from(p))), a);
        prop_assert_eq!(Point(a).bounds(), Aabb::new(a, a));
    }

    #[test]
    fn aabb_distance_matches_clamping(a in vec3(), b in vec3(), p in vec3()) {
        let boxed = Aabb::from_points([a, b]);
        let q = boxed.closest_point(p);
        prop_assert!(boxed.contains_point(q));
        prop_assert!((boxed.distance_squared(p) - (q - p).length_squared()).abs() <= 1e-4 * (1.0 + (q - p).length_squared()));
        prop_assert_eq!(boxed.distance_squared(p) == 0.0, boxed.contains_point(p));
    }
}

#[test]
fn triangle_regions_by_hand() {
    let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
    let cases = [
        (Vec3::new(0.25, 0.25, 1.0), Vec3::new(0.25, 0.25, 0.0)), // face
        (Vec3::new(-1.0, -1.0, 0.0), Vec3::ZERO),                 // vertex a
        (Vec3::new(2.0, -0.5, 0.0), Vec3::X),                     // vertex b
        (Vec3::new(0.5, -1.0, 3.0), Vec3::new(0.5, 0.0, 0.0)),    // edge ab
        (Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.5, 0.5, 0.0)),     // edge bc
    ];
    for (p, expected) in cases {
        assert_eq!(Vec3::from(t.closest_point(Vec3A::from(p))), expected, "query {p}");
    }
}

#[test]
fn aabb_helpers() {
    let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.0, 4.0));
    assert_eq!(b.center(), Vec3::new(1.0, 0.5, 3.0));
    assert_eq!(b.extents(), Vec3::new(2.0, 0.5, 1.0));
    assert_eq!(b.largest_axis(), 0);
    assert_eq!(b.surface_area(), 2.0 * (4.0 + 2.0 + 8.0));
    assert_eq!(b.volume(), 8.0);
    assert_eq!(b.corners()[7], b.max);
    assert_eq!(b.corners()[0], b.min);
    assert!(b.overlaps(&Aabb::new(Vec3::new(3.0, 1.0, 4.0), Vec3::splat(9.0)))); // touching counts
    assert!(!b.overlaps(&Aabb::new(Vec3::new(3.1, 1.0, 4.0), Vec3::splat(9.0))));
    assert!(Aabb::EMPTY.is_empty() && Aabb::EMPTY.merge(&b) == b);
    assert_eq!(b.distance_squared(Vec3::new(5.0, 0.5, 3.0)), 4.0);
    let inv = Vec3::new(0.0, 1.0, 0.0).recip();
    assert_eq!(
        b.ray_interval(Vec3::new(0.0, -2.0, 3.0), inv, 0.0, f32::INFINITY),
        Some((2.0, 3.0))
    );
    assert_eq!(b.ray_interval(Vec3::new(5.0, -2.0, 3.0), inv, 0.0, f32::INFINITY), None);
    assert_eq!(b.ray_interval(Vec3::new(0.0, -2.0, 3.0), inv, 0.0, 1.0), None);
}
