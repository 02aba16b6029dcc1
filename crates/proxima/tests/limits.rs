//! Resource limits: no input makes the library allocate without bound, loop
//! without end or recurse deeper than a fixed bound. Each limit has a test
//! here or in the file named beside it (see also `docs/errors.md`):
//!
//! - header counts checked against the bytes before allocating:
//!   `io.rs::ply_huge_counts_fail_fast_without_allocating`, and below;
//! - gzip decompression cap: `errors.rs::gzip_bomb`, and below;
//! - grid cells per primitive and entries per grid: below, and
//!   `grid.rs::errors_instead_of_exhaustion`;
//! - traversal step limit, `t_max` and the ±2^50 index range:
//!   `traversal.rs::huge_ranges_end`, and below;
//! - tree depth (the only recursion on user-sized data is the parallel part of
//!   the build, bounded by `MAX_DEPTH`; queries use fixed stacks): below.

mod common;

use proxima::bvh::{MAX_DEPTH, SplitMethod};
use proxima::grid::{GridConfig, HashGrid, VoxelConfig, voxelize};
use proxima::io::{Format, LoadOptions, parse};
use proxima::prelude::*;
use proxima::traversal::{GridTraversal, TraversalConfig};
use proxima::{AabbTree, BuildConfig, GridError, LinearSearch, LoadErrorKind, Point, PrimitiveSet, Vec3};
use std::io::Write;

#[test]
fn header_counts_beyond_the_input_fail_before_allocating() {
    // Each announces far more than 64 GiB; the check happens before any allocation.
    let cases: [(&[u8], Format); 4] = [
        (b"OFF\n4000000000 4000000000 0\n0 0 0\n", Format::Off),
        (
            b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty double x\nproperty double y\nproperty double z\nend_header\n",
            Format::Ply,
        ),
        (b"solid\0binary, count below", Format::Stl),
        (
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 999999999999\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
            Format::Ply,
        ),
    ];
    for (bytes, format) in cases {
        let e = parse(bytes, format, "big".as_ref()).unwrap_err();
        assert!(
            matches!(e.kind, LoadErrorKind::Implausible(_) | LoadErrorKind::Truncated(_)),
            "{e}"
        );
    }
    // A binary STL whose count needs 200 GB.
    let mut stl = vec![0u8; 80];
    stl.extend(4_000_000_000u32.to_le_bytes());
    stl.extend([0u8; 100]);
    assert!(matches!(
        parse(&stl, Format::Stl, "big.stl".as_ref()).unwrap_err().kind,
        LoadErrorKind::Truncated(_) | LoadErrorKind::Implausible(_)
    ));
}

#[test]
fn gzip_output_is_capped_whatever_the_ratio() {
    // 16 MiB of zeros, about 16 KB compressed; several members concatenated.
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    encoder.write_all(&vec![0u8; 16 << 20]).unwrap();
    let member = encoder.finish().unwrap();
    let bomb = [member.as_slice(), member.as_slice()].concat();
    for limit in [0u64, 1, 4096, (16 << 20) - 1, 16 << 20] {
        let result = proxima::io::gunzip(&bomb, limit);
        assert!(
            matches!(result, Err(LoadErrorKind::DecompressedTooLarge { limit: l }) if l == limit),
            "{limit}"
        );
    }
    assert_eq!(proxima::io::gunzip(&bomb, 32 << 20).unwrap().len(), 32 << 20);
    // 4 GiB, or less when half the available memory is less.
    let default = LoadOptions::default().max_decompressed_bytes;
    assert!(default <= 4 << 30 && default == proxima::io::default_max_input_bytes());
}

#[test]
fn grids_stop_at_their_cell_limits() {
    let tris = common::random_soup(200, 3).triangles();
    // Per primitive: checked from the box before any cell is visited.
    let config = GridConfig {
        max_cells_per_primitive: 1000,
        ..GridConfig::cubic(1e-3)
    };
    let e = HashGrid::<proxima::Triangle>::build(tris.clone(), &config).unwrap_err();
    assert!(matches!(e, GridError::PrimitiveTooLarge { limit: 1000, .. }), "{e}");
    // Per grid: a build stops once the entries pass the limit.
    let config = GridConfig {
        max_entries: 5000,
        ..GridConfig::cubic(0.01)
    };
    assert_eq!(
        HashGrid::<proxima::Triangle>::build(tris.clone(), &config).unwrap_err(),
        GridError::TooManyCells { limit: 5000 }
    );
    // Voxelization: dense storage only below its bit limit, sparse capped.
    let bounds = proxima::Aabb::new(Vec3::ZERO, Vec3::ONE);
    let config = VoxelConfig {
        dense_limit_bits: 1 << 12,
        max_occupied: 100,
        ..VoxelConfig::new(512)
    };
    assert_eq!(
        voxelize(&tris.primitives, &bounds, &config).unwrap_err(),
        GridError::TooManyCells { limit: 100 }
    );
}

