//! The bad-input catalogue (`docs/errors.md`), library side: one test per kind
//! of bad input, asserting the typed error, the line where the format is text,
//! the path in the message, and the text the catalogue quotes. The CLI side is
//! `crates/proxima-cli/tests/errors_cli.rs`, with the same test names.

use crate::common::temp_dir;
use proxima::build::MAX_COORDINATE;
use proxima::grid::{GridConfig, HashGrid, VoxelConfig, voxelize};
use proxima::grid::{GridTraversal, TraversalConfig};
use proxima::io::LoadOptions;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, BuildError, GridError, LinearSearch, LoadError, LoadErrorKind, MeshError, Vec3};
use std::io::Write;
use std::path::Path;

fn assert_load_error(
    e: &LoadError,
    path: &Path,
    line: Option<usize>,
    text: &str,
    kind: impl Fn(&LoadErrorKind) -> bool,
) {
    let message = e.to_string();
    assert!(kind(&e.kind), "unexpected kind: {message}");
    assert_eq!(e.line, line, "{message}");
    assert_eq!(e.path, path);
    let file = path.file_name().unwrap().to_string_lossy();
    assert!(message.contains(&*file), "{message}");
    assert!(message.contains(text), "'{text}' missing from {message}");
    assert_eq!(message.lines().count(), 1, "{message}");
}

/// A binary STL of 84 + 50 bytes whose header announces `count` triangles.
fn stl_with_count(count: u32) -> Vec<u8> {
    let mut bytes = vec![b'x'; 80];
    bytes.extend(count.to_le_bytes());
    bytes.extend([0u8; 50]);
    bytes
}

const TRIANGLE: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// ------------------------------------------------------------- loading ---

#[test]
fn missing_file() {
    let dir = temp_dir("missing_file");
    let path = dir.join("missing.obj");
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, None, "No such file", |k| matches!(k, LoadErrorKind::Io(_)));
}

#[test]
fn unknown_extension() {
    let dir = temp_dir("unknown_extension");
    let path = dir.join("mesh.xyz");
    std::fs::write(&path, b"1 2 3\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, None, "unknown mesh format", |k| {
        matches!(k, LoadErrorKind::UnknownFormat)
    });
}

#[test]
fn directory_instead_of_file() {
    let dir = temp_dir("directory_instead_of_file");
    let path = dir.join("dir.obj");
    std::fs::create_dir_all(&path).unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, None, "dir.obj", |k| matches!(k, LoadErrorKind::Io(_)));
}

#[test]
fn obj_bad_number() {
    let dir = temp_dir("obj_bad_number");
    let path = dir.join("badnum.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 x 0\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(2), "", |k| matches!(k, LoadErrorKind::Syntax(_)));
}

#[test]
fn obj_index_zero() {
    let dir = temp_dir("obj_index_zero");
    let path = dir.join("zero.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(4), "vertex index 0", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn obj_index_out_of_range() {
    let dir = temp_dir("obj_index_out_of_range");
    let path = dir.join("range.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(4), "refers to vertex", |k| {
        matches!(k, LoadErrorKind::Mesh(MeshError::IndexOutOfRange { .. }))
    });
}

#[test]
fn obj_relative_index_before_first() {
    let dir = temp_dir("obj_relative_index_before_first");
    let path = dir.join("rel.obj");
    std::fs::write(&path, b"v 0 0 0\nf -3 -2 -1\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(2), "before the first vertex", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn obj_face_too_small() {
    let dir = temp_dir("obj_face_too_small");
    let path = dir.join("small.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nf 1 2\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(3), "at least 3", |k| {
        matches!(k, LoadErrorKind::Mesh(MeshError::FaceTooSmall { .. }))
    });
}

#[test]
fn obj_nan_coordinate() {
    let dir = temp_dir("obj_nan_coordinate");
    let path = dir.join("nan.obj");
    std::fs::write(&path, b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(2), "non-finite", |k| {
        matches!(k, LoadErrorKind::Mesh(MeshError::NonFiniteVertex { index: 1 }))
    });
}

#[test]
fn off_overflowing_coordinate() {
    let dir = temp_dir("off_overflowing_coordinate");
    let path = dir.join("over.off");
    std::fs::write(&path, b"OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(4), "non-finite", |k| {
        matches!(k, LoadErrorKind::Mesh(MeshError::NonFiniteVertex { index: 1 }))
    });
}

#[test]
fn off_truncated() {
    let dir = temp_dir("off_truncated");
    let path = dir.join("trunc.off");
    std::fs::write(&path, b"OFF\n4 2 0\n0 0 0\n1 0 0\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(4), "", |k| {
        matches!(k, LoadErrorKind::Truncated(_) | LoadErrorKind::Implausible(_))
    });
}

