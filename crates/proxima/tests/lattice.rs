//! Exactness on lattice-aligned meshes: vertices that lie exactly on cell
//! planes or a few `f32` steps off them (on either side), triangles lying in
//! cell faces, edges along cell edges, meshes written as decimal text and
//! read back. Voxelization and the hash grid (both insertion methods)
//! must report exactly the SET of cells an exact integer oracle finds
//! (`common::exact`, cross-checked against exact rational clipping).

use crate::common;

use crate::common::exact::{ExactBox, triangle_touches_exact_box, triangle_touches_exact_box_by_clipping};
use proxima::grid::{
    Cell, FastHash, GridConfig, GridInsert, GridLayout, HashGrid, InsertMethod, VoxelConfig, voxelize,
};
use proxima::primitive::PrimitiveSet;
use proxima::sample::Rng;
use proxima::{Aabb, ConvexPolygon, LineSegment, Triangle, Vec3};
use rayon::prelude::*;
use std::collections::BTreeSet;

/// The cells whose closed boxes (planes `origin + i · size` exactly, the
/// grid's definition of its cells, computed by the oracle itself) touch the
/// triangle, by the exact oracle. Candidates: the cells around the
/// triangle's box, found by an `f64` estimate widened by one cell on each
/// side, so that the oracle decides every boundary itself.
fn oracle_cells(t: &Triangle, layout: &GridLayout, clip: bool) -> Vec<Cell> {
    let b = Aabb::from_points(t.vertices());
    let (o, s) = (layout.origin(), layout.cell_size());
    let index = |x: f32, a: usize| ((x as f64 - o[a] as f64) / s[a] as f64).floor() as i64;
    let lo: [i64; 3] = std::array::from_fn(|a| index(b.min[a], a) - 1);
    let hi: [i64; 3] = std::array::from_fn(|a| index(b.max[a], a) + 1);
    let mut out = Vec::new();
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                // Cells clearly apart from the triangle's box (by more than
                // any rounding of the f64 planes) need no exact test.
                let plane = |a: usize, n: i64| o[a] as f64 + n as f64 * s[a] as f64;
                let apart = (0..3).any(|a| {
                    let n = [i, j, k][a];
                    let hair = 1e-9 * (plane(a, n).abs() + s[a] as f64);
                    plane(a, n) - hair > b.max[a] as f64 || (b.min[a] as f64) > plane(a, n + 1) + hair
                });
                if apart {
                    continue;
                }
                let cell_box = ExactBox::of_cell(o, s, [i, j, k]);
                let touches = triangle_touches_exact_box(t, &cell_box);
                if clip {
                    assert_eq!(
                        touches,
                        triangle_touches_exact_box_by_clipping(t, &cell_box),
                        "the two exact oracles disagree on {t:?} and cell {:?}",
                        [i, j, k]
                    );
                }
                if touches {
                    out.push([i, j, k]);
                }
            }
        }
    }
    out
}

/// The union of the oracle's cells over all triangles, restricted to `keep`.
fn oracle_set(tris: &[Triangle], layout: &GridLayout, keep: impl Fn(Cell) -> bool + Sync) -> BTreeSet<Cell> {
    tris.par_iter()
        .enumerate()
        .flat_map_iter(|(i, t)| oracle_cells(t, layout, i % 64 == 0))
        .filter(|&c| keep(c))
        .collect::<Vec<_>>()
        .into_iter()
        .collect()
}

fn describe(name: &str, what: &str, got: &BTreeSet<Cell>, want: &BTreeSet<Cell>) -> String {
    let extra: Vec<_> = got.difference(want).take(5).collect();
    let missing: Vec<_> = want.difference(got).take(5).collect();
    format!(
        "{name}, {what}: {} cells no triangle touches (first {extra:?}), {} touched cells missing (first {missing:?}), of {}",
        got.difference(want).count(),
        want.difference(got).count(),
        want.len()
    )
}

