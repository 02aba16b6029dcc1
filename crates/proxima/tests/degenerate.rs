//! Every structure on the table of degenerate inputs (`tests/common/degenerate.rs`):
//! empty, one triangle, identical primitives, zero-area and collinear
//! triangles, repeated vertices and zero-length edges, tiny, large and huge
//! coordinates, small features far from the origin, faces lying on cell
//! boundaries; queries on vertices, edges, faces and cell corners, rays from
//! cell corners.
//!
//! Oracles (shared with the fuzz targets, `fuzz/bodies.rs`): trees must equal
//! `LinearSearch` on every field; grids must give each primitive exactly the
//! cells its own overlap test accepts (for the dyadic cases; otherwise within
//! 4 f32 epsilons of the coordinates' magnitude, see `check_cells_loosely`);
//! `first_hit` must equal a scan of every triangle; walks must equal the
//! cell-by-cell oracle.

use crate::bodies;

use crate::common::degenerate::{Case, cases};
use crate::common::exact::{ExactBox, triangle_touches_exact_box};
use proxima::build::{MAX_COORDINATE, SplitMethod};
use proxima::grid::GridTraversal;
use proxima::grid::{GridConfig, GridLayout, HashGrid, VoxelConfig, voxelize};
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, BuildError, GridError, LinearSearch, Point, PrimitiveSet, Triangle, Vec3};

fn configs() -> [BuildConfig; 3] {
    [
        BuildConfig {
            min_size: 1,
            ..BuildConfig::default()
        },
        BuildConfig {
            split: SplitMethod::BinnedSah,
            ..BuildConfig::default()
        },
        BuildConfig {
            max_depth: 1,
            ..BuildConfig::default()
        },
    ]
}

fn tree_cases() -> impl Iterator<Item = Case> {
    cases().into_iter().filter(|c| !c.beyond_tree_bound)
}

#[test]
fn trees_equal_brute_force_on_every_case() {
    for case in tree_cases() {
        println!("{}", case.name);
        let queries = case.queries();
        for config in configs() {
            for wide in [false, true] {
                bodies::check_tree(case.triangle_set(), &config, &queries, 3, wide);
                bodies::check_tree(case.segment_set(), &config, &queries, 3, wide);
                bodies::check_tree(case.point_set(), &config, &queries, 3, wide);
            }
        }
    }
}

#[test]
fn grids_equal_brute_force_on_every_case() {
    for case in cases() {
        for (cell, origin) in [
            (case.cell, 0.0),
            (case.cell * 0.5, case.cell * 0.25),
            (case.cell * 2.0, 0.0),
        ] {
            println!("{} cell {cell} origin {origin}", case.name);
            let config = GridConfig {
                origin: Vec3::splat(origin),
                max_cells_per_primitive: 1 << 16,
                ..GridConfig::cubic(cell)
            };
            let exact = case.exact;
            bodies::check_grid(&case.point_set(), &config, exact).expect("small cases fit");
            bodies::check_grid(&case.segment_set(), &config, exact).expect("small cases fit");
            let grid = bodies::check_grid(&case.triangle_set(), &config, exact).expect("small cases fit");
            let queries = case.queries();
            // Rays from every query (cell corners, vertices, edge midpoints) to
            // every vertex and to a few other queries.
            for &from in &queries {
                for &to in case.positions.iter().chain(queries.iter().step_by(7)) {
                    bodies::check_first_hit(&grid, from, to - from, exact);
                }
            }
        }
    }
}

#[test]
fn walks_from_cell_corners_edges_and_faces_equal_the_oracle() {
    let layout = GridLayout::new(Vec3::new(0.0, 0.5, -0.25), Vec3::new(0.5, 0.25, 1.0)).unwrap();
    // Round extents: every plane is an f32, so these points lie ON them.
    let b = |i: i64, j: i64, k: i64| {
        let (lo, _) = layout.cell_bounds([i, j, k]);
        assert_eq!(lo.as_vec3().as_dvec3(), lo);
        lo.as_vec3()
    };
    let corner = b(1, -2, 3);
    let starts = [
        corner,
        (corner + b(2, -2, 3)) * 0.5, // on a cell edge
        (corner + b(2, -1, 3)) * 0.5, // on a cell face
        (corner + b(2, -1, 4)) * 0.5, // a cell center
    ];
    let mut directions = Vec::new();
    for x in [-1.0f32, 0.0, 0.5, 1.0] {
        for y in [-0.25f32, 0.0, 0.25] {
            for z in [-1.0f32, 0.0, 1.0] {
                directions.push(Vec3::new(x, y, z));
            }
        }
    }
    // Exact diagonals through cell corners.
    directions.push(layout.cell_size());
    directions.push(layout.cell_size() * Vec3::new(-1.0, 1.0, -1.0));
    let mut compared = 0;
    for &o in &starts {
        for &d in &directions {
            if d == Vec3::ZERO {
                assert_eq!(
                    GridTraversal::in_layout(&layout, o, d, 0.0, 1.0).unwrap_err(),
                    GridError::Ray(proxima::RayError::Direction)
                );
                continue;
            }
            for (t_min, t_max) in [(0.0, 6.0), (-2.0, 3.0), (1.0, 1.0)] {
                let got: Vec<_> = GridTraversal::in_layout(&layout, o, d, t_min, t_max).unwrap().collect();
                assert_eq!(got, bodies::brute_walk(&layout, o, d, t_min, t_max), "o {o} d {d}");
                compared += got.len();
            }
        }
    }
    println!("{compared} cells compared");
}

