//! The hash grid against brute force: cell sets from an independent
//! triangle/box oracle (Sutherland–Hodgman clipping in f64) on real and
//! degenerate meshes, scan-line insertion against classic insertion on every
//! shared mesh, voxelization against the grid, ray casting against a linear
//! scan, and the error paths.

use crate::common;

use crate::common::oracle::{D3, Q, clip_by_bounds};
use proxima::grid::{
    Cell, ClassicHash, FastHash, GridConfig, GridInsert, GridLayout, HashGrid, InsertMethod, InsertParams, VoxelConfig,
    voxelize,
};
use proxima::primitive::WatertightRay;
use proxima::sample::Rng;
use proxima::{Aabb, GridError, LineSegment, Mesh, Point, PrimitiveSet, Triangle, Vec3};
use rayon::prelude::*;
use std::collections::hash_map::RandomState;
use std::path::Path;
use std::sync::OnceLock;

// ---------------------------------------------------------------- oracle ---

/// The oracle. Decided in f64 when shrinking and growing the box by a hair
/// does not change the answer; otherwise (touching, within rounding) exactly
/// for small dyadic coordinates, and in f64 on the box itself for others.
/// The box is a grid cell with exact `f64` planes.
fn clip_oracle(points: &[Vec3], lo: D3, hi: D3) -> bool {
    let scale = points
        .iter()
        .map(|p| p.abs().max_element() as f64)
        .chain(lo.iter().chain(&hi).map(|x| x.abs()))
        .fold(0.0f64, f64::max);
    let hair = scale * 1e-6;
    let (inner_lo, inner_hi) = (lo.map(|x| x + hair), hi.map(|x| x - hair));
    if (0..3).all(|a| inner_lo[a] <= inner_hi[a]) && clip_by_bounds::<f64>(points, inner_lo, inner_hi) {
        return true;
    }
    if !clip_by_bounds::<f64>(points, lo.map(|x| x - hair), hi.map(|x| x + hair)) {
        return false;
    }
    let dyadic = |x: f64| {
        let s = x * 1024.0;
        s == s.trunc() && s.abs() < 1e9
    };
    let all = points
        .iter()
        .flat_map(|p| p.to_array().map(|x| x as f64))
        .chain(lo)
        .chain(hi)
        .all(dyadic);
    if all {
        clip_by_bounds::<Q>(points, lo, hi)
    } else {
        clip_by_bounds::<f64>(points, lo, hi)
    }
}

/// Every cell whose closed box the polygon meets, by testing every cell of a
/// generously enlarged index range with the oracle.
fn brute_cells(points: &[Vec3], layout: &GridLayout) -> Vec<Cell> {
    let b = Aabb::from_points(points.iter().copied());
    let (o, s) = (layout.origin(), layout.cell_size());
    let lo: [i64; 3] = std::array::from_fn(|a| ((b.min[a] - o[a]) / s[a]).floor() as i64 - 1);
    let hi: [i64; 3] = std::array::from_fn(|a| ((b.max[a] - o[a]) / s[a]).floor() as i64 + 1);
    let mut out = Vec::new();
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                // The cell's planes o + i · s, exact in f64 for these grids.
                let plane = |a: usize, n: i64| o[a] as f64 + n as f64 * s[a] as f64;
                let lo = [plane(0, i), plane(1, j), plane(2, k)];
                let hi = [plane(0, i + 1), plane(1, j + 1), plane(2, k + 1)];
                if clip_oracle(points, lo, hi) {
                    out.push([i, j, k]);
                }
            }
        }
    }
    out.sort_unstable();
    out
}

/// The cells of each primitive, read back from a built grid.
fn cells_per_primitive<T, S: std::hash::BuildHasher>(grid: &HashGrid<T, S>) -> Vec<Vec<Cell>> {
    let mut per = vec![Vec::new(); grid.len()];
    for (cell, prims) in grid.occupied() {
        for &p in prims {
            per[p as usize].push(cell);
        }
    }
    per.iter_mut().for_each(|c| c.sort_unstable());
    per
}

