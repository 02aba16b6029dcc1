//! Inputs that used to panic, abort or run away and now succeed within bounds
//! (issue 21 §2); the ones that became errors are in `errors_cli.rs`.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn proxima(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .output()
        .expect("run proxima")
}

fn bunny() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj").to_string()
}

fn write(dir: &Path, name: &str, content: &str) -> String {
    let path: PathBuf = dir.join(name);
    std::fs::write(&path, content).unwrap();
    path.display().to_string()
}

fn stdout(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "stderr: {err}");
    String::from_utf8(out.stdout.clone()).unwrap()
}

#[test]
fn bench_with_fewer_queries_than_the_linear_minimum() {
    // Fewer than the 20 queries linear search is given at least: it used to
    // panic in `clamp` ("min > max").
    let dir = tempfile::tempdir().unwrap();
    let mesh = write(dir.path(), "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let one = write(dir.path(), "one.pts", "0.2 0.2 1\n");
    for (args, queries) in [
        (vec!["bench", &mesh, "--queries", "5", "--json"], 5),
        (vec!["bench", &mesh, "--points", &one, "--json"], 1),
    ] {
        let json: serde_json::Value = serde_json::from_str(&stdout(&proxima(&args))).unwrap();
        let results = json["results"].as_array().unwrap();
        assert!(!results.is_empty());
        for r in results {
            assert_eq!(r["queries"], queries, "{r}");
            assert_eq!(r["agree"], true, "{r}");
        }
    }
}

#[test]
fn a_full_stderr_ends_quietly() {
    // `2>/dev/full`: the error line cannot be written; the exit status still
    // says what happened (1), without a panic (101).
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        println!("skipped: /dev/full is not available");
        return;
    };
    let status = Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(["info", "surely-missing.obj"])
        .stderr(Stdio::from(full))
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(1));
}

#[test]
fn traverse_ends_where_t_leaves_f32() {
    // Cells of 1e36: the walk ends with the cell whose exit no longer fits
    // f32 (454 cells, see `limits::walks_end_where_t_no_longer_fits_f32`)
    // instead of printing rows at t = inf up to --steps.
    let out = stdout(&proxima(&[
        "traverse",
        "--origin",
        "0,0,0",
        "--dir",
        "1,0.3,0.1",
        "--cell",
        "1e36",
        "--steps",
        "10000000",
    ]));
    let rows: Vec<&str> = out.lines().skip(1).collect();
    assert_eq!(rows.len(), 454);
    assert!(
        rows.last().unwrap().starts_with("453,324,97,32,"),
        "{}",
        rows.last().unwrap()
    );
    assert!(rows.last().unwrap().ends_with(",inf"));
    assert!(rows[..453].iter().all(|r| !r.contains("inf")));
}

#[test]
fn closest_streams_answers_in_input_order_across_chunks() {
    // k = 1000 on the 3,674-face bunny: 1,048 queries per chunk of answers
    // (2^20 hits). 1,500 points take two chunks; each half (750) one. The
    // whole run must equal the halves run alone, renumbered.
    let dir = tempfile::tempdir().unwrap();
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let points: Vec<String> = (0..1500)
        .map(|_| format!("{} {} {}", next() * 10.0 - 5.0, next() * 10.0, next() * 8.0 - 4.0))
        .collect();
    let all = write(dir.path(), "all.pts", &points.join("\n"));
    let first = write(dir.path(), "first.pts", &points[..750].join("\n"));
    let second = write(dir.path(), "second.pts", &points[750..].join("\n"));
    for method in ["tree", "linear"] {
        let run = |file: &str| {
            stdout(&proxima(&[
                "closest",
                &bunny(),
                "--points",
                file,
                "-k",
                "1000",
                "--method",
                method,
            ]))
        };
        let whole = run(&all);
        let mut expected = run(&first);
        for line in run(&second).lines().skip(1) {
            let (query, rest) = line.split_once(',').unwrap();
            expected.push_str(&format!("{},{rest}\n", query.parse::<usize>().unwrap() + 750));
        }
        assert_eq!(whole.lines().count(), 1 + 1500 * 1000);
        assert!(whole == expected, "{method}: chunked output differs from the halves");
    }
}

#[test]
fn glb_json_members_not_read_cost_nothing() {
    // 30 million zeros (60 MB of JSON) in the document's `extras`: parsed
    // into values they took over 1 GiB (a 300 MB array aborted allocating
    // 8 GiB); skipped as they are read, the file loads under a 1 GiB
    // address-space limit.
    let dir = tempfile::tempdir().unwrap();
    let zeros = format!(r#""extras":[{}0],"#, "0,".repeat(30_000_000));
    let path = dir.path().join("extras.glb");
    std::fs::write(&path, common::instanced_glb(3, 1, 4, &zeros, "")).unwrap();
    let out = common::proxima_under_limit(1 << 20, &["info", &path.display().to_string()], &[]);
    let text = stdout(&out);
    assert!(text.contains("faces      1 "), "{text}");
}