#[test]
fn off_trailing_content() {
    let dir = temp_dir("off_trailing_content");
    let path = dir.join("trail.off");
    std::fs::write(&path, b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\nextra\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(7), "after the 1 faces", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn off_negative_index() {
    let dir = temp_dir("off_negative_index");
    let path = dir.join("neg.off");
    std::fs::write(&path, b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(6), "negative vertex index", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn ply_no_format_line() {
    let dir = temp_dir("ply_no_format_line");
    let path = dir.join("nofmt.ply");
    std::fs::write(&path, b"ply\nelement vertex 3\nend_header\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(3), "no `format` line", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn ply_implausible_vertex_count() {
    let dir = temp_dir("ply_implausible_vertex_count");
    let path = dir.join("huge.ply");
    std::fs::write(&path, b"ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(3), "1000000000000", |k| {
        matches!(k, LoadErrorKind::Implausible(_))
    });
}

#[test]
fn ply_binary_truncated() {
    let dir = temp_dir("ply_binary_truncated");
    let path = dir.join("trunc_bin.ply");
    std::fs::write(&path, b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n\x00\x00\x00\x00").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(3), "4 bytes", |k| {
        matches!(k, LoadErrorKind::Implausible(_))
    });
}

#[test]
fn ply_list_count_not_integer() {
    let dir = temp_dir("ply_list_count_not_integer");
    let path = dir.join("listtype.ply");
    std::fs::write(&path, b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(8), "integer type", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn ply_missing_z() {
    let dir = temp_dir("ply_missing_z");
    let path = dir.join("noz.ply");
    std::fs::write(
        &path,
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nend_header\n0 0\n1 0\n0 1\n",
    )
    .unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(3), "no property `z`", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn ply_ascii_fewer_values_than_announced() {
    let dir = temp_dir("ply_ascii_fewer_values_than_announced");
    let path = dir.join("count.ply");
    std::fs::write(&path, b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(3), "", |k| {
        matches!(k, LoadErrorKind::Truncated(_) | LoadErrorKind::Implausible(_))
    });
}

#[test]
fn stl_binary_count_beyond_size() {
    let dir = temp_dir("stl_binary_count_beyond_size");
    let path = dir.join("count.stl");
    std::fs::write(&path, stl_with_count(1000)).unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, None, "announces 1000 triangles", |k| {
        matches!(k, LoadErrorKind::Truncated(_))
    });
}

#[test]
fn stl_ascii_truncated() {
    let dir = temp_dir("stl_ascii_truncated");
    let path = dir.join("short.stl");
    std::fs::write(
        &path,
        b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0\n",
    )
    .unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, Some(5), "expected a coordinate", |k| {
        matches!(k, LoadErrorKind::Truncated(_))
    });
}

#[test]
fn gzip_corrupt() {
    let dir = temp_dir("gzip_corrupt");
    let path = dir.join("corrupt.obj.gz");
    std::fs::write(&path, b"not gzip at all").unwrap();
    let e = proxima::io::load(&path).unwrap_err();
    assert_load_error(&e, &path, None, "gzip", |k| matches!(k, LoadErrorKind::Io(_)));
}

#[test]
fn gzip_bomb() {
    let dir = temp_dir("gzip_bomb");
    let path = dir.join("bomb.obj.gz");
    // 2 MiB of blank lines compress to about 2 KB.
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    encoder
        .write_all(&[[b' '; 63].as_slice(), b"\n"].concat().repeat(32 << 10))
        .unwrap();
    let bomb = encoder.finish().unwrap();
    assert!(bomb.len() < 10_000);
    std::fs::write(&path, &bomb).unwrap();
    let options = LoadOptions {
        max_decompressed_bytes: 1 << 20,
        ..LoadOptions::default()
    };
    let e = proxima::io::load_with(&path, &options).unwrap_err();
    assert_load_error(&e, &path, None, "exceeds the limit of 1048576 bytes", |k| {
        matches!(k, LoadErrorKind::DecompressedTooLarge { limit: 1048576 })
    });
    // Within the limit (and with the default one) it is an ordinary empty OBJ.
    let mesh = proxima::io::load_with(
        &path,
        &LoadOptions {
            max_decompressed_bytes: 2 << 20,
            ..LoadOptions::default()
        },
    )
    .unwrap();
    assert_eq!(mesh.vertex_count(), 0);
    assert!(proxima::io::load(&path).is_ok());
}

// ------------------------------------------------------------ building ---

#[test]
fn coordinate_beyond_tree_bound() {
    let dir = temp_dir("coordinate_beyond_tree_bound");
    let path = dir.join("huge.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n").unwrap();
    let mesh = proxima::io::load(&path).expect("finite coordinates load");
    let e = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap_err();
    assert_eq!(
        e,
        BuildError::CoordinateTooLarge {
            index: 0,
            bound: MAX_COORDINATE
        }
    );
    assert!(e.to_string().contains("beyond"), "{e}");
    assert!(WideTree::build_set(mesh.vertices(), &BuildConfig::default()).is_err());
}

#[test]
fn empty_mesh() {
    // Not an error for the library: empty structures answer nothing.
    let mesh = proxima::io::parse(b"# nothing\n", proxima::io::Format::Obj, "empty.obj".as_ref()).unwrap();
    let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    assert_eq!(tree.closest(Vec3::ZERO), None);
    assert!(tree.k_nearest(Vec3::ZERO, 3).is_empty());
    let grid: HashGrid<_> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(1.0)).unwrap();
    assert_eq!(grid.first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY).unwrap(), None);
}

#[test]
fn non_finite_query_point() {
    let mesh = proxima::io::parse(TRIANGLE, proxima::io::Format::Obj, "t.obj".as_ref()).unwrap();
    let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    for p in [Vec3::new(f32::NAN, 0.0, 0.0), Vec3::new(0.0, f32::INFINITY, 0.0)] {
        assert_eq!(tree.closest(p), None);
        assert_eq!(LinearSearch::new(mesh.triangles()).closest(p), None);
        assert!(tree.k_nearest(p, 2).is_empty());
    }
}

#[test]
fn grid_primitive_spans_too_many_cells() {
    let mesh = proxima::io::parse(TRIANGLE, proxima::io::Format::Obj, "t.obj".as_ref()).unwrap();
    let e = HashGrid::<proxima::Triangle>::build(mesh.triangles(), &GridConfig::cubic(1e-6)).unwrap_err();
    assert!(matches!(e, GridError::PrimitiveTooLarge { index: 0, .. }), "{e}");
    assert!(e.to_string().contains("spans"), "{e}");
    let config = GridConfig {
        max_entries: 3,
        ..GridConfig::cubic(0.1)
    };
    assert_eq!(
        HashGrid::<proxima::Triangle>::build(mesh.triangles(), &config).unwrap_err(),
        GridError::TooManyCells { limit: 3 }
    );
}

#[test]
fn grid_cell_size_not_positive() {
    let mesh = proxima::io::parse(TRIANGLE, proxima::io::Format::Obj, "t.obj".as_ref()).unwrap();
    for size in [0.0, -1.0, f32::NAN] {
        let e = HashGrid::<proxima::Triangle>::build(mesh.triangles(), &GridConfig::cubic(size)).unwrap_err();
        assert!(matches!(e, GridError::CellSize { .. }), "{e}");
        assert!(e.to_string().contains("cell size"), "{e}");
    }
}

#[test]
fn grid_primitive_out_of_range() {
    let mesh = proxima::io::parse(
        b"v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n",
        proxima::io::Format::Obj,
        "t.obj".as_ref(),
    )
    .unwrap();
    let e = HashGrid::<proxima::Point>::build(mesh.vertices(), &GridConfig::cubic(1e-10)).unwrap_err();
    assert_eq!(e, GridError::PrimitiveOutOfRange { index: 1 });
    assert!(e.to_string().contains("primitive 1"), "{e}");
}

#[test]
fn ray_zero_direction() {
    let e = GridTraversal::new(Vec3::ZERO, Vec3::ZERO, &TraversalConfig::cubic(1.0)).unwrap_err();
    assert_eq!(e, GridError::Ray(proxima::RayError::Direction));
    assert!(e.to_string().contains("direction"), "{e}");
}

/// One set of ray rules for every ray query: a direction whose largest
/// component's reciprocal overflows (here 1e-45) is refused by the trees, the
/// hash grid and the traversal alike, as `proxima::Ray` refuses it; one just
/// above that limit is accepted by all.
#[test]
fn ray_direction_underflowing_everywhere() {
    let mesh = proxima::io::parse(TRIANGLE, proxima::io::Format::Obj, "t.obj".as_ref()).unwrap();
    let tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    let grid: HashGrid<_> = HashGrid::build(mesh.triangles(), &GridConfig::cubic(0.5)).unwrap();
    let tiny = Vec3::new(1e-45, 0.0, 0.0);
    assert_eq!(proxima::Ray::new(Vec3::ZERO, tiny), Err(proxima::RayError::Direction));
    assert_eq!(
        tree.first_hit(Vec3::ZERO, tiny, 0.0, f32::INFINITY).unwrap_err(),
        proxima::RayError::Direction
    );
    assert_eq!(
        grid.first_hit(Vec3::ZERO, tiny, 0.0, f32::INFINITY).unwrap_err(),
        GridError::Ray(proxima::RayError::Direction)
    );
    assert_eq!(
        GridTraversal::new(Vec3::ZERO, tiny, &TraversalConfig::cubic(1.0)).unwrap_err(),
        GridError::Ray(proxima::RayError::Direction)
    );
    let small = Vec3::new(1e-37, 0.0, 0.0);
    assert!(proxima::Ray::new(Vec3::ZERO, small).is_ok());
    assert!(tree.first_hit(Vec3::ZERO, small, 0.0, f32::INFINITY).is_ok());
    assert!(grid.first_hit(Vec3::ZERO, small, 0.0, f32::INFINITY).is_ok());
    assert!(GridTraversal::new(Vec3::ZERO, small, &TraversalConfig::cubic(1.0)).is_ok());
}

#[test]
fn traversal_origin_out_of_range() {
    let e = GridTraversal::new(Vec3::new(1e20, 0.0, 0.0), Vec3::X, &TraversalConfig::cubic(1e-6)).unwrap_err();
    assert_eq!(e, GridError::OutOfRange);
}

#[test]
fn voxelize_resolution_zero() {
    let mesh = proxima::io::parse(TRIANGLE, proxima::io::Format::Obj, "t.obj".as_ref()).unwrap();
    let tris = mesh.triangles().primitives;
    let e = voxelize(&tris, &mesh.bounds(), &VoxelConfig::new(0)).unwrap_err();
    assert_eq!(e, GridError::Resolution);
    assert!(e.to_string().contains("resolution"), "{e}");
}

#[test]
fn mesh_error_kinds_through_the_constructors() {
    // The same invariants, for meshes built in memory.
    let v = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    assert!(matches!(
        proxima::Mesh::from_triangles(v.clone(), &[[0, 1, 5]]),
        Err(MeshError::IndexOutOfRange { face: 0, vertex: 5, .. })
    ));
    let mut nan = v.clone();
    nan[1].y = f32::NAN;
    assert_eq!(
        proxima::Mesh::from_triangles(nan, &[[0, 1, 2]]).unwrap_err(),
        MeshError::NonFiniteVertex { index: 1 }
    );
    assert!(matches!(
        proxima::Mesh::from_faces(v, &[vec![0, 1]]),
        Err(MeshError::FaceTooSmall { face: 0, len: 2 })
    ));
}

/// Two triangles making the unit square in the plane z = 0.
const SQUARE: &[u8] = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";

#[test]
fn voxelize_resolution_beyond_the_work_limit() {
    let mesh = proxima::io::parse(SQUARE, proxima::io::Format::Obj, "sq.obj".as_ref()).unwrap();
    let tris = mesh.triangles().primitives;
    // Each triangle's cell range, clipped to the grid, is N × N × 1 cells
    // (x and y reach cell N, outside the grid; z = 0 touches cell -1 too):
    // 2 N² cells in all, refused before anything is allocated — N = 2^30
    // used to panic in the chunking, N = 2^22 to overflow N³.
    for (res, limit) in [(1u32 << 30, None), (1 << 22, None), (65536, Some(1u64 << 32))] {
        let config = VoxelConfig {
            max_cell_tests: limit.unwrap_or(VoxelConfig::new(1).max_cell_tests),
            ..VoxelConfig::new(res)
        };
        let e = voxelize(&tris, &mesh.bounds(), &config).unwrap_err();
        let expected = 2 * (res as u128).pow(2);
        assert_eq!(
            e,
            GridError::CellTests {
                cells: expected,
                limit: config.max_cell_tests
            },
            "res {res}"
        );
        assert!(e.to_string().contains(&format!("{expected} cells")), "{e}");
    }
}

#[test]
fn voxelize_beyond_the_memory_budget() {
    let mesh = proxima::io::parse(SQUARE, proxima::io::Format::Obj, "sq.obj".as_ref()).unwrap();
    let tris = mesh.triangles().primitives;
    // 16384² cells of the square are occupied (2^28): sparse storage, which
    // stops at the budget; the whole is estimated from the share done.
    for parallel in [false, true] {
        let config = VoxelConfig {
            memory_budget: 1 << 20,
            parallel,
            ..VoxelConfig::new(16384)
        };
        let e = voxelize(&tris, &mesh.bounds(), &config).unwrap_err();
        let GridError::MemoryBudget {
            what,
            count,
            bytes,
            budget,
        } = e.clone()
        else {
            panic!("{e}")
        };
        assert_eq!((what, budget), ("occupied cells", 1 << 20));
        assert!((1u128 << 27..=1 << 29).contains(&count), "{e}");
        assert_eq!(bytes, count * proxima::budget::VOXEL_BYTES_PER_SPARSE_CELL as u128);
        assert!(e.to_string().contains("memory budget of 1.0 MiB"), "{e}");
    }
    // A dense bitset larger than the budget (64³ bits: 32 KiB) is not used:
    // sparse storage, the same cells. The unit square in a box of side 64
    // at cells of 1 touches cells 0 and 1 along x and y, layer 0 along z.
    let bounds = proxima::Aabb::new(Vec3::ZERO, Vec3::splat(64.0));
    let small = VoxelConfig {
        memory_budget: 16 << 10,
        ..VoxelConfig::new(64)
    };
    let sparse = voxelize(&tris, &bounds, &small).unwrap();
    let dense = voxelize(&tris, &bounds, &VoxelConfig::new(64)).unwrap();
    assert!(!sparse.is_dense() && dense.is_dense());
    assert_eq!(sparse.cells(), dense.cells());
    assert_eq!(dense.cells(), [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]);
    assert_eq!(sparse.iter().collect::<Vec<_>>(), dense.iter().collect::<Vec<_>>());
}

#[test]
fn grid_cells_beyond_the_work_limit() {
    let mesh = proxima::io::parse(TRIANGLE, proxima::io::Format::Obj, "t.obj".as_ref()).unwrap();
    // Cells of 0.25: the triangle's box [0, 1]² × {0} touches cells -1..=4
    // along x and y, and -1..=0 along z: 6 × 6 × 2 = 72 cells.
    let config = GridConfig {
        max_cell_tests: 71,
        ..GridConfig::cubic(0.25)
    };
    let e = HashGrid::<proxima::Triangle>::build(mesh.triangles(), &config).unwrap_err();
    assert_eq!(e, GridError::CellTests { cells: 72, limit: 71 });
    assert!(e.to_string().contains("72 cells to test"), "{e}");
    let config = GridConfig {
        max_cell_tests: 72,
        ..config
    };
    assert!(HashGrid::<proxima::Triangle>::build(mesh.triangles(), &config).is_ok());
}

#[test]
fn grid_beyond_the_memory_budget() {
    // 100 copies of the triangle, 10 apart: each has the same cells.
    let copies: Vec<proxima::Triangle> = (0..100)
        .map(|i| {
            let shift = Vec3::new(10.0 * i as f32, 0.0, 0.0);
            proxima::Triangle::new(shift, Vec3::X + shift, Vec3::Y + shift)
        })
        .collect();
    let config = GridConfig::cubic(0.25);
    let one: HashGrid<proxima::Triangle> =
        HashGrid::build(proxima::PrimitiveSet::from_primitives(copies[..1].to_vec()), &config).unwrap();
    let per_copy = one.entry_count() as u128;
    let bytes = |entries: u128| {
        entries * (proxima::budget::GRID_BYTES_PER_ENTRY + proxima::budget::GRID_BYTES_PER_CELL) as u128
    };
    // Room for about ten copies: the build stops there and estimates the
    // whole (100 copies) from the share of the work done.
    let budget = bytes(10 * per_copy) as u64;
    let config = GridConfig {
        memory_budget: budget,
        ..config
    };
    let e = HashGrid::<proxima::Triangle>::build(proxima::PrimitiveSet::from_primitives(copies), &config).unwrap_err();
    let GridError::MemoryBudget {
        what,
        count,
        bytes: estimate,
        budget: b,
    } = e.clone()
    else {
        panic!("{e}")
    };
    assert_eq!((what, b), ("cell entries", budget));
    assert!(
        (90 * per_copy..=100 * per_copy).contains(&count),
        "{e}: {per_copy} per copy"
    );
    assert!(
        (bytes(90 * per_copy)..=bytes(100 * per_copy)).contains(&estimate),
        "{e}"
    );
    assert!(e.to_string().contains("memory budget of"), "{e}");
}

/// An endless reader of one repeated line: a well-formed stream that never ends.
struct Endless {
    line: &'static [u8],
    pos: usize,
}

#[test]
fn input_endless_zeros() {
    use proxima::io::{Format, read_with};
    let path = Path::new("zeros.obj");
    // Zeros forever: a NUL byte on line 1, found in the first chunk.
    let start = std::time::Instant::now();
    for format in [Format::Obj, Format::Off, Format::Ply] {
        let e = read_with(std::io::repeat(0), format, path, &LoadOptions::default()).unwrap_err();
        assert_load_error(&e, path, Some(1), "a NUL byte", |k| matches!(k, LoadErrorKind::NotText));
    }
    // Spaces forever: one endless line.
    let e = read_with(std::io::repeat(b' '), Format::Obj, path, &LoadOptions::default()).unwrap_err();
    assert_load_error(&e, path, Some(1), "line longer than 1048576 bytes", |k| {
        matches!(k, LoadErrorKind::LineTooLong { limit: 1048576 })
    });
    // Zeros forever as binary STL: 0 triangles announced, the rest ignored, not read.
    let mesh = read_with(
        std::io::repeat(0),
        Format::Stl,
        "zeros.stl".as_ref(),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(mesh.vertex_count(), 0);
    // Valid text forever: stopped at the size limit.
    let endless = Endless {
        line: b"v 0 0 0\n",
        pos: 0,
    };
    let options = LoadOptions {
        max_input_bytes: 8 << 20,
        ..LoadOptions::default()
    };
    let e = read_with(endless, Format::Obj, path, &options).unwrap_err();
    assert_load_error(&e, path, None, "exceeds the limit of 8388608 bytes", |k| {
        matches!(k, LoadErrorKind::InputTooLarge { limit: 8388608 })
    });
    assert!(start.elapsed().as_secs() < 10, "{:?}", start.elapsed());
    // Random bytes forever as binary STL: stopped at the first non-finite corner.
    let random = RandomReader(0x9E37_79B9_7F4A_7C15);
    let e = read_with(random, Format::Stl, "random.stl".as_ref(), &LoadOptions::default()).unwrap_err();
    assert!(
        matches!(e.kind, LoadErrorKind::Mesh(MeshError::NonFiniteVertex { .. })),
        "{e}"
    );
    // The default limit is bounded by the memory the system has.
    let default = LoadOptions::default();
    assert!(default.max_input_bytes <= 4 << 30 && default.max_decompressed_bytes <= 4 << 30);
    assert_eq!(default.max_input_bytes, proxima::io::default_max_input_bytes());
}

/// Endless pseudo-random bytes (xorshift64).
struct RandomReader(u64);

#[test]
fn input_line_too_long() {
    let path = Path::new("long.obj");
    let mut bytes = b"v 0 0 0\nv ".to_vec();
    bytes.extend(std::iter::repeat_n(b'1', 2 << 20));
    let e = proxima::io::parse(&bytes, proxima::io::Format::Obj, path).unwrap_err();
    assert_load_error(&e, path, Some(2), "line longer than 1048576 bytes", |k| {
        matches!(k, LoadErrorKind::LineTooLong { limit: 1048576 })
    });
    assert!(e.to_string().len() < 200, "the line is not echoed");
}

#[test]
fn input_too_large() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.obj");
    std::fs::write(&path, b"v 0 0 0\n".repeat(100)).unwrap();
    let options = LoadOptions {
        max_input_bytes: 100,
        ..LoadOptions::default()
    };
    let e = proxima::io::load_with(&path, &options).unwrap_err();
    assert_load_error(&e, &path, None, "the input exceeds the limit of 100 bytes", |k| {
        matches!(k, LoadErrorKind::InputTooLarge { limit: 100 })
    });
    // Exactly at the limit is fine.
    let options = LoadOptions {
        max_input_bytes: 800,
        ..LoadOptions::default()
    };
    assert_eq!(proxima::io::load_with(&path, &options).unwrap().vertex_count(), 100);
}

#[test]
fn load_beyond_the_memory_budget() {
    // One triangle: 32 bytes of input, 3 vertices and 1 triangle counted at
    // the bytes of `proxima::budget`, against a budget of 200 bytes.
    let path = Path::new("tri.obj");
    let need =
        TRIANGLE.len() as u64 + 3 * proxima::budget::LOAD_BYTES_PER_VERTEX + proxima::budget::LOAD_BYTES_PER_TRIANGLE;
    let options = |memory_budget| LoadOptions {
        memory_budget,
        ..LoadOptions::default()
    };
    let e = proxima::io::parse_with(TRIANGLE, proxima::io::Format::Obj, path, &options(200)).unwrap_err();
    // Counted as the text is read: stopped after its last line.
    let text = format!(
        "at least 3 vertices and 1 triangles, with their trees (96 and 136 bytes each) and the 32 bytes of input, \
         need about {need} bytes, more than the memory budget of 200 bytes (PROXIMA_MEMORY_BUDGET sets it)"
    );
    assert_load_error(
        &e,
        path,
        Some(5),
        &text,
        |k| matches!(k, LoadErrorKind::MemoryBudget { bytes, budget: 200, .. } if *bytes == u128::from(need)),
    );
    assert!(proxima::io::parse_with(TRIANGLE, proxima::io::Format::Obj, path, &options(need)).is_ok());
    // The default budget is the library's (`default_memory_budget`).
    assert_eq!(
        LoadOptions::default().memory_budget,
        proxima::budget::default_memory_budget()
    );
}

#[test]
fn obj_vertex_extra_numbers() {
    let path = Path::new("extra.obj");
    let parse = |text: &[u8]| proxima::io::parse(text, proxima::io::Format::Obj, path);
    // x y z, x y z w and x y z r g b are OBJ; the extra numbers are ignored.
    for line in ["v 1 2 3", "v 1 2 3 1", "v 1 2 3 0.5 0.25 1"] {
        let mesh = parse(format!("v 0 0 0\n{line}\n").as_bytes()).unwrap();
        assert_eq!(mesh.positions()[1], Vec3::new(1.0, 2.0, 3.0), "{line}");
    }
    for (line, text) in [
        (
            "v 1 2 3 4 5",
            "vertex has 5 numbers; expected 3 (x y z), 4 (x y z w) or 6 (x y z r g b)",
        ),
        ("v 1 2 3 4 5 6 7", "vertex has 7 numbers"),
        ("v 1 2 3 garbage", "bad number `garbage`"),
    ] {
        let e = parse(format!("v 0 0 0\n{line}\n").as_bytes()).unwrap_err();
        assert_load_error(&e, path, Some(2), text, |k| matches!(k, LoadErrorKind::Syntax(_)));
    }
}

const PLY_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

#[test]
fn ply_ascii_value_out_of_range() {
    let path = Path::new("uchar.ply");
    let parse = |data: &str| proxima::io::parse(format!("{PLY_HEAD}{data}").as_bytes(), proxima::io::Format::Ply, path);
    assert!(parse("0 0 0 255\n1 0 0 0\n0 1 0 7\n3 0 1 2\n").is_ok());
    let e = parse("0 0 0 1\n1 0 0 300\n0 1 0 7\n3 0 1 2\n").unwrap_err();
    assert_load_error(
        &e,
        path,
        Some(12),
        "number 300 is out of the range of its type `uchar` (0 to 255)",
        |k| matches!(k, LoadErrorKind::Syntax(_)),
    );
    // A list count beyond its type, and a fraction where an integer is declared.
    let e = parse("0 0 0 1\n1 0 0 1\n0 1 0 7\n256 0 1 2\n").unwrap_err();
    assert_load_error(&e, path, Some(14), "list length 256 is out of the range", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
    let e = parse("0 0 0 1.5\n1 0 0 1\n0 1 0 7\n3 0 1 2\n").unwrap_err();
    assert_load_error(&e, path, Some(11), "bad number `1.5`", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
}

#[test]
fn ply_ascii_trailing_value() {
    let path = Path::new("trail.ply");
    let text = format!("{PLY_HEAD}0 0 0 1\n1 0 0 1 9\n0 1 0 7\n3 0 1 2\n");
    let e = proxima::io::parse(text.as_bytes(), proxima::io::Format::Ply, path).unwrap_err();
    assert_load_error(
        &e,
        path,
        Some(12),
        "unexpected `9` after the 4 values of `vertex` element number 2",
        |k| matches!(k, LoadErrorKind::Syntax(_)),
    );
}

#[test]
fn obj_cr_line_ends() {
    let path = Path::new("cr.obj");
    let mesh = proxima::io::parse(b"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", proxima::io::Format::Obj, path).unwrap();
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (3, 1));
    // Lines are counted at lone CRs, with CRLF still one line end.
    let e = proxima::io::parse(
        b"v 0 0 0\r\nv 1 0 0\rv 0 1 0\rf 1 2 9\r",
        proxima::io::Format::Obj,
        path,
    )
    .unwrap_err();
    assert_eq!(e.line, Some(4), "{e}");
}

#[test]
fn error_echo_escaped() {
    let path = Path::new("esc.obj");
    let e = proxima::io::parse(b"v 0 0 0\nv 1 \x1b[31mred 0\n", proxima::io::Format::Obj, path).unwrap_err();
    let message = e.to_string();
    assert!(!message.contains('\x1b'), "{message:?}");
    assert_load_error(&e, path, Some(2), "bad number `\\u{1b}[31mred`", |k| {
        matches!(k, LoadErrorKind::Syntax(_))
    });
    // A long token is cut to 80 characters.
    let long = format!("v 0 0 {}\n", "x".repeat(100_000));
    let e = proxima::io::parse(long.as_bytes(), proxima::io::Format::Obj, path).unwrap_err();
    let message = e.to_string();
    assert!(message.contains(&format!("`{}…`", "x".repeat(80))), "{message}");
    assert!(message.len() < 200, "{message}");
}

#[test]
fn points_file_bom_and_utf8() {
    let path = Path::new("q.pts");
    let points = proxima::io::parse_points(b"\xEF\xBB\xBF1,2,3\n", path).unwrap();
    assert_eq!(points, [Vec3::new(1.0, 2.0, 3.0)]);
    let e = proxima::io::parse_points(b"1,2,3\n\xff,2,3\n", path).unwrap_err();
    assert_load_error(&e, path, Some(2), "invalid UTF-8", |k| {
        matches!(k, LoadErrorKind::InvalidUtf8)
    });
}

#[test]
fn query_point_beyond_bound() {
    use proxima::build::MAX_QUERY_COORDINATE;
    use proxima::{QueryError, Triangle, check_query_point};
    let triangle = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
    let tree = AabbTree::build(vec![triangle], &BuildConfig::default()).unwrap();
    let wide = WideTree::from_tree(AabbTree::build(vec![triangle], &BuildConfig::default()).unwrap());
    let linear = LinearSearch::new(proxima::PrimitiveSet::from_primitives(vec![triangle]));
    let far = Vec3::new(1e30, 0.0, 0.0);
    let e = check_query_point(far).unwrap_err();
    assert_eq!(
        e,
        QueryError::CoordinateTooLarge {
            bound: MAX_QUERY_COORDINATE
        }
    );
    assert!(e.to_string().contains("beyond ±4.611686e18"), "{e}");
    // Answered as a NaN point is: nothing, rather than primitive 0 at distance inf.
    assert_eq!(tree.closest(far), None);
    assert!(tree.k_nearest(far, 3).is_empty());
    assert_eq!(wide.closest(far), None);
    assert!(wide.k_nearest(far, 3).is_empty());
    assert_eq!(wide.closest_batch(&[far, Vec3::ZERO])[0], None);
    assert_eq!(linear.closest(far), None);
    assert!(linear.k_nearest(far, 3).is_empty());
    // At the bound, distances are finite.
    let edge = Vec3::new(MAX_QUERY_COORDINATE, 0.0, 0.0);
    assert!(check_query_point(edge).is_ok());
    assert!(tree.closest(edge).unwrap().distance.is_finite());
    // Points files refuse such a point on its line.
    let e = proxima::io::parse_points(b"0 0 0\n1e30 0 0\n", Path::new("far.pts")).unwrap_err();
    assert_load_error(
        &e,
        Path::new("far.pts"),
        Some(2),
        "'1e30' is beyond ±4.611686e18",
        |k| matches!(k, LoadErrorKind::Syntax(_)),
    );
}

#[test]
fn degenerate_bounding_box() {
    use proxima::{Aabb, Triangle};
    let p = Vec3::new(1.0, 2.0, 3.0);
    let triangle = Triangle::new(p, p, p);
    for bounds in [Aabb::new(p, p), Aabb::EMPTY] {
        let e = voxelize(&[triangle], &bounds, &VoxelConfig::new(4)).unwrap_err();
        assert_eq!(e, GridError::DegenerateBounds);
        let message = e.to_string();
        assert!(message.contains("bounding box is degenerate"), "{message}");
        assert!(!message.contains("cell size must be"), "{message}");
    }
}
impl std::io::Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        for b in buf.iter_mut() {
            *b = self.line[self.pos % self.line.len()];
            self.pos += 1;
        }
        Ok(buf.len())
    }
}

impl std::io::Read for RandomReader {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        for b in buf.iter_mut() {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            *b = (self.0 >> 24) as u8;
        }
        Ok(buf.len())
    }
}

