//! The bodies of the fuzz targets, shared by the libFuzzer targets
//! (`fuzz/fuzz_targets/*.rs`, run by `fuzz/run.sh`) and by the smoke test that
//! CI runs (`crates/proxima/tests/fuzz_smoke.rs`), both through
//! `#[path = ".../fuzz/bodies.rs"] mod bodies;` (for the tests, once in
//! `crates/proxima/tests/integration.rs`).
//!
//! Every body takes arbitrary bytes and must not panic: loaders return a mesh
//! or a typed error; structures are built over bounded geometry decoded from
//! the bytes (with [`arbitrary::Unstructured`]) and every query is compared
//! with brute force by `assert_eq!`, so a wrong answer is a crash too.
//!
//! To add a structure (sphere tree, frustum, polygons, tree rays): write a
//! `pub fn my_structure(data: &[u8])` here using [`Geometry::decode`], add it to
//! [`TARGETS`], and copy one of the three-line files in `fuzz/fuzz_targets/`.
#![allow(dead_code)]

use arbitrary::{Result, Unstructured};
use proxima::GridError;
use proxima::build::SplitMethod;
use proxima::grid::{ClassicHash, FastHash, GridConfig, GridInsert, GridLayout, HashGrid, InsertMethod};
use proxima::grid::{GridTraversal, TraversalStep};
use proxima::io::{Format, LoadOptions, parse_with};
use proxima::prelude::*;
use proxima::primitive::WatertightRay;
use std::path::Path;

/// Loader inputs longer than this are cut: the loaders allocate in proportion
/// to their input, and a fuzzer gains nothing from megabytes.
pub const MAX_INPUT: usize = 1 << 20;
/// Decompression limit of the gzip target (the library's default is 4 GiB).
pub const MAX_GUNZIP: u64 = 8 << 20;
/// The memory budget of the loaders here (the library's default is up to
/// 2 GiB): a GLB scene of a few instances of a large primitive, or a JSON
/// chunk of many values, reaches it from a small input.
pub const LOAD_BUDGET: u64 = 64 << 20;

/// A fuzz target's body.
pub type Body = fn(&[u8]);

/// Every target: its name (the file in `fuzz/fuzz_targets/`) and body.
pub const TARGETS: &[(&str, Body)] = &[
    ("load_obj", load_obj),
    ("load_ply", load_ply),
    ("load_stl", load_stl),
    ("load_off", load_off),
    ("load_glb", load_glb),
    ("load_gzip", load_gzip),
    ("aabb_tree", aabb_tree),
    ("wide_tree", wide_tree),
    ("hash_grid", hash_grid),
    ("traversal", traversal),
];

fn load(data: &[u8], format: Format) {
    let data = &data[..data.len().min(MAX_INPUT)];
    let options = LoadOptions {
        memory_budget: LOAD_BUDGET,
        ..LoadOptions::default()
    };
    let loaded = parse_with(data, format, Path::new("fuzz-input"), &options);
    if let Err(proxima::LoadError {
        kind: proxima::LoadErrorKind::MemoryBudget { bytes, budget, .. },
        ..
    }) = &loaded
    {
        assert!(*bytes > u128::from(*budget) && *budget == LOAD_BUDGET);
    }
    if let Ok(mesh) = loaded {
        // What a loader accepts fits the budget it was given.
        let counted = data.len() as u128
            + mesh.vertex_count() as u128 * u128::from(proxima::budget::LOAD_BYTES_PER_VERTEX)
            + mesh.triangle_count() as u128 * u128::from(proxima::budget::LOAD_BYTES_PER_TRIANGLE);
        assert!(counted <= u128::from(LOAD_BUDGET), "{counted} bytes counted");
        // Extraction must hold for whatever a loader accepts.
        let triangles = mesh.triangles();
        assert_eq!(triangles.len(), mesh.triangle_count());
        let edges = mesh.edges();
        assert!(edges.len() <= mesh.faces().map(|f| f.len()).sum::<usize>());
        assert_eq!(mesh.vertices().len(), mesh.vertex_count());
    }
}

