//! The bad-input catalogue (`docs/errors.md`), command-line side: one test per
//! kind of bad input, with the same names as the library side
//! (`crates/proxima/tests/errors.rs`). Every failure on input prints exactly
//! one line, `proxima: FILE[:LINE]: what`, never "panicked", and exits with 1;
//! usage errors (clap) exit with 2.

mod common;

use common::{TempDir, temp_dir};
use std::io::Write;
use std::path::Path;
use std::process::{Command, Output};

fn proxima(args: &[&str]) -> Output {
    proxima_env(args, &[])
}

fn proxima_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_proxima"));
    command.args(args);
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().expect("run proxima")
}

/// Exit status `code`, no panic, and (for status 1) exactly one line on
/// stderr starting with `proxima: ` and containing every needle.
fn assert_one_line_error(out: &Output, code: i32, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    if code == 1 {
        assert_eq!(err.trim_end().lines().count(), 1, "one line expected: {err}");
        assert!(err.starts_with("proxima: "), "{err}");
    }
    for needle in needles {
        assert!(err.contains(needle), "'{needle}' missing from: {err}");
    }
}

/// A binary STL of 84 + 50 bytes whose header announces `count` triangles.
fn stl_with_count(count: u32) -> Vec<u8> {
    let mut bytes = vec![b'x'; 80];
    bytes.extend(count.to_le_bytes());
    bytes.extend([0u8; 50]);
    bytes
}

const TRIANGLE: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// A file path that keeps its temporary directory alive; reads as a `str`.
struct TempFile {
    _dir: TempDir,
    path: String,
}

impl std::ops::Deref for TempFile {
    type Target = str;
    fn deref(&self) -> &str {
        &self.path
    }
}

/// Writes the one-triangle OBJ into a fresh directory.
fn triangle_file(name: &str) -> TempFile {
    let dir = temp_dir(name);
    let path = dir.join("ok.obj");
    std::fs::write(&path, TRIANGLE).unwrap();
    TempFile {
        path: path.display().to_string(),
        _dir: dir,
    }
}

// ------------------------------------------------------------- loading ---

#[test]
fn missing_file() {
    let dir = temp_dir("missing_file");
    let path = dir.join("missing.obj");
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["missing.obj"]);
}

#[test]
fn unknown_extension() {
    let dir = temp_dir("unknown_extension");
    let path = dir.join("mesh.xyz");
    std::fs::write(&path, b"1 2 3\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["mesh.xyz", "unknown mesh format"]);
}

#[test]
fn directory_instead_of_file() {
    let dir = temp_dir("directory_instead_of_file");
    let path = dir.join("dir.obj");
    std::fs::create_dir_all(&path).unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["dir.obj"]);
}

