//! Frustum queries against independent oracles.
//!
//! - Points: the clip-space test `-w <= x, y, z <= w` on `M·(p, 1)` in f64.
//! - Segments and triangles: clipping in homogeneous clip space (f64) by the
//!   six half-spaces `w ± x >= 0`, `w ± y >= 0`, `w ± z >= 0` (Liang–Barsky
//!   for segments, Sutherland–Hodgman for triangles); the primitive overlaps
//!   when something is left. The map `p -> M·(p, 1)` is affine, so clipping
//!   there is clipping in world space, with no perspective division.
//! - Trees: the same index set as brute force, for every primitive type and
//!   build configuration, on random soups and on the real meshes.

use crate::common::{bumpy_sphere, random_soup, shared_meshes};
use proptest::prelude::*;
use proxima::frustum::{Cull, Frustum, FrustumOverlap, PlaneMask};
use proxima::math::Vec4;
use proxima::math::camera;
use proxima::prelude::*;
use proxima::sample::Rng;
use proxima::{
    Aabb, AabbTree, BuildConfig, FrustumError, LineSegment, LinearSearch, Mat4, Mesh, Point, PrimitiveSet, Triangle,
    Vec3,
};

// ---------------------------------------------------------------- oracles

/// Clip coordinates `M·(p, 1)` in f64.
fn clip(m: &Mat4, p: Vec3) -> [f64; 4] {
    let c = m.to_cols_array();
    let p = [p.x as f64, p.y as f64, p.z as f64, 1.0];
    std::array::from_fn(|row| (0..4).map(|col| c[col * 4 + row] as f64 * p[col]).sum())
}

/// The six clip-space half-space functions, each `>= 0` inside.
fn boundaries(h: &[f64; 4]) -> [f64; 6] {
    [
        h[3] + h[0],
        h[3] - h[0],
        h[3] + h[1],
        h[3] - h[1],
        h[3] + h[2],
        h[3] - h[2],
    ]
}

fn point_oracle(m: &Mat4, p: Vec3) -> bool {
    boundaries(&clip(m, p)).iter().all(|&v| v >= 0.0)
}

fn lerp(a: &[f64; 4], b: &[f64; 4], t: f64) -> [f64; 4] {
    std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t)
}

/// Liang–Barsky in homogeneous clip space.
fn segment_oracle(m: &Mat4, a: Vec3, b: Vec3) -> bool {
    let (ha, hb) = (clip(m, a), clip(m, b));
    let (da, db) = (boundaries(&ha), boundaries(&hb));
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for k in 0..6 {
        let (u, v) = (da[k], db[k]);
        if u < 0.0 && v < 0.0 {
            return false;
        }
        if u < 0.0 {
            t0 = t0.max(u / (u - v));
        } else if v < 0.0 {
            t1 = t1.min(u / (u - v));
        }
    }
    t0 <= t1
}

/// Sutherland–Hodgman in homogeneous clip space; non-empty means overlap.
fn triangle_oracle(m: &Mat4, t: &Triangle) -> bool {
    let mut polygon: Vec<[f64; 4]> = t.vertices().iter().map(|&v| clip(m, v)).collect();
    for k in 0..6 {
        let mut next = Vec::with_capacity(polygon.len() + 2);
        for i in 0..polygon.len() {
            let (a, b) = (&polygon[i], &polygon[(i + 1) % polygon.len()]);
            let (u, v) = (boundaries(a)[k], boundaries(b)[k]);
            if u >= 0.0 {
                next.push(*a);
            }
            if (u >= 0.0) != (v >= 0.0) && (u < 0.0 || v < 0.0) && u != v {
                let t = u / (u - v);
                if t > 0.0 && t < 1.0 {
                    next.push(lerp(a, b, t));
                }
            }
        }
        if next.is_empty() {
            return false;
        }
        polygon = next;
    }
    true
}

// ---------------------------------------------------------------- cameras