/// Wavefront OBJ bytes.
pub fn load_obj(data: &[u8]) {
    load(data, Format::Obj)
}
/// PLY bytes (ascii and binary: the header decides).
pub fn load_ply(data: &[u8]) {
    load(data, Format::Ply)
}
/// STL bytes (ascii and binary: the size and content decide).
pub fn load_stl(data: &[u8]) {
    load(data, Format::Stl)
}
/// OFF bytes.
pub fn load_off(data: &[u8]) {
    load(data, Format::Off)
}

/// Binary glTF bytes.
pub fn load_glb(data: &[u8]) {
    load(data, Format::Glb)
}

/// First byte picks the format, the rest is a gzip stream.
pub fn load_gzip(data: &[u8]) {
    let Some((&which, rest)) = data.split_first() else {
        return;
    };
    let format = [Format::Obj, Format::Ply, Format::Stl, Format::Off, Format::Glb][which as usize % 5];
    let rest = &rest[..rest.len().min(MAX_INPUT)];
    match proxima::io::gunzip(rest, MAX_GUNZIP) {
        Ok(bytes) => {
            assert!(bytes.len() as u64 <= MAX_GUNZIP);
            load(&bytes, format);
        }
        Err(proxima::LoadErrorKind::DecompressedTooLarge { limit }) => assert_eq!(limit, MAX_GUNZIP),
        Err(_) => {}
    }
}

// ------------------------------------------------------------- geometry ---

/// Bounded geometry decoded from fuzz bytes: a pool of vertices (so
/// primitives repeat vertices, collapse and share edges) in one of several
/// coordinate regimes, primitives indexing it, and query points.
#[derive(Debug)]
pub struct Geometry {
    /// The vertex pool.
    pub vertices: Vec<Vec3>,
    /// Triples of pool indices.
    pub triangles: Vec<[usize; 3]>,
    /// Query points: pool vertices, edge midpoints, face points and free points.
    pub queries: Vec<Vec3>,
    /// The feature scale of the regime (cell sizes are multiples of it).
    pub scale: f32,
    /// The coordinate regime (see [`coordinate`]); 0 is the quarter lattice.
    pub regime: u8,
}

/// The coordinate regimes: unit lattice (cell boundaries, ties), free values in
/// the unit cube, tiny (1e-30), huge (1e17), far from the origin (1e7 offset)
/// with small features, and raw `f32` bits within the tree's bound.
fn coordinate(u: &mut Unstructured<'_>, regime: u8) -> Result<f32> {
    let lattice = f32::from(u.int_in_range::<i8>(-8..=8)?) * 0.25;
    let unit = u.int_in_range::<u32>(0..=1 << 24)? as f32 / (1 << 24) as f32 * 2.0 - 1.0;
    Ok(match regime % 6 {
        0 => lattice,
        1 => unit,
        2 => lattice * 1e-30,
        3 => lattice * 1e17,
        4 => 1e7 + lattice,
        _ => {
            let raw = f32::from_bits(u.arbitrary()?);
            if raw.is_finite() && raw.abs() <= proxima::build::MAX_COORDINATE {
                raw
            } else {
                lattice
            }
        }
    })
}

impl Geometry {
    /// Up to 16 pool vertices, 40 triangles and 8 queries.
    pub fn decode(u: &mut Unstructured<'_>) -> Result<Geometry> {
        let regime = u.arbitrary::<u8>()? % 6;
        let scale = [0.25, 0.5, 1e-30, 1e17, 0.25, 1.0][regime as usize % 6];
        let mut vertices = Vec::new();
        for _ in 0..u.int_in_range(1..=16)? {
            vertices.push(Vec3::new(
                coordinate(u, regime)?,
                coordinate(u, regime)?,
                coordinate(u, regime)?,
            ));
        }
        let n = vertices.len();
        let mut triangles = Vec::new();
        for _ in 0..u.int_in_range(0..=40)? {
            triangles.push([u.choose_index(n)?, u.choose_index(n)?, u.choose_index(n)?]);
        }
        let mut queries = Vec::new();
        for _ in 0..u.int_in_range(1..=8)? {
            let a = vertices[u.choose_index(n)?];
            let b = vertices[u.choose_index(n)?];
            let c = vertices[u.choose_index(n)?];
            queries.push(match u.int_in_range(0..=3)? {
                0 => a,
                1 => (a + b) * 0.5,
                2 => (a + b + c) / 3.0,
                _ => Vec3::new(coordinate(u, regime)?, coordinate(u, regime)?, coordinate(u, regime)?),
            });
        }
        Ok(Geometry {
            vertices,
            triangles,
            queries,
            scale,
            regime,
        })
    }