#[test]
fn ray_origin_too_far() {
    let tree = AabbTree::build(
        vec![proxima::Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y)],
        &BuildConfig::default(),
    )
    .unwrap();
    let far = Vec3::new(0.2, 0.2, 1e30);
    assert_eq!(
        tree.first_hit(far, -Vec3::Z, 0.0, f32::INFINITY),
        Err(proxima::RayError::OriginTooFar)
    );
    // 2^29 times the size is still answered, at the right face.
    let hit = tree
        .first_hit(Vec3::new(0.2, 0.2, 5e8), -Vec3::Z, 0.0, f32::INFINITY)
        .unwrap()
        .unwrap();
    assert_eq!(hit.primitive, 0);
}

// ------------------------------------------------------ signed distance ---

/// The field of a closed sphere of radius about 1 around the origin.
fn sphere_field() -> proxima::SignedDistanceField {
    let sphere = proxima::mesh::generate::noisy_icosphere(3, 1);
    proxima::SignedDistanceField::new(&sphere, &proxima::SdfConfig::default()).unwrap()
}

#[test]
fn sdf_non_finite_query_point() {
    // Not an error: no answer, winding number 0, not inside; batches alike.
    for sign in [proxima::Sign::WindingNumber, proxima::Sign::Pseudonormal] {
        let sphere = proxima::mesh::generate::noisy_icosphere(3, 1);
        let config = proxima::SdfConfig {
            sign,
            ..Default::default()
        };
        let field = proxima::SignedDistanceField::new(&sphere, &config).unwrap();
        let points = [
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::new(0.0, f32::INFINITY, 0.0),
            Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
        ];
        for p in points {
            assert_eq!(field.signed_distance(p), None);
            assert_eq!(field.winding_number(p), 0.0);
            assert!(!field.contains(p));
        }
        let batch = field.signed_distance_batch(&[points[0], Vec3::ZERO, points[1]]);
        assert_eq!((batch[0], batch[2]), (None, None));
        assert!(batch[1].unwrap().distance < 0.0, "the finite point between is answered");
    }
}

