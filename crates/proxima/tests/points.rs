//! Point clouds (`proxima::points`) against brute force: k-nearest and
//! radius search in the tree's own `f32` squared distances for the order,
//! ball membership in exact rationals, Chamfer and Hausdorff by scanning
//! every pair. Clouds: uniform, clustered, all points equal, and an integer
//! lattice where many points lie exactly on the query spheres (and the
//! radius is nudged by ulps either way).

use num_rational::BigRational;
use proxima::Vec3;
use proxima::math::Vec3A;
use proxima::points::{PointCloud, PointsError, chamfer, hausdorff};
use proxima::sample::Rng;

/// The tree's squared distance, in the same `f32` operations.
fn d2(p: Vec3, q: Vec3) -> f32 {
    (Vec3A::from(p) - Vec3A::from(q)).length_squared()
}

/// `|q - p| <= r`: in `f64` when far from the sphere (a margin of 1e-12
/// relative, a thousand times the rounding), in exact rationals otherwise.
fn inside(p: Vec3, q: Vec3, r: f64) -> bool {
    let d2 = (q.as_dvec3() - p.as_dvec3()).length_squared();
    let margin = 1e-12 * (d2 + r * r);
    if (d2 - r * r).abs() > margin {
        return d2 < r * r;
    }
    let x = |v: f64| BigRational::from_float(v).unwrap();
    let mut s = x(0.0);
    for k in 0..3 {
        let d = x(f64::from(q[k])) - x(f64::from(p[k]));
        s += &d * &d;
    }
    s <= x(r) * x(r)
}

/// The indices of `points` sorted as the queries order them: by `f32`
/// squared distance to `q`, then index.
fn by_distance(points: &[Vec3], q: Vec3, keep: impl Fn(usize) -> bool) -> Vec<u32> {
    let mut all: Vec<(f32, u32)> = (0..points.len())
        .filter(|&i| keep(i))
        .map(|i| (d2(points[i], q), i as u32))
        .collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    all.into_iter().map(|(_, i)| i).collect()
}

fn clouds(rng: &mut Rng) -> Vec<(&'static str, Vec<Vec3>)> {
    let uniform = (0..3000)
        .map(|_| Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)))
        .collect();
    let clustered = (0..3000)
        .map(|i| {
            let centre = Vec3::splat((i % 5) as f32 * 3.0);
            centre + Vec3::new(rng.range(-0.01, 0.01), rng.range(-0.01, 0.01), rng.range(-0.01, 0.01))
        })
        .collect();
    let equal = vec![Vec3::new(0.25, -0.5, 2.0); 300];
    let lattice = (0..1000)
        .map(|i| Vec3::new((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32))
        .collect();
    vec![
        ("uniform", uniform),
        ("clustered", clustered),
        ("equal", equal),
        ("lattice", lattice),
    ]
}

fn queries(rng: &mut Rng, points: &[Vec3]) -> Vec<Vec3> {
    let mut q: Vec<Vec3> = (0..60).map(|i| points[(i * 37) % points.len()]).collect();
    q.extend((0..60).map(|_| Vec3::new(rng.range(-2.0, 11.0), rng.range(-2.0, 11.0), rng.range(-2.0, 11.0))));
    // Lattice-like queries on integer and half-integer positions.
    q.extend((0..30).map(|i| Vec3::new((i % 7) as f32 * 0.5, (i % 5) as f32, 4.0)));
    q
}

#[test]
fn k_nearest_matches_brute_force_on_every_cloud() {
    let mut rng = Rng::new(39);
    for (name, points) in clouds(&mut rng) {
        let cloud = PointCloud::new(&points).unwrap();
        let q = queries(&mut rng, &points);
        for k in [1, 8, 32] {
            let batch = cloud.k_nearest_batch(&q, k).unwrap();
            for (i, &p) in q.iter().enumerate() {
                let expected: Vec<u32> = by_distance(&points, p, |_| true).into_iter().take(k).collect();
                let row = &batch.indices[i * k..(i + 1) * k];
                assert_eq!(&row[..expected.len()], &expected[..], "{name} k={k} query {i}");
                assert!(row[expected.len()..].iter().all(|&j| j == u32::MAX));
                let single: Vec<u32> = cloud.k_nearest(p, k).unwrap().iter().map(|n| n.index).collect();
                assert_eq!(single, expected);
                for (j, &index) in expected.iter().enumerate() {
                    assert_eq!(batch.distances[i * k + j], d2(points[index as usize], p).sqrt());
                }
            }
        }
    }
}

