//! The `pairs` binary end to end on small meshes: a workload folder made,
//! run, its dump judged as a peer's answers (every answer agrees with
//! itself), self-intersections judged; bad input is one line on stderr and
//! exit status 1.

use proxima_bench::poses::{ply_bytes, scaled_to};
use serde_json::Value;
use std::path::Path;
use std::process::{Command, Output};

fn pairs(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pairs"))
        .args(args)
        .output()
        .expect("the pairs binary runs")
}

fn json(o: &Output) -> Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("JSON on stdout")
}

/// Two bumpy spheres of one size as PLY files in `dir`.
fn meshes(dir: &Path) -> (String, String) {
    let a = proxima::mesh::generate::noisy_icosphere(4, 1);
    let b = scaled_to(&proxima::mesh::generate::noisy_icosphere(3, 2), a.bounds().diagonal()).unwrap();
    let (pa, pb) = (dir.join("in-a.ply"), dir.join("in-b.ply"));
    std::fs::write(&pa, ply_bytes(&a)).unwrap();
    std::fs::write(&pb, ply_bytes(&b)).unwrap();
    (pa.display().to_string(), pb.display().to_string())
}

#[test]
fn a_workload_runs_and_proxima_agrees_with_its_own_dump() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = meshes(dir.path());
    let w = dir.path().join("w");
    let w = w.to_str().unwrap();
    let made = json(&pairs(&["poses", &a, &b, "--out", w, "--count", "8", "--seed", "4"]));
    assert_eq!(made.as_array().unwrap().len(), 3);
    let dump = dir.path().join("dump.json");
    let report = json(&pairs(&[
        "run",
        w,
        "--distance-poses",
        "8",
        "--peer-poses",
        "8",
        "--peer-distance-poses",
        "2",
        "--dump",
        dump.to_str().unwrap(),
    ]));
    for check in report["checks"].as_array().unwrap() {
        assert_eq!(check["batch_mismatches"], 0, "{check}");
        assert_eq!(check["intersects_not_distance_zero"], 0, "{check}");
    }
    // proxima's dump as a peer's answers: every distance and collision equal.
    let mut peer: Value = serde_json::from_str(&std::fs::read_to_string(&dump).unwrap()).unwrap();
    for class in ["near", "far", "overlap"] {
        peer["classes"][class]["pose"] = (0..8).collect::<Vec<_>>().into();
    }
    peer["peer"] = "proxima".into();
    let peer_file = dir.path().join("peer.json");
    std::fs::write(&peer_file, peer.to_string()).unwrap();
    let verdicts = json(&pairs(&["judge", w, peer_file.to_str().unwrap()]));
    assert_eq!(verdicts.as_array().unwrap().len(), 3);
    for v in verdicts.as_array().unwrap() {
        assert_eq!(v["distances"], 8, "{v}");
        assert_eq!(v["within_1e-6_diagonal"], 8, "{v}");
        assert_eq!(v["collisions_equal"], 8, "{v}");
        assert_eq!(v["bad_witnesses"], 0, "{v}");
    }
    // Self-intersections of a closed sphere: none, and judged equal to none.
    let ours = dir.path().join("self.json");
    let found = json(&pairs(&["self", &a, "--reps", "1", "--dump", ours.to_str().unwrap()]));
    assert_eq!(found["pairs"], 0);
    let judged = json(&pairs(&[
        "judge-self",
        &a,
        ours.to_str().unwrap(),
        ours.to_str().unwrap(),
    ]));
    assert_eq!(judged["only_proxima"], 0);
    assert_eq!(judged["only_peer"], 0);
}

#[test]
fn bad_input_is_one_line_and_status_1() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothing");
    let bad_pose = dir.path().join("w");
    let (a, b) = meshes(dir.path());
    std::fs::create_dir(&bad_pose).unwrap();
    std::fs::copy(&a, bad_pose.join("a.ply")).unwrap();
    std::fs::copy(&b, bad_pose.join("b.ply")).unwrap();
    std::fs::write(bad_pose.join("near.poses"), "2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n").unwrap();
    let cases: [(Vec<&str>, &str); 3] = [
        (vec!["run", missing.to_str().unwrap()], "a.ply"),
        (
            vec!["run", bad_pose.to_str().unwrap(), "--class", "near"],
            "not a rotation",
        ),
        (vec!["self", missing.to_str().unwrap()], "nothing"),
    ];
    for (args, expected) in cases {
        let out = pairs(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(expected), "{args:?}: {err}");
    }
}