    /// The faces as triangles.
    pub fn triangle_set(&self) -> PrimitiveSet<Triangle> {
        let v = &self.vertices;
        PrimitiveSet::from_primitives(
            self.triangles
                .iter()
                .map(|t| Triangle::new(v[t[0]], v[t[1]], v[t[2]]))
                .collect(),
        )
    }

    /// The first two corners of every face, as segments.
    pub fn segment_set(&self) -> PrimitiveSet<LineSegment> {
        let v = &self.vertices;
        PrimitiveSet::from_primitives(
            self.triangles
                .iter()
                .map(|t| LineSegment::new(v[t[0]], v[t[1]]))
                .collect(),
        )
    }

    /// The first corner of every face, as points.
    pub fn point_set(&self) -> PrimitiveSet<Point> {
        PrimitiveSet::from_primitives(self.triangles.iter().map(|t| Point(self.vertices[t[0]])).collect())
    }
}

fn build_config(u: &mut Unstructured<'_>) -> Result<BuildConfig> {
    Ok(BuildConfig {
        max_depth: u.int_in_range(1..=proxima::build::MAX_DEPTH)?,
        min_size: u.int_in_range(1..=8)?,
        split: if u.arbitrary()? {
            SplitMethod::BinnedSah
        } else {
            SplitMethod::Median
        },
    })
}

// ---------------------------------------------------------------- trees ---

/// Builds a tree (binary, or wide when `wide`) over `set` and asserts that
/// closest, k-nearest and batch answers equal [`LinearSearch`]'s
/// on every field.
pub fn check_tree<T>(set: PrimitiveSet<T>, config: &BuildConfig, queries: &[Vec3], k: usize, wide: bool)
where
    T: proxima::ClosestPoint + proxima::wide_tree::WidePrimitive + Copy + Send + Sync + std::fmt::Debug,
{
    let linear = LinearSearch::new(set.clone());
    let tree = AabbTree::build_set(set, config).expect("bounded finite geometry builds");
    tree.validate().expect("tree invariants");
    if wide {
        let wide = WideTree::from_tree(tree);
        for &q in queries {
            assert_eq!(wide.closest(q), linear.closest(q), "wide closest at {q:?}");
            assert_eq!(wide.k_nearest(q, k), linear.k_nearest(q, k), "wide k-nearest at {q:?}");
        }
        assert_eq!(
            wide.closest_batch(queries),
            queries.iter().map(|&q| linear.closest(q)).collect::<Vec<_>>()
        );
    } else {
        for &q in queries {
            assert_eq!(tree.closest(q), linear.closest(q), "closest at {q:?}");
            assert_eq!(tree.k_nearest(q, k), linear.k_nearest(q, k), "k-nearest at {q:?}");
        }
        assert_eq!(
            tree.closest_batch(queries),
            queries.iter().map(|&q| linear.closest(q)).collect::<Vec<_>>()
        );
    }
}

fn tree_body(data: &[u8], wide: bool) -> Result<()> {
    let mut u = Unstructured::new(data);
    let geometry = Geometry::decode(&mut u)?;
    let config = build_config(&mut u)?;
    let k = u.int_in_range(1..=6)?;
    let q = &geometry.queries;
    match u.int_in_range(0..=2)? {
        0 => check_tree(geometry.triangle_set(), &config, q, k, wide),
        1 => check_tree(geometry.segment_set(), &config, q, k, wide),
        _ => check_tree(geometry.point_set(), &config, q, k, wide),
    }
    Ok(())
}

/// AabbTree closest, k-nearest and batch against LinearSearch.
pub fn aabb_tree(data: &[u8]) {
    let _ = tree_body(data, false);
}

/// WideTree closest, k-nearest and batch against LinearSearch.
pub fn wide_tree(data: &[u8]) {
    let _ = tree_body(data, true);
}

// ----------------------------------------------------------------- grid ---

/// Limits that keep one fuzz input cheap: the build must fail with a typed
/// error rather than exceed them.
const GRID_MAX_CELLS: u64 = 512;
const GRID_MAX_ENTRIES: u64 = 1 << 13;