/// Voxelizes at `resolution` over `bounds` with both insertion methods and
/// both storages, and compares the cell sets with the oracle's.
fn check_voxelize(name: &str, tris: &[Triangle], bounds: &Aabb, resolution: u32) {
    let mut config = VoxelConfig::new(resolution);
    let reference = voxelize(tris, bounds, &config).unwrap();
    let layout = *reference.layout();
    let n = resolution as i64;
    let want = oracle_set(tris, &layout, |c| c.iter().all(|&i| (0..n).contains(&i)));
    for (insert, dense_limit) in [
        (InsertMethod::Scanline, config.dense_limit_bits),
        (InsertMethod::Classic, config.dense_limit_bits),
        (InsertMethod::Scanline, 0),
    ] {
        config.insert = insert;
        config.dense_limit_bits = dense_limit;
        let vox = voxelize(tris, bounds, &config).unwrap();
        let got: BTreeSet<Cell> = vox.cells().into_iter().collect();
        assert!(
            got == want,
            "{}",
            describe(
                name,
                &format!("voxelize {resolution}³ {insert:?} dense={}", vox.is_dense()),
                &got,
                &want
            )
        );
    }
}

/// The oracle's cell sets of `shapes` (each a triangle, possibly degenerate),
/// cross-checked by exact clipping one time in 64.
fn oracle_sets(shapes: &[Triangle], layout: &GridLayout) -> Vec<BTreeSet<Cell>> {
    (0..shapes.len())
        .into_par_iter()
        .map(|p| oracle_cells(&shapes[p], layout, p % 64 == 0).into_iter().collect())
        .collect()
}

/// Builds the hash grid of `primitives` with both insertion methods and
/// compares the cell set of every primitive with `want`.
fn check_grid_of<T: GridInsert + Clone + Send + Sync>(
    name: &str,
    kind: &str,
    primitives: &[T],
    want: &[BTreeSet<Cell>],
    config: GridConfig,
) {
    for insert in [InsertMethod::Classic, InsertMethod::Scanline] {
        let grid: HashGrid<T, FastHash> = HashGrid::build(
            PrimitiveSet::from_primitives(primitives.to_vec()),
            &GridConfig { insert, ..config },
        )
        .unwrap();
        let mut got: Vec<BTreeSet<Cell>> = vec![BTreeSet::new(); primitives.len()];
        for (cell, members) in grid.occupied() {
            for &p in members {
                got[p as usize].insert(cell);
            }
        }
        let bad: Vec<String> = (0..primitives.len())
            .filter(|&p| got[p] != want[p])
            .map(|p| {
                describe(
                    name,
                    &format!("grid of {kind} {insert:?}, number {p}"),
                    &got[p],
                    &want[p],
                )
            })
            .collect();
        assert!(bad.is_empty(), "{} {kind} differ; first: {}", bad.len(), bad[0]);
    }
}

fn grid_config(origin: Vec3, cell: Vec3) -> GridConfig {
    GridConfig {
        origin,
        ..GridConfig::new(cell)
    }
}

/// The grid of the triangles, against the exact oracle.
fn check_grid(name: &str, tris: &[Triangle], origin: Vec3, cell: Vec3) {
    let config = grid_config(origin, cell);
    let want = oracle_sets(tris, &config.layout().unwrap());
    check_grid_of(name, "triangles", tris, &want, config);
}

/// The grid of the triangles' edges (segments): the oracle tests each as the
/// degenerate triangle a, b, b, which is the segment (cross-checked by
/// clipping the segment itself).
fn check_edge_grid(name: &str, tris: &[Triangle], origin: Vec3, cell: Vec3) {
    let edges: Vec<LineSegment> = tris
        .iter()
        .flat_map(|t| [LineSegment::new(t.a, t.b), LineSegment::new(t.b, t.c)])
        .collect();
    let as_triangles: Vec<Triangle> = edges.iter().map(|s| Triangle::new(s.a, s.b, s.b)).collect();
    let config = grid_config(origin, cell);
    let want = oracle_sets(&as_triangles, &config.layout().unwrap());
    check_grid_of(name, "segments", &edges, &want, config);
}

/// The grid of convex polygons (the quads formed by consecutive triangle
/// pairs a, b, c / a, c, d of a voxel surface): a quad touches a cell exactly
/// when one of its two triangles does.
fn check_polygon_grid(name: &str, tris: &[Triangle], origin: Vec3, cell: Vec3) {
    let quads: Vec<ConvexPolygon> = tris
        .chunks_exact(2)
        .map(|p| ConvexPolygon::new(&[p[0].a, p[0].b, p[0].c, p[1].c]).expect("a planar square"))
        .collect();
    let config = grid_config(origin, cell);
    let halves = oracle_sets(tris, &config.layout().unwrap());
    let want: Vec<BTreeSet<Cell>> = halves
        .chunks_exact(2)
        .map(|h| h[0].union(&h[1]).copied().collect())
        .collect();
    check_grid_of(name, "quads", &quads, &want, config);
}

