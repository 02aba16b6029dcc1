//! `proxima knn` and `proxima radius` against brute force over every point
//! (the order: f32 squared distances, ties by index; radius membership in
//! f64, exact for the small integer coordinates used here).

mod common;

use common::temp_dir;
use std::process::Command;

fn run(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_proxima")).args(args).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

fn d2(p: [f32; 3], q: [f32; 3]) -> f32 {
    (0..3).map(|k| (p[k] - q[k]) * (p[k] - q[k])).sum()
}

#[test]
fn knn_and_radius_match_brute_force_on_a_lattice() {
    let dir = temp_dir("points_cli");
    // A 6 x 6 x 6 lattice: many neighbours tie, many lie exactly on the spheres.
    let points: Vec<[f32; 3]> = (0..216)
        .map(|i| [(i % 6) as f32, (i / 6 % 6) as f32, (i / 36) as f32])
        .collect();
    let queries: Vec<[f32; 3]> = vec![[0.0, 0.0, 0.0], [2.5, 2.0, 3.0], [5.0, 5.0, 5.0], [-1.0, 2.0, 2.0]];
    let write = |name: &str, pts: &[[f32; 3]]| {
        let text: String = pts.iter().map(|p| format!("{} {} {}\n", p[0], p[1], p[2])).collect();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    let (cloud, query_file) = (write("cloud.xyz", &points), write("q.xyz", &queries));
    let sorted = |q: [f32; 3], keep: &dyn Fn(usize) -> bool| {
        let mut all: Vec<(f32, usize)> = (0..points.len())
            .filter(|&i| keep(i))
            .map(|i| (d2(points[i], q), i))
            .collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        all.into_iter().map(|(_, i)| i).collect::<Vec<_>>()
    };
    let knn = run(&["knn", &cloud, "--queries", &query_file, "-k", "7"]);
    let mut lines = knn.lines();
    assert_eq!(lines.next(), Some("query,rank,index,distance"));
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(String::from).collect()).collect();
    for (q, &query) in queries.iter().enumerate() {
        let expected = sorted(query, &|_| true);
        let got: Vec<usize> = rows
            .iter()
            .filter(|r| r[0] == q.to_string())
            .map(|r| r[2].parse().unwrap())
            .collect();
        assert_eq!(got, expected[..7], "query {q}");
    }
    for (r, max) in [("1", None), ("2", None), ("2", Some(3))] {
        let mut args = vec!["radius", &cloud, "--queries", &query_file, "--radius", r];
        let max_text = max.map(|m: usize| m.to_string());
        if let Some(m) = &max_text {
            args.extend(["--max", m.as_str()]);
        }
        let out = run(&args);
        let rows: Vec<Vec<String>> = out
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(String::from).collect())
            .collect();
        let radius: f32 = r.parse().unwrap();
        for (q, &query) in queries.iter().enumerate() {
            let mut expected = sorted(query, &|i| d2(points[i], query) <= radius * radius);
            expected.truncate(max.unwrap_or(usize::MAX));
            let got: Vec<usize> = rows
                .iter()
                .filter(|row| row[0] == q.to_string())
                .map(|row| row[1].parse().unwrap())
                .collect();
            assert_eq!(got, expected, "r={r} max={max:?} query {q}");
        }
    }
}
