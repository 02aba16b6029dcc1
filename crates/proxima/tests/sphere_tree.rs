//! The sphere tree against brute force and against the AABB tree: closest,
//! closest-within and k-nearest answers must be identical on every field, for
//! every primitive type, build configuration and kind of query; every node's
//! sphere must hold its primitives' vertices.

mod common;

use common::{bumpy_sphere, queries, random_soup, shared_meshes};
use proptest::prelude::*;
use proxima::bvh::SplitMethod;
use proxima::prelude::*;
use proxima::{
    AabbTree, BoundingPoints, BuildConfig, ClosestPoint, LineSegment, LinearSearch, Mesh, Point, PrimitiveSet, Sphere,
    SphereTree, Triangle, Vec3,
};

fn configs() -> Vec<BuildConfig> {
    let d = BuildConfig::default();
    vec![
        d,
        BuildConfig { min_size: 1, ..d },
        BuildConfig { min_size: 7, ..d },
        BuildConfig { max_depth: 1, ..d },
        BuildConfig {
            max_depth: 3,
            min_size: 2,
            split: SplitMethod::Median,
        },
        BuildConfig::fast_queries(),
    ]
}

/// Checks the sphere tree against linear search and the AABB tree on `points`.
fn check<T: ClosestPoint + BoundingPoints + Copy + Send + Sync + std::fmt::Debug>(
    set: PrimitiveSet<T>,
    points: &[Vec3],
    config: &BuildConfig,
    ks: &[usize],
) {
    let tree = SphereTree::build_set(set.clone(), config).unwrap();
    tree.validate().unwrap();
    let boxes = AabbTree::build_set(set.clone(), config).unwrap();
    assert_eq!(tree.stats(), boxes.stats(), "same hierarchy as the AABB tree");
    let linear = LinearSearch::new(set);
    let mut scratch = KnnScratch::new();
    let mut out = Vec::new();
    for &p in points {
        let expected = linear.closest(p);
        assert_eq!(tree.closest(p), expected, "closest at {p}, config {config:?}");
        assert_eq!(boxes.closest(p), expected, "AABB tree at {p}");
        let (hit, stats) = tree.closest_with_stats(p);
        assert_eq!(hit, expected);
        assert!(stats.primitives_tested >= expected.is_some() as u64 && stats.nodes_visited >= 1);
        if let Some(e) = expected {
            for max in [e.distance * 2.0, e.distance * 1.000001, e.distance * 0.5, 0.0] {
                assert_eq!(
                    tree.closest_within(p, max),
                    boxes.closest_within(p, max),
                    "within {max} at {p}"
                );
            }
        }
        for &k in ks {
            let want = linear.k_nearest(p, k);
            assert_eq!(tree.k_nearest(p, k), want, "k = {k} at {p}");
            tree.k_nearest_into(p, k, &mut scratch, &mut out);
            assert_eq!(out, want, "k = {k} at {p}, reused scratch");
        }
    }
}

fn check_mesh(mesh: &Mesh, n_queries: usize, config: &BuildConfig, ks: &[usize]) {
    let points = queries(mesh, n_queries, 7);
    check(mesh.vertices(), &points, config, ks);
    check(mesh.edges(), &points, config, ks);
    check(mesh.triangles(), &points, config, ks);
}

#[test]
fn random_soups_match_brute_force_and_the_aabb_tree() {
    for seed in 0..3 {
        let mesh = random_soup(300 + 50 * seed as usize, seed);
        for config in configs() {
            check_mesh(&mesh, 50, &config, &[0, 1, 5, 10_000]);
        }
    }
}

#[test]
fn bumpy_sphere_inside_and_out() {
    let mesh = bumpy_sphere(12, 3);
    check_mesh(&mesh, 200, &BuildConfig::default(), &[3]);
    let inside: Vec<Vec3> = (0..20).map(|i| Vec3::splat(i as f32 * 0.01)).collect();
    check(mesh.triangles(), &inside, &BuildConfig::default(), &[2]);
}

