//! `--primitives polygons` on the command line: the same answers as faces on
//! exactly planar quads (up to f32 rounding), the fallback note on stderr for
//! faces that are not planar or convex, and the grid, bench and info rows.

mod common;

use common::temp_dir;
use std::path::Path;
use std::process::{Command, Output};

fn proxima(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .output()
        .expect("run proxima")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn write(dir: &Path, name: &str, content: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.display().to_string()
}

/// A unit cube of six planar quads, and the same with one bent face (vertex
/// 8 lifted off the top face) and one dart (a non-convex quad).
const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
const BENT: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1.25\nv 0.25 0.25 0\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 9 3 4\n";

/// The CSV rows of `closest`, parsed: (query, rank, face, point, distance).
fn rows(o: &Output) -> Vec<(String, f32)> {
    assert_eq!(o.status.code(), Some(0), "stderr: {}", text(&o.stderr));
    text(&o.stdout)
        .lines()
        .skip(1)
        .map(|line| {
            let cols: Vec<&str> = line.split(',').collect();
            (cols[..3].join(","), cols[6].parse().unwrap())
        })
        .collect()
}

#[test]
fn closest_on_planar_quads_equals_faces() {
    let dir = temp_dir("closest");
    let mesh = write(&dir, "cube.obj", CUBE);
    let points = write(
        &dir,
        "q.pts",
        "0.25 0.5 -1\n2 0.5 0.5\n0.5 0.5 0.5\n-1 -1 -1\n0.5 3 1.5\n",
    );
    let mut answers = Vec::new();
    for kind in ["faces", "polygons"] {
        for method in ["tree", "linear"] {
            let o = proxima(&[
                "closest",
                &mesh,
                "--primitives",
                kind,
                "--points",
                &points,
                "-k",
                "2",
                "--method",
                method,
            ]);
            assert!(
                text(&o.stderr).is_empty(),
                "no note for planar quads: {}",
                text(&o.stderr)
            );
            answers.push(rows(&o));
        }
    }
    assert_eq!(answers[0].len(), 10);
    // Faces and polygons name the same faces at the same distances (within
    // f32 rounding; the faces' second rank is the quad's other triangle).
    for (face, polygon) in answers[0].iter().zip(&answers[2]).step_by(2) {
        assert_eq!(face.0, polygon.0);
        assert!((face.1 - polygon.1).abs() <= 1e-6, "{face:?} vs {polygon:?}");
    }
    assert_eq!(answers[2], answers[3], "tree and linear agree on polygons");
}

#[test]
fn fallback_is_reported_on_stderr() {
    let dir = temp_dir("note");
    let mesh = write(&dir, "bent.obj", BENT);
    let o = proxima(&["closest", &mesh, "--primitives", "polygons", "--point", "0.5,0.5,2"]);
    assert_eq!(o.status.code(), Some(0));
    let err = text(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("bent.obj: 2 of 3 faces with more than 3 vertices are not planar/convex"),
        "{err}"
    );
    assert!(err.contains("fan-triangulated"), "{err}");
    // A loose tolerance keeps the bent face whole: only the dart falls back.
    let o = proxima(&[
        "closest",
        &mesh,
        "--primitives",
        "polygons",
        "--point",
        "0.5,0.5,2",
        "--planarity",
        "0.2",
    ]);
    assert!(text(&o.stderr).contains(": 1 of 3 faces"), "{}", text(&o.stderr));
    // A bad tolerance is a usage error.
    let o = proxima(&[
        "closest",
        &mesh,
        "--primitives",
        "polygons",
        "--point",
        "0,0,0",
        "--planarity",
        "x",
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn grid_bench_and_info_take_polygons() {
    let dir = temp_dir("grid");
    let mesh = write(&dir, "cube.obj", CUBE);
    let grid = |kind: &str, insert: &str| {
        let o = proxima(&[
            "grid",
            &mesh,
            "--cell",
            "0.5",
            "--primitives",
            kind,
            "--insert",
            insert,
            "--json",
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let v: serde_json::Value = serde_json::from_str(&text(&o.stdout)).unwrap();
        let g = &v["grids"][0];
        (
            g["occupied_cells"].as_u64().unwrap(),
            g["primitives"].as_str().unwrap().to_string(),
        )
    };
    // Planar quads on cell boundaries: the same occupied cells as the triangles.
    for insert in ["classic", "scanline"] {
        let (polygons, name) = grid("polygons", insert);
        assert_eq!(name, "polygons");
        assert_eq!(polygons, grid("faces", insert).0);
    }
    let o = proxima(&["bench", &mesh, "--primitives", "polygons", "--queries", "50", "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&text(&o.stdout)).unwrap();
    let results = v["results"].as_array().unwrap();
    assert!(
        results
            .iter()
            .all(|r| r["primitives"] == "polygons" && r["agree"] == true)
    );
    let o = proxima(&["info", &mesh, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&text(&o.stdout)).unwrap();
    let trees = v["trees"].as_array().unwrap();
    assert_eq!(trees.len(), 4);
    assert_eq!(
        (trees[3]["primitives"].as_str(), trees[3]["count"].as_u64()),
        (Some("polygons"), Some(6))
    );
}