// ------------------------------------------------------------ generators ---

/// The surface of a blob of voxels, as two triangles per exposed voxel face:
/// every vertex on a lattice point, every triangle in a cell face plane
/// (a voxel- or Minecraft-style mesh). `lattice(i)` gives plane `i`'s value.
fn voxel_surface(n: i64, seed: u64, lattice: impl Fn(usize, i64) -> f32) -> Vec<Triangle> {
    let mut rng = Rng::new(seed);
    let solid: Vec<bool> = (0..n * n * n).map(|_| rng.range(0.0, 1.0) < 0.4).collect();
    let filled = |c: [i64; 3]| c.iter().all(|&i| (0..n).contains(&i)) && solid[((c[2] * n + c[1]) * n + c[0]) as usize];
    let point = |c: [i64; 3]| Vec3::new(lattice(0, c[0]), lattice(1, c[1]), lattice(2, c[2]));
    let mut tris = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = [i, j, k];
                if !filled(c) {
                    continue;
                }
                for axis in 0..3 {
                    for side in [0, 1] {
                        let mut next = c;
                        next[axis] += if side == 1 { 1 } else { -1 };
                        if filled(next) {
                            continue;
                        }
                        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                        let mut corner = c;
                        corner[axis] += side;
                        let mut q = [corner; 4];
                        q[1][u] += 1;
                        q[2][u] += 1;
                        q[2][v] += 1;
                        q[3][v] += 1;
                        let q = q.map(point);
                        tris.push(Triangle::new(q[0], q[1], q[2]));
                        tris.push(Triangle::new(q[0], q[2], q[3]));
                    }
                }
            }
        }
    }
    tris
}

/// Triangles whose vertices lie on lattice lines, as in a marching-cubes
/// mesh: two coordinates on cell planes, the third anywhere (or, one time in
/// four, on a plane too, or one `f32` step beside one).
fn lattice_line_triangles(count: usize, n: i64, seed: u64, lattice: impl Fn(usize, i64) -> f32) -> Vec<Triangle> {
    let mut rng = Rng::new(seed);
    let vertex = |rng: &mut Rng, near: Option<[i64; 3]>| {
        let base: [i64; 3] =
            near.unwrap_or_else(|| std::array::from_fn(|_| (rng.range(0.0, n as f32) as i64).min(n - 1)));
        let cell: [i64; 3] = std::array::from_fn(|a| (base[a] + (rng.range(-1.5, 1.5) as i64)).clamp(0, n - 1));
        let free = (rng.range(0.0, 3.0) as usize).min(2);
        let mut p = Vec3::new(lattice(0, cell[0]), lattice(1, cell[1]), lattice(2, cell[2]));
        let roll = rng.range(0.0, 4.0);
        let (lo, hi) = (lattice(free, cell[free]), lattice(free, cell[free] + 1));
        p[free] = if roll < 1.0 {
            lo
        } else if roll < 1.5 {
            f32::from_bits(lo.to_bits().wrapping_add(1)).max(lo.min(hi))
        } else if roll < 2.0 {
            next_down(lo)
        } else {
            lo + (hi - lo) * rng.range(0.0, 1.0)
        };
        (p, cell)
    };
    (0..count)
        .map(|_| {
            let (a, cell) = vertex(&mut rng, None);
            let (b, _) = vertex(&mut rng, Some(cell));
            let (c, _) = vertex(&mut rng, Some(cell));
            Triangle::new(a, b, c)
        })
        .collect()
}

