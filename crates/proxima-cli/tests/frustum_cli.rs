//! The command-line contract of `frustum`.

use proxima::math::camera;
use proxima::{Mat4, Vec3};
use std::path::PathBuf;
use std::process::{Command, Output};

fn proxima(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .output()
        .expect("runs")
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The bunny shipped with the CLI (always present).
fn bunny() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj").to_string()
}

/// A file path that keeps its temporary directory (`tempfile`) alive; reads as a `str`.
struct TempFile {
    _dir: tempfile::TempDir,
    path: String,
}

impl std::ops::Deref for TempFile {
    type Target = str;
    fn deref(&self) -> &str {
        &self.path
    }
}

fn temp(name: &str, content: &str) -> TempFile {
    let dir = tempfile::Builder::new()
        .prefix("proxima-frustum-cli-")
        .tempdir()
        .unwrap();
    let path: PathBuf = dir.path().join(name);
    std::fs::write(&path, content).unwrap();
    TempFile {
        path: path.display().to_string(),
        _dir: dir,
    }
}

/// A camera looking at the bunny's left side from the front, seeing part of it.
const CAMERA: [&str; 10] = [
    "--look-at",
    "-3,4,12,-2,4,0,0,1,0",
    "--fov",
    "25",
    "--aspect",
    "1.5",
    "--near",
    "1",
    "--far",
    "14",
];

fn json_indices(out: &Output) -> (u64, Vec<u64>) {
    assert!(out.status.success(), "{}", stderr(out));
    let j: serde_json::Value = serde_json::from_str(&stdout(out)).expect("one JSON object");
    let indices: Vec<u64> = j["indices"]
        .as_array()
        .expect("indices")
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    (j["count"].as_u64().unwrap(), indices)
}

fn run_json(kind: &str, camera: &[&str], extra: &[&str]) -> (u64, Vec<u64>) {
    let mesh = bunny();
    let mut args = vec!["frustum", mesh.as_str(), "--primitives", kind, "--json"];
    args.extend_from_slice(camera);
    args.extend_from_slice(extra);
    json_indices(&proxima(&args))
}

/// Clip-space oracle on the vertices of the OBJ, read here by hand.
fn visible_vertices(m: &Mat4) -> Vec<u64> {
    let text = std::fs::read_to_string(bunny()).unwrap();
    let c = m.to_cols_array();
    text.lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse::<f32>().unwrap() as f64).collect();
            let p = [v[0], v[1], v[2], 1.0];
            let h: [f64; 4] = std::array::from_fn(|r| (0..4).map(|k| c[k * 4 + r] as f64 * p[k]).sum());
            (0..3).all(|k| -h[3] <= h[k] && h[k] <= h[3])
        })
        .enumerate()
        .filter(|&(_, inside)| inside)
        .map(|(i, _)| i as u64)
        .collect()
}

#[test]
fn json_lists_sorted_unique_source_indices_matching_the_oracle() {
    let matrix = camera::perspective(25f32.to_radians(), 1.5, 1.0, 14.0)
        * camera::look_at_mat4(Vec3::new(-3.0, 4.0, 12.0), Vec3::new(-2.0, 4.0, 0.0), Vec3::Y);
    let expected = visible_vertices(&matrix);
    let (count, vertices) = run_json("vertices", &CAMERA, &[]);
    assert_eq!(count as usize, vertices.len());
    assert_eq!(vertices, expected);
    assert!(!vertices.is_empty() && vertices.len() < 1839, "{}", vertices.len());
    // The same camera as a matrix (16 numbers, column-major), negative entries as typed.
    let numbers: Vec<String> = matrix.to_cols_array().iter().map(|x| format!("{x:?}")).collect();
    let numbers = numbers.join(",");
    let (_, by_matrix) = run_json("vertices", &["--view-proj", &numbers], &[]);
    assert_eq!(by_matrix, vertices);
    for kind in ["vertices", "edges", "faces", "polygons"] {
        let (count, tree) = run_json(kind, &CAMERA, &[]);
        assert!(tree.windows(2).all(|w| w[0] < w[1]), "{kind}: sorted and unique");
        assert_eq!(count as usize, tree.len());
        let (_, linear) = run_json(kind, &CAMERA, &["--method", "linear"]);
        assert_eq!(tree, linear, "{kind}: tree and brute force");
        let (_, sah) = run_json(kind, &CAMERA, &["--split", "sah"]);
        assert_eq!(tree, sah, "{kind}: split");
        let (_, spheres) = run_json(kind, &CAMERA, &["--tree", "sphere"]);
        assert_eq!(tree, spheres, "{kind}: sphere tree");
    }
}