#[test]
fn radius_search_is_exact_on_the_sphere_and_ulps_off_it() {
    let mut rng = Rng::new(40);
    let mut on_sphere = 0;
    for (name, points) in clouds(&mut rng) {
        let cloud = PointCloud::new(&points).unwrap();
        let q = queries(&mut rng, &points);
        // Integer radii meet lattice points exactly (distances 1, 2, 3 and
        // the diagonals' sqrt(2)... are not f64, so 1 and 2); then nudged.
        for r in [
            0.0,
            1.0,
            1f64.next_up(),
            1f64.next_down(),
            2.0,
            2f64.next_down(),
            0.05,
            1.7,
        ] {
            let rows = cloud.within_batch(&q, r, None).unwrap();
            let counts = cloud.count_within_batch(&q, r).unwrap();
            assert_eq!(rows.len(), q.len());
            for (i, &p) in q.iter().enumerate() {
                let expected = by_distance(&points, p, |j| inside(p, points[j], r));
                on_sphere += expected
                    .iter()
                    .filter(|&&j| (f64::from(d2(points[j as usize], p)) - r * r).abs() == 0.0)
                    .count();
                assert_eq!(rows.of(i).0, &expected[..], "{name} r={r} query {i}");
                assert_eq!(counts[i] as usize, expected.len());
                let single: Vec<u32> = cloud.within(p, r, None).unwrap().iter().map(|n| n.index).collect();
                assert_eq!(single, expected);
                // The ball query: the nearest `most` of them.
                for most in [1, 5] {
                    let capped: Vec<u32> = cloud
                        .within(p, r, Some(most))
                        .unwrap()
                        .iter()
                        .map(|n| n.index)
                        .collect();
                    assert_eq!(capped, expected[..expected.len().min(most)]);
                }
            }
            let capped = cloud.within_batch(&q, r, Some(3)).unwrap();
            for i in 0..q.len() {
                let all = rows.of(i).0;
                assert_eq!(capped.of(i).0, &all[..all.len().min(3)]);
            }
        }
    }
    assert!(on_sphere > 1000, "{on_sphere} neighbours exactly on a sphere");
}

#[test]
fn pairs_within_match_brute_force() {
    let mut rng = Rng::new(41);
    for (name, points) in clouds(&mut rng) {
        let points = &points[..points.len().min(1500)];
        let cloud = PointCloud::new(points).unwrap();
        for r in [0.0, 0.03, 1.0] {
            let mut expected = Vec::new();
            for i in 0..points.len() {
                for j in i + 1..points.len() {
                    if inside(points[i], points[j], r) {
                        expected.push([i as u32, j as u32]);
                    }
                }
            }
            assert_eq!(cloud.pairs_within(r).unwrap(), expected, "{name} r={r}");
        }
    }
}

#[test]
fn chamfer_and_hausdorff_match_brute_force() {
    let mut rng = Rng::new(42);
    let all = clouds(&mut rng);
    for (na, a) in &all {
        for (nb, b) in &all {
            let (ca, cb) = (PointCloud::new(a).unwrap(), PointCloud::new(b).unwrap());
            let c = chamfer(&ca, &cb);
            // The nearest by f32 squared distance (ties by index), measured in f64.
            let nearest = |p: Vec3, to: &[Vec3]| {
                let j = (0..to.len())
                    .min_by(|&x, &y| d2(to[x], p).total_cmp(&d2(to[y], p)).then(x.cmp(&y)))
                    .unwrap();
                (to[j].as_dvec3() - p.as_dvec3()).length()
            };
            let forward: Vec<f64> = a.iter().map(|&p| nearest(p, b)).collect();
            let backward: Vec<f64> = b.iter().map(|&p| nearest(p, a)).collect();
            let sum: f64 = forward.iter().sum();
            assert_eq!(c.forward.sum, sum, "{na} -> {nb}");
            assert_eq!(c.forward.mean, sum / a.len() as f64);
            assert_eq!(c.forward.sum_squared, forward.iter().map(|d| d * d).sum::<f64>());
            assert_eq!(c.backward.sum, backward.iter().sum::<f64>());
            let max = forward.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            assert_eq!(c.forward.max, max);
            assert_eq!(
                c.forward.argmax as usize,
                forward.iter().position(|&d| d == max).unwrap()
            );
            let symmetric = max.max(backward.iter().copied().fold(f64::NEG_INFINITY, f64::max));
            assert_eq!(hausdorff(&ca, &cb), symmetric);
        }
    }
}