/// `x` moved by `steps` `f32` steps (up for positive).
fn ulps(x: f32, steps: i32) -> f32 {
    let mut y = x;
    for _ in 0..steps.unsigned_abs() {
        y = if steps > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

/// Every vertex coordinate moved by −3 to +3 `f32` steps: the `n`-th
/// distinct vertex (in order of first appearance) takes the `n mod 343`-th
/// of the 7³ combinations, so that with 343 vertices or more each is seen.
/// A vertex shared by several triangles moves once. With `in_plane`, a pair
/// of triangles (a quad `a b c`, `a c d`) lying in a plane of constant
/// coordinate keeps that coordinate, so the quad stays planar. Returns the
/// moved triangles and how many combinations were used.
fn moved_by_ulps(tris: &[Triangle], in_plane: bool) -> (Vec<Triangle>, usize) {
    use std::collections::HashMap;
    let mut order: HashMap<[u32; 3], usize> = HashMap::new();
    let mut seen = BTreeSet::new();
    let mut out = Vec::with_capacity(tris.len());
    for pair in tris.chunks(if in_plane { 2 } else { 1 }) {
        let points: Vec<Vec3> = pair.iter().flat_map(|t| t.vertices()).collect();
        let fixed = (0..3).find(|&a| in_plane && points.iter().all(|p| p[a] == points[0][a]));
        for t in pair {
            let [a, b, c] = t.vertices().map(|v| {
                let next = order.len();
                let n = *order.entry(v.to_array().map(f32::to_bits)).or_insert(next) % 343;
                let combo = [n % 7, n / 7 % 7, n / 49].map(|d| d as i32 - 3);
                seen.insert(combo);
                Vec3::from_array(std::array::from_fn(|a| {
                    if Some(a) == fixed { v[a] } else { ulps(v[a], combo[a]) }
                }))
            });
            out.push(Triangle::new(a, b, c));
        }
    }
    (out, seen.len())
}

/// The largest `f32` below `x`.
fn next_down(x: f32) -> f32 {
    if x > 0.0 {
        f32::from_bits(x.to_bits() - 1)
    } else if x == 0.0 {
        -f32::from_bits(1)
    } else {
        f32::from_bits(x.to_bits() + 1)
    }
}

/// A real mesh's triangles, rescaled so that its bounding box is `±half`, and
/// with every coordinate snapped to the nearest quarter cell of an
/// `resolution`-cell grid spanning the box: the values a CAD or voxel export
/// would hold (like `-0.05 + 0.003125 · k`, rounded once to `f32`), half of
/// them on cell planes. Returns the triangles and the box.
fn rescaled_and_snapped(tris: &[Triangle], half: f32, resolution: u32) -> (Vec<Triangle>, Aabb) {
    let b = Aabb::from_points(tris.iter().flat_map(|t| t.vertices()));
    let center = (b.min + b.max) * 0.5;
    let scale = 2.0 * half as f64 / b.size().max_element() as f64;
    let quarter = 2.0 * half as f64 / (4 * resolution) as f64;
    let snap = |x: f32, c: f32| {
        let k = (((x - c) as f64 * scale + half as f64) / quarter).round();
        (-half as f64 + k * quarter) as f32
    };
    let out: Vec<Triangle> = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t
                .vertices()
                .map(|v| Vec3::new(snap(v.x, center.x), snap(v.y, center.y), snap(v.z, center.z)));
            Triangle::new(a, b, c)
        })
        .collect();
    (out, Aabb::new(Vec3::splat(-half), Vec3::splat(half)))
}

// ----------------------------------------------------------------- tests ---

/// The `f32` nearest each of the grid's exact planes `origin + i · cell`: on
/// the plane when it is an `f32`, within half a step of it otherwise.
fn grid_planes(origin: f32, cell: f32) -> impl Fn(usize, i64) -> f32 {
    move |_, i| (origin as f64 + i as f64 * cell as f64) as f32
}

/// Lattice planes as a user would write them in decimal: `f32(-0.05 + 0.003125 · i)`,
/// which are not always the grid's `f32` planes (one step off, some of them).
fn decimal_planes(origin: f64, cell: f64) -> impl Fn(usize, i64) -> f32 {
    move |_, i| (origin + cell * i as f64) as f32
}

