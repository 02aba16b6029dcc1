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

use crate::common;

use crate::common::glb_writer::instanced_glb;

use proxima::build::{MAX_DEPTH, SplitMethod};
use proxima::grid::{GridConfig, HashGrid, VoxelConfig, voxelize};
use proxima::grid::{GridTraversal, TraversalConfig};
use proxima::io::{Format, LoadOptions, parse};
use proxima::prelude::*;
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

// ---------------------------------------------------------------- memory budget of loading ---

use proxima::budget::{LOAD_BYTES_PER_TRIANGLE, LOAD_BYTES_PER_VERTEX, default_memory_budget};
use proxima::io::{load_with, parse_with, read_with};
use std::cell::Cell;
use std::rc::Rc;

/// The budget error's fields, or a panic naming what came instead.
fn budget_error(result: Result<proxima::Mesh, proxima::LoadError>) -> (String, u128, u64, Option<usize>) {
    let e = result.expect_err("over the budget");
    match e.kind {
        LoadErrorKind::MemoryBudget { what, bytes, budget } => (what, bytes, budget, e.line),
        other => panic!("{other:?} instead of MemoryBudget"),
    }
}

fn with_budget(memory_budget: u64) -> LoadOptions {
    LoadOptions {
        memory_budget,
        ..LoadOptions::default()
    }
}

#[test]
fn glb_instances_are_counted_against_the_budget_before_expanding() {
    // The issue's files: 960,000 byte indices shown by 100 nodes (a 964 KB
    // file, 32 million triangles: `sdf` aborted at 4.1 GB), and a strip of
    // 90,002 shown by 200 (98 KB, 18 million: `info` took 30 s and 2.2 GB).
    // Refused from the accessors' counts, before a vertex is read.
    for (corners, nodes, mode, triangles) in [(960_000, 100, 4, 32_000_000u64), (90_002, 200, 5, 18_000_000)] {
        let file = instanced_glb(corners, nodes, mode, "", "");
        let (what, bytes, budget, _) = budget_error(parse(&file, Format::Glb, "scene.glb".as_ref()));
        assert_eq!(budget, default_memory_budget());
        let counts = format!("({} vertices and {triangles} triangles, {nodes} primitives)", 3 * nodes);
        assert!(what.contains(&counts), "{what}");
        let least = file.len() as u128
            + (3 * nodes) as u128 * u128::from(LOAD_BYTES_PER_VERTEX)
            + u128::from(triangles) * u128::from(LOAD_BYTES_PER_TRIANGLE);
        assert!(bytes >= least && bytes < least + (1 << 20), "{bytes} against {least}");
    }
    // Smaller, the same way: loaded within a budget that holds it, with one
    // triangle per instance and index triple; refused below its counted bytes.
    let file = instanced_glb(3000, 20, 4, "", "");
    let mesh = parse_with(&file, Format::Glb, "scene.glb".as_ref(), &with_budget(64 << 20)).unwrap();
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (60, 20_000));
    assert_eq!(mesh.positions()[3], Vec3::new(1.0, 0.0, 0.0)); // the second node's first vertex
    let least = file.len() as u64 + 60 * LOAD_BYTES_PER_VERTEX + 20_000 * LOAD_BYTES_PER_TRIANGLE;
    let (what, ..) = budget_error(parse_with(
        &file,
        Format::Glb,
        "scene.glb".as_ref(),
        &with_budget(least - 1),
    ));
    assert!(what.contains("60 vertices and 20000 triangles"), "{what}");
}

