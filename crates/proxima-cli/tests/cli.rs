//! The `proxima` binary: output formats, and one clear line for every kind of
//! bad input (never a panic, always a non-zero exit).

mod common;

use common::temp_dir;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn proxima(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .output()
        .expect("run proxima")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn write(dir: &Path, name: &str, content: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.display().to_string()
}

const TETRA: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// Asserts a failure with exit status 1, one line on stderr containing every
/// `needle`, and no panic.
fn assert_clear_error(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "exit status; stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line expected: {err}");
    for needle in needles {
        assert!(err.contains(needle), "'{needle}' missing from: {err}");
    }
}

#[test]
fn closest_prints_the_documented_csv() {
    let dir = temp_dir("csv");
    let mesh = write(&dir, "tetra.obj", TETRA);
    let points = write(&dir, "q.pts", "# comment\n0.2 0.2 -1\n\n0.2, 0.2, -2\n");
    let o = proxima(&[
        "closest",
        &mesh,
        "--primitives",
        "faces",
        "--points",
        &points,
        "-k",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "query,rank,primitive,cx,cy,cz,distance");
    assert_eq!(lines.len(), 5);
    // Face 0 (1 3 2) lies in z = 0, right under both queries.
    assert_eq!(lines[1], "0,0,0,0.2,0.2,0,1");
    assert!(lines[3].starts_with("1,0,0,0.2,0.2,0,2"));
    assert!(lines[2].starts_with("0,1,") && lines[4].starts_with("1,1,"));
    // Tree and linear search print the same thing.
    for kind in ["vertices", "edges", "faces"] {
        let tree = proxima(&["closest", &mesh, "--primitives", kind, "--points", &points, "-k", "3"]);
        let linear = proxima(&[
            "closest",
            &mesh,
            "--primitives",
            kind,
            "--points",
            &points,
            "-k",
            "3",
            "--method",
            "linear",
        ]);
        assert!(tree.status.success() && linear.status.success());
        assert_eq!(stdout(&tree), stdout(&linear), "{kind}");
    }
    // Negative coordinates are accepted as typed.
    let o = proxima(&["closest", &mesh, "--point", "-0.1,-2,0.3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).lines().nth(1).unwrap().starts_with("0,0,"));
}

#[test]
fn info_and_bench_json_have_the_documented_keys() {
    let dir = temp_dir("json");
    let mesh = write(&dir, "tetra.obj", TETRA);
    let o = proxima(&["info", &mesh, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let info: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(info["vertices"], 4);
    assert_eq!(info["edges"], 6);
    assert_eq!(info["triangles"], 4);
    assert_eq!(info["trees"].as_array().unwrap().len(), 3);
    let o = proxima(&["bench", &mesh, "--queries", "50", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bench: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(bench["triangles"], 4);
    let results = bench["results"].as_array().unwrap();
    // Per primitive type: linear, tree, tree-wide, tree-batch, sphere-tree.
    // The shipped binary has no peer row: parry3d's is proxima-bench's
    // (`crates/proxima-bench/tests/bench.rs`).
    assert_eq!(results.len(), 15);
    assert_eq!(results.iter().filter(|r| r["method"] == "sphere-tree").count(), 3);
    assert!(results.iter().all(|r| r["method"] != "parry3d"));
    for r in results {
        for key in [
            "primitives",
            "method",
            "build_seconds",
            "queries",
            "seconds",
            "queries_per_second",
        ] {
            assert!(r.get(key).is_some(), "{key} missing in {r}");
        }
        assert_eq!(r["agree"], true);
    }
}

#[test]
fn demo_runs_on_the_embedded_model() {
    let o = proxima(&["demo", "--queries", "100"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("3674 triangles") && out.contains("tree-batch"), "{out}");
    assert!(!out.contains(" NO"), "tree and linear disagree: {out}");
}

#[test]
fn every_bad_input_gets_one_clear_line() {
    let dir = temp_dir("bad");
    let good = write(&dir, "tetra.obj", TETRA);
    let cases: Vec<(Vec<String>, Vec<&str>)> = vec![
        (
            vec!["info".into(), dir.join("missing.obj").display().to_string()],
            vec!["missing.obj"],
        ),
        (
            vec!["info".into(), write(&dir, "mesh.xyz", "1 2 3\n")],
            vec!["mesh.xyz", "unknown mesh format"],
        ),
        (
            vec!["info".into(), write(&dir, "badnum.obj", "v 0 0 0\nv 1 x 0\n")],
            vec!["badnum.obj:2"],
        ),
        (
            vec![
                "info".into(),
                write(&dir, "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            ],
            vec!["range.obj:4"],
        ),
        (
            vec![
                "info".into(),
                write(&dir, "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
            ],
            vec!["nan.obj:2"],
        ),
        (
            vec!["info".into(), write(&dir, "trunc.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n")],
            vec!["trunc.off"],
        ),
        (
            vec![
                "info".into(),
                write(
                    &dir,
                    "count.ply",
                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n",
                ),
            ],
            vec!["count.ply"],
        ),
        (
            vec![
                "closest".into(),
                write(&dir, "points.obj", "v 0 0 0\nv 1 1 1\n"),
                "--primitives".into(),
                "faces".into(),
                "--point".into(),
                "0,0,0".into(),
            ],
            vec!["points.obj", "no faces"],
        ),
        (
            vec![
                "closest".into(),
                good.clone(),
                "--points".into(),
                write(&dir, "bad.pts", "0 0 0\n# ok\n1 2\n"),
            ],
            vec!["bad.pts:3"],
        ),
        (
            vec![
                "closest".into(),
                good.clone(),
                "--points".into(),
                dir.join("nope.pts").display().to_string(),
            ],
            vec!["nope.pts"],
        ),
        (
            vec![
                "bench".into(),
                write(&dir, "empty.obj", "# nothing\n"),
                "--queries".into(),
                "5".into(),
            ],
            vec!["empty.obj"],
        ),
        (
            vec![
                "closest".into(),
                dir.join("empty.obj").display().to_string(),
                "--primitives".into(),
                "vertices".into(),
                "--point".into(),
                "0,0,0".into(),
            ],
            vec!["empty.obj", "no vertices"],
        ),
        (
            vec![
                "closest".into(),
                dir.join("points.obj").display().to_string(),
                "--primitives".into(),
                "edges".into(),
                "--point".into(),
                "0,0,0".into(),
            ],
            vec!["points.obj", "no edges"],
        ),
        (
            vec![
                "info".into(),
                write(&dir, "inf.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n"),
            ],
            vec!["inf.off:4"],
        ),
        (
            vec![
                "info".into(),
                write(
                    &dir,
                    "short.stl",
                    "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
                ),
            ],
            vec!["short.stl"],
        ),
    ];
    for (args, needles) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = proxima(&args);
        assert_clear_error(&o, &needles);
    }
    // Usage errors are clap's: exit status 2, no panic.
    for args in [
        vec!["closest", good.as_str(), "--point", "1,2"],
        vec!["closest", good.as_str(), "--point", "1,nan,2"],
    ] {
        let o = proxima(&args);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"));
    }
}

/// A reader that stops early (`proxima traverse ... | head -1`) closes the
/// pipe: the writer ends quietly with status 0, without a panic message.
#[test]
fn a_closed_output_pipe_ends_quietly() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    for args in [
        &[
            "traverse",
            "--origin",
            "0,0,0",
            "--dir",
            "1,0.3,0.2",
            "--cell",
            "0.001",
            "--steps",
            "2000000",
        ][..],
        &[
            "info",
            "--json",
            concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj"),
        ][..],
        &["demo"][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_proxima"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        assert!(!first.is_empty(), "{args:?}: no output");
        // The reader is dropped here: the pipe is closed while the child still writes.
        let output = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&output.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(
            output.status.success(),
            "{args:?}: status {:?}, stderr {err}",
            output.status
        );
    }
}

/// `closest -k` over faces of more than three vertices: each face once, at the
/// distance of its nearest fan triangle, in order. The oracle: every face's
/// distance by brute force over its own triangles, sorted (ties by face).
#[test]
fn closest_k_lists_each_face_once() {
    use proxima::{ClosestPoint, Vec3, Vec3A};
    let dir = tempfile::tempdir().unwrap();
    // A cube of quads, plus a hexagon fan: every face splits into 2 or 4 triangles.
    let cube = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                v 3 0 0\nv 4 0 0\nv 4.5 1 0\nv 4 2 0\nv 3 2 0\nv 2.5 1 0\n\
                f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\nf 9 10 11 12 13 14\n";
    let handmade = write(dir.path(), "quads.obj", cube);
    let shared = std::env::var_os("PROXIMA_DATA_DIR")
        .map_or_else(
            || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
            PathBuf::from,
        )
        .join("spot_quadrangulated.obj");
    let mut meshes = vec![PathBuf::from(&handmade)];
    if shared.exists() {
        meshes.push(shared);
    } else {
        println!("skipped: {} (absent)", shared.display());
    }
    for path in &meshes {
        let mesh = proxima::io::load(path).unwrap();
        let bounds = mesh.bounds();
        let triangles = mesh.triangles();
        let queries: Vec<Vec3> = (0..6)
            .map(|i| {
                let t = Vec3::new(0.13 * i as f32 + 0.05, 0.71 - 0.09 * i as f32, 0.37 + 0.11 * i as f32);
                bounds.min + (bounds.max - bounds.min) * t * 1.2 - (bounds.max - bounds.min) * 0.1
            })
            .collect();
        for &q in &queries {
            let p = Vec3A::from(q);
            let mut per_face = vec![f32::INFINITY; mesh.face_count()];
            for (triangle, &face) in triangles.primitives.iter().zip(&triangles.sources) {
                let d = (triangle.closest_point(p) - p).length_squared().sqrt();
                per_face[face as usize] = per_face[face as usize].min(d);
            }
            let mut want: Vec<(usize, f32)> = per_face.into_iter().enumerate().collect();
            want.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            for k in [1usize, 3, 5, 8] {
                let want: Vec<(usize, f32)> = want.iter().copied().take(k).collect();
                for method in ["tree", "linear"] {
                    let point = format!("{},{},{}", q.x, q.y, q.z);
                    let o = proxima(&[
                        "closest",
                        path.to_str().unwrap(),
                        "--primitives",
                        "faces",
                        "--point",
                        &point,
                        "-k",
                        &k.to_string(),
                        "--method",
                        method,
                    ]);
                    assert!(o.status.success(), "{}", stderr(&o));
                    let got: Vec<(usize, f32)> = stdout(&o)
                        .lines()
                        .skip(1)
                        .map(|line| {
                            let fields: Vec<&str> = line.split(',').collect();
                            (fields[2].parse().unwrap(), fields[6].parse().unwrap())
                        })
                        .collect();
                    assert_eq!(got, want, "{} {method} k={k} at {q}", path.display());
                }
            }
        }
    }
}

/// The shipped binary has no peer library: `bench --help` says where the
/// parry3d rows are.
#[test]
fn bench_help_names_the_peer_rows() {
    let o = proxima(&["bench", "--help"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let help = stdout(&o);
    assert!(
        help.contains("parry3d") && help.contains("cargo run -p proxima-bench --release --bin bench -- MESH"),
        "{help}"
    );
}