#[test]
fn voxel_meshes_on_the_grid_planes() {
    for (half, n) in [(0.05f32, 16u32), (1e-3, 12), (1.0, 8), (3.0, 10)] {
        let cell = 2.0 * half / n as f32;
        let bounds = Aabb::new(Vec3::splat(-half), Vec3::splat(half));
        let tris = voxel_surface(n as i64, 7, grid_planes(-half, cell));
        check_voxelize(&format!("voxel surface ±{half}"), &tris, &bounds, n);
        check_voxelize(
            &format!("voxel surface ±{half}, half resolution"),
            &tris,
            &bounds,
            n / 2,
        );
        check_voxelize(
            &format!("voxel surface ±{half}, odd resolution"),
            &tris,
            &bounds,
            n * 3 / 4 + 1,
        );
        check_grid(
            &format!("voxel surface ±{half}"),
            &tris,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
        check_edge_grid(
            &format!("voxel surface ±{half}"),
            &tris,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
        check_polygon_grid(
            &format!("voxel surface ±{half}"),
            &tris,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
        let decimal = voxel_surface(n as i64, 8, decimal_planes(-half as f64, 2.0 * half as f64 / n as f64));
        check_voxelize(&format!("decimal voxel surface ±{half}"), &decimal, &bounds, n);
        check_grid(
            &format!("decimal voxel surface ±{half}"),
            &decimal,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
        check_polygon_grid(
            &format!("decimal voxel surface ±{half}"),
            &decimal,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
    }
}

#[test]
fn marching_cubes_style_meshes() {
    for (half, n, seed) in [(0.05f32, 32u32, 1u64), (1e-3, 16, 2), (0.5, 10, 3), (100.0, 20, 4)] {
        let cell = 2.0 * half / n as f32;
        let bounds = Aabb::new(Vec3::splat(-half), Vec3::splat(half));
        let tris = lattice_line_triangles(2000, n as i64, seed, grid_planes(-half, cell));
        check_voxelize(&format!("lattice lines ±{half}"), &tris, &bounds, n);
        check_grid(
            &format!("lattice lines ±{half}"),
            &tris,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
        check_edge_grid(
            &format!("lattice lines ±{half}"),
            &tris,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
        let decimal = lattice_line_triangles(
            2000,
            n as i64,
            seed + 10,
            decimal_planes(-half as f64, 2.0 * half as f64 / n as f64),
        );
        check_voxelize(&format!("decimal lattice lines ±{half}"), &decimal, &bounds, n);
        check_grid(
            &format!("decimal lattice lines ±{half}"),
            &decimal,
            Vec3::splat(-half),
            Vec3::splat(cell),
        );
    }
}

#[test]
fn real_meshes_rescaled_onto_the_lattice() {
    let Some(dir) = common::data_dir() else { return };
    for name in ["fandisk.obj", "rocker-arm.obj", "bunny-npm.obj", "blade.off"] {
        let mesh = proxima::io::load(dir.join(name)).unwrap();
        let tris = mesh.triangles().primitives;
        for (half, n) in [(0.05f32, 32u32), (1e-3, 24)] {
            let (snapped, bounds) = rescaled_and_snapped(&tris, half, n);
            check_voxelize(&format!("{name} ±{half}"), &snapped, &bounds, n);
            check_voxelize(&format!("{name} ±{half} at {}", 2 * n), &snapped, &bounds, 2 * n);
            let cell = 2.0 * half / n as f32;
            check_grid(
                &format!("{name} ±{half}"),
                &snapped,
                Vec3::splat(-half),
                Vec3::splat(cell),
            );
        }
    }
}

/// The two triangles of the issue that found the rounded planes: vertices
/// 0.4 `f32` step beside the grid's exact planes (origin −0.05, cells of
/// 0.1/32 as `f32`), which rounded planes put ON them. Exactly 220 cells are
/// touched (counted by exact rational clipping when the issue was filed).
#[test]
fn vertices_a_fraction_of_a_step_off_the_planes() {
    // The file of the issue, read as a user's file is.
    let off = "OFF\n6 2 0\n\
        -0.0437499993 -0.0500000007 -0.0375000015\n\
        -0.0437199995 -0.0437199995 -0.0381130017\n\
        -0.0437499993 -0.0437499993 -0.0375000015\n\
        -0.0500000007 -0.0500000007 -0.0500000007\n\
        0.0500000007 0.0500000007 0.0500000007\n\
        0.0500000007 0.0500000007 0.0499000000\n\
        3 0 1 2\n3 3 4 5\n";
    let mesh = proxima::io::parse(
        off.as_bytes(),
        proxima::io::Format::Off,
        std::path::Path::new("tri.off"),
    )
    .unwrap();
    let tris = mesh.triangles().primitives;
    let bounds = Aabb::from_points(tris.iter().flat_map(|t| t.vertices()));
    let vox = voxelize(&tris, &bounds, &VoxelConfig::new(32)).unwrap();
    assert_eq!(vox.occupied(), 220);
    // The first triangle's lowest x is 2.00000045 cells from the origin and
    // its largest z 3.9999997 cells: no cell with i = 1 or k = 4 touches it.
    for cell in [[1, 0, 3], [1, 1, 3], [1, 1, 4], [1, 0, 4], [1, 2, 3], [1, 2, 4]] {
        assert!(!vox.contains(cell), "{cell:?}");
    }
    check_voxelize("the issue's two triangles", &tris, &bounds, 32);
    check_voxelize("the issue's two triangles", &tris, &bounds, 64);
}

#[test]
fn lattice_meshes_moved_a_few_steps_off_the_planes() {
    for (half, n, seed) in [(0.05f32, 8u32, 21u64), (1.0, 8, 22), (3.0, 10, 23), (1e-3, 8, 24)] {
        let cell = 2.0 * half / n as f32;
        let (origin, size) = (Vec3::splat(-half), Vec3::splat(cell));
        let bounds = Aabb::new(origin, Vec3::splat(half));
        let surface = voxel_surface(n as i64, seed, grid_planes(-half, cell));
        let (moved, combos) = moved_by_ulps(&surface, false);
        assert_eq!(combos, 343, "every combination of moves on the voxel surface ±{half}");
        let name = format!("voxel surface ±{half} moved by ulps");
        check_voxelize(&name, &moved, &bounds, n);
        check_voxelize(&name, &moved, &bounds, n / 2);
        check_grid(&name, &moved, origin, size);
        check_edge_grid(&name, &moved, origin, size);
        let (planar, _) = moved_by_ulps(&surface, true);
        check_polygon_grid(&format!("{name}, in plane"), &planar, origin, size);
        let lines = lattice_line_triangles(1500, n as i64, seed, grid_planes(-half, cell));
        let (moved, combos) = moved_by_ulps(&lines, false);
        assert_eq!(combos, 343, "every combination of moves on the lattice lines ±{half}");
        let name = format!("lattice lines ±{half} moved by ulps");
        check_voxelize(&name, &moved, &bounds, n);
        check_grid(&name, &moved, origin, size);
        check_edge_grid(&name, &moved, origin, size);
    }
}

/// Real meshes rescaled to ±0.05, snapped to quarter cells, written as OBJ
/// text with 10 decimals and read back (the CAD export of the issue: values
/// like −0.0437499993, a fraction of a step off the planes), at several
/// resolutions.
#[test]
fn real_meshes_written_as_decimal_text() {
    let Some(dir) = common::data_dir() else { return };
    let temp = std::env::temp_dir().join(format!("proxima-lattice-{}", std::process::id()));
    std::fs::create_dir_all(&temp).unwrap();
    for name in ["fandisk.obj", "bunny-npm.obj"] {
        let mesh = proxima::io::load(dir.join(name)).unwrap();
        let (snapped, _) = rescaled_and_snapped(&mesh.triangles().primitives, 0.05, 32);
        let mut text = String::new();
        for t in &snapped {
            for v in t.vertices() {
                text += &format!("v {:.10} {:.10} {:.10}\n", v.x, v.y, v.z);
            }
        }
        for f in 0..snapped.len() {
            text += &format!("f {} {} {}\n", 3 * f + 1, 3 * f + 2, 3 * f + 3);
        }
        let path = temp.join(name);
        std::fs::write(&path, text).unwrap();
        let read = proxima::io::load(&path).unwrap().triangles().primitives;
        assert_eq!(read.len(), snapped.len());
        let off = read.iter().zip(&snapped).filter(|(a, b)| a != b).count();
        println!("{name}: {off} of {} triangles moved by the decimal text", read.len());
        let bounds = Aabb::from_points(read.iter().flat_map(|t| t.vertices()));
        for resolution in [32, 64, 128] {
            check_voxelize(&format!("{name} as decimal text"), &read, &bounds, resolution);
        }
        let cell = Vec3::splat(0.1f32 / 32.0);
        check_grid(&format!("{name} as decimal text"), &read, Vec3::splat(-0.05), cell);
        check_edge_grid(&format!("{name} as decimal text"), &read, Vec3::splat(-0.05), cell);
    }
    std::fs::remove_dir_all(&temp).ok();
}