/// A random camera: perspective or orthographic, looking from a random eye
/// toward a random target near the unit cube.
fn random_camera(rng: &mut Rng) -> (Mat4, Frustum) {
    loop {
        let eye = Vec3::new(rng.range(-3.0, 4.0), rng.range(-3.0, 4.0), rng.range(-3.0, 4.0));
        let target = Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        let up = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let near = rng.range(0.05, 2.0);
        let far = near + rng.range(0.2, 6.0);
        let aspect = rng.range(0.5, 2.0);
        let view = camera::look_at_mat4(eye, target, up);
        let projection = if rng.below(3) == 0 {
            let half = rng.range(0.2, 1.5);
            camera::orthographic(
                -half * aspect,
                half * aspect * rng.range(0.5, 1.0),
                -half,
                half,
                near,
                far,
            )
        } else {
            camera::perspective(rng.range(10.0, 120.0).to_radians(), aspect, near, far)
        };
        let m = projection * view;
        if let Ok(f) = Frustum::from_view_projection(m) {
            return (m, f);
        }
    }
}

/// The frustum `|x|, |y| <= -z`, `1 <= -z <= 3` (90° field of view), whose
/// matrix entries are small integers: its planes and corners are exact, so
/// touching cases really touch.
fn exact_perspective() -> (Mat4, Frustum) {
    let m = Mat4::from_cols(
        Vec4::new(1.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -2.0, -1.0),
        Vec4::new(0.0, 0.0, -3.0, 0.0),
    );
    (m, Frustum::from_view_projection(m).unwrap())
}

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
    Triangle::new(Vec3::from(a), Vec3::from(b), Vec3::from(c))
}

// ---------------------------------------------------------------- primitive tests vs oracles

fn random_triangle(rng: &mut Rng) -> Triangle {
    let center = Vec3::new(rng.range(-2.0, 3.0), rng.range(-2.0, 3.0), rng.range(-2.0, 3.0));
    let size = [0.05, 0.5, 3.0][rng.below(3)];
    let mut v = [Vec3::ZERO; 3];
    for p in &mut v {
        *p = center + Vec3::new(rng.range(-size, size), rng.range(-size, size), rng.range(-size, size));
    }
    match rng.below(10) {
        0 => v[2] = v[0],                       // repeated vertex
        1 => v[2] = v[0] + (v[1] - v[0]) * 2.5, // collinear
        2 => v = [v[0]; 3],                     // a point
        _ => {}
    }
    Triangle::new(v[0], v[1], v[2])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn points_match_the_clip_space_test(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let (m, f) = random_camera(&mut rng);
        for _ in 0..200 {
            let p = Vec3::new(rng.range(-3.0, 4.0), rng.range(-3.0, 4.0), rng.range(-3.0, 4.0));
            prop_assert_eq!(Point(p).overlaps_frustum(&f), point_oracle(&m, p), "point {}", p);
        }
    }

    #[test]
    fn segments_match_homogeneous_clipping(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let (m, f) = random_camera(&mut rng);
        for _ in 0..200 {
            let t = random_triangle(&mut rng);
            let s = LineSegment::new(t.a, t.b);
            prop_assert_eq!(s.overlaps_frustum(&f), segment_oracle(&m, s.a, s.b), "segment {:?}", s);
        }
    }

    #[test]
    fn triangles_match_sutherland_hodgman(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let (m, f) = random_camera(&mut rng);
        for _ in 0..200 {
            let t = random_triangle(&mut rng);
            prop_assert_eq!(t.overlaps_frustum(&f), triangle_oracle(&m, &t), "triangle {:?}", t);
        }
    }

    /// Culling never contradicts the exact tests: an `Outside` box holds no
    /// inside point, an `Inside` box no outside point, and a child classified
    /// with its parent's mask gets the answer it gets with all planes.
    #[test]
    fn box_and_sphere_culling_is_conservative(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let (_, f) = random_camera(&mut rng);
        for _ in 0..100 {
            let center = Vec3::new(rng.range(-3.0, 4.0), rng.range(-3.0, 4.0), rng.range(-3.0, 4.0));
            let half = Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let b = Aabb::new(center - half, center + half);
            let samples: Vec<Vec3> = b.corners().into_iter().chain((0..20).map(|_| rng.in_box(&b))).collect();
            let cull = f.classify_box(&b, PlaneMask::ALL);
            match cull {
                Cull::Outside => prop_assert!(samples.iter().all(|&p| !f.contains_point(p))),
                Cull::Inside => prop_assert!(samples.iter().all(|&p| f.contains_point(p))),
                Cull::Partial(mask) => {
                    let child = Aabb::new(center - half * 0.5, center + half * 0.3);
                    let full = f.classify_box(&child, PlaneMask::ALL);
                    let masked = f.classify_box(&child, mask);
                    match full {
                        Cull::Partial(m) => prop_assert_eq!(masked, Cull::Partial(PlaneMask(m.0 & mask.0))),
                        other => prop_assert_eq!(masked, other),
                    }
                }
            }
            let radius = half.length();
            let sphere_points: Vec<Vec3> = samples
                .iter()
                .map(|&p| center + (p - center).normalize_or_zero() * radius * rng.range(0.0, 1.0))
                .collect();
            match f.classify_sphere(center, radius, PlaneMask::ALL) {
                // The ball holds the box: its verdict, when certain, is the box's.
                Cull::Outside => {
                    prop_assert!(sphere_points.iter().all(|&p| !f.contains_point(p)));
                    prop_assert_eq!(cull, Cull::Outside);
                }
                Cull::Inside => {
                    prop_assert!(sphere_points.iter().all(|&p| f.contains_point(p)));
                    prop_assert_eq!(cull, Cull::Inside);
                }
                Cull::Partial(_) => {}
            }
        }
    }
}