fn cells_of<T: GridInsert>(prim: &T, layout: &GridLayout, method: InsertMethod) -> Vec<Cell> {
    let mut out = Vec::new();
    let params = InsertParams {
        method,
        ..InsertParams::new(layout)
    };
    prim.visit_cells(&params, |c| out.push(c)).unwrap();
    out.sort_unstable();
    out
}

fn load(path: &Path) -> Mesh {
    proxima::io::load(path).unwrap_or_else(|e| panic!("{e}"))
}

/// Every shared mesh with its triangles, loaded once for all tests.
fn shared() -> &'static [(String, Mesh, Vec<Triangle>)] {
    static MESHES: OnceLock<Vec<(String, Mesh, Vec<Triangle>)>> = OnceLock::new();
    MESHES.get_or_init(|| {
        common::shared_meshes()
            .par_iter()
            .map(|path| {
                let mesh = load(path);
                let tris = mesh.triangles().primitives;
                (path.file_name().unwrap().to_string_lossy().into_owned(), mesh, tris)
            })
            .collect()
    })
}

/// Mean edge length of the triangles: cell sizes are chosen relative to it.
fn mean_edge(tris: &[Triangle]) -> f32 {
    let sum: f64 = tris
        .iter()
        .map(|t| ((t.b - t.a).length() + (t.c - t.b).length() + (t.a - t.c).length()) as f64)
        .sum();
    (sum / (3.0 * tris.len().max(1) as f64)) as f32
}

// ------------------------------------------------------- brute force ---

fn check_grid_against_oracle(name: &str, tris: &[Triangle], cell: Vec3, origin: Vec3, stride: usize) -> usize {
    let config = GridConfig {
        origin,
        ..GridConfig::new(cell)
    };
    let grid: HashGrid<Triangle, FastHash> =
        HashGrid::build(PrimitiveSet::from_primitives(tris.to_vec()), &config).unwrap();
    let per = cells_per_primitive(&grid);
    let layout = *grid.layout();
    let bad: Vec<usize> = (0..tris.len())
        .into_par_iter()
        .step_by(stride)
        .filter(|&p| brute_cells(&tris[p].vertices(), &layout) != per[p])
        .collect();
    assert!(
        bad.is_empty(),
        "{name}, cell {cell:?}: {} triangles differ from the oracle, first {:?}: grid {:?} oracle {:?}",
        bad.len(),
        tris[bad[0]],
        per[bad[0]],
        brute_cells(&tris[bad[0]].vertices(), &layout)
    );
    tris.len().div_ceil(stride)
}

#[test]
fn grid_matches_oracle_on_real_meshes() {
    let mut checked = 0;
    for (name, _, tris) in shared() {
        let e = mean_edge(tris);
        // Every triangle is inserted; about 1,000 per size are checked cell by
        // cell (all of them on the small meshes at the coarse size).
        let factors: &[f32] = if tris.len() < 20_000 {
            &[2.0, 0.7, 0.3]
        } else {
            &[2.0, 0.7]
        };
        for &factor in factors {
            let stride = (tris.len() / 1_000).max(1);
            // Non-cubic cells, and an origin off the world origin.
            let cell = Vec3::new(e * factor, e * factor * 1.3, e * factor * 0.8);
            checked += check_grid_against_oracle(name, tris, cell, Vec3::new(0.1, -0.2, 0.05) * e, stride);
        }
    }
    println!("{checked} triangles checked against the oracle");
}