#[test]
fn obj_bad_number() {
    let dir = temp_dir("obj_bad_number");
    let path = dir.join("badnum.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 x 0\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["badnum.obj:2"]);
}

#[test]
fn obj_index_zero() {
    let dir = temp_dir("obj_index_zero");
    let path = dir.join("zero.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["zero.obj:4", "index 0"]);
}

#[test]
fn obj_index_out_of_range() {
    let dir = temp_dir("obj_index_out_of_range");
    let path = dir.join("range.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["range.obj:4"]);
}

#[test]
fn obj_relative_index_before_first() {
    let dir = temp_dir("obj_relative_index_before_first");
    let path = dir.join("rel.obj");
    std::fs::write(&path, b"v 0 0 0\nf -3 -2 -1\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["rel.obj:2"]);
}

#[test]
fn obj_face_too_small() {
    let dir = temp_dir("obj_face_too_small");
    let path = dir.join("small.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nf 1 2\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["small.obj:3", "at least 3"]);
}

#[test]
fn obj_nan_coordinate() {
    let dir = temp_dir("obj_nan_coordinate");
    let path = dir.join("nan.obj");
    std::fs::write(&path, b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["nan.obj:2", "non-finite"]);
}

#[test]
fn off_overflowing_coordinate() {
    let dir = temp_dir("off_overflowing_coordinate");
    let path = dir.join("over.off");
    std::fs::write(&path, b"OFF\n3 1 0\n0 0 0\n1e999 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["over.off:4"]);
}

#[test]
fn off_truncated() {
    let dir = temp_dir("off_truncated");
    let path = dir.join("trunc.off");
    std::fs::write(&path, b"OFF\n4 2 0\n0 0 0\n1 0 0\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["trunc.off"]);
}

#[test]
fn off_trailing_content() {
    let dir = temp_dir("off_trailing_content");
    let path = dir.join("trail.off");
    std::fs::write(&path, b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\nextra\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["trail.off:7"]);
}

#[test]
fn off_negative_index() {
    let dir = temp_dir("off_negative_index");
    let path = dir.join("neg.off");
    std::fs::write(&path, b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["neg.off:6"]);
}

#[test]
fn ply_no_format_line() {
    let dir = temp_dir("ply_no_format_line");
    let path = dir.join("nofmt.ply");
    std::fs::write(&path, b"ply\nelement vertex 3\nend_header\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["nofmt.ply:3"]);
}

#[test]
fn ply_implausible_vertex_count() {
    let dir = temp_dir("ply_implausible_vertex_count");
    let path = dir.join("huge.ply");
    std::fs::write(&path, b"ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["huge.ply:3", "implausible"]);
}

#[test]
fn ply_binary_truncated() {
    let dir = temp_dir("ply_binary_truncated");
    let path = dir.join("trunc_bin.ply");
    std::fs::write(&path, b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n\x00\x00\x00\x00").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["trunc_bin.ply"]);
}

#[test]
fn ply_list_count_not_integer() {
    let dir = temp_dir("ply_list_count_not_integer");
    let path = dir.join("listtype.ply");
    std::fs::write(&path, b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["listtype.ply:8"]);
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
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["noz.ply:3"]);
}

#[test]
fn ply_ascii_fewer_values_than_announced() {
    let dir = temp_dir("ply_ascii_fewer_values_than_announced");
    let path = dir.join("count.ply");
    std::fs::write(&path, b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["count.ply"]);
}

#[test]
fn stl_binary_count_beyond_size() {
    let dir = temp_dir("stl_binary_count_beyond_size");
    let path = dir.join("count.stl");
    std::fs::write(&path, stl_with_count(1000)).unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["count.stl", "1000 triangles"]);
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
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["short.stl:5"]);
}

#[test]
fn gzip_corrupt() {
    let dir = temp_dir("gzip_corrupt");
    let path = dir.join("corrupt.obj.gz");
    std::fs::write(&path, b"not gzip at all").unwrap();
    let out = proxima(&["info", path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["corrupt.obj.gz", "gzip"]);
}

#[test]
fn gzip_bomb() {
    let dir = temp_dir("gzip_bomb");
    let path = dir.join("bomb.obj.gz");
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    encoder
        .write_all(&[[b' '; 63].as_slice(), b"\n"].concat().repeat(32 << 10))
        .unwrap();
    std::fs::write(&path, encoder.finish().unwrap()).unwrap();
    let path = path.to_str().unwrap();
    let out = proxima_env(&["info", path], &[("PROXIMA_MAX_DECOMPRESSED_BYTES", "1000000")]);
    assert_one_line_error(&out, 1, &["bomb.obj.gz", "exceeds the limit of 1000000 bytes"]);
    let out = proxima_env(&["info", path], &[("PROXIMA_MAX_DECOMPRESSED_BYTES", "lots")]);
    assert_one_line_error(&out, 1, &["PROXIMA_MAX_DECOMPRESSED_BYTES", "lots"]);
}

#[test]
fn load_beyond_the_memory_budget() {
    // One triangle: 32 bytes, 3 vertices and a triangle counted at 96 and 136
    // bytes, more than a budget of 200 bytes; the text is counted as it is
    // read, so the line is the one reading stopped at.
    let mesh = triangle_file("load_beyond_the_memory_budget");
    let out = proxima_env(&["info", &mesh], &[("PROXIMA_MEMORY_BUDGET", "200")]);
    assert_one_line_error(
        &out,
        1,
        &[
            "ok.obj:5: at least 3 vertices and 1 triangles, with their trees (96 and 136 bytes each) and the 32 \
             bytes of input, need about 456 bytes, more than the memory budget of 200 bytes (PROXIMA_MEMORY_BUDGET \
             sets it)",
        ],
    );
    assert!(
        proxima_env(&["info", &mesh], &[("PROXIMA_MEMORY_BUDGET", "456")])
            .status
            .success()
    );
}

#[test]
fn glb_instancing_beyond_the_memory_budget() {
    // The issue's files: one primitive of 960,000 byte indices shown by 100
    // nodes (964 KB: `sdf` aborted allocating 840 MB, at 4.1 GB), and a strip
    // of 90,002 shown by 200 (98 KB: `info` ran 30 s at 2.2 GB). Under a
    // 3 GiB address-space limit (the default budget stays 2 GiB), both are
    // refused from the scene's counts before a vertex is read.
    let dir = temp_dir("glb_instancing_beyond_the_memory_budget");
    let cases = [
        (
            "tris.glb",
            960_000,
            100,
            4,
            "sdf",
            "(300 vertices and 32000000 triangles, 100 primitives)",
        ),
        (
            "strip.glb",
            90_002,
            200,
            5,
            "info",
            "(600 vertices and 18000000 triangles, 200 primitives)",
        ),
    ];
    for (name, corners, nodes, mode, command, counts) in cases {
        let path = dir.join(name);
        std::fs::write(&path, common::instanced_glb(corners, nodes, mode, "", "")).unwrap();
        let path = path.display().to_string();
        let mut args = vec![command, &path];
        if command == "sdf" {
            args.extend(["--point", "0,0,0"]);
        }
        let out = common::proxima_under_limit(3 << 20, &args, &[]);
        assert_one_line_error(
            &out,
            1,
            &[
                &format!("{name}: the scene's {nodes} mesh instances {counts}"),
                "more than the memory budget of 2.0 GiB",
            ],
        );
    }
}

#[test]
fn glb_cycle_without_a_scene() {
    // nodes[0] and nodes[1] each other's child, no scene: no node is a root.
    // It was "the mesh is empty"; it is the cycle, as with a scene.
    let dir = temp_dir("glb_cycle_without_a_scene");
    let positions: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let json = r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
        "nodes":[{"mesh":0,"children":[1]},{"children":[0]}]}"#;
    let path = dir.join("cycle.glb");
    std::fs::write(&path, common::glb(json, &positions)).unwrap();
    let out = proxima(&["info", &path.display().to_string()]);
    assert_one_line_error(
        &out,
        1,
        &["cycle.glb: nodes[0] is reached twice: the node hierarchy is not a tree (a cycle, or a shared child)"],
    );
}

#[test]
fn gzip_text_beyond_the_memory_budget() {
    // The issue's file, scaled: `v 0 0 0` lines inflating to 200 MiB (26
    // million vertices; 3.2 GB aborted under a 6 GB address-space limit),
    // read under a 1.5 GiB limit. The default budget follows that limit
    // (three quarters of the room under it, about 1.1 GiB) and the lines are
    // counted as they are inflated: reading stops after about 11 million.
    let dir = temp_dir("gzip_text_beyond_the_memory_budget");
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    encoder.write_all(&b"v 0 0 0\n".repeat(1 << 17)).unwrap();
    let member = encoder.finish().unwrap();
    let path = dir.join("zeros.obj.gz");
    std::fs::write(&path, member.repeat(200)).unwrap();
    let limit: u64 = 1536 << 20;
    let out = common::proxima_under_limit(limit >> 10, &["info", &path.display().to_string()], &[]);
    assert_one_line_error(
        &out,
        1,
        &[
            "zeros.obj.gz:",
            ": at least ",
            " vertices and 0 triangles",
            "memory budget of",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    let budget: u64 = err
        .split("memory budget of ")
        .nth(1)
        .and_then(|rest| rest.split(['(', ' ']).nth(3))
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no budget in {err}"));
    // Three quarters of the limit less what the process had mapped (well under 256 MiB).
    assert!(
        budget <= limit / 4 * 3 && budget >= (limit - (256 << 20)) / 4 * 3,
        "{budget}: {err}"
    );
}

// ------------------------------------------------------------ building ---

#[test]
fn coordinate_beyond_tree_bound() {
    let path_dir = temp_dir("coordinate_beyond_tree_bound");
    let path = path_dir.join("huge.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n").unwrap();
    let path = path.to_str().unwrap();
    let out = proxima(&["closest", path, "--primitives", "faces", "--point", "0,0,0"]);
    assert_one_line_error(&out, 1, &["huge.obj", "beyond"]);
}

#[test]
fn empty_mesh() {
    let path_dir = temp_dir("empty_mesh");
    let path = path_dir.join("empty.obj");
    std::fs::write(&path, b"# nothing\n").unwrap();
    let path = path.to_str().unwrap();
    let out = proxima(&["closest", path, "--primitives", "faces", "--point", "0,0,0"]);
    assert_one_line_error(&out, 1, &["empty.obj", "no faces"]);
    let out = proxima(&["raycast", path, "--origin", "0,0,0", "--dir", "1,0,0"]);
    assert_one_line_error(&out, 1, &["empty.obj", "no faces"]);
}

#[test]
fn points_file_bad_line() {
    let mesh = triangle_file("points_file_bad_line");
    let points_dir = temp_dir("points_file_bad_line_pts");
    let points = points_dir.join("bad.pts");
    std::fs::write(&points, b"0 0 0\n# ok\n1 2\n").unwrap();
    let out = proxima(&["closest", &mesh, "--points", points.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["bad.pts:3", "three numbers"]);
}

#[test]
fn non_finite_query_point() {
    let mesh = triangle_file("non_finite_query_point");
    let out = proxima(&["closest", &mesh, "--point", "nan,0,0"]);
    assert_one_line_error(&out, 2, &["not a finite number"]);
}

#[test]
fn grid_primitive_spans_too_many_cells() {
    let mesh = triangle_file("grid_primitive_spans_too_many_cells");
    let out = proxima(&["grid", &mesh, "--cell", "1e-6"]);
    assert_one_line_error(&out, 1, &["ok.obj", "spans", "more than the limit"]);
}

#[test]
fn grid_cell_size_not_positive() {
    let mesh = triangle_file("grid_cell_size_not_positive");
    let out = proxima(&["grid", &mesh, "--cell", "0"]);
    assert_one_line_error(&out, 1, &["cell size must be finite and positive"]);
}

#[test]
fn grid_primitive_out_of_range() {
    let path_dir = temp_dir("grid_primitive_out_of_range");
    let path = path_dir.join("far.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = proxima(&[
        "grid",
        path.to_str().unwrap(),
        "--cell",
        "1e-10",
        "--primitives",
        "vertices",
    ]);
    assert_one_line_error(&out, 1, &["far.obj", "primitive 1", "out of range"]);
}

#[test]
fn ray_zero_direction() {
    let out = proxima(&["traverse", "--origin", "0,0,0", "--dir", "0,0,0", "--cell", "1"]);
    assert_one_line_error(&out, 1, &["ray direction must be finite and non-zero"]);
    let mesh = triangle_file("ray_zero_direction");
    let out = proxima(&["raycast", &mesh, "--origin", "0,0,0", "--dir", "0,0,0"]);
    assert_one_line_error(&out, 1, &["ray direction"]);
}

#[test]
fn traversal_origin_out_of_range() {
    let out = proxima(&["traverse", "--origin", "1e20,0,0", "--dir", "1,0,0", "--cell", "1e-6"]);
    assert_one_line_error(&out, 1, &["out of range"]);
}

#[test]
fn voxelize_resolution_zero() {
    let mesh = triangle_file("voxelize_resolution_zero");
    let out = proxima(&["voxelize", &mesh, "--res", "0"]);
    assert_one_line_error(&out, 1, &["resolution must be at least 1"]);
}

// --------------------------------------------------------------- usage ---

#[test]
fn usage_unknown_subcommand() {
    assert_one_line_error(&proxima(&["frobnicate"]), 2, &["unrecognized subcommand"]);
}

#[test]
fn usage_unknown_primitive_kind() {
    let mesh = triangle_file("usage_unknown_primitive_kind");
    let out = proxima(&["closest", &mesh, "--primitives", "cubes", "--point", "0,0,0"]);
    assert_one_line_error(&out, 2, &["cubes"]);
}

#[test]
fn usage_missing_argument() {
    let mesh = triangle_file("usage_missing_argument");
    assert_one_line_error(&proxima(&["closest", &mesh]), 2, &["--point"]);
    assert_one_line_error(&proxima(&["info"]), 2, &["MESH"]);
}

/// Writes the unit square (two triangles in the plane z = 0) into a fresh directory.
fn square_file(name: &str) -> TempFile {
    let dir = temp_dir(name);
    let path = dir.join("sq.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n").unwrap();
    TempFile {
        path: path.display().to_string(),
        _dir: dir,
    }
}

#[test]
fn voxelize_resolution_beyond_the_work_limit() {
    // 2 N² cells of cell ranges, refused at once (2^30 used to panic in the
    // chunking, 2^22 to overflow N³, 65536 to run for ever at 4.9 GB).
    let mesh = square_file("voxelize_resolution_beyond_the_work_limit");
    for (res, cells) in [
        ("1073741824", "2305843009213693952"),
        ("4194304", "35184372088832"),
        ("65536", "8589934592"),
    ] {
        let out = proxima(&["voxelize", &mesh, "--res", res]);
        assert_one_line_error(
            &out,
            1,
            &[
                &format!("sq.obj: --res {res}: "),
                &format!("hold {cells} cells to test, more than the limit of 4294967296"),
            ],
        );
    }
}

#[test]
fn voxelize_beyond_the_memory_budget() {
    let mesh = square_file("voxelize_beyond_the_memory_budget");
    let out = proxima_env(
        &["voxelize", &mesh, "--res", "16384"],
        &[("PROXIMA_MEMORY_BUDGET", "1M")],
    );
    assert_one_line_error(
        &out,
        1,
        &[
            "sq.obj: --res 16384: needs about",
            "occupied cells, more than the memory budget of 1.0 MiB",
        ],
    );
}

#[test]
fn grid_cells_beyond_the_work_limit() {
    // 6 × 6 × 2 = 72 cells in the triangle's cell range at cells of 0.25.
    let mesh = triangle_file("grid_cells_beyond_the_work_limit");
    let args = ["grid", &mesh, "--cell", "0.25", "--primitives", "faces"];
    let out = proxima_env(&args, &[("PROXIMA_MAX_CELL_TESTS", "71")]);
    assert_one_line_error(
        &out,
        1,
        &[
            "ok.obj: --cell 0.25: ",
            "hold 72 cells to test, more than the limit of 71",
        ],
    );
    assert!(proxima_env(&args, &[("PROXIMA_MAX_CELL_TESTS", "72")]).status.success());
}

#[test]
fn grid_beyond_the_memory_budget_is_counted_before_storing() {
    // A unit square in cells of 2e-4: about 2.5e7 cell entries (3.6 GB). Under a
    // budget of 2 GiB but an address-space limit of 1 GiB, filling the grid
    // up to its budget aborted; counting first refuses it having stored
    // nothing.
    let dir = temp_dir("grid_beyond_the_memory_budget_is_counted_before_storing");
    let path = dir.join("square.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n").unwrap();
    let path = path.display().to_string();
    let args = ["grid", &path, "--cell", "2e-4", "--primitives", "faces"];
    let out = common::proxima_under_limit(1 << 20, &args, &[("PROXIMA_MEMORY_BUDGET", "2G")]);
    assert_one_line_error(
        &out,
        1,
        &[
            "square.obj: --cell 0.0002: needs about",
            "cell entries, more than the memory budget of 2.0 GiB",
        ],
    );
}

#[test]
fn grid_beyond_the_memory_budget() {
    let mesh = triangle_file("grid_beyond_the_memory_budget");
    let out = proxima_env(
        &["grid", &mesh, "--cell", "0.01", "--primitives", "faces"],
        &[("PROXIMA_MEMORY_BUDGET", "10000")],
    );
    assert_one_line_error(
        &out,
        1,
        &[
            "ok.obj: --cell 0.01: needs about",
            "cell entries, more than the memory budget of 9.8 KiB",
        ],
    );
    // The grid ray cast builds the same grid, under the same budget.
    let out = proxima_env(
        &[
            "raycast",
            &mesh,
            "--origin",
            "0.2,0.2,1",
            "--dir",
            "0,0,-1",
            "--cell",
            "0.01",
        ],
        &[("PROXIMA_MEMORY_BUDGET", "10000")],
    );
    assert_one_line_error(&out, 1, &["ok.obj: --cell 0.01: needs about", "memory budget"]);
}

#[test]
fn budget_variable_not_a_number() {
    let mesh = triangle_file("budget_variable_not_a_number");
    for (name, value) in [("PROXIMA_MEMORY_BUDGET", "lots"), ("PROXIMA_MAX_CELL_TESTS", "-1")] {
        let out = proxima_env(&["voxelize", &mesh, "--res", "4"], &[(name, value)]);
        assert_one_line_error(&out, 1, &[name, &format!("'{value}' is not a number")]);
    }
}

#[test]
fn bench_query_count_beyond_the_budget() {
    // Refused before the points are drawn (these used to abort in the allocator).
    let mesh = triangle_file("bench_query_count_beyond_the_budget");
    for queries in ["18446744073709551615", "1000000000"] {
        let out = proxima(&["bench", &mesh, "--queries", queries]);
        assert_one_line_error(
            &out,
            1,
            &[&format!("--queries {queries}: "), "more than the memory budget"],
        );
    }
}

/// `--queries 0` is refused as the option it is, for every query kind; it
/// used to be reported as a property of the mesh ("the mesh has no area",
/// "the bounding box is a point", "no query points in the near set").
#[test]
fn bench_query_count_zero() {
    let mesh = triangle_file("bench_query_count_zero");
    for query in ["closest", "rays", "sdf"] {
        let out = proxima(&["bench", &mesh, "--query", query, "--queries", "0"]);
        assert_one_line_error(&out, 1, &["proxima: --queries must be at least 1"]);
    }
    assert!(proxima(&["bench", &mesh, "--queries", "1"]).status.success());
}

/// A structure that searches like a linear scan (faces all on one point: a
/// tie at every query, nothing to prune) gets the linear row's budget: its
/// row answers the linear row's queries and says why, in the JSON
/// (`capped`, `note`) and after the table; a row of 10,000 queries on a
/// million such faces ran for many minutes. Rows on a mesh answer all their
/// queries whatever the linear budget. The cap comes from counted tests, not
/// time, so the counts below are exact.
#[test]
fn bench_rows_that_search_like_a_linear_scan_are_capped() {
    let (_dir, point) = file_with("point.obj", format!("v 1 2 3\n{}", "f 1 1 1\n".repeat(5000)).as_bytes());
    let budget = [("PROXIMA_BENCH_LINEAR_BUDGET", "200000")];
    let args = [
        "bench",
        &point,
        "--primitives",
        "faces",
        "--set",
        "uniform",
        "--queries",
        "1000",
        "--json",
    ];
    let out = proxima_env(&args, &budget);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // 200000 tests on 5000 faces: 40 queries.
    for r in json["results"].as_array().unwrap() {
        let method = r["method"].as_str().unwrap();
        for key in [
            "primitives",
            "build_seconds",
            "queries",
            "seconds",
            "queries_per_second",
        ] {
            assert!(!r[key].is_null(), "{key} missing: {r}");
        }
        assert_eq!(r["agree"], true, "{r}");
        let capped = method != "parry3d";
        assert_eq!(r["queries"], if capped { 40 } else { 1000 }, "{r}");
        assert_eq!(r["capped"], capped, "{r}");
        match method {
            "linear" | "parry3d" => assert!(r["note"].is_null(), "{r}"),
            _ => {
                let note = r["note"].as_str().unwrap();
                assert!(
                    note.contains("ran on the first 40 queries only, as linear search does")
                        && note.contains("tested 5000 of the 5000 primitives each"),
                    "{note}"
                );
            }
        }
    }
    let text = proxima_env(&args[..args.len() - 1], &budget);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("(faces: tree ran on the first 40 queries only")
            && text.contains("(faces: tree-wide and tree-batch ran on the first 40 queries only")
            && text.contains("(faces: sphere-tree ran on the first 40 queries only"),
        "{text}"
    );
    // A mesh's rows answer every query, though the linear row is capped.
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj");
    let out = proxima_env(
        &["bench", mesh, "--primitives", "faces", "--queries", "1000", "--json"],
        &budget,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for r in json["results"].as_array().unwrap() {
        let linear = r["method"] == "linear";
        assert_eq!(r["capped"], linear, "{r}");
        assert_eq!(r["queries"].as_u64().unwrap() < 1000, linear, "{r}");
        assert!(r["note"].is_null(), "{r}");
    }
    let out = proxima_env(&args, &[("PROXIMA_BENCH_LINEAR_BUDGET", "lots")]);
    assert_one_line_error(
        &out,
        1,
        &["PROXIMA_BENCH_LINEAR_BUDGET: 'lots' is not a positive whole number of primitive tests"],
    );
}

#[test]
fn traverse_steps_beyond_the_limit() {
    let out = proxima(&[
        "traverse",
        "--origin",
        "0,0,0",
        "--dir",
        "1,0.3,0.1",
        "--cell",
        "1e30",
        "--steps",
        "18446744073709551615",
    ]);
    assert_one_line_error(
        &out,
        1,
        &["--steps 18446744073709551615 is more than the limit of 10000000 cells"],
    );
}

#[test]
fn voxelize_binvox_beyond_its_resolution_limit() {
    let mesh = triangle_file("voxelize_binvox_beyond_its_resolution_limit");
    let dir = temp_dir("voxelize_binvox_beyond_its_resolution_limit_out");
    let out_path = dir.join("v.binvox");
    let out = proxima(&["voxelize", &mesh, "--res", "1025", "--out", out_path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["v.binvox: --res 1025: ", "limited to --res 1024"]);
    assert!(!out_path.exists());
}

#[test]
fn threads_beyond_the_limit() {
    // 4 per core (at least 8): more would only cost memory and scheduling.
    let mesh = triangle_file("threads_beyond_the_limit");
    let out = proxima(&["voxelize", &mesh, "--res", "4", "--threads", "100000"]);
    assert_one_line_error(&out, 1, &["--threads 100000 is more than the limit of", "4 per core"]);
    let out = proxima(&["bench", &mesh, "--queries", "30", "--threads", "100000"]);
    assert_one_line_error(&out, 1, &["--threads 100000 is more than the limit of"]);
    assert!(
        proxima(&["voxelize", &mesh, "--res", "4", "--threads", "8"])
            .status
            .success()
    );
}

/// A fresh self-cleaning directory holding `name` with `bytes`.
/// A path named `file` in a fresh temporary directory, for an output that
/// must not be written.
fn output_path(name: &str, file: &str) -> (TempDir, std::path::PathBuf) {
    let dir = temp_dir(name);
    let path = dir.join(file);
    (dir, path)
}

fn file_with(name: &str, bytes: &[u8]) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let path = path.display().to_string();
    (dir, path)
}

#[test]
fn input_endless_zeros() {
    let dir = tempfile::tempdir().unwrap();
    for (device, name, needles) in [
        ("/dev/zero", "zero.obj", &["zero.obj:1", "a NUL byte"][..]),
        ("/dev/zero", "zero.ply", &["zero.ply:1", "a NUL byte"]),
        ("/dev/zero", "zero.stl", &["zero.stl", "the mesh is empty"]),
        ("/dev/urandom", "random.off", &["random.off:", "a NUL byte"]),
        ("/dev/urandom", "random.stl", &["random.stl", "non-finite coordinate"]),
    ] {
        if !Path::new(device).exists() {
            println!("skipped: no {device}");
            return;
        }
        let link = dir.path().join(name);
        std::os::unix::fs::symlink(device, &link).unwrap();
        let start = std::time::Instant::now();
        let out = proxima(&["info", link.to_str().unwrap()]);
        assert_one_line_error(&out, 1, needles);
        assert!(start.elapsed().as_secs() < 5, "{name}: {:?}", start.elapsed());
    }
}

#[test]
fn input_line_too_long() {
    let mut bytes = b"v 0 0 0\nv ".to_vec();
    bytes.extend(std::iter::repeat_n(b'1', 2 << 20));
    let (_dir, path) = file_with("long.obj", &bytes);
    let out = proxima(&["info", &path]);
    assert_one_line_error(&out, 1, &["long.obj:2", "line longer than 1048576 bytes"]);
    assert!(out.stderr.len() < 300, "the line is not echoed");
}

#[test]
fn input_too_large() {
    let (_dir, path) = file_with("big.obj", &b"v 0 0 0\n".repeat(100));
    let out = proxima_env(&["info", &path], &[("PROXIMA_MAX_INPUT_BYTES", "100")]);
    assert_one_line_error(&out, 1, &["big.obj", "the input exceeds the limit of 100 bytes"]);
    let out = proxima_env(&["info", &path], &[("PROXIMA_MAX_INPUT_BYTES", "lots")]);
    assert_one_line_error(&out, 1, &["PROXIMA_MAX_INPUT_BYTES", "not a number of bytes"]);
}

#[test]
fn obj_vertex_extra_numbers() {
    let (_dir, path) = file_with("extra.obj", b"v 0 0 0 1\nv 1 0 0 1 0 0\nv 0 1 0 1 2\nf 1 2 3\n");
    let out = proxima(&["info", &path]);
    assert_one_line_error(&out, 1, &["extra.obj:3", "vertex has 5 numbers"]);
    let (_dir, path) = file_with("ok.obj", b"v 0 0 0 1\nv 1 0 0 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(proxima(&["info", &path]).status.success());
}

const PLY_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

#[test]
fn ply_ascii_value_out_of_range() {
    let text = format!("{PLY_HEAD}0 0 0 1\n1 0 0 300\n0 1 0 7\n3 0 1 2\n");
    let (_dir, path) = file_with("uchar.ply", text.as_bytes());
    let out = proxima(&["info", &path]);
    assert_one_line_error(
        &out,
        1,
        &["uchar.ply:12", "300 is out of the range of its type `uchar`"],
    );
}

#[test]
fn ply_ascii_trailing_value() {
    let text = format!("{PLY_HEAD}0 0 0 1\n1 0 0 1 9\n0 1 0 7\n3 0 1 2\n");
    let (_dir, path) = file_with("trail.ply", text.as_bytes());
    let out = proxima(&["info", &path]);
    assert_one_line_error(&out, 1, &["trail.ply:12", "unexpected `9`"]);
}

#[test]
fn obj_cr_line_ends() {
    let (_dir, path) = file_with("cr.obj", b"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r");
    let out = proxima(&["info", &path, "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("\"faces\": 1"), "{text}");
    let (_dir, path) = file_with("cr_bad.obj", b"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 9\r");
    assert_one_line_error(&proxima(&["info", &path]), 1, &["cr_bad.obj:4"]);
}

#[test]
fn error_echo_escaped() {
    let (_dir, path) = file_with("esc.obj", b"v 0 0 0\nv 1 \x1b[31mred 0\n");
    let out = proxima(&["info", &path]);
    assert_one_line_error(&out, 1, &["esc.obj:2", "\\u{1b}[31mred"]);
    assert!(!out.stderr.contains(&0x1b), "raw escape byte on stderr");
    let long = format!("v 0 0 {}\n", "x".repeat(100_000));
    let (_dir, path) = file_with("long_token.obj", long.as_bytes());
    let out = proxima(&["info", &path]);
    assert_one_line_error(&out, 1, &["long_token.obj:1", "…"]);
    assert!(out.stderr.len() < 300, "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn points_file_bom_and_utf8() {
    let mesh = triangle_file("points_file_bom_and_utf8");
    let (_dir, points) = file_with("bom.pts", b"\xEF\xBB\xBF0.2,0.2,1\n");
    let out = proxima(&["closest", &mesh, "--points", &points]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (_dir, points) = file_with("bad8.pts", b"0,0,0\n\xff,2,3\n");
    let out = proxima(&["closest", &mesh, "--points", &points]);
    assert_one_line_error(&out, 1, &["bad8.pts:2", "invalid UTF-8"]);
}

#[test]
fn query_point_beyond_bound() {
    let mesh = triangle_file("query_point_beyond_bound");
    for k in ["1", "3"] {
        let out = proxima(&["closest", &mesh, "--point", "1e30,0,0", "-k", k]);
        assert_one_line_error(&out, 1, &["--point", "beyond ±4.611686e18"]);
    }
    let (_dir, points) = file_with("far.pts", b"0 0 0\n1e30 0 0\n");
    let out = proxima(&["closest", &mesh, "--points", &points, "-k", "2"]);
    assert_one_line_error(&out, 1, &["far.pts:2", "beyond ±4.611686e18"]);
    let out = proxima(&["bench", &mesh, "--points", &points]);
    assert_one_line_error(&out, 1, &["far.pts:2", "beyond ±4.611686e18"]);
    // At the bound the distance is finite.
    let out = proxima(&["closest", &mesh, "--point", "4.6e18,0,0"]);
    assert!(out.status.success());
    assert!(!String::from_utf8_lossy(&out.stdout).contains("inf"));
}

#[test]
fn empty_mesh_every_command() {
    let (_dir, empty) = file_with("empty.obj", b"");
    let (_dir2, vertices) = file_with("verts.obj", b"v 0 0 0\nv 1 0 0\n");
    for (args, needles) in [
        (vec!["info", &empty], &["empty.obj", "the mesh is empty"][..]),
        (vec!["grid", &empty, "--cell", "1"], &["empty.obj", "the mesh is empty"]),
        (vec!["voxelize", &empty, "--res", "4"], &["empty.obj", "no faces"]),
        (
            vec!["grid", &vertices, "--cell", "1", "--primitives", "faces"],
            &["verts.obj", "no faces"],
        ),
        (vec!["voxelize", &vertices, "--res", "4"], &["verts.obj", "no faces"]),
        (
            vec!["raycast", &vertices, "--origin", "0,0,1", "--dir", "0,0,-1"],
            &["verts.obj", "no faces"],
        ),
    ] {
        assert_one_line_error(&proxima(&args), 1, needles);
    }
    // A mesh of vertices only still has vertices to report and search.
    assert!(proxima(&["info", &vertices]).status.success());
    assert!(
        proxima(&["closest", &vertices, "--primitives", "vertices", "--point", "0,0,0"])
            .status
            .success()
    );
}

#[test]
fn degenerate_bounding_box() {
    let (_dir, point) = file_with("point.obj", b"v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n");
    for args in [
        vec!["voxelize", &point, "--res", "4"],
        vec![
            "raycast", &point, "--origin", "1,2,4", "--dir", "0,0,-1", "--method", "grid",
        ],
    ] {
        let out = proxima(&args);
        assert_one_line_error(&out, 1, &["point.obj", "bounding box is degenerate"]);
        assert!(!String::from_utf8_lossy(&out.stderr).contains("cell size must be"));
    }
}

/// Finite directions whose squared length overflows or underflows `f32` are
/// directions, not errors: normalized in `f64`.
#[test]
fn ray_direction_extreme_but_finite() {
    for dir in ["0,0,-3e38", "1e-30,0,0", "-1e-44,1e-44,0"] {
        let out = proxima(&[
            "traverse",
            "--origin",
            "0.5,0.5,0.5",
            "--dir",
            dir,
            "--cell",
            "1",
            "--steps",
            "3",
        ]);
        assert!(out.status.success(), "{dir}: {}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(
            String::from_utf8_lossy(&out.stdout).lines().count(),
            4,
            "{dir}: header and three cells"
        );
    }
    let mesh = triangle_file("ray_direction_extreme_but_finite");
    let out = proxima(&["raycast", &mesh, "--origin", "0.25,0.25,1", "--dir", "0,0,-3e38"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("0.25") && !text.to_lowercase().contains("no hit"),
        "{text}"
    );
}

#[test]
fn ray_origin_too_far() {
    let mesh = triangle_file("ray_origin_too_far");
    let out = proxima(&["raycast", &mesh, "--origin", "0.2,0.2,1e30", "--dir", "0,0,-1"]);
    assert_one_line_error(&out, 1, &["ray origin lies too far from the mesh"]);
    let out = proxima(&[
        "raycast",
        &mesh,
        "--origin",
        "0.2,0.2,1e30",
        "--dir",
        "0,0,-1",
        "--method",
        "grid",
        "--cell",
        "0.5",
    ]);
    assert_one_line_error(&out, 1, &["out of range"]);
    let out = proxima(&["raycast", &mesh, "--origin", "0.2,0.2,1e8", "--dir", "0,0,-1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

// ------------------------------------------------------ signed distance ---

#[test]
fn sdf_non_finite_query_point() {
    let mesh = triangle_file("sdf_non_finite_query_point");
    for point in ["nan,0,0", "0,inf,0", "0,0,-inf"] {
        let out = proxima(&["sdf", &mesh, "--point", point]);
        assert_one_line_error(&out, 2, &["not a finite number"]);
    }
    let (_dir, points) = file_with("nan.pts", b"0 0 0\n0.1 nan 0\n");
    let out = proxima(&["sdf", &mesh, "--points", &points]);
    assert_one_line_error(&out, 1, &["nan.pts:2", "'nan' is not a finite number"]);
}

#[test]
fn sdf_grid_resolution_zero() {
    let mesh = triangle_file("sdf_grid_resolution_zero");
    let (_dir, out_path) = output_path("sdf_grid_resolution_zero_out", "g.npy");
    let out = proxima(&["sdf", &mesh, "--grid", "0", "--out", out_path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["--grid must be at least 1"]);
    assert!(!out_path.exists(), "nothing written");
}

#[test]
fn sdf_grid_beyond_the_memory_budget() {
    let mesh = triangle_file("sdf_grid_beyond_the_memory_budget");
    let (_dir, out_path) = output_path("sdf_grid_beyond_the_memory_budget_out", "g.npy");
    let start = std::time::Instant::now();
    let out = proxima(&["sdf", &mesh, "--grid", "100000", "--out", out_path.to_str().unwrap()]);
    assert_one_line_error(
        &out,
        1,
        &[
            "--grid 100000: needs about 3.6 PiB (1000000000000000 × 4 = 4000000000000000 bytes), \
             more than the memory budget of",
        ],
    );
    assert!(start.elapsed().as_secs_f64() < 5.0, "refused before any work");
    assert!(!out_path.exists(), "nothing written");
    // The budget of the environment applies: 64³ cells of 4 bytes are 1 MiB.
    let args = ["sdf", &mesh, "--grid", "65", "--out", out_path.to_str().unwrap()];
    let out = proxima_env(&args, &[("PROXIMA_MEMORY_BUDGET", "1M")]);
    assert_one_line_error(
        &out,
        1,
        &["--grid 65: needs about 1.0 MiB (274625 × 4", "memory budget of 1.0 MiB"],
    );
    let args = ["sdf", &mesh, "--grid", "64", "--out", out_path.to_str().unwrap()];
    assert!(proxima_env(&args, &[("PROXIMA_MEMORY_BUDGET", "1M")]).status.success());
}

#[test]
fn sdf_sample_count_zero() {
    let mesh = triangle_file("sdf_sample_count_zero");
    let (_dir, out_path) = output_path("sdf_sample_count_zero_out", "s.npz");
    let out = proxima(&["sdf", &mesh, "--sample", "0", "--out", out_path.to_str().unwrap()]);
    assert_one_line_error(&out, 1, &["--sample must be at least 1"]);
    assert!(!out_path.exists(), "nothing written");
    // And beyond the budget: 128 bytes per sample counted.
    let args = [
        "sdf",
        &mesh,
        "--sample",
        "18446744073709551615",
        "--out",
        out_path.to_str().unwrap(),
    ];
    assert_one_line_error(&proxima(&args), 1, &["--sample 18446744073709551615", "memory budget"]);
    // Without --out: a usage error.
    assert_one_line_error(&proxima(&["sdf", &mesh, "--sample", "10"]), 2, &["--out"]);
}

/// `--sample` writes a `.npz` archive and `--grid` one `.npy` array: an
/// `--out` named for the other format is refused before the mesh is read
/// (`.npy` used to be accepted for an archive); other names are taken as
/// given, as `/dev/null` is.
#[test]
fn sdf_output_suffix_of_the_other_format() {
    let mesh = triangle_file("sdf_output_suffix_of_the_other_format");
    let (_dir, npy) = output_path("sdf_output_suffix_of_the_other_format_out", "s.npy");
    let out = proxima(&["sdf", &mesh, "--sample", "10", "--out", npy.to_str().unwrap()]);
    assert_one_line_error(
        &out,
        1,
        &["s.npy: --sample writes a .npz archive (arrays points and sdf), not a .npy array: give --out FILE.npz"],
    );
    assert!(!npy.exists(), "nothing written");
    let npz = npy.with_extension("NPZ");
    let out = proxima(&["sdf", &mesh, "--grid", "4", "--out", npz.to_str().unwrap()]);
    assert_one_line_error(
        &out,
        1,
        &["s.NPZ: --grid writes one .npy array, not a .npz archive: give --out FILE.npy"],
    );
    assert!(!npz.exists(), "nothing written");
    for args in [["--sample", "10"], ["--grid", "4"]] {
        let out = proxima(&[&["sdf", &*mesh][..], &args, &["--out", "/dev/null"]].concat());
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Output to a full disk (`/dev/full`: every write fails with ENOSPC) is
/// one line naming the file, for the `.npz` archive as for the `.npy` grid;
/// the archive used to print the zip writer's debug dump
/// (`ZipWriter::drop: failed to finalize archive: Io(Os { code: 28, … })`)
/// glued to the message.
#[test]
fn sdf_output_to_a_full_disk() {
    if !Path::new("/dev/full").exists() {
        println!("note: no /dev/full on this system; skipped");
        return;
    }
    let mesh = triangle_file("sdf_output_to_a_full_disk");
    for args in [["--sample", "10"], ["--sample", "100000"], ["--grid", "4"]] {
        let out = proxima(&[&["sdf", &*mesh][..], &args, &["--out", "/dev/full"]].concat());
        assert_one_line_error(&out, 1, &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            err, "proxima: /dev/full: No space left on device (os error 28)\n",
            "{args:?}"
        );
    }
}

/// `bench --query rays` casts the BENCHMARKS rays at the faces: query
/// points, another primitive type, or a mesh without faces are refused.
#[test]
fn bench_rays_options() {
    let mesh = triangle_file("bench_rays_options");
    let (_dir, points) = file_with("some.pts", b"0 0 0\n");
    let bench = ["bench", &*mesh, "--query", "rays"];
    let with = |extra: &[&str]| proxima(&[&bench[..], extra].concat());
    assert_one_line_error(
        &with(&["--primitives", "edges"]),
        1,
        &["--query rays casts rays at the faces"],
    );
    assert_one_line_error(
        &with(&["--points", &points]),
        1,
        &["--points and --set choose query points"],
    );
    assert_one_line_error(
        &with(&["--set", "uniform"]),
        1,
        &["--points and --set choose query points"],
    );
    let (_dir, vertices) = file_with("verts.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    assert_one_line_error(
        &proxima(&["bench", &vertices, "--query", "rays"]),
        1,
        &["verts.obj: the mesh has no faces to hit"],
    );
    assert!(with(&["--queries", "50"]).status.success());
}

#[test]
fn sdf_mesh_without_faces() {
    let (_dir, vertices) = file_with("verts.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for args in [
        vec!["sdf", &vertices, "--point", "0,0,0"],
        vec!["sdf", &vertices, "--grid", "4", "--out", "/dev/null"],
        vec!["bench", &vertices, "--query", "sdf", "--queries", "10"],
    ] {
        assert_one_line_error(&proxima(&args), 1, &["verts.obj: the mesh has no faces"]);
    }
}

#[test]
fn sdf_points_file_bad_line() {
    let mesh = triangle_file("sdf_points_file_bad_line");
    let (_dir, points) = file_with("bad.pts", b"0 0 0\n# ok\n1 2\n");
    let out = proxima(&["sdf", &mesh, "--points", &points]);
    assert_one_line_error(&out, 1, &["bad.pts:3", "expected three numbers X,Y,Z, got '1 2'"]);
}

#[test]
fn sdf_near_sigma_negative() {
    let mesh = triangle_file("sdf_near_sigma_negative");
    let (_dir, out_path) = output_path("sdf_near_sigma_negative_out", "s.npz");
    for (sigma, shown) in [("-1", "-1"), ("nan", "NaN"), ("inf", "inf")] {
        let args = [
            "sdf",
            &mesh,
            "--sample",
            "10",
            "--near-sigma",
            sigma,
            "--out",
            out_path.to_str().unwrap(),
        ];
        assert_one_line_error(
            &proxima(&args),
            1,
            &[&format!("--near-sigma must be finite and not negative, got {shown}")],
        );
    }
    assert!(!out_path.exists(), "nothing written");
}

/// A spread that would put samples where no query is answered (NaN
/// distances before the library refused it).
#[test]
fn sdf_near_sigma_too_far() {
    let mesh = triangle_file("sdf_near_sigma_too_far");
    let (_dir, out_path) = output_path("sdf_near_sigma_too_far_out", "s.npz");
    let args = [
        "sdf",
        &mesh,
        "--sample",
        "10",
        "--near-sigma",
        "1e30",
        "--out",
        out_path.to_str().unwrap(),
    ];
    assert_one_line_error(
        &proxima(&args),
        1,
        &["--near-sigma = 1000000000000000000000000000000 puts samples beyond"],
    );
    assert!(!out_path.exists(), "nothing written");
}

/// A rays file: a line that is not six numbers, with its line number.
#[test]
fn raycast_rays_file_bad_line() {
    let mesh = triangle_file("raycast_rays_file_bad_line");
    let (_dir, rays) = file_with("bad.rays", b"0 0 -1 0 0 1\n# ok\n0 0 0 1 0\n");
    let out = proxima(&["raycast", &mesh, "--rays", &rays]);
    assert_one_line_error(
        &out,
        1,
        &["bad.rays:3", "expected six numbers OX,OY,OZ,DX,DY,DZ, got '0 0 0 1 0'"],
    );
    let (_dir, rays) = file_with("nan.rays", b"0 0 -1 0 0 1\nnan 0 0 0 0 1\n");
    let out = proxima(&["raycast", &mesh, "--rays", &rays]);
    assert_one_line_error(&out, 1, &["nan.rays:2", "'nan' is not a finite number"]);
}

/// A rays file: a zero (or underflowing, or infinite) direction, with its line number.
#[test]
fn raycast_rays_file_zero_direction() {
    let mesh = triangle_file("raycast_rays_file_zero_direction");
    for direction in ["0 0 0", "1e-45 0 0", "inf 0 0"] {
        let text = format!("0 0 -1 0 0 1\n\n0 0 -1 {direction}\n");
        let (_dir, rays) = file_with("zero.rays", text.as_bytes());
        let out = proxima(&["raycast", &mesh, "--rays", &rays]);
        let expected = if direction.starts_with("inf") {
            "'inf' is not a finite number"
        } else {
            "ray direction must be finite and non-zero"
        };
        assert_one_line_error(&out, 1, &["zero.rays:3", expected]);
    }
}

/// A rays file whose ray starts too far from the mesh for its hits to be
/// told apart: the ray named by its position, nothing on standard output.
#[test]
fn raycast_rays_origin_too_far() {
    let mesh = triangle_file("raycast_rays_origin_too_far");
    let (_dir, rays) = file_with("far.rays", b"0 0 -1 0 0 1\n1e15 0 0 -1 0 0\n");
    let out = proxima(&["raycast", &mesh, "--rays", &rays]);
    assert_one_line_error(&out, 1, &["far.rays: ray 1 (counting from 0): ray origin lies too far"]);
    assert!(out.stdout.is_empty(), "no partial output");
}