#[test]
fn walks_end_at_the_step_limit_and_the_index_range() {
    let dir = Vec3::new(1.0, 0.7, -0.3);
    for max_steps in [0, 1, 17, 100_000] {
        let config = TraversalConfig {
            max_steps,
            ..TraversalConfig::cubic(1e-3)
        };
        assert_eq!(
            GridTraversal::new(Vec3::ZERO, dir, &config).unwrap().count() as u64,
            max_steps
        );
    }
    // No step limit and t up to infinity: the walk still ends, at the edge
    // of the supported index range, after about 2^50 / (cells per step)...
    // which is too long to run; starting near that edge shows it ends.
    // (The grid origin at −2^50 puts x = −64 in cell 2^50 − 64.)
    let config = TraversalConfig {
        grid_origin: Vec3::new(-(2f32.powi(50)), 0.0, 0.0),
        ..TraversalConfig::cubic(1.0)
    };
    let walk = GridTraversal::new(Vec3::new(-64.0, 0.5, 0.5), Vec3::X, &config).unwrap();
    let n = walk.count();
    assert!(n <= 65, "{n}");
}

#[test]
fn walks_end_where_t_no_longer_fits_f32() {
    // Cells of 1e36, direction (1, 0.3, 0.1) normalized (`proxima traverse`
    // printed rows at t = ∞ on and on past f32::MAX). Boundary crossings
    // along x, y and z lie at t = i · 1e36 / d, and f32 ends at 3.4028e38:
    // before the first crossing past it (x at i = 325, t = 3.4086e38) come
    // 324 crossings along x, 97 along y (the 98th is at 3.426e38) and 32
    // along z (the 33rd at 3.461e38). The walk yields those 453 cells and
    // the one it then never leaves in f32, and ends.
    let dir = Vec3::new(1.0, 0.3, 0.1).normalize();
    let walk = GridTraversal::new(Vec3::ZERO, dir, &TraversalConfig::cubic(1e36)).unwrap();
    let steps: Vec<_> = walk.take(1_000_000).collect();
    let last = steps.last().unwrap();
    assert_eq!(last.t_exit, f32::INFINITY);
    assert!(last.t_enter.is_finite() && last.t_enter > 3.39e38, "{last:?}");
    assert!(steps[..steps.len() - 1].iter().all(|s| s.t_exit.is_finite()));
    assert_eq!(steps.len(), 454, "{last:?}");
    assert_eq!(last.cell, [324, 97, 32]);
    // A finite t_max still ends the walk where it did.
    let config = TraversalConfig {
        t_max: 2.5e36,
        ..TraversalConfig::cubic(1e36)
    };
    let cells: Vec<_> = GridTraversal::new(Vec3::ZERO, Vec3::X, &config)
        .unwrap()
        .map(|s| s.cell[0])
        .collect();
    assert_eq!(cells, [0, 1, 2]);
}

#[test]
fn tree_depth_is_bounded_on_adversarial_input() {
    // All primitives identical, and a geometric series (each point halves the
    // distance to 0), which makes every split maximally unbalanced for SAH.
    let identical = vec![Point(Vec3::splat(0.5)); 50_000];
    let series: Vec<Point> = (0..50_000)
        .map(|i| Point(Vec3::new(0.5f32.powi(i % 140), 0.0, 0.0)))
        .collect();
    for points in [identical, series] {
        for split in [SplitMethod::Median, SplitMethod::BinnedSah] {
            let config = BuildConfig {
                min_size: 1,
                max_depth: MAX_DEPTH,
                split,
            };
            let tree = AabbTree::build(points.clone(), &config).unwrap();
            assert!(tree.depth() <= MAX_DEPTH);
            tree.validate().unwrap();
            let linear = LinearSearch::new(PrimitiveSet::from_primitives(points.clone()));
            let wide = WideTree::from_tree(tree.clone());
            for q in [
                Vec3::ZERO,
                Vec3::new(0.25, 0.0, 0.0),
                Vec3::splat(0.5),
                Vec3::new(1e-30, 0.0, 0.0),
            ] {
                assert_eq!(tree.closest(q), linear.closest(q));
                assert_eq!(wide.closest(q), linear.closest(q));
                assert_eq!(tree.k_nearest(q, 5), linear.k_nearest(q, 5));
            }
        }
    }
}