#[test]
fn glb_json_members_not_read_are_skipped_and_the_rest_counted() {
    // 5 million zeros (10 MB of JSON) in the document's `extras` member:
    // skipped as they are parsed, so the file loads within a
    // budget of its own size and 4 MiB (kept, the values would take 320 MB).
    let zeros = format!("[{}0]", "0,".repeat(5_000_000));
    let file = instanced_glb(3, 1, 4, &format!(r#""extras":{zeros},"#), "");
    let budget = file.len() as u64 + (4 << 20);
    let mesh = parse_with(&file, Format::Glb, "extras.glb".as_ref(), &with_budget(budget)).unwrap();
    assert_eq!(mesh.face_count(), 1);
    // The same zeros as a member the reader keeps (a scene's roots): counted
    // as they are built, and refused at the budget.
    let scene = format!(r#""scene":0,"scenes":[{{"nodes":{zeros}}}],"#);
    let file = instanced_glb(3, 1, 4, &scene, "");
    let (what, bytes, _, line) = budget_error(parse_with(
        &file,
        Format::Glb,
        "kept.glb".as_ref(),
        &with_budget(budget),
    ));
    assert!(what.contains("JSON values"), "{what}");
    assert!(bytes > u128::from(budget) && line.is_none());
}

/// An endless reader of one repeated text, counting the bytes it hands out.
struct Repeat {
    text: &'static [u8],
    pos: usize,
    handed: Rc<Cell<u64>>,
}

impl std::io::Read for Repeat {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        for b in buf.iter_mut() {
            *b = self.text[self.pos];
            self.pos = (self.pos + 1) % self.text.len();
        }
        self.handed.set(self.handed.get() + buf.len() as u64);
        Ok(buf.len())
    }
}

fn repeat(text: &'static [u8]) -> (Repeat, Rc<Cell<u64>>) {
    let handed = Rc::new(Cell::new(0));
    let reader = Repeat {
        text,
        pos: 0,
        handed: handed.clone(),
    };
    (reader, handed)
}

/// `at least V vertices and T triangles` of a budget message.
fn counts(what: &str) -> (u64, u64) {
    let words: Vec<&str> = what.split_whitespace().collect();
    let at = |word: &str| {
        let i = words.iter().position(|w| w.trim_end_matches(',') == word).unwrap();
        words[i - 1].parse().unwrap()
    };
    (at("vertices"), at("triangles"))
}

#[test]
fn text_is_counted_against_the_budget_as_it_is_read() {
    let budget: u64 = 64 << 20;
    // Vertices without end: stopped once the bytes read and the vertices
    // counted (8 + 96 bytes a line) pass the budget, within a chunk (1 MiB).
    let (reader, handed) = repeat(b"v 0 0 0\n");
    let (what, bytes, b, line) = budget_error(read_with(reader, Format::Obj, "v.obj".as_ref(), &with_budget(budget)));
    let (vertices, triangles) = counts(&what);
    assert_eq!((b, triangles, line), (budget, 0, Some(vertices as usize + 1)));
    assert!(bytes > u128::from(budget) && what.starts_with("at least"), "{what}");
    let lines_in_budget = budget / (8 + LOAD_BYTES_PER_VERTEX);
    assert!(vertices <= lines_in_budget + (1 << 17), "{vertices}");
    assert!(handed.get() <= 8 * lines_in_budget + (2 << 20), "{}", handed.get());
    // Faces of five corners count three triangles each.
    let (reader, _) = repeat(b"v 0 0 0\nf 1 1 1 1 1\n");
    let (what, ..) = budget_error(read_with(reader, Format::Obj, "f.obj".as_ref(), &with_budget(budget)));
    let (vertices, triangles) = counts(&what);
    assert!(triangles == 3 * vertices || triangles + 3 == 3 * vertices, "{what}");
    // Comments hold nothing, but are held: stopped at the budget, never past it.
    let (reader, handed) = repeat(b"# nothing to see here\n");
    let (what, ..) = budget_error(read_with(reader, Format::Obj, "c.obj".as_ref(), &with_budget(budget)));
    assert!(what.contains("bytes of input (so far)"), "{what}");
    assert!(handed.get() <= budget, "{}", handed.get());
    // Ascii STL facets, and OFF lines (counted as vertices).
    let (reader, _) =
        repeat(b"facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n");
    let stl = [b"solid s\n".as_slice()].concat();
    let reader = std::io::Read::chain(std::io::Cursor::new(stl), reader);
    let (what, ..) = budget_error(read_with(reader, Format::Stl, "s.stl".as_ref(), &with_budget(budget)));
    assert!(counts(&what).1 > budget / (60 + LOAD_BYTES_PER_TRIANGLE) / 2, "{what}");
    let (reader, _) = repeat(b"0 0 0\n");
    let off = std::io::Read::chain(std::io::Cursor::new(b"OFF\n".to_vec()), reader);
    let (what, ..) = budget_error(read_with(off, Format::Off, "o.off".as_ref(), &with_budget(budget)));
    assert!(counts(&what).0 > budget / (6 + LOAD_BYTES_PER_VERTEX) / 2, "{what}");
}

#[test]
fn gzip_text_is_counted_as_it_is_inflated() {
    // The issue's file, scaled to the budget: `v 0 0 0` lines that inflate
    // to 16 MiB (3.2 GB aborted under a 6 GB address-space limit), as
    // gzip members of 1 MiB each; a budget of 4 MiB stops it after about
    // 40,000 lines (4 MiB / 104 bytes), the rest never inflated.
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    encoder.write_all(&b"v 0 0 0\n".repeat(1 << 17)).unwrap();
    let member = encoder.finish().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("zeros.obj.gz");
    std::fs::write(&path, member.repeat(16)).unwrap();
    let (what, _, _, line) = budget_error(load_with(&path, &with_budget(4 << 20)));
    let (vertices, _) = counts(&what);
    assert_eq!(line, Some(vertices as usize + 1));
    assert!((4 << 20) / (8 + LOAD_BYTES_PER_VERTEX) < vertices, "{what}");
    assert!(vertices < (4 << 20) / (8 + LOAD_BYTES_PER_VERTEX) + (1 << 17), "{what}");
    // Under a budget that holds it, the same file loads.
    let mesh = load_with(&path, &with_budget(1 << 30)).unwrap();
    assert_eq!(mesh.vertex_count(), 16 << 17);
}

#[test]
fn header_counts_are_checked_against_the_budget_before_the_data() {
    // Binary PLY: 100,000 vertices and triangles, all there (2.5 MB), a
    // budget of 8 MiB: refused at `end_header` (line 10), from the counts.
    let n = 100_000u32;
    let mut ply = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n\
         property float z\nelement face {n}\nproperty list uchar int vertex_indices\ncomment end\nend_header\n"
    )
    .into_bytes();
    for i in 0..n {
        ply.extend([i as f32, 0.0, 0.0].iter().flat_map(|x| x.to_le_bytes()));
    }
    for i in 0..n {
        ply.push(3);
        ply.extend([i, (i + 1) % n, (i + 2) % n].iter().flat_map(|x| x.to_le_bytes()));
    }
    let (what, bytes, _, line) = budget_error(parse_with(&ply, Format::Ply, "p.ply".as_ref(), &with_budget(8 << 20)));
    assert_eq!(line, Some(10));
    assert!(what.contains("100000 vertices and 100000 triangles"), "{what}");
    let counted = ply.len() as u128 + u128::from(n) * u128::from(LOAD_BYTES_PER_VERTEX + LOAD_BYTES_PER_TRIANGLE);
    assert_eq!(bytes, counted);
    let mesh = parse_with(&ply, Format::Ply, "p.ply".as_ref(), &with_budget(bytes as u64)).unwrap();
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (n as usize, n as usize));
    // OFF: 3 vertices and 100,000 faces (the lines counted as they arrive
    // at a vertex's bytes fit; the header's counts do not).
    let mut off = format!("OFF\n3 {n} 0\n0 0 0\n1 0 0\n0 1 0\n").into_bytes();
    off.extend(b"3 0 1 2\n".repeat(n as usize));
    let budget = off.len() as u64 + 3 * LOAD_BYTES_PER_VERTEX + u64::from(n) * LOAD_BYTES_PER_TRIANGLE - 1;
    let (_, _, _, line) = budget_error(parse_with(&off, Format::Off, "o.off".as_ref(), &with_budget(budget)));
    assert_eq!(line, Some(2));
    assert!(parse_with(&off, Format::Off, "o.off".as_ref(), &with_budget(budget + 1)).is_ok());
    // Binary STL: 100,000 triangles (5 MB) in 8 MiB.
    let mut stl = vec![0u8; 80];
    stl.extend(n.to_le_bytes());
    for i in 0..n {
        stl.extend([0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
        stl.extend(
            [i as f32, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
                .iter()
                .flat_map(|x| x.to_le_bytes()),
        );
        stl.extend([0u8; 2]);
    }
    let (what, ..) = budget_error(parse_with(&stl, Format::Stl, "s.stl".as_ref(), &with_budget(8 << 20)));
    assert!(what.contains("0 vertices and 100000 triangles"), "{what}");
}

#[test]
fn a_mesh_loaded_always_fits_its_budget() {
    // Counted while read, a face is a triangle at least: 1,000 faces of 12
    // corners, each continued on a second line, are counted as 2,000
    // triangles from their first lines. The mesh made is counted again,
    // exactly: 10,000 triangles.
    let mut obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\n".to_vec();
    obj.extend(b"f 1 2 3 \\\n1 2 3 1 2 3 1 2 3\n".repeat(1000));
    let exact = obj.len() as u64 + 3 * LOAD_BYTES_PER_VERTEX + 10_000 * LOAD_BYTES_PER_TRIANGLE;
    let mesh = parse_with(&obj, Format::Obj, "poly.obj".as_ref(), &with_budget(exact)).unwrap();
    assert_eq!(mesh.triangle_count(), 10_000);
    let (what, bytes, _, _) = budget_error(parse_with(
        &obj,
        Format::Obj,
        "poly.obj".as_ref(),
        &with_budget(exact - 1),
    ));
    assert_eq!(bytes, u128::from(exact));
    assert!(what.starts_with("3 vertices and 10000 triangles"), "{what}");
}

#[test]
fn grids_are_counted_against_the_budget_before_storing() {
    // A square of two triangles in cells of 1/500: about 250,000 cells, those
    // of the diagonal shared, so the occupied cells are estimated by sampling.
    let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
    let square =
        || PrimitiveSet::from_primitives(vec![proxima::Triangle::new(a, b, c), proxima::Triangle::new(a, c, d)]);
    let config = GridConfig::cubic(1.0 / 500.0);
    let grid = HashGrid::<proxima::Triangle>::build(square(), &config).unwrap();
    let (entries, cells) = (grid.entry_count() as u64, grid.stats().occupied_cells as u64);
    assert!(cells > 1 << 14 && entries > cells, "{entries} {cells}");
    let need = entries * proxima::budget::GRID_BYTES_PER_ENTRY + cells * proxima::budget::GRID_BYTES_PER_CELL;
    // Exactly its need: built (the count's estimate does not refuse it).
    let fits = GridConfig {
        memory_budget: need,
        ..config
    };
    let again = HashGrid::<proxima::Triangle>::build(square(), &fits).unwrap();
    assert_eq!(again.entry_count() as u64, entries);
    // Less: refused, with the whole estimated from the share counted.
    for budget in [need - 1, need / 2, need / 10] {
        let config = GridConfig {
            memory_budget: budget,
            ..config
        };
        let e = HashGrid::<proxima::Triangle>::build(square(), &config).unwrap_err();
        let GridError::MemoryBudget {
            what,
            count,
            bytes,
            budget: b,
        } = e.clone()
        else {
            panic!("{e}")
        };
        assert_eq!((what, b), ("cell entries", budget));
        let near = |x: u128, y: u64| (x as f64 - y as f64).abs() <= 0.15 * y as f64;
        assert!(
            near(count, entries) && near(bytes, need),
            "{e}: {entries} entries, {need} bytes"
        );
    }
}

/// The memory budget of the environment (`PROXIMA_MEMORY_BUDGET`) bounds the
/// library's signed-distance grids and samples as it bounds every front end
/// (they used to be checked against the default budget only). The test runs
/// itself again in a child process with the variable set: setting it here
/// would race the other tests of this process.
#[test]
fn sdf_grids_and_samples_follow_the_budget_of_the_environment() {
    const CHILD: &str = "PROXIMA_TEST_SDF_BUDGET_CHILD";
    const NAME: &str = "sdf_grids_and_samples_follow_the_budget_of_the_environment";
    if std::env::var_os(CHILD).is_some() {
        return sdf_budget_child(&std::env::var("PROXIMA_MEMORY_BUDGET").unwrap_or_default());
    }
    for budget in ["64K", "lots"] {
        let out = crate::common::rerun_with_budget(module_path!(), NAME, CHILD, budget);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && stdout.contains("1 passed"),
            "child with PROXIMA_MEMORY_BUDGET={budget}: {stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// The child of `sdf_grids_and_samples_follow_the_budget_of_the_environment`.
fn sdf_budget_child(budget: &str) {
    use proxima::SdfError;
    use proxima::budget::BudgetError;
    use proxima::sdf::{SdfConfig, SdfGrid, SignedDistanceField};
    let field =
        SignedDistanceField::new(&proxima::mesh::generate::noisy_icosphere(4, 1), &SdfConfig::default()).unwrap();
    let cube = proxima::Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
    let grid = |n| SdfGrid::around(&field.bounds(), n, 0.05).unwrap();
    if budget == "lots" {
        let e = field.sdf_grid(&grid(2), |_, _| {}).unwrap_err();
        assert!(matches!(&e, SdfError::Budget(BudgetError::Environment(_))), "{e:?}");
        assert!(
            e.to_string().contains("PROXIMA_MEMORY_BUDGET: 'lots' is not a number"),
            "{e}"
        );
        let e = field.sample_in(&cube, 10, 1).unwrap_err();
        assert!(matches!(e, SdfError::Budget(BudgetError::Environment(_))), "{e:?}");
        return;
    }
    assert_eq!(budget, "64K");
    // 16³ values of 4 bytes fit 64 KiB; 26³ (70,304 bytes) do not.
    assert_eq!(field.sdf_grid(&grid(16), |_, _| {}).unwrap().len(), 4096);
    assert_eq!(
        field.sdf_grid(&grid(26), |_, _| {}).unwrap_err(),
        SdfError::MemoryBudget {
            option: "resolution",
            value: 26 * 26 * 26,
            bytes: 26 * 26 * 26 * 4,
            budget: 64 << 10,
        }
    );
    // Samples are counted at 32 bytes: 2,048 fit, 2,049 do not.
    assert_eq!(field.sample_in(&cube, 2048, 1).unwrap().points.len(), 2048);
    let over = SdfError::MemoryBudget {
        option: "count",
        value: 2049,
        bytes: 2049 * 32,
        budget: 64 << 10,
    };
    assert_eq!(field.sample_in(&cube, 2049, 1).unwrap_err(), over);
    assert_eq!(field.sample_near_surface(2049, 0.01, 1).unwrap_err(), over);
    assert_eq!(field.training_samples(2000, 0.01, 49, &cube, 1).unwrap_err(), over);
}