#[test]
fn grid_matches_oracle_on_degenerate_input() {
    // Random soup with collinear triangles and repeated vertices.
    let soup = common::random_soup(3000, 5).triangles().primitives;
    for size in [0.013, 0.05, 0.21] {
        check_grid_against_oracle("soup", &soup, Vec3::splat(size), Vec3::ZERO, 1);
    }
    // Vertices exactly on cell boundaries, triangles lying in cell planes,
    // edges along cell edges, at negative coordinates too.
    let mut rng = Rng::new(9);
    let mut grid_tris = Vec::new();
    for _ in 0..1500 {
        let mut p = || {
            Vec3::new(
                rng.below(7) as f32 - 3.0,
                rng.below(7) as f32 - 3.0,
                rng.below(7) as f32 - 3.0,
            ) * 0.5
        };
        let (a, b, c) = (p(), p(), p());
        grid_tris.push(Triangle::new(a, b, c));
        grid_tris.push(Triangle::new(a, b, Vec3::new(c.x, c.y, a.z))); // in a z plane when a.z == b.z
        grid_tris.push(Triangle::new(a, a, b)); // a segment
        grid_tris.push(Triangle::new(a, a, a)); // a point
    }
    check_grid_against_oracle("boundaries", &grid_tris, Vec3::splat(0.5), Vec3::ZERO, 1);
    check_grid_against_oracle(
        "boundaries, shifted",
        &grid_tris,
        Vec3::splat(0.25),
        Vec3::splat(-0.25),
        1,
    );
    // Huge coordinates far from the grid origin.
    let far: Vec<Triangle> = soup
        .iter()
        .map(|t| {
            Triangle::new(
                t.a * 1000.0 + Vec3::splat(1e6),
                t.b * 1000.0 + Vec3::splat(1e6),
                t.c * 1000.0 + Vec3::splat(1e6),
            )
        })
        .collect();
    check_grid_against_oracle("far", &far, Vec3::splat(40.0), Vec3::ZERO, 1);
}

#[test]
fn edges_and_vertices_match_oracle() {
    let mesh = common::random_soup(2000, 8);
    let layout = GridLayout::new(Vec3::splat(-0.01), Vec3::new(0.03, 0.02, 0.05)).unwrap();
    let config = GridConfig {
        origin: layout.origin(),
        ..GridConfig::new(layout.cell_size())
    };
    let edges = mesh.edges();
    let grid: HashGrid<LineSegment, FastHash> = HashGrid::build(edges.clone(), &config).unwrap();
    let per = cells_per_primitive(&grid);
    for (p, e) in edges.primitives.iter().enumerate() {
        assert_eq!(per[p], brute_cells(&[e.a, e.b], &layout), "edge {p}: {e:?}");
        assert_eq!(per[p], cells_of(e, &layout, InsertMethod::Scanline), "edge {p}: {e:?}");
    }
    let mut verts = mesh.vertices();
    verts.primitives.push(Point(Vec3::new(0.02, 0.01, -0.01))); // a cell corner: 8 cells
    verts.sources.push(u32::MAX);
    let grid: HashGrid<Point> = HashGrid::build(verts.clone(), &config).unwrap();
    let per = cells_per_primitive(&grid);
    for (p, v) in verts.primitives.iter().enumerate() {
        assert_eq!(per[p], brute_cells(&[v.0], &layout), "vertex {p}: {v:?}");
    }
    assert_eq!(per.last().unwrap().len(), 8);
}

// --------------------------------------------------- scan-line = classic ---

#[test]
fn scanline_equals_classic_on_every_shared_mesh() {
    let mut compared = 0u64;
    for (name, mesh, tris) in shared() {
        let e = mean_edge(tris);
        // Cells of 1, 0.3 and 0.08 mean edges: about 1-4, 10 and 100 cells
        // per triangle (the last on meshes of up to 15k triangles, to keep the test short).
        let factors: &[f32] = if tris.len() > 150_000 {
            &[1.0, 0.3]
        } else {
            &[1.0, 0.3, 0.08]
        };
        for &factor in factors {
            let layout = GridLayout::new(Vec3::splat(0.37 * e), Vec3::splat(e * factor)).unwrap();
            // An order-free digest of each triangle's cell set (count and sum of
            // mixed keys) for all triangles, and the sorted sets themselves for
            // every 8th.
            let differ = tris
                .par_iter()
                .enumerate()
                .map_init(
                    || (Vec::new(), Vec::new()),
                    |(a, b), (n, t)| {
                        if n % 8 == 0 {
                            visit_into(t, &layout, InsertMethod::Classic, a);
                            visit_into(t, &layout, InsertMethod::Scanline, b);
                            a != b
                        } else {
                            digest(t, &layout, InsertMethod::Classic) != digest(t, &layout, InsertMethod::Scanline)
                        }
                    },
                )
                .filter(|&d| d)
                .count();
            assert_eq!(differ, 0, "{name}: cell {}: {differ} triangles differ", e * factor);
            compared += tris.len() as u64;
        }
        // Edges too, at one size.
        let edges = mesh.edges().primitives;
        let layout = GridLayout::cubic(e * 0.2).unwrap();
        assert!(
            edges
                .par_iter()
                .all(|s| cells_of(s, &layout, InsertMethod::Classic) == cells_of(s, &layout, InsertMethod::Scanline))
        );
    }
    println!("{compared} triangle insertions compared");
}

