//! The command-line contract of `raycast --method tree|grid` and `--any`.

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

fn bunny() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj").to_string()
}

/// The hit line up to the method-specific count in parentheses.
fn hit_part(text: &str) -> &str {
    text.split(" (").next().unwrap()
}

#[test]
fn tree_and_grid_print_the_same_hits() {
    let rays = [
        ("-0.1,5,20", "0,0,-1"),
        ("0,20,0", "0,-1,0"),
        ("3,4,5", "-1,-0.5,-1"),
        ("0,4,0", "1,0,0"),
        ("0,50,0", "1,0,0"),
    ];
    for (origin, dir) in rays {
        let run = |extra: &[&str]| {
            let mesh = bunny();
            let mut args = vec!["raycast", mesh.as_str(), "--origin", origin, "--dir", dir];
            args.extend_from_slice(extra);
            let out = proxima(&args);
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            stdout(&out)
        };
        let (tree, grid, default) = (run(&["--method", "tree"]), run(&["--method", "grid"]), run(&[]));
        assert_eq!(hit_part(&tree), hit_part(&grid), "{origin} {dir}");
        assert_eq!(default, tree, "tree is the default");
        if tree.starts_with("hit face") {
            assert!(tree.contains("nodes visited, tree of"), "{tree}");
            assert!(grid.contains("cells visited, grid cell"), "{grid}");
        } else {
            assert_eq!(tree.trim(), "no hit");
        }
        let any = run(&["--any"]);
        assert_eq!(any.trim(), if tree.starts_with("hit") { "hit" } else { "no hit" });
        assert_eq!(run(&["--any", "--method", "grid"]), any);
        // JSON: the same hit fields, with the method's own count.
        let t: serde_json::Value = serde_json::from_str(&run(&["--json"])).unwrap();
        let g: serde_json::Value = serde_json::from_str(&run(&["--json", "--method", "grid"])).unwrap();
        assert_eq!(t["method"], "tree");
        assert_eq!(g["method"], "grid");
        for key in ["face", "t", "point"] {
            assert_eq!(t["hit"][key], g["hit"][key], "{key}");
        }
        let a: serde_json::Value = serde_json::from_str(&run(&["--json", "--any"])).unwrap();
        assert_eq!(a["any_hit"], !t["hit"].is_null());
    }
}

#[test]
fn raycast_errors() {
    let out = proxima(&["raycast", &bunny(), "--origin", "0,0,0", "--dir", "0,0,0"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("direction") && err.lines().count() == 1, "{err}");
    let out = proxima(&[
        "raycast",
        &bunny(),
        "--origin",
        "0,0,0",
        "--dir",
        "0,0,1",
        "--method",
        "tree",
        "--cell",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(2), "usage error");
    let out = proxima(&[
        "raycast",
        &bunny(),
        "--origin",
        "0,0,0",
        "--dir",
        "0,0,1",
        "--method",
        "octree",
    ]);
    assert_eq!(out.status.code(), Some(2), "usage error");
    let out = proxima(&["raycast", "/nonexistent.obj", "--origin", "0,0,0", "--dir", "0,0,1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent.obj"));
}