#[test]
fn sdf_grid_resolution_zero() {
    let field = sphere_field();
    let e = proxima::sdf::SdfGrid::around(&field.bounds(), 0, 0.05).unwrap_err();
    assert_eq!(e, proxima::SdfError::Zero { option: "resolution" });
    assert_eq!(e.to_string(), "resolution must be at least 1");
}

#[test]
fn sdf_grid_beyond_the_memory_budget() {
    let field = sphere_field();
    let grid = proxima::sdf::SdfGrid::around(&field.bounds(), 100_000, 0.05).unwrap();
    let start = std::time::Instant::now();
    let mut reports = 0;
    let e = field.sdf_grid(&grid, |_, _| reports += 1).unwrap_err();
    assert!(start.elapsed().as_secs_f64() < 1.0, "refused before any work");
    assert_eq!(reports, 0);
    let budget = proxima::budget::default_memory_budget();
    assert_eq!(
        e,
        proxima::SdfError::MemoryBudget {
            option: "resolution",
            value: 1_000_000_000_000_000,
            bytes: 4_000_000_000_000_000,
            budget
        }
    );
    assert!(e.to_string().contains("more than the memory budget"), "{e}");
}

#[test]
fn sdf_sample_count_zero() {
    let field = sphere_field();
    let zero = proxima::SdfError::Zero { option: "count" };
    assert_eq!(field.sample_near_surface(0, 0.01, 1).unwrap_err(), zero);
    assert_eq!(field.sample_uniform(0, 0.05, 1).unwrap_err(), zero);
    assert_eq!(zero.to_string(), "count must be at least 1");
    // A count beyond the budget is refused before anything is drawn.
    let e = field.sample_uniform(usize::MAX, 0.05, 1).unwrap_err();
    assert!(
        matches!(e, proxima::SdfError::MemoryBudget { option: "count", .. }),
        "{e}"
    );
}