#[test]
fn large_mesh_parallel_build() {
    let mesh = bumpy_sphere(60, 5);
    assert!(mesh.triangle_count() > 70_000);
    let points = queries(&mesh, 30, 11);
    check(mesh.triangles(), &points, &BuildConfig::default(), &[2]);
}

#[test]
fn degenerate_inputs() {
    let empty: SphereTree<Triangle> = SphereTree::build(Vec::new(), &BuildConfig::default()).unwrap();
    assert_eq!(empty.closest(Vec3::ZERO), None);
    assert!(empty.k_nearest(Vec3::ZERO, 3).is_empty());
    assert_eq!(empty.stats().nodes, 0);
    empty.validate().unwrap();
    let one = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    check_mesh(&one, 20, &BuildConfig::default(), &[0, 1, 2, 9]);
    let same = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]; 50]).unwrap();
    check_mesh(&same, 20, &BuildConfig::default(), &[1, 7]);
    let point = Mesh::from_triangles(vec![Vec3::ONE; 3], &[[0, 1, 2]; 9]).unwrap();
    check_mesh(&point, 10, &BuildConfig::default(), &[1, 4]);
    for (scale, offset) in [(1e15f32, 0.0f32), (1e-30, 0.0), (1e-3, 1e7), (1.0, -3e5)] {
        let positions = (0..30)
            .map(|i| Vec3::new(i as f32 % 5.0, (i / 5) as f32, (i % 3) as f32) * scale + Vec3::splat(offset))
            .collect();
        let tris: Vec<[u32; 3]> = (0..28).map(|i| [i, i + 1, i + 2]).collect();
        let m = Mesh::from_triangles(positions, &tris).unwrap();
        check_mesh(&m, 30, &BuildConfig::default(), &[1, 3]);
    }
}

#[test]
fn non_finite_queries_and_bad_input() {
    let mesh = random_soup(50, 1);
    let tree = SphereTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    for p in [Vec3::NAN, Vec3::new(f32::INFINITY, 0.0, 0.0)] {
        assert_eq!(tree.closest(p), None);
        assert!(tree.k_nearest(p, 3).is_empty());
    }
    let bad = vec![Point(Vec3::new(0.0, f32::NAN, 0.0))];
    assert!(SphereTree::build(bad, &BuildConfig::default()).is_err());
    let zero_depth = BuildConfig {
        max_depth: 0,
        ..Default::default()
    };
    assert!(SphereTree::build_set(mesh.triangles(), &zero_depth).is_err());
}

/// Spheres against an independent check: every point inside, and the tight
/// sphere never larger than Ritter's nor smaller than half the widest pair.
#[test]
fn bounding_spheres_hold_their_points() {
    let mut rng = proxima::sample::Rng::new(5);
    for n in [1usize, 2, 3, 10, 1000] {
        for scale in [1e-20f32, 1.0, 1e20] {
            let points: Vec<Vec3> = (0..n)
                .map(|_| Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 3.0), rng.range(0.0, 0.1)) * scale)
                .collect();
            let ritter = Sphere::from_points(&points).unwrap();
            let tight = Sphere::from_points_tight(&points).unwrap();
            let mut widest = 0.0f64;
            for a in &points {
                for b in points.iter().take(50) {
                    widest = widest.max(a.as_dvec3().distance(b.as_dvec3()));
                }
            }
            for s in [ritter, tight] {
                assert!(points.iter().all(|&p| s.contains_point(p)), "{s:?}");
                assert!(s.radius as f64 >= 0.5 * widest * (1.0 - 1e-6));
            }
            assert!(tight.radius <= ritter.radius, "{tight:?} {ritter:?}");
            let other = Sphere::new(points[0] * 2.0 + Vec3::ONE * scale, 0.3 * scale);
            let merged = tight.merge(&other);
            assert!(merged.contains(&tight) && merged.contains(&other));
            assert!(
                merged.radius <= tight.radius.max(other.radius) + tight.center.distance(other.center) + 1e-6 * scale
            );
        }
    }
}