#[test]
fn voxelization_of_degenerate_cases() {
    for case in cases() {
        let tris = case.triangle_set().primitives;
        if tris.is_empty() {
            continue;
        }
        let bounds = proxima::Aabb::from_points(case.positions.iter().copied());
        match voxelize(&tris, &bounds, &VoxelConfig::new(4)) {
            Ok(voxels) => {
                // Exactly the cells the exact oracle finds some triangle touching.
                let layout = *voxels.layout();
                let (origin, size) = (layout.origin(), layout.cell_size());
                let mut want: Vec<_> = tris
                    .iter()
                    .flat_map(|t| {
                        // The library's range widened by a cell: the oracle decides the edges.
                        let range = layout.cell_range(&proxima::Bounded::bounds(t)).unwrap();
                        let range = proxima::grid::CellRange {
                            min: range.min.map(|i| i - 1),
                            max: range.max.map(|i| i + 1),
                        };
                        range
                            .iter()
                            .filter(|&c| triangle_touches_exact_box(t, &ExactBox::of_cell(origin, size, c)))
                            .collect::<Vec<_>>()
                    })
                    .filter(|c| c.iter().all(|&i| (0..4).contains(&i)))
                    .collect();
                want.sort_unstable();
                want.dedup();
                let mut got = voxels.cells();
                got.sort_unstable();
                if case.exact {
                    assert_eq!(got, want, "{}", case.name);
                } else {
                    assert!(!got.is_empty(), "{}", case.name);
                }
            }
            // A flat or point-like bounding box has no cube to divide.
            Err(e) => assert_eq!(e, GridError::DegenerateBounds, "{}", case.name),
        }
    }
}

#[test]
fn coordinates_beyond_the_tree_bound_are_a_typed_error() {
    let huge = cases().into_iter().find(|c| c.beyond_tree_bound).unwrap();
    let e = AabbTree::build_set(huge.triangle_set(), &BuildConfig::default()).unwrap_err();
    assert_eq!(
        e,
        BuildError::CoordinateTooLarge {
            index: 0,
            bound: MAX_COORDINATE
        }
    );
    assert!(e.to_string().contains("beyond"), "{e}");
    assert!(WideTree::build_set(huge.point_set(), &BuildConfig::default()).is_err());
    // Brute force has no build step: its squared distances overflow, and it
    // answers None rather than a meaningless primitive.
    assert_eq!(
        LinearSearch::new(huge.triangle_set()).closest(Vec3::new(-1e30, 0.0, 0.0)),
        None
    );
    // One coordinate just past the bound is enough; the index is reported.
    let mut points = vec![Point(Vec3::ZERO); 3];
    points[2] = Point(Vec3::new(0.0, -MAX_COORDINATE.next_up(), 0.0));
    assert_eq!(
        AabbTree::build(points, &BuildConfig::default()).unwrap_err(),
        BuildError::CoordinateTooLarge {
            index: 2,
            bound: MAX_COORDINATE
        }
    );
    // Grids: a cell index beyond ±2^52 is a typed error naming the primitive.
    let far = PrimitiveSet::from_primitives(vec![Point(Vec3::ZERO), Point(Vec3::splat(1e30))]);
    assert_eq!(
        HashGrid::<Point>::build(far, &GridConfig::cubic(1e-10)).unwrap_err(),
        GridError::PrimitiveOutOfRange { index: 1 }
    );
}

#[test]
fn distances_stay_finite_up_to_the_bound() {
    // Triangles and queries at ±MAX_COORDINATE: every squared distance fits f32.
    let m = MAX_COORDINATE;
    let positions = [
        v(-m, -m, -m),
        v(m, -m, -m),
        v(-m, m, -m),
        v(m, m, m),
        v(0.0, 0.0, m),
        v(1.0, 0.0, 0.0),
    ];
    let tris = vec![
        Triangle::new(positions[0], positions[1], positions[2]),
        Triangle::new(positions[3], positions[4], positions[5]),
        Triangle::new(positions[5], positions[5], positions[0]),
    ];
    let set = PrimitiveSet::from_primitives(tris);
    let queries = [
        v(m, m, -m),
        v(-m, -m, m),
        v(0.0, 0.0, 0.0),
        v(m, -m, m),
        v(2.0 * m, -2.0 * m, 0.0),
    ];
    let linear = LinearSearch::new(set.clone());
    for &q in &queries {
        let hit = linear.closest(q).expect("finite distance");
        assert!(hit.distance.is_finite());
    }
    for config in configs() {
        bodies::check_tree(set.clone(), &config, &queries, 3, false);
        bodies::check_tree(set.clone(), &config, &queries, 3, true);
    }
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}