#[test]
fn sdf_mesh_without_faces() {
    let mesh = proxima::io::parse(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\n",
        proxima::io::Format::Obj,
        "verts.obj".as_ref(),
    )
    .unwrap();
    let e = proxima::SignedDistanceField::new(&mesh, &proxima::SdfConfig::default()).unwrap_err();
    assert_eq!(e, proxima::SdfError::NoFaces);
    assert_eq!(
        e.to_string(),
        "the mesh has no faces: a signed distance needs triangles"
    );
}

#[test]
fn sdf_points_file_bad_line() {
    // The points reader `sdf --points` shares with `closest --points`.
    let e = proxima::io::parse_points(b"0 0 0\n# ok\n1 2\n", "bad.pts".as_ref()).unwrap_err();
    assert_load_error(
        &e,
        Path::new("bad.pts"),
        Some(3),
        "expected three numbers X,Y,Z, got '1 2'",
        |k| matches!(k, LoadErrorKind::Syntax(_)),
    );
}

#[test]
fn sdf_near_sigma_negative() {
    let field = sphere_field();
    for sigma in [-1.0, f32::NAN, f32::INFINITY] {
        let e = field.sample_near_surface(10, sigma, 1).unwrap_err();
        assert!(
            matches!(e, proxima::SdfError::Parameter { option: "sigma", value } if value.to_bits() == sigma.to_bits()),
            "{e}"
        );
    }
    assert_eq!(
        field.sample_near_surface(10, -1.0, 1).unwrap_err().to_string(),
        "sigma must be finite and not negative, got -1"
    );
    // Zero is a spread: the points on the surface.
    assert_eq!(field.sample_near_surface(10, 0.0, 1).unwrap().points.len(), 10);
}