/// Any matrix: an error or a frustum whose corners lie on its planes, and
/// whose exact tests agree with clipping. Cameras with every entry perturbed
/// are general projective maps: near and far planes are no longer parallel,
/// so all twelve edge directions matter.
#[test]
fn arbitrary_matrices_are_errors_or_consistent_frustums() {
    let mut rng = Rng::new(99);
    let mut valid = 0;
    for case in 0..600 {
        let m = if case % 3 == 0 {
            // Entirely random: mostly errors (some corner behind the eye); must not panic.
            Mat4::from_cols_array(&std::array::from_fn(|_| rng.range(-2.0, 2.0)))
        } else {
            let (m, _) = random_camera(&mut rng);
            let scale = m.to_cols_array().iter().fold(0f32, |a, x| a.max(x.abs()));
            let noise = Mat4::from_cols_array(&std::array::from_fn(|_| rng.range(-0.15, 0.15) * scale));
            m + noise
        };
        let Ok(f) = Frustum::from_view_projection(m) else {
            continue;
        };
        valid += 1;
        for c in f.corners() {
            let scale = c.iter().map(|x| x.abs()).fold(1.0, f64::max);
            for p in f.planes() {
                let distance = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] + p[3];
                assert!(
                    distance >= -1e-9 * scale * (1.0 + p[3].abs()),
                    "corner {c:?} outside plane {p:?}"
                );
            }
        }
        let lo = f
            .corners()
            .iter()
            .fold([f64::INFINITY; 3], |a, c| std::array::from_fn(|k| a[k].min(c[k])));
        let hi = f
            .corners()
            .iter()
            .fold([f64::NEG_INFINITY; 3], |a, c| std::array::from_fn(|k| a[k].max(c[k])));
        let mut around = || {
            Vec3::from(std::array::from_fn::<f32, 3, _>(|k| {
                let (a, b) = (lo[k] as f32, hi[k] as f32);
                let margin = 0.3 * (b - a);
                rng.range(a - margin, b + margin)
            }))
        };
        for _ in 0..100 {
            let t = Triangle::new(around(), around(), around());
            assert_eq!(t.overlaps_frustum(&f), triangle_oracle(&m, &t), "{t:?} in {m:?}");
            let s = LineSegment::new(t.a, t.b);
            assert_eq!(s.overlaps_frustum(&f), segment_oracle(&m, s.a, s.b), "{s:?}");
            assert_eq!(f.contains_point(t.c), point_oracle(&m, t.c));
        }
    }
    assert!(valid > 200, "only {valid} valid frustums");
}

// ---------------------------------------------------------------- touching, deliberately

#[test]
fn exact_frustum_corners_and_planes() {
    let (_, f) = exact_perspective();
    let expected = [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-3.0, -3.0, -3.0],
        [3.0, -3.0, -3.0],
        [-3.0, 3.0, -3.0],
        [3.0, 3.0, -3.0],
    ];
    for (c, e) in f.corners().iter().zip(expected) {
        for k in 0..3 {
            assert!((c[k] - e[k]).abs() < 1e-12, "{c:?} vs {e:?}");
        }
    }
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let left = f.planes()[0];
    assert!((left[0] - s).abs() < 1e-15 && (left[2] + s).abs() < 1e-15 && left[3] == 0.0);
    let near = f.planes()[4];
    assert_eq!(near, [0.0, 0.0, -1.0, -1.0]);
}