/// The number of cells of `prim` and the wrapping sum of a mixed hash of each.
fn digest<T: GridInsert>(prim: &T, layout: &GridLayout, method: InsertMethod) -> (u64, u64) {
    let mut d = (0u64, 0u64);
    let params = InsertParams {
        method,
        ..InsertParams::new(layout)
    };
    prim.visit_cells(&params, |c| {
        let mut x = (c[0] as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
            ^ (c[1] as u64).rotate_left(21)
            ^ (c[2] as u64).rotate_left(42);
        x = (x ^ (x >> 31)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        d = (d.0 + 1, d.1.wrapping_add(x ^ (x >> 29)));
    })
    .unwrap();
    d
}

/// The sorted cells of `prim` into a reused buffer.
fn visit_into<T: GridInsert>(prim: &T, layout: &GridLayout, method: InsertMethod, out: &mut Vec<Cell>) {
    out.clear();
    let params = InsertParams {
        method,
        ..InsertParams::new(layout)
    };
    prim.visit_cells(&params, |c| out.push(c)).unwrap();
    out.sort_unstable();
}

#[test]
fn scanline_equals_classic_on_big_and_degenerate_triangles() {
    let mut rng = Rng::new(4);
    let layout = GridLayout::new(Vec3::new(0.01, -0.02, 0.003), Vec3::new(0.05, 0.07, 0.04)).unwrap();
    for _ in 0..3000 {
        let mut p = || Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let (a, b, c) = (p(), p(), p());
        for tri in [
            Triangle::new(a, b, c),
            Triangle::new(a, b, a + (b - a) * 0.37),
            Triangle::new(a, a, b),
        ] {
            assert_eq!(
                cells_of(&tri, &layout, InsertMethod::Classic),
                cells_of(&tri, &layout, InsertMethod::Scanline),
                "{tri:?}"
            );
        }
    }
    // Axis-aligned triangles lying exactly in cell planes.
    let layout = GridLayout::cubic(0.25).unwrap();
    for tri in [
        Triangle::new(
            Vec3::new(0.0, 0.0, 0.5),
            Vec3::new(2.0, 0.0, 0.5),
            Vec3::new(0.0, 2.0, 0.5),
        ),
        Triangle::new(
            Vec3::new(0.5, -1.0, -1.0),
            Vec3::new(0.5, 1.0, -1.0),
            Vec3::new(0.5, -1.0, 1.0),
        ),
        Triangle::new(
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, 1.0, -1.0),
        ),
    ] {
        let classic = cells_of(&tri, &layout, InsertMethod::Classic);
        assert_eq!(classic, cells_of(&tri, &layout, InsertMethod::Scanline));
        assert_eq!(classic, brute_cells(&tri.vertices(), &layout));
    }
}

// ------------------------------------------------------------ the grid ---

#[test]
fn hashers_give_the_same_grid() {
    let mesh = common::bumpy_sphere(20, 2);
    let config = GridConfig {
        insert: InsertMethod::Scanline,
        ..GridConfig::cubic(0.07)
    };
    let a: HashGrid<Triangle, ClassicHash> = HashGrid::build(mesh.triangles(), &config).unwrap();
    let b: HashGrid<Triangle, FastHash> = HashGrid::build(mesh.triangles(), &config).unwrap();
    let c: HashGrid<Triangle, RandomState> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(0.07)).unwrap();
    assert_eq!(a.occupied_count(), b.occupied_count());
    assert_eq!(a.occupied_count(), c.occupied_count());
    for (cell, prims) in a.occupied() {
        assert_eq!(prims, b.cell(&cell));
        assert_eq!(prims, c.cell(&cell));
        assert!(prims.windows(2).all(|w| w[0] < w[1]), "cell contents in input order");
    }
    let stats = a.stats();
    assert_eq!(stats.entries, a.entry_count());
    assert_eq!(stats.occupied_cells, a.occupied_count());
    assert!(stats.max_per_cell >= 1 && stats.mean_per_cell >= 1.0);
    let bounds = a.bounds().unwrap();
    assert!(a.occupied().all(|(c, _)| bounds.contains(c)));
    // Point lookup: the half-open cell holding a vertex lists a triangle using it.
    let v = mesh.positions()[17];
    assert!(
        a.at_point(v)
            .unwrap()
            .iter()
            .any(|&p| a.primitives()[p as usize].vertices().contains(&v))
    );
}

