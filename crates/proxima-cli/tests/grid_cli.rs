//! The command-line contract of `grid`, `voxelize`, `traverse` and `raycast`.

use std::path::{Path, PathBuf};
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

/// The bunny shipped with the CLI (always present).
fn bunny() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj").to_string()
}

/// A path in a fresh temporary directory (`tempfile`), removed with it when
/// dropped; reads as a `Path`.
struct TempPath {
    _dir: tempfile::TempDir,
    path: PathBuf,
}

impl std::ops::Deref for TempPath {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for TempPath {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

fn temp(name: &str) -> TempPath {
    let dir = tempfile::Builder::new().prefix("proxima-grid-cli-").tempdir().unwrap();
    TempPath {
        path: dir.path().join(name),
        _dir: dir,
    }
}

#[test]
fn traverse_worked_example() {
    let out = proxima(&[
        "traverse",
        "--origin",
        "1,0.2,0.5",
        "--dir",
        "0.3,0.5,1",
        "--cell",
        "0.3",
        "--steps",
        "4",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "step,i,j,k,t_enter,t_exit");
    let cells: Vec<String> = lines[1..]
        .iter()
        .map(|l| l.split(',').skip(1).take(3).collect::<Vec<_>>().join(","))
        .collect();
    assert_eq!(cells, ["3,0,1", "3,0,2", "3,1,2", "3,1,3"]);
    let t: Vec<f64> = lines[1].split(',').skip(4).map(|x| x.parse().unwrap()).collect();
    assert_eq!(t[0], 0.0);
    assert!((t[1] - 0.1158).abs() < 1e-4);
    let t2: f64 = lines[2].split(',').nth(5).unwrap().parse().unwrap();
    assert!((t2 - 0.2315).abs() < 1e-4);
}

#[test]
fn traverse_accepts_negative_values_and_refuses_zero_direction() {
    let out = proxima(&[
        "traverse",
        "--origin",
        "-1.5,0.5,0.5",
        "--dir",
        "-1,0,0",
        "--cell",
        "1",
        "--steps",
        "2",
    ]);
    assert!(out.status.success());
    assert_eq!(stdout(&out).lines().nth(1).unwrap(), "0,-2,0,0,0,0.5");
    let out = proxima(&["traverse", "--origin", "0,0,0", "--dir", "0,0,0", "--cell", "1"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("direction") && !err.contains("panicked"), "{err}");
    for cell in ["0", "-1", "nan"] {
        let out = proxima(&["traverse", "--origin", "0,0,0", "--dir", "1,0,0", "--cell", cell]);
        assert!(!out.status.success(), "cell {cell}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("cell size"),
            "cell {cell}"
        );
    }
}

#[test]
fn voxelize_json_and_outputs() {
    let out = proxima(&["voxelize", &bunny(), "--res", "16", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["res"], 16);
    assert!(
        j["occupied"].as_u64().unwrap() > 0
            && j["seconds"].as_f64().unwrap() >= 0.0
            && j["cell"].as_f64().unwrap() > 0.0
    );
    // Single thread and classic insertion: the same count.
    let one = proxima(&[
        "voxelize",
        &bunny(),
        "--res",
        "16",
        "--json",
        "--threads",
        "1",
        "--insert",
        "classic",
    ]);
    let j1: serde_json::Value = serde_json::from_slice(&one.stdout).unwrap();
    assert_eq!(j1["occupied"], j["occupied"]);
    assert_eq!(j1["threads"], 1);
    // CSV, PLY and binvox outputs.
    let csv = temp("v.csv");
    assert!(
        proxima(&["voxelize", &bunny(), "--res", "16", "--out", csv.to_str().unwrap()])
            .status
            .success()
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().next(), Some("i,j,k"));
    assert_eq!(text.lines().count() as u64 - 1, j["occupied"].as_u64().unwrap());
    assert!(
        text.lines()
            .skip(1)
            .all(|l| l.split(',').all(|v| (0..16).contains(&v.parse::<i64>().unwrap())))
    );
    let binvox = temp("v.binvox");
    assert!(
        proxima(&["voxelize", &bunny(), "--res", "16", "--out", binvox.to_str().unwrap()])
            .status
            .success()
    );
    let bytes = std::fs::read(&binvox).unwrap();
    let header_end = bytes.windows(5).position(|w| w == b"data\n").unwrap() + 5;
    assert!(bytes.starts_with(b"#binvox 1\ndim 16 16 16\n"));
    let (mut total, mut set) = (0u64, 0u64);
    for pair in bytes[header_end..].chunks(2) {
        total += pair[1] as u64;
        set += pair[0] as u64 * pair[1] as u64;
    }
    assert_eq!((total, set), (16 * 16 * 16, j["occupied"].as_u64().unwrap()));
    let ply = temp("v.ply");
    assert!(
        proxima(&["voxelize", &bunny(), "--res", "8", "--out", ply.to_str().unwrap()])
            .status
            .success()
    );
    assert!(
        std::fs::read_to_string(&ply)
            .unwrap()
            .starts_with("ply\nformat ascii 1.0")
    );
    // Bad input.
    let out = proxima(&["voxelize", &bunny(), "--res", "0"]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("resolution"));
    let out = proxima(&["voxelize", &bunny(), "--res", "8", "--out", "x.txt"]);
    assert!(!out.status.success());
}

#[test]
fn grid_statistics_and_cells() {
    let out = proxima(&["grid", &bunny(), "--cell", "0.5", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let grids = j["grids"].as_array().unwrap();
    let kinds: Vec<&str> = grids.iter().map(|g| g["primitives"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["vertices", "edges", "faces"]);
    for g in grids {
        assert!(g["occupied_cells"].as_u64().unwrap() > 0);
        assert!(g["max_per_cell"].as_u64().unwrap() >= 1 && g["mean_per_cell"].as_f64().unwrap() >= 1.0);
        assert!(g["build_seconds"].as_f64().unwrap() >= 0.0);
    }
    // The same cells whatever the insertion and the hash; CSV of the cells.
    let mut previous: Option<String> = None;
    for (insert, hasher) in [("classic", "classic"), ("scanline", "fast")] {
        let csv = temp(&format!("cells-{insert}.csv"));
        let out = proxima(&[
            "grid",
            &bunny(),
            "--cell",
            "0.4,0.5,0.3",
            "--primitives",
            "faces",
            "--insert",
            insert,
            "--hasher",
            hasher,
            "--cells-out",
            csv.to_str().unwrap(),
        ]);
        assert!(out.status.success());
        let text = std::fs::read_to_string(&csv).unwrap();
        assert_eq!(text.lines().next(), Some("i,j,k,count"));
        let mut rows: Vec<&str> = text.lines().skip(1).collect();
        rows.sort_unstable();
        let rows = rows.join("\n");
        if let Some(p) = &previous {
            assert_eq!(p, &rows, "{insert}/{hasher}");
        }
        previous = Some(rows);
    }
    let ply = temp("cells.ply");
    assert!(
        proxima(&[
            "grid",
            &bunny(),
            "--cell",
            "1",
            "--primitives",
            "edges",
            "--cells-out",
            ply.to_str().unwrap()
        ])
        .status
        .success()
    );
    assert!(std::fs::read_to_string(&ply).unwrap().contains("element face"));
    let out = proxima(&["grid", &bunny(), "--cell", "0,1,1"]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("cell size"));
}

#[test]
fn raycast_hits_and_misses() {
    // Straight down onto the bunny's top from above.
    let out = proxima(&["raycast", &bunny(), "--origin", "0,20,0", "--dir", "0,-1,0", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let t = j["hit"]["t"].as_f64().unwrap();
    let y = j["hit"]["point"][1].as_f64().unwrap();
    assert!((20.0 - t - y).abs() < 1e-3, "t {t} point.y {y}");
    assert!(y > 5.0 && y < 9.7, "the top of the bunny: y = {y}");
    let out = proxima(&[
        "raycast",
        &bunny(),
        "--origin",
        "0,50,0",
        "--dir",
        "1,0,0",
        "--cell",
        "0.7",
    ]);
    assert_eq!(stdout(&out).trim(), "no hit");
    let text = stdout(&proxima(&[
        "raycast",
        &bunny(),
        "--origin",
        "-0.1,5,20",
        "--dir",
        "0,0,-1",
    ]));
    assert!(text.starts_with("hit face "), "{text}");
    let out = proxima(&["raycast", &bunny(), "--origin", "0,0,0", "--dir", "0,0,0"]);
    assert!(!out.status.success());
}