/// A spread that would put samples where no query is answered.
#[test]
fn sdf_near_sigma_too_far() {
    let field = sphere_field();
    let e = field.sample_near_surface(10, 1e30, 1).unwrap_err();
    assert!(matches!(e, proxima::SdfError::TooFar { option: "sigma", .. }), "{e}");
    assert!(
        e.to_string()
            .starts_with("sigma = 1000000000000000000000000000000 puts samples beyond ±"),
        "{e}"
    );
    assert!(matches!(
        field.sample_uniform(10, 1e30, 1),
        Err(proxima::SdfError::TooFar { option: "margin", .. })
    ));
}

#[test]
fn raycast_rays_file_bad_line() {
    let e = proxima::io::parse_rays(b"0 0 -1 0 0 1\n# ok\n0 0 0 1 0\n", "bad.rays".as_ref()).unwrap_err();
    assert_load_error(
        &e,
        Path::new("bad.rays"),
        Some(3),
        "expected six numbers OX,OY,OZ,DX,DY,DZ, got '0 0 0 1 0'",
        |k| matches!(k, LoadErrorKind::Syntax(_)),
    );
}

#[test]
fn raycast_rays_file_zero_direction() {
    for direction in ["0 0 0", "1e-45 0 0"] {
        let text = format!("0 0 -1 0 0 1\n\n0 0 -1 {direction}\n");
        let e = proxima::io::parse_rays(text.as_bytes(), "zero.rays".as_ref()).unwrap_err();
        assert_load_error(
            &e,
            Path::new("zero.rays"),
            Some(3),
            "ray direction must be finite and non-zero",
            |k| matches!(k, LoadErrorKind::Syntax(_)),
        );
    }
    // Not unit length is fine: the direction is normalized when cast.
    let rays = proxima::io::parse_rays(b"0 0 -1 0 0 7\n", "ok.rays".as_ref()).unwrap();
    assert_eq!(
        rays,
        [(proxima::Vec3::new(0.0, 0.0, -1.0), proxima::Vec3::new(0.0, 0.0, 7.0))]
    );
}