#[test]
fn points_on_the_boundary_are_inside() {
    let (m, f) = exact_perspective();
    // (on the boundary, just outside it)
    let cases = [
        ([2.0, 0.0, -2.0], [2.001, 0.0, -2.0]),   // right face
        ([0.0, -2.5, -2.5], [0.0, -2.501, -2.5]), // bottom face
        ([-2.0, 0.0, -2.0], [-2.001, 0.0, -2.0]), // left face
        ([0.0, 0.0, -1.0], [0.0, 0.0, -0.999]),   // near face
        ([0.5, 0.5, -3.0], [0.5, 0.5, -3.001]),   // far face
        ([1.0, 1.0, -1.0], [1.001, 1.0, -1.0]),   // a near corner
        ([-3.0, 3.0, -3.0], [-3.0, 3.0, -3.001]), // a far corner
    ];
    for (on, out) in cases {
        let (on, out) = (Vec3::from(on), Vec3::from(out));
        assert!(f.contains_point(on), "{on}");
        assert!(point_oracle(&m, on), "{on}");
        assert!(!f.contains_point(out), "{out}");
        assert!(!point_oracle(&m, out), "{out}");
    }
}

#[test]
fn triangles_touching_at_one_vertex_overlap() {
    let (m, f) = exact_perspective();
    let cases = [
        // A vertex on the left face (x = z), the others beyond it.
        (tri([-2.0, 0.0, -2.0], [-3.0, 0.5, -2.0], [-3.0, -0.5, -2.25]), true),
        (tri([-2.001, 0.0, -2.0], [-3.0, 0.5, -2.0], [-3.0, -0.5, -2.25]), false),
        // A vertex on the near face, the others between it and the eye.
        (tri([0.0, 0.0, -1.0], [0.25, 0.0, -0.5], [-0.25, 0.25, -0.5]), true),
        (tri([0.0, 0.0, -0.999], [0.25, 0.0, -0.5], [-0.25, 0.25, -0.5]), false),
        // A vertex on the far face.
        (tri([0.5, 0.5, -3.0], [0.5, 0.5, -4.0], [0.0, 1.0, -5.0]), true),
        (tri([0.5, 0.5, -3.001], [0.5, 0.5, -4.0], [0.0, 1.0, -5.0]), false),
        // A vertex at the right-top-near corner, the rest outside past it.
        (tri([1.0, 1.0, -1.0], [2.0, 2.0, -0.5], [2.0, 1.5, 0.0]), true),
        (tri([1.001, 1.0, -1.0], [2.0, 2.0, -0.5], [2.0, 1.5, 0.0]), false),
        // An edge lying in the bottom face.
        (tri([0.0, -2.0, -2.0], [0.5, -2.5, -2.5], [0.0, -5.0, -2.0]), true),
        // Straddling the left and near planes, but passing outside their
        // common edge (at depth 1 the edge is at x = -1.25): outside.
        (tri([-2.0, 0.0, -1.5], [-0.5, 0.0, -0.5], [-2.0, 0.0, -0.5]), false),
        // The same, crossing inside the edge.
        (tri([-1.5, 0.0, -1.5], [-0.5, 0.0, -0.5], [-2.0, 0.0, -0.5]), true),
        // Enclosing the whole frustum (a big triangle across it).
        (
            tri([-100.0, -100.0, -2.0], [100.0, -100.0, -2.0], [0.0, 100.0, -2.0]),
            true,
        ),
    ];
    for (t, expected) in cases {
        assert_eq!(t.overlaps_frustum(&f), expected, "{t:?}");
        assert_eq!(triangle_oracle(&m, &t), expected, "oracle {t:?}");
        let s = LineSegment::new(t.a, t.b);
        assert_eq!(s.overlaps_frustum(&f), segment_oracle(&m, s.a, s.b), "{s:?}");
    }
    // Segments touching at an end point, or along a face.
    let segments = [
        (
            LineSegment::new(Vec3::new(2.0, 0.0, -2.0), Vec3::new(3.0, 0.0, -2.0)),
            true,
        ),
        (
            LineSegment::new(Vec3::new(2.001, 0.0, -2.0), Vec3::new(3.0, 0.0, -2.0)),
            false,
        ),
        (
            LineSegment::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(-3.0, -3.0, -3.0)),
            true,
        ),
        (
            LineSegment::new(Vec3::new(-5.0, 0.0, -2.0), Vec3::new(5.0, 0.0, -2.0)),
            true,
        ),
        (
            LineSegment::new(Vec3::new(-5.0, 0.0, -0.5), Vec3::new(5.0, 0.0, -0.5)),
            false,
        ),
    ];
    for (s, expected) in segments {
        assert_eq!(s.overlaps_frustum(&f), expected, "{s:?}");
        assert_eq!(segment_oracle(&m, s.a, s.b), expected, "oracle {s:?}");
    }
}