#[test]
fn empty_and_single_triangle_grids() {
    let empty: HashGrid<Triangle> = HashGrid::build(PrimitiveSet::default(), &GridConfig::cubic(1.0)).unwrap();
    assert_eq!((empty.occupied_count(), empty.bounds()), (0, None));
    assert_eq!(empty.first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY).unwrap(), None);
    let one = PrimitiveSet::from_primitives(vec![Triangle::new(
        Vec3::splat(0.1),
        Vec3::splat(0.2),
        Vec3::new(0.1, 0.2, 0.3),
    )]);
    let grid: HashGrid<Triangle> = HashGrid::build(one, &GridConfig::cubic(1.0)).unwrap();
    assert_eq!(grid.occupied().collect::<Vec<_>>(), vec![([0, 0, 0], &[0u32][..])]);
}

#[test]
fn errors_instead_of_exhaustion() {
    let tris = common::random_soup(50, 1).triangles();
    for size in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let e = HashGrid::<Triangle>::build(tris.clone(), &GridConfig::cubic(size)).unwrap_err();
        assert!(matches!(e, GridError::CellSize { .. }), "{size}: {e}");
    }
    let e = HashGrid::<Triangle>::build(tris.clone(), &GridConfig::new(Vec3::new(1.0, 0.0, 1.0))).unwrap_err();
    assert!(matches!(e, GridError::CellSize { .. }));
    let config = GridConfig {
        origin: Vec3::new(0.0, f32::NAN, 0.0),
        ..GridConfig::cubic(1.0)
    };
    assert_eq!(
        HashGrid::<Triangle>::build(tris.clone(), &config).unwrap_err(),
        GridError::GridOrigin
    );
    // A tiny cell: the first triangle's box spans far more than the limit.
    let e = HashGrid::<Triangle>::build(tris.clone(), &GridConfig::cubic(1e-5)).unwrap_err();
    assert!(
        matches!(
            e,
            GridError::PrimitiveTooLarge {
                index: 0,
                limit: 134_217_728,
                ..
            }
        ),
        "{e}"
    );
    let config = GridConfig {
        max_cells_per_primitive: 10,
        ..GridConfig::cubic(0.01)
    };
    assert!(matches!(
        HashGrid::<Triangle>::build(tris.clone(), &config),
        Err(GridError::PrimitiveTooLarge { .. })
    ));
    let config = GridConfig {
        max_entries: 100,
        ..GridConfig::cubic(0.01)
    };
    assert_eq!(
        HashGrid::<Triangle>::build(tris.clone(), &config).unwrap_err(),
        GridError::TooManyCells { limit: 100 }
    );
    // Coordinates beyond the supported cell indices.
    let far = PrimitiveSet::from_primitives(vec![Point(Vec3::splat(1e30))]);
    assert_eq!(
        HashGrid::<Point>::build(far, &GridConfig::cubic(1e-10)).unwrap_err(),
        GridError::PrimitiveOutOfRange { index: 0 }
    );
    let nan = PrimitiveSet::from_primitives(vec![Point(Vec3::ZERO), Point(Vec3::new(f32::NAN, 0.0, 0.0))]);
    assert_eq!(
        HashGrid::<Point>::build(nan, &GridConfig::cubic(1.0)).unwrap_err(),
        GridError::NonFinite { index: 1 }
    );
    let mut bad = tris.clone();
    bad.sources.pop();
    assert!(matches!(
        HashGrid::<Triangle>::build(bad, &GridConfig::cubic(1.0)),
        Err(GridError::SourceCount { .. })
    ));
    // Voxelization.
    let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
    assert_eq!(
        voxelize(&tris.primitives, &b, &VoxelConfig::new(0)).unwrap_err(),
        GridError::Resolution
    );
    // A point-like box: no cell size follows from it.
    let point = Aabb::new(Vec3::ZERO, Vec3::ZERO);
    assert_eq!(
        voxelize(&tris.primitives, &point, &VoxelConfig::new(8)).unwrap_err(),
        GridError::DegenerateBounds
    );
    let sparse = VoxelConfig {
        dense_limit_bits: 0,
        max_occupied: 10,
        ..VoxelConfig::new(64)
    };
    assert_eq!(
        voxelize(&tris.primitives, &b, &sparse).unwrap_err(),
        GridError::TooManyCells { limit: 10 }
    );
}

