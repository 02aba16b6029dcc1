//! proxima against parry3d and brute force, in one run, single thread.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin compare -- [MESH|ico1m|ico100k ...] [--queries N] [--linear N]
//! ```
//!
//! For each mesh: tree build time (best of 3) of both libraries; closest-face
//! queries per second on the `near` and `uniform` query sets, per query in
//! input order and as a Morton-ordered batch; the largest distance difference
//! to parry3d relative to the bbox diagonal; and with `--linear N`, the
//! tree/linear ratio on N queries. Ratios are what to compare across runs: the
//! machine is shared and noisy.

use proxima::bvh::BatchOptions;
use proxima::{AabbTree, BuildConfig, LinearSearch, Mesh};
use proxima_bench::{load_named, parry_distance, parry_trimesh};
use std::time::Instant;

fn best_of<T>(runs: usize, mut f: impl FnMut() -> T) -> (T, f64) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..runs {
        let start = Instant::now();
        let v = f();
        best = best.min(start.elapsed().as_secs_f64());
        out = Some(v);
    }
    (out.expect("at least one run"), best)
}

fn rate(n: usize, seconds: f64) -> f64 {
    n as f64 / seconds
}

fn compare(name: &str, mesh: &Mesh, n_queries: usize, n_linear: usize, config: &BuildConfig) {
    let diagonal = mesh.bounds().diagonal();
    println!(
        "\n## {name}: {} triangles, bbox diagonal {diagonal}",
        mesh.triangle_count()
    );
    let triangles = mesh.triangles();
    let (tree, ours_build) = best_of(3, || AabbTree::build_set(triangles.clone(), config).unwrap());
    let (trimesh, parry_build) = best_of(3, || parry_trimesh(mesh));
    println!(
        "build: proxima {:.3} s, parry3d {:.3} s, ratio {:.2}x",
        ours_build,
        parry_build,
        parry_build / ours_build
    );
    println!(
        "| query set | proxima q/s | proxima batch q/s | parry3d q/s | ours/parry | batch/parry | max |d - d_parry| / diag |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (set, points) in [
        ("near", proxima::sample::near_surface(mesh, n_queries, 0.01, 1)),
        ("uniform", proxima::sample::uniform_in_box(mesh, n_queries, 2)),
    ] {
        let (ours, t_ours) = best_of(3, || {
            points
                .iter()
                .map(|&p| tree.closest(p).unwrap().distance)
                .collect::<Vec<_>>()
        });
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let (_, t_batch) = best_of(3, || {
            pool.install(|| tree.closest_batch_with(&points, BatchOptions { reorder: true }))
        });
        let (theirs, t_parry) = best_of(3, || {
            points.iter().map(|&p| parry_distance(&trimesh, p)).collect::<Vec<_>>()
        });
        let worst = ours
            .iter()
            .zip(&theirs)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max)
            / diagonal;
        let visits: (u64, u64) = points.iter().fold((0, 0), |acc, &p| {
            let s = tree.closest_with_stats(p).1;
            (acc.0 + s.nodes_visited, acc.1 + s.primitives_tested)
        });
        println!(
            "{set}: {:.1} nodes and {:.1} primitives visited per query",
            visits.0 as f64 / points.len() as f64,
            visits.1 as f64 / points.len() as f64
        );
        println!(
            "| {set} | {:.0} | {:.0} | {:.0} | {:.2}x | {:.2}x | {:.1e} |",
            rate(points.len(), t_ours),
            rate(points.len(), t_batch),
            rate(points.len(), t_parry),
            t_parry / t_ours,
            t_parry / t_batch,
            worst
        );
    }
    if n_linear > 0 {
        let points = proxima::sample::near_surface(mesh, n_linear, 0.01, 3);
        let linear = LinearSearch::new(triangles);
        let (a, t_linear) = best_of(1, || {
            points
                .iter()
                .map(|&p| linear.closest(p).unwrap().distance)
                .collect::<Vec<_>>()
        });
        let (b, t_tree) = best_of(3, || {
            points
                .iter()
                .map(|&p| tree.closest(p).unwrap().distance)
                .collect::<Vec<_>>()
        });
        assert_eq!(a, b, "tree and linear search disagree");
        println!(
            "tree/linear on {} near queries: {:.0}x (linear {:.0} q/s, tree {:.0} q/s)",
            points.len(),
            t_linear / t_tree,
            rate(points.len(), t_linear),
            rate(points.len(), t_tree)
        );
    }
}

fn main() {
    let mut names = Vec::new();
    let mut n_queries = 20_000;
    let mut n_linear = 0;
    let mut config = BuildConfig::default();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--queries" => n_queries = args.next().and_then(|v| v.parse().ok()).expect("--queries N"),
            "--leaf" => config.min_size = args.next().and_then(|v| v.parse().ok()).expect("--leaf N"),
            "--linear" => n_linear = args.next().and_then(|v| v.parse().ok()).expect("--linear N"),
            _ => names.push(a),
        }
    }
    if names.is_empty() {
        names = vec!["dragon_vrip.ply.gz".into(), "ico1m".into()];
    }
    for name in names {
        match load_named(&name) {
            Ok(mesh) => compare(&name, &mesh, n_queries, n_linear, &config),
            Err(e) => eprintln!("{name}: {e}"),
        }
    }
}