#[test]
fn orthographic_touching_cases() {
    let m = camera::orthographic(-1.0, 1.0, -1.0, 1.0, 1.0, 3.0);
    let f = Frustum::from_view_projection(m).unwrap();
    // The box -1 <= x, y <= 1, -3 <= z <= -1.
    let cases = [
        (tri([1.0, 0.0, -2.0], [2.0, 0.0, -2.0], [2.0, 1.0, -2.5]), true),
        (tri([1.0, 0.0, -2.0], [2.0, 0.0, -2.0], [2.0, 1.0, -2.5]), true),
        (tri([1.0, 1.0, -3.0], [2.0, 2.0, -4.0], [2.0, 1.0, -3.5]), true),
        (tri([1.0, 1.5, -3.0], [2.0, 2.0, -4.0], [2.0, 1.0, -3.5]), false),
        (tri([-0.5, -0.5, 0.0], [0.5, -0.5, 0.0], [0.0, 0.5, -1.0]), true),
    ];
    for (t, expected) in cases {
        assert_eq!(t.overlaps_frustum(&f), expected, "{t:?}");
        assert_eq!(triangle_oracle(&m, &t), expected, "oracle {t:?}");
    }
    assert!(f.contains_point(Vec3::new(-1.0, 1.0, -1.0)));
    assert!(!f.contains_point(Vec3::new(-1.0, 1.0, -0.999_999)));
}

// ---------------------------------------------------------------- degenerate input

#[test]
fn degenerate_matrices_are_errors() {
    let perspective = camera::perspective(1.0, 1.0, 1.0, 10.0);
    let mut nan = perspective;
    nan.x_axis.y = f32::NAN;
    let mut infinite = perspective;
    infinite.w_axis.w = f32::INFINITY;
    let repeated_rows = Mat4::from_cols(Vec4::ONE, Vec4::ONE, Vec4::Z, Vec4::W);
    // An infinite far plane: w - z no longer depends on the point.
    let infinite_far = Mat4::from_cols(
        Vec4::new(1.0, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -1.0, -1.0),
        Vec4::new(0.0, 0.0, -2.0, 0.0),
    );
    let cases = [
        (Mat4::ZERO, FrustumError::Singular),
        (nan, FrustumError::NonFinite),
        (infinite, FrustumError::NonFinite),
        (repeated_rows, FrustumError::Singular),
        (infinite_far, FrustumError::ZeroNormal { plane: "far" }),
        // Negated: every clip corner maps to w < 0, nothing is kept.
        (-perspective, FrustumError::NoVolume),
        // Nearly singular: the rows are dependent up to f32 noise.
        (
            Mat4::from_cols(Vec4::X, Vec4::X * (1.0 + 1e-7), Vec4::Z, Vec4::W),
            FrustumError::Singular,
        ),
    ];
    for (m, expected) in cases {
        assert_eq!(Frustum::from_view_projection(m), Err(expected.clone()), "{m:?}");
    }
    // Identity (the cube [-1, 1]³) and a projection flipped in x are fine.
    assert!(Frustum::from_view_projection(Mat4::IDENTITY).is_ok());
    assert!(Frustum::from_view_projection(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) * perspective).is_ok());
}