/// The cells of `prim` by brute force: every cell of its box range, kept when
/// the closed cell box passes the primitive's own overlap test.
fn brute_cells<T: GridInsert>(prim: &T, layout: &GridLayout) -> Vec<[i64; 3]> {
    let range = layout.cell_range(&prim.bounds()).expect("range checked by the build");
    let mut cells: Vec<_> = range
        .iter()
        .filter(|&c| prim.overlaps_box(&layout.cell_box(c)))
        .collect();
    cells.sort_unstable();
    cells
}

/// `b` grown (`by > 0`) or shrunk by `|by|` on every side.
fn nudge(b: &proxima::Aabb, by: f32) -> proxima::Aabb {
    proxima::Aabb::new(b.min - by, b.max + by)
}

/// The overlap tests evaluate their separating axes in `f64`: exact for small
/// dyadic coordinates (the lattice regime), within a few `f64` ulps of the
/// coordinates' magnitude otherwise, where one test and another (the grid's
/// prepared test against `overlaps_box`) may round a touching contact
/// differently. Outside the lattice, a cell must be in the grid when the
/// primitive meets the cell box shrunk by a tolerance of 4 `f32` epsilons of
/// the largest coordinate involved, and may be only when it meets the box
/// grown by that much.
fn check_cells_loosely<T: GridInsert>(prim: &T, layout: &GridLayout, got: &[[i64; 3]], p: usize) {
    let range = layout.cell_range(&prim.bounds()).expect("range checked by the build");
    let pb = prim.bounds();
    for cell in range.iter() {
        let b = layout.cell_box(cell);
        let magnitude = b
            .min
            .abs()
            .max(b.max.abs())
            .max(pb.min.abs())
            .max(pb.max.abs())
            .max_element();
        let tolerance = 4.0 * f32::EPSILON * magnitude;
        let inside = got.binary_search(&cell).is_ok();
        if inside {
            assert!(
                prim.overlaps_box(&nudge(&b, tolerance)),
                "primitive {p}: cell {cell:?} is not touched"
            );
        } else {
            // Cells thinner than the tolerance (small cells far from the origin) have no inside.
            let core = nudge(&b, -tolerance);
            let thin = (0..3).any(|a| core.min[a] > core.max[a]);
            assert!(
                thin || !prim.overlaps_box(&core),
                "primitive {p}: cell {cell:?} is missing"
            );
        }
    }
}

/// Builds the grid with both insertions and both hashers, asserts they agree,
/// and checks every primitive's cells against brute force (exactly when
/// `exact`, else within the tolerance of [`check_cells_loosely`]). `None` when
/// the build fails with a typed limit error, as both insertions must then.
pub fn check_grid<T: GridInsert + Copy>(
    set: &PrimitiveSet<T>,
    config: &GridConfig,
    exact: bool,
) -> Option<HashGrid<T>> {
    let classic = HashGrid::<T>::build(set.clone(), config);
    let scanline = HashGrid::<T, FastHash>::build(
        set.clone(),
        &GridConfig {
            insert: InsertMethod::Scanline,
            ..*config
        },
    );
    let grid = match (classic, scanline) {
        (Ok(a), Ok(b)) => {
            assert_eq!(a.occupied_count(), b.occupied_count());
            for (cell, prims) in a.occupied() {
                assert_eq!(prims, b.cell(&cell), "cell {cell:?}: classic and scan-line differ");
            }
            a
        }
        (Err(a), Err(b)) => {
            assert!(
                matches!(
                    a,
                    GridError::PrimitiveTooLarge { .. }
                        | GridError::TooManyCells { .. }
                        | GridError::PrimitiveOutOfRange { .. }
                ),
                "unexpected {a}"
            );
            // Scan-line and classic check the same limits in the same order, except
            // that the entry count depends on which cells were kept (equal here).
            assert_eq!(std::mem::discriminant(&a), std::mem::discriminant(&b), "{a} / {b}");
            return None;
        }
        (a, b) => panic!("classic {:?} but scan-line {:?}", a.err(), b.err()),
    };
    let mut per = vec![Vec::new(); grid.len()];
    for (cell, prims) in grid.occupied() {
        for &p in prims {
            per[p as usize].push(cell);
        }
    }
    for (p, cells) in per.iter_mut().enumerate() {
        cells.sort_unstable();
        if exact {
            assert_eq!(
                *cells,
                brute_cells(&grid.primitives()[p], grid.layout()),
                "primitive {p}"
            );
        } else {
            check_cells_loosely(&grid.primitives()[p], grid.layout(), cells, p);
        }
    }
    Some(grid)
}

