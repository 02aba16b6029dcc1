//! The AABB tree against brute force: closest and k-nearest answers must be
//! identical (primitive, point, distance), for every primitive type, build
//! configuration, and kind of query.

mod common;

use common::{bumpy_sphere, queries, random_soup, shared_meshes};
use proxima::bvh::SplitMethod;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, ClosestPoint, LinearSearch, Mesh, PrimitiveSet, Vec3};

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
    ]
}

/// Checks tree against linear search on `points`, for closest, best-first,
/// k-nearest and batch queries.
fn check<T: ClosestPoint + Copy + Send + Sync + std::fmt::Debug>(
    set: PrimitiveSet<T>,
    points: &[Vec3],
    config: &BuildConfig,
    ks: &[usize],
) {
    let tree = AabbTree::build_set(set.clone(), config).unwrap();
    tree.validate().unwrap();
    let linear = LinearSearch::new(set);
    for &p in points {
        let expected = linear.closest(p);
        assert_eq!(tree.closest(p), expected, "closest at {p}, config {config:?}");
        #[cfg(feature = "experimental")]
        assert_eq!(tree.closest_best_first(p), expected, "best-first at {p}");
        for &k in ks {
            assert_eq!(tree.k_nearest(p, k), linear.k_nearest(p, k), "k = {k} at {p}");
        }
    }
    let batch = tree.closest_batch(points);
    for (i, &p) in points.iter().enumerate() {
        assert_eq!(batch[i], linear.closest(p));
    }
    // Every batch configuration gives the same answers.
    for options in common::batch_options() {
        assert_eq!(tree.closest_batch_with(points, options), batch, "{options:?}");
    }
    if let Some(&k) = ks.iter().max() {
        let batch = tree.k_nearest_batch(points, k);
        for (i, &p) in points.iter().enumerate() {
            assert_eq!(batch[i], linear.k_nearest(p, k));
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
fn random_soups_match_brute_force() {
    for seed in 0..4 {
        let mesh = random_soup(300 + 50 * seed as usize, seed);
        for config in configs() {
            check_mesh(&mesh, 60, &config, &[0, 1, 5, 10_000]);
        }
    }
}

#[test]
fn bumpy_sphere_matches_brute_force_inside_and_out() {
    let mesh = bumpy_sphere(12, 3);
    assert_eq!(mesh.triangle_count(), 20 * 144);
    check_mesh(&mesh, 200, &BuildConfig::default(), &[3]);
    // Deep inside a closed mesh every primitive is far: the hardest case.
    let inside: Vec<Vec3> = (0..20).map(|i| Vec3::splat(i as f32 * 0.01)).collect();
    check(mesh.triangles(), &inside, &BuildConfig::default(), &[2]);
}

#[test]
fn large_meshes_use_the_parallel_build_and_stay_exact() {
    // Above 32k primitives subtrees are built in parallel and joined.
    let mesh = bumpy_sphere(60, 5);
    assert!(mesh.triangle_count() > 70_000);
    let points = queries(&mesh, 40, 11);
    for split in [SplitMethod::Median, SplitMethod::BinnedSah] {
        check(
            mesh.triangles(),
            &points,
            &BuildConfig {
                split,
                ..BuildConfig::default()
            },
            &[2],
        );
    }
}

#[test]
fn parallel_build_gives_the_single_thread_tree_and_median_halves() {
    // Above 32k primitives the top nodes are split before the subtrees are
    // built in parallel; the tree must not depend on the number of threads.
    let mesh = bumpy_sphere(60, 5);
    let triangles = mesh.triangles();
    let pool = |threads| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let (one, two) = (pool(1), pool(2));
    for split in [SplitMethod::Median, SplitMethod::BinnedSah] {
        let config = BuildConfig {
            split,
            ..BuildConfig::default()
        };
        let single = one.install(|| AabbTree::build_set(triangles.clone(), &config).unwrap());
        let parallel = two.install(|| AabbTree::build_set(triangles.clone(), &config).unwrap());
        assert!(
            single.nodes().map(|(_, n)| n).eq(parallel.nodes().map(|(_, n)| n)),
            "{split:?}"
        );
        assert!((0..single.len()).all(|slot| single.input_index(slot) == parallel.input_index(slot)));
        assert_eq!(single.depth(), parallel.depth());
        if split == SplitMethod::Median {
            // Every inner node halves its primitives: the left child holds len / 2.
            let mut stack = vec![0usize];
            while let Some(i) = stack.pop() {
                let node = single.node(i);
                if node.is_leaf() {
                    continue;
                }
                let [left, right] = node.children().map(|c| span(&single, c as usize));
                let len = left.len() + right.len();
                assert_eq!(left.len(), len / 2, "node {i}");
                assert_eq!(left.end, right.start);
                stack.extend(node.children().map(|c| c as usize));
            }
        }
    }
}

/// The primitive slots under node `i`.
fn span<T: proxima::Bounded>(tree: &AabbTree<T>, i: usize) -> std::ops::Range<usize> {
    let node = tree.node(i);
    if node.is_leaf() {
        return node.primitive_range();
    }
    let [left, right] = node.children().map(|c| span(tree, c as usize));
    left.start..right.end
}

#[test]
fn degenerate_inputs() {
    // Empty.
    let empty: AabbTree<proxima::Triangle> = AabbTree::build(Vec::new(), &BuildConfig::default()).unwrap();
    assert_eq!(empty.closest(Vec3::ZERO), None);
    assert!(empty.k_nearest(Vec3::ZERO, 3).is_empty());
    assert_eq!(empty.stats().nodes, 0);
    // One triangle, and many identical ones.
    let one = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    check_mesh(&one, 20, &BuildConfig::default(), &[0, 1, 2, 9]);
    let same = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]; 50]).unwrap();
    check_mesh(&same, 20, &BuildConfig::default(), &[1, 7]);
    // All vertices equal: every triangle and edge is a point.
    let point = Mesh::from_triangles(vec![Vec3::ONE; 3], &[[0, 1, 2]; 9]).unwrap();
    check_mesh(&point, 10, &BuildConfig::default(), &[1, 4]);
    // Huge and far-offset coordinates with small features.
    for (scale, offset) in [(1e15f32, 0.0f32), (1e-30, 0.0), (1e-3, 1e7)] {
        let positions = (0..30)
            .map(|i| Vec3::new(i as f32 % 5.0, (i / 5) as f32, (i % 3) as f32) * scale + Vec3::splat(offset))
            .collect();
        let tris: Vec<[u32; 3]> = (0..28).map(|i| [i, i + 1, i + 2]).collect();
        let m = Mesh::from_triangles(positions, &tris).unwrap();
        check_mesh(&m, 30, &BuildConfig::default(), &[1, 3]);
    }
}