// -------------------------------------------------------------- voxelize ---

#[test]
fn voxelize_matches_the_grid() {
    let mut meshes = vec![
        ("ico", common::bumpy_sphere(30, 3)),
        ("soup", common::random_soup(2000, 3)),
    ];
    if let Some((_, mesh, _)) = shared().iter().find(|m| m.0 == "fandisk.obj") {
        meshes.push(("fandisk", mesh.clone()));
    }
    for (name, mesh) in meshes {
        let tris = mesh.triangles().primitives;
        let bounds = mesh.bounds();
        for res in [1, 7, 32, 100] {
            let vox = voxelize(&tris, &bounds, &VoxelConfig::new(res)).unwrap();
            // The same cells through the hash grid, keeping indices in [0, res).
            let config = GridConfig {
                origin: bounds.min,
                ..GridConfig::cubic(vox.cell_size())
            };
            let grid: HashGrid<Triangle, FastHash> =
                HashGrid::build(PrimitiveSet::from_primitives(tris.clone()), &config).unwrap();
            let mut expected: Vec<Cell> = grid
                .occupied()
                .map(|(c, _)| c)
                .filter(|c| c.iter().all(|&i| (0..res as i64).contains(&i)))
                .collect();
            expected.sort_unstable_by_key(|c| [c[2], c[1], c[0]]);
            assert_eq!(vox.cells(), expected, "{name} at {res}");
            assert_eq!(vox.occupied(), expected.len() as u64);
            // Sequential, classic and sparse storage agree.
            for config in [
                VoxelConfig {
                    parallel: false,
                    ..VoxelConfig::new(res)
                },
                VoxelConfig {
                    insert: InsertMethod::Classic,
                    ..VoxelConfig::new(res)
                },
                VoxelConfig {
                    dense_limit_bits: 0,
                    ..VoxelConfig::new(res)
                },
            ] {
                let other = voxelize(&tris, &bounds, &config).unwrap();
                assert_eq!(other.cells(), expected, "{name} at {res} with {config:?}");
                assert_eq!(other.is_dense(), config.dense_limit_bits > 0);
            }
            assert!(expected.iter().all(|&c| vox.contains(c)));
            assert!(!vox.contains([res as i64, 0, 0]));
        }
    }
}

#[test]
fn voxelize_keeps_the_far_face_closed() {
    // A unit square at z = 1, the top of the box [0, 1]³: at res 2, cell
    // k = 2 would hold it under closed-box rules, but only k ∈ [0, 2) exist;
    // it touches the top of the cells k = 1.
    let v = Vec3::new;
    let tris = [
        Triangle::new(v(0.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(1.0, 1.0, 1.0)),
        Triangle::new(v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0)),
    ];
    let vox = voxelize(&tris, &Aabb::new(Vec3::ZERO, Vec3::ONE), &VoxelConfig::new(2)).unwrap();
    assert_eq!(vox.cells(), vec![[0, 0, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]]);
}