#[test]
fn bad_cameras_are_errors() {
    let (eye, target, up) = (Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y);
    let look = |eye, target, up, fov, aspect, near, far| Frustum::look_at(eye, target, up, fov, aspect, near, far);
    assert!(look(eye, target, up, 60.0, 1.0, 0.1, 10.0).is_ok());
    for fov in [0.0, 180.0, -5.0, 200.0] {
        assert_eq!(
            look(eye, target, up, fov, 1.0, 0.1, 10.0),
            Err(FrustumError::FieldOfView { degrees: fov })
        );
    }
    assert!(matches!(
        look(eye, target, up, f32::NAN, 1.0, 0.1, 10.0),
        Err(FrustumError::FieldOfView { .. })
    ));
    for aspect in [0.0, -1.0, f32::INFINITY] {
        assert_eq!(
            look(eye, target, up, 60.0, aspect, 0.1, 10.0),
            Err(FrustumError::Aspect { aspect })
        );
    }
    for near in [0.0, -1.0, f32::INFINITY] {
        assert_eq!(
            look(eye, target, up, 60.0, 1.0, near, 10.0),
            Err(FrustumError::Near { near })
        );
    }
    for far in [0.1, 0.05, f32::INFINITY] {
        assert_eq!(
            look(eye, target, up, 60.0, 1.0, 0.1, far),
            Err(FrustumError::Far { near: 0.1, far })
        );
    }
    assert_eq!(look(eye, eye, up, 60.0, 1.0, 0.1, 10.0), Err(FrustumError::View));
    assert_eq!(
        look(eye, target, Vec3::Z, 60.0, 1.0, 0.1, 10.0),
        Err(FrustumError::View)
    );
    assert_eq!(
        look(eye, target, Vec3::ZERO, 60.0, 1.0, 0.1, 10.0),
        Err(FrustumError::View)
    );
    assert_eq!(
        look(Vec3::new(f32::NAN, 0.0, 0.0), target, up, 60.0, 1.0, 0.1, 10.0),
        Err(FrustumError::View)
    );
}

// ---------------------------------------------------------------- trees against brute force

fn configs() -> Vec<BuildConfig> {
    let d = BuildConfig::default();
    vec![
        d,
        BuildConfig::fast_queries(),
        BuildConfig { min_size: 1, ..d },
        BuildConfig { max_depth: 2, ..d },
    ]
}

/// Tree answers (AABB tree and sphere tree) equal brute force; returns how
/// many were found.
fn check_tree<T: FrustumOverlap + proxima::ClosestPoint + proxima::BoundingPoints + Copy + Send + Sync>(
    set: PrimitiveSet<T>,
    frustums: &[Frustum],
    config: &BuildConfig,
) -> usize {
    let tree = AabbTree::build_set(set.clone(), config).unwrap();
    let spheres = proxima::SphereTree::build_set(set.clone(), config).unwrap();
    let linear = LinearSearch::new(set);
    let mut reused = Vec::new();
    let mut found = 0;
    for f in frustums {
        let expected = linear.frustum(f);
        assert!(expected.windows(2).all(|w| w[0] < w[1]));
        let got = tree.frustum(f);
        assert_eq!(got, expected, "camera {:?}", f.matrix());
        let (from_spheres, sphere_stats) = spheres.frustum_with_stats(f);
        assert_eq!(from_spheres, expected, "sphere tree, camera {:?}", f.matrix());
        assert!(sphere_stats.primitives_tested <= spheres.len() as u64);
        tree.frustum_into(f, &mut reused);
        assert_eq!(reused, expected);
        let (with_stats, stats) = tree.frustum_with_stats(f);
        assert_eq!(with_stats, expected);
        assert!(stats.primitives_tested <= tree.len() as u64);
        assert!(stats.nodes_visited <= tree.node_count() as u64);
        found += expected.len();
    }
    found
}

fn check_all_kinds(mesh: &Mesh, frustums: &[Frustum], config: &BuildConfig) {
    check_tree(mesh.vertices(), frustums, config);
    check_tree(mesh.edges(), frustums, config);
    check_tree(mesh.triangles(), frustums, config);
    check_tree(mesh.polygons(), frustums, config);
}

fn random_cameras(n: usize, seed: u64) -> Vec<Frustum> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| random_camera(&mut rng).1).collect()
}

#[test]
fn tree_equals_brute_force_on_random_soups() {
    let frustums = random_cameras(40, 11);
    for (i, mesh) in [random_soup(3000, 1), random_soup(50, 2), bumpy_sphere(12, 3)]
        .iter()
        .enumerate()
    {
        for config in configs() {
            check_all_kinds(mesh, &frustums, &config);
        }
        // Cameras that see part of it, all of it, or none of it: the answer is not trivial.
        let counts: Vec<usize> = frustums
            .iter()
            .map(|f| check_tree(mesh.triangles(), std::slice::from_ref(f), &BuildConfig::default()))
            .collect();
        let n = mesh.triangles().len();
        assert!(counts.iter().any(|&c| c > 0 && c < n), "mesh {i}: {counts:?}");
        assert!(counts.contains(&0), "mesh {i}: {counts:?}");
    }
}