#[test]
fn non_finite_queries_answer_nothing() {
    let mesh = random_soup(50, 1);
    let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    for p in [
        Vec3::NAN,
        Vec3::new(f32::INFINITY, 0.0, 0.0),
        Vec3::new(0.0, f32::NAN, 1.0),
    ] {
        assert_eq!(tree.closest(p), None);
        #[cfg(feature = "experimental")]
        assert_eq!(tree.closest_best_first(p), None);
        assert!(tree.k_nearest(p, 3).is_empty());
        // Between finite queries, whose answers seed the next search.
        let mixed = common::mixed_with(p);
        let expected: Vec<_> = mixed.iter().map(|&q| tree.closest(q)).collect();
        assert!(expected[0].is_some() && expected[1].is_none());
        for options in common::batch_options() {
            assert_eq!(tree.closest_batch_with(&mixed, options), expected, "{options:?}");
        }
    }
}

#[test]
fn bad_build_parameters_are_errors() {
    let tris = random_soup(10, 2).triangles();
    for config in [
        BuildConfig {
            max_depth: 0,
            ..Default::default()
        },
        BuildConfig {
            max_depth: 1000,
            ..Default::default()
        },
        BuildConfig {
            min_size: 0,
            ..Default::default()
        },
    ] {
        assert!(AabbTree::build_set(tris.clone(), &config).is_err());
    }
    let bad = vec![proxima::Point(Vec3::new(0.0, f32::NAN, 0.0))];
    assert!(AabbTree::build(bad, &BuildConfig::default()).is_err());
    assert!(AabbTree::build_with_sources(tris.primitives.clone(), vec![1], &BuildConfig::default()).is_err());
}

#[test]
fn classic_median_build_shape() {
    // 2^10 points, leaves of 4: a perfect tree of depth 8 with 256 leaves.
    let points: Vec<proxima::Point> = (0..1024)
        .map(|i| proxima::Point(Vec3::new(i as f32, (i * 7 % 13) as f32 * 1e-3, 0.0)))
        .collect();
    let tree = AabbTree::build(points, &BuildConfig::default()).unwrap();
    let stats = tree.stats();
    assert_eq!(
        (
            stats.depth,
            stats.leaves,
            stats.nodes,
            stats.min_leaf_size,
            stats.max_leaf_size
        ),
        (8, 256, 511, 4, 4)
    );
    // Sorted along x (the largest extent) and halved: leaf i holds x in 4i..4i+4.
    let leaf_xs: Vec<f32> = tree.primitives().iter().map(|p| p.0.x).collect();
    for (slot, chunk) in leaf_xs.chunks(4).enumerate() {
        let mut xs = chunk.to_vec();
        xs.sort_by(f32::total_cmp);
        assert_eq!(xs, (0..4).map(|j| (4 * slot + j) as f32).collect::<Vec<_>>());
    }
}

#[test]
fn real_meshes_match_brute_force() {
    for path in shared_meshes() {
        let mesh = proxima::io::load(&path).unwrap();
        // Linear search is O(n) per query: fewer queries on big meshes.
        let n = (3_000_000 / mesh.triangle_count().max(1)).clamp(4, 150);
        println!(
            "{}: {} triangles, {} queries per kind",
            path.display(),
            mesh.triangle_count(),
            n
        );
        check_mesh(&mesh, n, &BuildConfig::default(), &[4]);
    }
}
