//! The AABB tree's own shape: the parallel build gives the single-thread
//! tree, the median split halves, sources match primitives. Its answers
//! against brute force are checked by the suite every structure runs
//! (`structures.rs`).

use crate::common::{bumpy_sphere, random_soup};
use proxima::build::SplitMethod;
use proxima::{AabbTree, BuildConfig, Vec3};

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

/// The bad configurations and primitives every structure refuses are in the
/// suite (`structures.rs`); sources are the binary tree's own.
#[test]
fn sources_must_match_the_primitives() {
    let tris = random_soup(10, 2).triangles();
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