#[test]
fn empty_and_single_primitive_trees() {
    let f = exact_perspective().1;
    let empty: AabbTree<Point> = AabbTree::build(Vec::new(), &Default::default()).unwrap();
    assert!(empty.frustum(&f).is_empty());
    let one = AabbTree::build(vec![Point(Vec3::new(0.0, 0.0, -2.0))], &Default::default()).unwrap();
    assert_eq!(one.frustum(&f), [0]);
    // Points exactly on the planes, in a tree: boxes touching a plane must not be culled.
    let boundary: Vec<Point> = [
        [1.0, 0.0, -2.0],
        [0.0, 0.0, -1.0],
        [3.0, 3.0, -3.0],
        [1.0, 1.0, -1.0],
        [3.0001, 0.0, -3.0],
        [0.0, 0.0, -0.9999],
    ]
    .iter()
    .map(|&p| Point(Vec3::from(p)))
    .collect();
    for config in configs() {
        let tree = AabbTree::build(boundary.clone(), &config).unwrap();
        assert_eq!(tree.frustum(&f), [0, 1, 2, 3]);
    }
}

/// Cameras for a real mesh: from outside looking at it, from inside along
/// each axis, with near and far planes cutting through it, orthographic.
fn mesh_cameras(mesh: &Mesh) -> Vec<(&'static str, Frustum)> {
    let b = mesh.bounds();
    let (c, d) = (b.center(), b.diagonal());
    let mut out = Vec::new();
    let up_for = |dir: Vec3| if dir.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
    for dir in [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::new(1.0, 1.0, 1.0).normalize()] {
        let up = up_for(dir);
        let mut add = |name, eye: Vec3, fov, near, far| {
            out.push((name, Frustum::look_at(eye, eye + dir, up, fov, 1.3, near, far).unwrap()));
        };
        add("outside, whole", c - dir * 2.0 * d, 40.0, 0.01 * d, 10.0 * d);
        add("outside, narrow", c - dir * 2.0 * d, 4.0, 0.01 * d, 10.0 * d);
        add("inside", c, 70.0, 0.001 * d, 2.0 * d);
        add("near and far cut it", c - dir * 0.6 * d, 50.0, 0.45 * d, 0.75 * d);
        let view = camera::look_at_mat4(c - dir * d, c, up);
        let ortho = camera::orthographic(-0.2 * d, 0.3 * d, -0.25 * d, 0.1 * d, 0.8 * d, 1.1 * d);
        out.push(("orthographic", Frustum::from_view_projection(ortho * view).unwrap()));
    }
    out
}

#[test]
fn tree_equals_brute_force_and_oracles_on_shared_meshes() {
    for path in shared_meshes() {
        let mesh = proxima::io::load(&path).unwrap();
        let cameras = mesh_cameras(&mesh);
        let frustums: Vec<Frustum> = cameras.iter().map(|(_, f)| f.clone()).collect();
        let big = mesh.face_count() > 200_000;
        let triangles = mesh.triangles();
        let counts = if big {
            vec![check_tree(triangles.clone(), &frustums, &BuildConfig::default())]
        } else {
            check_all_kinds(&mesh, &frustums, &BuildConfig::fast_queries());
            vec![check_tree(triangles.clone(), &frustums, &BuildConfig::default())]
        };
        // The oracle, primitive by primitive, on a few cameras.
        let limit = if big { 2 } else { cameras.len() };
        let mut partial = 0;
        for (name, f) in cameras.iter().take(limit) {
            let m = f.matrix();
            let mut hits = 0;
            for t in &triangles.primitives {
                let expected = triangle_oracle(&m, t);
                assert_eq!(t.overlaps_frustum(f), expected, "{}: {name}: {t:?}", path.display());
                hits += expected as usize;
            }
            for &p in mesh.positions() {
                assert_eq!(
                    Point(p).overlaps_frustum(f),
                    point_oracle(&m, p),
                    "{}: {name}",
                    path.display()
                );
            }
            partial += (hits > 0 && hits < triangles.len()) as usize;
        }
        assert!(partial > 0, "{}: every camera saw all or nothing", path.display());
        println!(
            "{}: {} cameras, {:?} triangles found",
            path.display(),
            cameras.len(),
            counts
        );
    }
}