#[test]
fn text_output_is_the_count_then_one_index_per_line() {
    let mesh = bunny();
    let mut args = vec!["frustum", mesh.as_str(), "--primitives", "faces"];
    args.extend_from_slice(&CAMERA);
    let out = proxima(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let mut lines = text.lines();
    let head = lines.next().unwrap();
    let count: usize = head.strip_suffix(" faces in the frustum").expect(head).parse().unwrap();
    let indices: Vec<u64> = lines.map(|l| l.parse().unwrap()).collect();
    assert_eq!(indices.len(), count);
    assert_eq!(indices, run_json("faces", &CAMERA, &[]).1);
}

#[test]
fn faces_split_into_triangles_are_listed_once() {
    // A quad (two triangles) and a far triangle; the camera sees the quad.
    let mesh = temp(
        "quad.obj",
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv 0 0 -50\nv 1 0 -50\nv 0 1 -50\nf 1 2 3 4\nf 5 6 7\n",
    );
    let out = proxima(&[
        "frustum",
        &mesh,
        "--primitives",
        "faces",
        "--look-at",
        "0,0,5,0,0,0,0,1,0",
        "--near",
        "1",
        "--far",
        "10",
        "--json",
    ]);
    assert_eq!(json_indices(&out), (1, vec![0]));
}

#[test]
fn bench_reports_timing_and_work() {
    let mesh = bunny();
    let mut args = vec!["frustum", mesh.as_str(), "--bench", "--json"];
    args.extend_from_slice(&CAMERA);
    let out = proxima(&args);
    assert!(out.status.success(), "{}", stderr(&out));
    let j: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert!(j["bench"]["tree_seconds_per_query"].as_f64().unwrap() > 0.0);
    assert!(j["bench"]["linear_seconds_per_query"].as_f64().unwrap() > 0.0);
    let tested = j["primitives_tested"].as_u64().unwrap();
    assert!(tested < 3674, "the tree tests fewer faces than brute force: {tested}");
    assert!(j["nodes_visited"].as_u64().unwrap() > 0);
}

#[test]
fn bad_cameras_fail_with_one_line() {
    let mesh = bunny();
    let cases: [(&[&str], &str); 6] = [
        (
            &["--look-at", "0,0,5,0,0,0,0,1,0", "--near", "0", "--far", "10"],
            "near",
        ),
        (
            &["--look-at", "0,0,5,0,0,0,0,1,0", "--near", "-1", "--far", "10"],
            "near",
        ),
        (&["--look-at", "0,0,5,0,0,0,0,1,0", "--near", "2", "--far", "2"], "far"),
        (
            &[
                "--look-at",
                "0,0,5,0,0,0,0,1,0",
                "--near",
                "1",
                "--far",
                "9",
                "--fov",
                "0",
            ],
            "field of view",
        ),
        (&["--look-at", "0,0,5,0,0,0,0,0,1", "--near", "1", "--far", "9"], "up"),
        (&["--view-proj", "1,0,0,0,1,0,0,0,0,0,1,0,0,0,0,1"], "singular"),
    ];
    for (camera, needle) in cases {
        let mut args = vec!["frustum", mesh.as_str()];
        args.extend_from_slice(camera);
        let out = proxima(&args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{camera:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(needle) && !err.contains("panicked"), "{err}");
    }
    // Missing file: one line naming it.
    let out = proxima(&[
        "frustum",
        "/nonexistent/mesh.obj",
        "--view-proj",
        "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("/nonexistent/mesh.obj"));
    // Usage errors are clap's: exit status 2, the problem on the first line, no panic.
    for camera in [
        vec!["--look-at", "0,0,5,0,0,0", "--near", "1", "--far", "9"],
        vec!["--view-proj", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0"],
        vec!["--view-proj", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,nan"],
        vec!["--look-at", "0,0,5,0,0,0,0,1,0"],
        vec![],
    ] {
        let mut args = vec!["frustum", mesh.as_str()];
        args.extend_from_slice(&camera);
        let out = proxima(&args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{camera:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = proxima(&["frustum", &mesh, "--look-at", "0,0,5,0,0", "--near", "1", "--far", "9"]);
    assert!(stderr(&out).lines().next().unwrap().contains("expected 9 numbers"));
}

/// `--look-at` builds the camera in `f64`: a tiny `up` is a direction (the
/// same faces as `up` = (1, 1, 0)), and a camera an `f32` matrix cannot hold
/// is refused for what it is, in one line naming the values (all three used
/// to get "needs finite vectors, eye != target, and up not parallel").
#[test]
fn look_at_cameras_name_what_f32_cannot_hold() {
    let mesh = bunny();
    let run = |camera: &str, near: &str, far: &str| {
        proxima(&["frustum", &mesh, "--look-at", camera, "--near", near, "--far", far])
    };
    let tiny_up = run("0,0,5,0,0,0,1e-45,1e-45,0", "1", "10");
    assert!(tiny_up.status.success(), "{}", stderr(&tiny_up));
    let diagonal_up = run("0,0,5,0,0,0,1,1,0", "1", "10");
    assert_eq!(stdout(&tiny_up), stdout(&diagonal_up));
    assert!(
        stdout(&tiny_up).contains(" faces in the frustum"),
        "{}",
        stdout(&tiny_up)
    );
    for (camera, near, far, needle) in [
        (
            "1e30,0,0,0,0,0,0,1,0",
            "1",
            "1e31",
            "invalid camera: the projection of near = 1, far = 1e31 (far / near = 1e31), a field of view of 60 \
             degrees and aspect 1 is beyond an f32 view-projection matrix: the far plane of the view-projection \
             matrix has a zero normal",
        ),
        (
            "1e30,0,0,0,0,0,0,1,0",
            "1",
            "1e7",
            "invalid camera: the eye lies 1e30 from the origin, too far for an f32 view-projection matrix with near \
             = 1 and far = 1e7: the view-projection matrix is singular",
        ),
        (
            "3e38,3e38,3e38,0,0,0,0,1,0",
            "1e37",
            "3e38",
            "invalid camera: the camera's eye distance along a view axis is -5.196152e38, beyond f32",
        ),
    ] {
        let out = run(camera, near, far);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{camera}: {err}");
        assert_eq!(err, format!("proxima: {needle}\n"));
    }
}