#[test]
fn real_meshes_match_brute_force() {
    for path in shared_meshes() {
        let mesh = proxima::io::load(&path).unwrap();
        let n = (2_000_000 / mesh.triangle_count().max(1)).clamp(4, 100);
        println!(
            "{}: {} triangles, {n} queries per kind",
            path.display(),
            mesh.triangle_count()
        );
        check_mesh(&mesh, n, &BuildConfig::default(), &[4]);
    }
}

/// A random soup whose kind is chosen by `mode`: spread, all identical,
/// collinear, one primitive; coordinates scaled and offset.
fn soup(mode: u8, n: usize, scale: f32, offset: f32, seed: u64) -> Vec<Triangle> {
    let mut rng = proxima::sample::Rng::new(seed);
    let mut v = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
    let first = Triangle::new(v(), v(), v());
    let tris: Vec<Triangle> = match mode {
        0 => (0..n).map(|_| Triangle::new(v(), v(), v())).collect(),
        1 => vec![first; n],
        2 => {
            let dir = v();
            (0..n)
                .map(|i| {
                    let t = i as f32 * 0.37;
                    Triangle::new(dir * t, dir * (t + 0.5), dir * (t - 0.2))
                })
                .collect()
        }
        _ => vec![first],
    };
    let f = |p: Vec3| p * scale + Vec3::splat(offset);
    tris.into_iter()
        .map(|t| Triangle::new(f(t.a), f(t.b), f(t.c)))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Bounding spheres hold every point (checked in f64), at any scale and
    /// offset; the tight one is never larger than Ritter's; merges hold both.
    #[test]
    fn spheres_hold_their_points(
        raw in prop::collection::vec((-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0), 1..60),
        scale in prop::sample::select(vec![1e-30f32, 1e-6, 1.0, 1e4, 1e20]),
        offset in prop::sample::select(vec![0.0f32, 1.0, -1e4, 1e7]),
        flat in any::<bool>(),
    ) {
        let points: Vec<Vec3> = raw
            .iter()
            .map(|&(x, y, z)| Vec3::new(x, y, if flat { 0.0 } else { z }) * scale + Vec3::splat(offset))
            .collect();
        let ritter = Sphere::from_points(&points).unwrap();
        let tight = Sphere::from_points_tight(&points).unwrap();
        prop_assert!(tight.radius <= ritter.radius);
        for s in [ritter, tight] {
            for &p in &points {
                prop_assert!(s.contains_point(p), "{:?} outside {:?}", p, s);
            }
        }
        let (half, rest) = points.split_at(points.len() / 2);
        if let (Some(a), Some(b)) = (Sphere::from_points_tight(half), Sphere::from_points_tight(rest)) {
            let m = a.merge(&b);
            prop_assert!(m.contains(&a) && m.contains(&b), "{:?} {:?} {:?}", a, b, m);
            for &p in &points {
                prop_assert!(m.contains_point(p));
            }
        }
    }

    #[test]
    fn random_and_degenerate_sets_match_brute_force(
        mode in 0u8..4,
        n in 1usize..80,
        scale in prop::sample::select(vec![1e-30f32, 1e-6, 1.0, 1e4, 1e15]),
        offset in prop::sample::select(vec![0.0f32, 1.0, -1e4, 1e7]),
        min_size in 1u32..6,
        seed in 0u64..1000,
        queries in prop::collection::vec((-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0), 1..12),
    ) {
        let tris = soup(mode, n, scale, offset, seed);
        let config = BuildConfig { min_size, ..BuildConfig::default() };
        let mut points: Vec<Vec3> = queries.iter().map(|&(x, y, z)| Vec3::new(x, y, z) * scale + Vec3::splat(offset)).collect();
        points.push(tris[0].a);
        let segments: Vec<LineSegment> = tris.iter().map(|t| LineSegment::new(t.a, t.b)).collect();
        let vertices: Vec<Point> = tris.iter().map(|t| Point(t.c)).collect();
        check(PrimitiveSet::from_primitives(tris), &points, &config, &[1, 3, 100]);
        check(PrimitiveSet::from_primitives(segments), &points, &config, &[2]);
        check(PrimitiveSet::from_primitives(vertices), &points, &config, &[1, 5]);
    }
}
