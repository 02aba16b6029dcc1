//! The sphere tree's own shape: every bounding sphere holds its points (checked
//! in f64), the tight one is never larger than Ritter's, merges hold both.
//! Its answers against brute force, and its hierarchy equal to the AABB
//! tree's, are checked by the suite every structure runs (`structures.rs`).

use proptest::prelude::*;
use proxima::{Sphere, Vec3};

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
}