fn grid_body(data: &[u8]) -> Result<()> {
    let mut u = Unstructured::new(data);
    let geometry = Geometry::decode(&mut u)?;
    let cell = Vec3::new(
        geometry.scale * f32::from(u.int_in_range::<u8>(1..=8)?) * 0.5,
        geometry.scale * f32::from(u.int_in_range::<u8>(1..=8)?) * 0.5,
        geometry.scale * f32::from(u.int_in_range::<u8>(1..=8)?) * 0.5,
    );
    let origin = geometry.vertices[u.choose_index(geometry.vertices.len())?];
    let config = GridConfig {
        origin: if u.arbitrary()? { origin } else { Vec3::ZERO },
        max_cells_per_primitive: GRID_MAX_CELLS,
        max_entries: GRID_MAX_ENTRIES,
        ..GridConfig::new(cell)
    };
    if config.layout().is_err() {
        return Ok(());
    }
    let exact = geometry.regime == 0;
    check_grid(&geometry.point_set(), &config, exact);
    check_grid(&geometry.segment_set(), &config, exact);
    let triangles = geometry.triangle_set();
    if let Some(grid) = check_grid(&triangles, &config, exact) {
        let _: &HashGrid<Triangle, ClassicHash> = &grid;
        for &q in &geometry.queries {
            let target = geometry.vertices[u.choose_index(geometry.vertices.len())?];
            check_first_hit(&grid, q, target - q, exact);
        }
    }
    Ok(())
}

/// Asserts that the grid's first hit along `origin + t · direction`, `t ≥ 0`,
/// equals a scan of every triangle with the same watertight test (ties to the
/// lowest index). Outside exact geometry, of several triangles hit at the same
/// `t`, another than the lowest may be reported (see the comment inside).
pub fn check_first_hit(grid: &HashGrid<Triangle>, origin: Vec3, direction: Vec3, exact: bool) {
    let Some(ray) = WatertightRay::new(origin, direction) else {
        return;
    };
    let triangles = grid.primitives();
    let mut want: Option<(u32, f32)> = None;
    for (p, t) in triangles.iter().enumerate() {
        if let Some(h) = ray.intersect(t, 0.0, f32::INFINITY)
            && want.is_none_or(|(_, bt)| h.t < bt)
        {
            want = Some((p as u32, h.t));
        }
    }
    match grid.first_hit(origin, direction, 0.0, f32::INFINITY) {
        // Outside the lattice, triangles that touch a cell only within
        // rounding of the overlap test may be missing from it: of several
        // triangles hit at the same t (a shared vertex or edge), the grid may
        // then report another one than the lowest.
        Ok(Some(got))
            if !exact
                && want.is_some_and(|(p, t)| p != got.primitive && t == got.t)
                && ray
                    .intersect(&triangles[got.primitive as usize], 0.0, f32::INFINITY)
                    .map(|h| h.t)
                    == Some(got.t) => {}
        Ok(got) => assert_eq!(
            got.map(|h| (h.primitive, h.t)),
            want,
            "ray {origin:?} + t {direction:?}"
        ),
        // A direction too small for its reciprocal (which the watertight
        // test alone accepts) is refused as every structure refuses it.
        Err(GridError::Ray(proxima::RayError::Direction)) => {
            assert_eq!(proxima::Ray::new(origin, direction), Err(proxima::RayError::Direction))
        }
        // The walk over cells beyond ±2^50 is a typed error, not an answer.
        Err(e) => assert_eq!(e, GridError::OutOfRange),
    }
}

/// HashGrid (classic and scan-line, both hashers) against per-primitive brute
/// force, and `first_hit` against a scan of every triangle.
pub fn hash_grid(data: &[u8]) {
    let _ = grid_body(data);
}

// ------------------------------------------------------------ traversal ---