#[test]
fn bad_input_is_refused_with_the_argument_named() {
    let e = PointCloud::new(&[]).unwrap_err();
    assert_eq!(e.to_string(), "points: the point cloud is empty");
    let e = PointCloud::new(&[Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0)]).unwrap_err();
    assert!(matches!(e, PointsError::Build { .. }), "{e}");
    assert!(
        e.to_string()
            .starts_with("points: primitive 1 has a non-finite coordinate"),
        "{e}"
    );
    let cloud = PointCloud::new(&[Vec3::ZERO, Vec3::X]).unwrap();
    let message = |e: PointsError| e.to_string();
    assert_eq!(
        message(cloud.k_nearest(Vec3::ZERO, 0).unwrap_err()),
        "k = 0: must be between 1 and 2^31"
    );
    assert_eq!(
        message(cloud.k_nearest_batch(&[Vec3::ZERO], (1 << 31) + 1).unwrap_err()),
        "k = 2147483649: must be between 1 and 2^31"
    );
    assert_eq!(
        message(cloud.within(Vec3::ZERO, -1.0, None).unwrap_err()),
        "radius = -1: must be a non-negative number"
    );
    assert_eq!(
        message(cloud.within_batch(&[Vec3::ZERO], f64::NAN, None).unwrap_err()),
        "radius = NaN: must be a non-negative number"
    );
    assert_eq!(
        message(cloud.within(Vec3::ZERO, 1.0, Some(0)).unwrap_err()),
        "max_neighbors = 0: must be at least 1"
    );
    let e = cloud
        .within_batch(&[Vec3::ZERO, Vec3::new(0.0, f32::INFINITY, 0.0)], 1.0, None)
        .unwrap_err();
    assert_eq!(e.to_string(), "queries[1]: query point has a non-finite coordinate");
    // A k whose answers would not fit the budget is refused before allocating.
    let e = cloud.k_nearest_batch(&vec![Vec3::ZERO; 1 << 20], 1 << 30).unwrap_err();
    assert!(matches!(e, PointsError::Budget(_)), "{e}");
    assert!(e.to_string().starts_with("k 1073741824: needs about"), "{e}");
    // Infinity is a radius: every point.
    assert_eq!(cloud.within(Vec3::ZERO, f64::INFINITY, None).unwrap().len(), 2);
}

#[test]
fn radius_answers_stop_at_the_memory_budget() {
    const CHILD: &str = "PROXIMA_TEST_POINTS_BUDGET_CHILD";
    const NAME: &str = "radius_answers_stop_at_the_memory_budget";
    if std::env::var_os(CHILD).is_some() {
        // 64 KiB hold 4,096 neighbours at 16 bytes each at the peak.
        let points: Vec<Vec3> = (0..100).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        let cloud = PointCloud::new(&points).unwrap();
        assert_eq!(
            cloud.within_batch(&points[..10], 1000.0, None).unwrap().indices.len(),
            1000
        );
        let Err(e) = cloud.within_batch(&points, 1000.0, None) else {
            panic!("10,000 neighbours fit 64 KiB");
        };
        assert!(matches!(e, PointsError::Budget(_)), "{e}");
        assert!(e.to_string().starts_with("radius 1000: needs about"), "{e}");
        return;
    }
    let out = crate::common::rerun_with_budget(module_path!(), NAME, CHILD, "64K");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("1 passed"), "{stdout}");
}

#[test]
fn points_exactly_on_large_spheres_are_found() {
    // Integer offsets (a, b, c) with a² + b² + c² = d² exactly, from
    // (m² + n² - p² - q², 2(mq + np), 2(nq - mp), m² + n² + p² + q²): their
    // squares need more bits than f32 has, so the walk's f32 squared
    // distances round on either side of d², while the exact test must keep
    // every point on the sphere and drop those one unit off it.
    let mut rng = Rng::new(43);
    let mut on = 0;
    for _ in 0..200 {
        let [m, n, p, q] = [0; 4].map(|_| 20 + rng.below(70) as i64);
        let (a, b, c, d) = (
            m * m + n * n - p * p - q * q,
            2 * (m * q + n * p),
            2 * (n * q - m * p),
            m * m + n * n + p * p + q * q,
        );
        assert_eq!(a * a + b * b + c * c, d * d);
        let centre = Vec3::new(rng.below(1000) as f32, rng.below(1000) as f32, rng.below(1000) as f32);
        let mut points = Vec::new();
        for (x, y, z) in [(a, b, c), (b, c, a), (c, a, b), (-a, b, -c)] {
            for nudge in [-1, 0, 1] {
                points.push(centre + Vec3::new((x + nudge) as f32, y as f32, z as f32));
            }
        }
        let cloud = PointCloud::new(&points).unwrap();
        let r = d as f64;
        let found: Vec<u32> = cloud.within(centre, r, None).unwrap().iter().map(|n| n.index).collect();
        let expected = by_distance(&points, centre, |j| inside(centre, points[j], r));
        assert_eq!(found, expected, "{centre:?} r={r}");
        on += expected.len();
        let pairs = cloud.within_batch(&[centre], r, Some(100)).unwrap();
        assert_eq!(pairs.of(0).0, &expected[..]);
    }
    assert!(on >= 800, "{on} points on the spheres");
}