/// The grid reaches the box's far corner on every axis, computed exactly
/// (`f64` holds `min + n · cell` of two `f32` without rounding for these
/// sizes), though the cell size is a rounded `side / n`; and a point-like
/// triangle at the far corner is in the grid's last cells, not clipped away.
/// Boxes where the rounding falls short were seen from Python (a box from 0
/// to 0.9, 3 cells).
#[test]
fn voxel_grids_reach_the_far_corner() {
    let mut rng = Rng::new(11);
    let mut cases = vec![(Vec3::ZERO, Vec3::new(0.9, 0.0, 0.45), 3)];
    for _ in 0..2000 {
        let min = Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        let size = Vec3::new(rng.range(0.01, 3.0), rng.range(0.01, 3.0), rng.range(0.01, 3.0));
        cases.push((min, min + size, 1 + rng.below(60) as u32));
    }
    let mut short_before = 0;
    for (min, max, n) in cases {
        let bounds = Aabb::new(min, max);
        let corner = Triangle::new(max, max, max);
        let vox = voxelize(&[corner], &bounds, &VoxelConfig::new(n)).unwrap();
        let (origin, cell) = (vox.origin().as_dvec3(), vox.cell_size() as f64);
        let end = origin + glam::DVec3::splat(cell * n as f64);
        assert!(
            end.cmpge(max.as_dvec3()).all(),
            "{min} {max} {n}: the grid ends at {end}"
        );
        let naive = (max - min).max_element() / n as f32;
        short_before += usize::from(
            (origin + glam::DVec3::splat(naive as f64 * n as f64))
                .cmplt(max.as_dvec3())
                .any(),
        );
        assert_eq!(vox.occupied(), 1, "{min} {max} {n}");
        let c = vox.cells()[0];
        assert!(c.iter().all(|&i| (0..n as i64).contains(&i)), "{c:?}");
    }
    // The case the fix is for occurs among the random boxes too.
    assert!(short_before > 0);
}

// ------------------------------------------------------------------ rays ---

fn brute_first_hit(tris: &[Triangle], o: Vec3, d: Vec3) -> Option<(u32, f32)> {
    let ray = WatertightRay::new(o, d).unwrap();
    let mut best: Option<(u32, f32)> = None;
    for (p, t) in tris.iter().enumerate() {
        if let Some(h) = ray.intersect(t, 0.0, f32::INFINITY)
            && best.is_none_or(|(_, bt)| h.t < bt)
        {
            best = Some((p as u32, h.t));
        }
    }
    best
}

#[test]
fn raycast_matches_brute_force() {
    let mut meshes = vec![
        ("ico", common::bumpy_sphere(40, 6)),
        ("soup", common::random_soup(3000, 4)),
    ];
    if let Some((_, mesh, _)) = shared().iter().find(|m| m.0 == "bunny-npm.obj") {
        meshes.push(("bunny", mesh.clone()));
    }
    for (name, mesh) in meshes {
        let tris = mesh.triangles().primitives;
        let b = mesh.bounds();
        let e = mean_edge(&tris);
        for cell in [e * 0.7, e * 3.0, b.size().max_element() / 4.0] {
            let grid: HashGrid<Triangle, FastHash> =
                HashGrid::build(mesh.triangles(), &GridConfig::cubic(cell)).unwrap();
            let mut rng = Rng::new(1);
            let mut hits = 0;
            for q in 0..400 {
                let big = b.inflate(b.diagonal() * 0.3);
                let o = rng.in_box(&big);
                // Aim at a vertex every 4th ray: rays through vertices and edges.
                let target = if q % 4 == 0 {
                    mesh.positions()[rng.below(mesh.vertex_count())]
                } else {
                    rng.in_box(&b)
                };
                let d = (target - o).normalize_or(Vec3::X);
                let got = grid.first_hit(o, d, 0.0, f32::INFINITY).unwrap();
                let want = brute_first_hit(&tris, o, d);
                assert_eq!(got.map(|h| h.t), want.map(|w| w.1), "{name}, cell {cell}, ray {q}");
                if let (Some(g), Some(w)) = (got, want) {
                    // Same t; the reported triangle is the first of those hit at t.
                    assert_eq!(g.primitive, w.0, "{name}: tie broken differently");
                    assert_eq!(g.source, mesh.triangles().sources[g.primitive as usize]);
                    assert!((g.point - (o + d * g.t)).length() < 1e-4 * (1.0 + g.t));
                    hits += 1;
                }
            }
            assert!(hits > 100, "{name}: only {hits} hits");
        }
    }
    // Range and error handling.
    let grid: HashGrid<Triangle> =
        HashGrid::build(common::bumpy_sphere(8, 1).triangles(), &GridConfig::cubic(0.3)).unwrap();
    assert!(
        grid.first_hit(Vec3::ZERO, Vec3::X, 0.0, 0.5).unwrap().is_none(),
        "the sphere is beyond t = 0.5"
    );
    assert!(grid.first_hit(Vec3::ZERO, Vec3::X, 0.0, 2.0).unwrap().is_some());
    assert_eq!(
        grid.first_hit(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0).unwrap_err(),
        GridError::Ray(proxima::RayError::Direction)
    );
    assert_eq!(
        grid.first_hit(Vec3::splat(f32::NAN), Vec3::X, 0.0, 1.0).unwrap_err(),
        GridError::Ray(proxima::RayError::Origin)
    );
}