/// A look-at camera is built in `f64`, so `f32` overflow or underflow of a
/// squared length no longer passes for a bad view: an `up` of
/// `(1e-45, 1e-45, 0)` or `(0, 3e38, 0)` is a direction like any other, and
/// a target 1e-25 from the eye a view direction (all were `View` errors).
/// What an `f32` matrix cannot hold is named instead: a value beyond `f32`,
/// a `far / near` beyond its depth resolution, an eye too far from the
/// origin for its near plane.
#[test]
fn look_at_cameras_are_built_in_f64() {
    let (eye, target) = (Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
    let look = |eye, target, up, near, far| Frustum::look_at(eye, target, up, 60.0, 1.0, near, far);
    let diagonal_up = look(eye, target, Vec3::new(1.0, 1.0, 0.0), 1.0, 10.0).unwrap();
    assert_eq!(
        look(eye, target, Vec3::new(1e-45, 1e-45, 0.0), 1.0, 10.0),
        Ok(diagonal_up)
    );
    let upright = look(eye, target, Vec3::Y, 1.0, 10.0).unwrap();
    assert_eq!(
        look(eye, target, Vec3::new(0.0, 3e38, 0.0), 1.0, 10.0),
        Ok(upright.clone())
    );
    let close = Vec3::new(0.0, 0.0, 5.0 - 1e-6);
    assert_eq!(look(eye, close, Vec3::Y, 1.0, 10.0), Ok(upright.clone()));
    let tiny = look(Vec3::new(0.0, 0.0, 1e-25), Vec3::ZERO, Vec3::Y, 1.0, 10.0).unwrap();
    // The clip-space oracle on the camera's own matrix: in view between
    // near and far on the axis, not behind the eye nor beyond far.
    for (f, z) in [(&upright, 5.0), (&tiny, 0.0)] {
        let m = f.matrix();
        for (p, inside) in [(z - 2.0, true), (z - 9.5, true), (z + 1.0, false), (z - 11.0, false)] {
            let p = Vec3::new(0.1, -0.1, p);
            assert_eq!(point_oracle(&m, p), inside, "{p}");
            assert_eq!(f.contains_point(p), inside, "{p}");
        }
    }

    let far_eye = Vec3::new(1e30, 0.0, 0.0);
    let error = look(far_eye, Vec3::ZERO, Vec3::Y, 1.0, 1e31).unwrap_err();
    assert!(
        matches!(&error, FrustumError::Projection { error, .. } if **error == FrustumError::ZeroNormal { plane: "far" }),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("near = 1, far = 1e31 (far / near = 1e31)"),
        "{error}"
    );
    // The same depth range at the origin fails alike: the projection is to blame.
    assert!(matches!(
        look(eye, target, Vec3::Y, 1.0, 1e31),
        Err(FrustumError::Projection { .. })
    ));
    let error = look(far_eye, Vec3::ZERO, Vec3::Y, 1.0, 1e7).unwrap_err();
    assert!(matches!(error, FrustumError::EyeTooFar { .. }), "{error:?}");
    assert!(
        error.to_string().starts_with("the eye lies 1e30 from the origin"),
        "{error}"
    );
    assert!(
        look(eye, target, Vec3::Y, 1.0, 1e7).is_ok(),
        "the same projection at the origin holds"
    );
    let error = look(Vec3::splat(3e38), Vec3::ZERO, Vec3::Y, 1e37, 3e38).unwrap_err();
    assert!(
        matches!(error, FrustumError::Overflow { what: "eye distance along a view axis", value } if value < -3.4e38),
        "{error:?}"
    );
    let error = Frustum::look_at(eye, target, Vec3::Y, 60.0, 1e-40, 1.0, 10.0).unwrap_err();
    assert!(
        matches!(
            error,
            FrustumError::Overflow {
                what: "horizontal scale cot(fov / 2) / aspect",
                ..
            }
        ),
        "{error:?}"
    );
    // Still refused as a view: parallel, zero and non-finite vectors.
    assert_eq!(
        look(eye, target, Vec3::new(0.0, 1e-45, 1.0), 1.0, 10.0),
        Err(FrustumError::View)
    );
    assert_eq!(look(eye, eye, Vec3::Y, 1.0, 10.0), Err(FrustumError::View));
}