/// The cells the ray spends positive length in, within `[t_min, t_max]`, by
/// entry parameter, from the documented crossing formula in `f64`, cell by
/// cell (the oracle of `tests/traversal.rs`).
pub fn brute_walk(layout: &GridLayout, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Vec<TraversalStep> {
    let (o64, inv) = (o.to_array().map(|x| x as f64), d.to_array().map(|x| 1.0 / x as f64));
    let crossing = |a: usize, n: i64| (layout.boundary(a, n) - o64[a]) * inv[a];
    let (p0, p1) = (o + d * t_min, o + d * t_max);
    let (s, g) = (layout.cell_size(), layout.origin());
    let lo: [i64; 3] = std::array::from_fn(|a| ((p0[a].min(p1[a]) - g[a]) / s[a]).floor() as i64 - 2);
    let hi: [i64; 3] = std::array::from_fn(|a| ((p0[a].max(p1[a]) - g[a]) / s[a]).floor() as i64 + 2);
    let mut out = Vec::new();
    for k in lo[2]..=hi[2] {
        for j in lo[1]..=hi[1] {
            for i in lo[0]..=hi[0] {
                let cell = [i, j, k];
                let (mut t0, mut t1) = (t_min as f64, t_max as f64);
                let mut inside = true;
                for a in 0..3 {
                    if d[a] == 0.0 {
                        let (b0, b1) = (layout.boundary(a, cell[a]), layout.boundary(a, cell[a] + 1));
                        inside &= b0 <= o64[a] && o64[a] < b1;
                    } else {
                        let (c0, c1) = (crossing(a, cell[a]), crossing(a, cell[a] + 1));
                        t0 = t0.max(c0.min(c1));
                        t1 = t1.min(c0.max(c1));
                    }
                }
                if inside && t1 > t0 {
                    let step = TraversalStep {
                        cell,
                        t_enter: t0 as f32,
                        t_exit: t1 as f32,
                    };
                    out.push((t0, step));
                }
            }
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out.into_iter().map(|(_, s)| s).collect()
}

fn traversal_body(data: &[u8]) -> Result<()> {
    let mut u = Unstructured::new(data);
    let lattice = |u: &mut Unstructured<'_>| -> Result<f32> { Ok(f32::from(u.int_in_range::<i8>(-16..=16)?) * 0.25) };
    let free = |u: &mut Unstructured<'_>| -> Result<f32> {
        Ok(u.int_in_range::<u32>(0..=1 << 20)? as f32 / (1 << 20) as f32 * 8.0 - 4.0)
    };
    let value = |u: &mut Unstructured<'_>| -> Result<f32> { if u.arbitrary()? { lattice(u) } else { free(u) } };
    let cell = Vec3::new(
        f32::from(u.int_in_range::<u8>(1..=8)?) * 0.125,
        f32::from(u.int_in_range::<u8>(1..=8)?) * 0.125,
        f32::from(u.int_in_range::<u8>(1..=8)?) * 0.125,
    );
    let origin = Vec3::new(value(&mut u)?, value(&mut u)?, value(&mut u)?);
    let layout = GridLayout::new(origin * 0.25, cell).expect("positive finite cells");
    let o = Vec3::new(value(&mut u)?, value(&mut u)?, value(&mut u)?);
    // Directions with zero components and exact diagonals come from the lattice.
    let d = Vec3::new(lattice(&mut u)?, lattice(&mut u)?, lattice(&mut u)?) * 0.25;
    let d = if u.arbitrary()? {
        d + Vec3::new(free(&mut u)?, 0.0, free(&mut u)?) * 0.01
    } else {
        d
    };
    if d == Vec3::ZERO {
        assert!(GridTraversal::in_layout(&layout, o, d, 0.0, 1.0).is_err());
        return Ok(());
    }
    let t_min = if u.arbitrary()? { 0.0 } else { -free(&mut u)?.abs() };
    // At most 2 units of ray: the oracle tests every cell of the segment's box.
    let t_max = t_min + free(&mut u)?.abs() * 0.5;
    let got: Vec<_> = GridTraversal::in_layout(&layout, o, d, t_min, t_max)
        .expect("valid ray")
        .collect();
    assert_eq!(
        got,
        brute_walk(&layout, o, d, t_min, t_max),
        "o {o:?} d {d:?} [{t_min}, {t_max}] {layout:?}"
    );
    Ok(())
}

/// GridTraversal against the cell-by-cell oracle.
pub fn traversal(data: &[u8]) {
    let _ = traversal_body(data);
}