/// The planes are `origin + i · size` exactly, as exact rationals say, up to
/// the layout's own index limit and one past it; a coordinate beyond the
/// limit is out of range, not placed by a rounded plane; an origin whose
/// planes cannot be exact even beside it is refused.
#[test]
fn planes_are_exact_up_to_the_layouts_limit() {
    use num_rational::BigRational;
    let q = |x: f64| BigRational::from_float(x).unwrap();
    let mut rng = Rng::new(77);
    let mut limits = Vec::new();
    for n in 0..400 {
        let origin = match n % 4 {
            0 => 0.0,
            1 => rng.range(-1.0, 1.0),
            2 => rng.range(-1e4, 1e4),
            _ => rng.range(-1e-6, 1e-6),
        };
        let size = match n % 3 {
            0 => rng.range(1e-3, 1.0),
            1 => 2f32.powi(rng.range(-20.0, 10.0) as i32),
            _ => rng.range(1.0, 100.0),
        };
        let layout = match GridLayout::new(Vec3::splat(origin), Vec3::splat(size)) {
            Ok(layout) => layout,
            Err(e) => {
                assert!(matches!(e, GridError::InexactPlanes { .. }), "{e}");
                continue;
            }
        };
        let max = layout.max_index(0);
        limits.push(max);
        assert!((1..=proxima::grid::MAX_CELL_INDEX).contains(&max));
        for i in [0, 1, -1, 7, max / 3, -max / 2, max, -max, max + 1, -max - 1] {
            if i.abs() > max + 1 {
                continue;
            }
            let plane = q(origin as f64) + BigRational::from_integer(i.into()) * q(size as f64);
            assert_eq!(q(layout.boundary(0, i)), plane, "origin {origin} size {size} plane {i}");
        }
        // Beyond the limit: out of range (the planes there need not be exact).
        let far = (origin as f64 + (max as f64 + 4.0) * size as f64) as f32;
        if far.is_finite() && (far as f64 - origin as f64) / size as f64 > max as f64 + 1.0 {
            assert_eq!(layout.cell_of(Vec3::new(far, 0.0, 0.0)), Err(GridError::OutOfRange));
        }
    }
    limits.sort_unstable();
    println!(
        "{} layouts, index limits from {} to {}",
        limits.len(),
        limits[0],
        limits[limits.len() - 1]
    );
    // An origin of 1e-30 beside cells of 1: the first plane, 1 + 1e-30, needs 100 bits.
    let e = GridLayout::new(Vec3::new(0.0, 1e-30, 0.0), Vec3::ONE).unwrap_err();
    assert!(matches!(e, GridError::InexactPlanes { axis: 'y', .. }), "{e}");
    assert!(e.to_string().contains("cannot be exact"), "{e}");
    // Voxelizing a box whose minimum is 1e-30 still works: its origin is rounded down.
    let tris = [Triangle::new(
        Vec3::new(1e-30, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 1.0),
    )];
    let vox = voxelize(
        &tris,
        &Aabb::new(Vec3::new(1e-30, 0.0, 0.0), Vec3::ONE),
        &VoxelConfig::new(8),
    )
    .unwrap();
    assert!(vox.layout().origin().x <= 1e-30 && vox.layout().origin().x > -1e-6);
    assert!(vox.occupied() > 0);
}
