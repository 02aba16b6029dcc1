//! proxima against parry3d and brute force, in one run, single thread.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin compare -- [MESH|ico1m|ico100k ...] [--queries N] [--linear N] [--leaf N] [--sah] [--wide] [--rays] [--aimed N]
//! ```
//!
//! For each mesh: tree build time of both libraries (best of 5 alternating
//! rounds, so that both reach the allocator's steady state; ours on one
//! thread and on all threads); closest-face queries per second on the `near`
//! and `uniform` query sets, per query in input order and as a Morton-ordered
//! batch on one thread; the largest distance difference to parry3d relative to
//! the bbox diagonal; and with `--linear N`, the tree/linear ratio on N
//! queries. The two libraries are timed in interleaved rounds and the best
//! round of each is kept, so a burst of load from another process hits both
//! alike. Each timing follows an untimed run of the same queries, so that
//! each structure is measured warm rather than after the others evicted it. Compare ratios across runs, not absolute figures: the machine is
//! shared and noisy.
//!
//! `--rays` compares ray casting instead (see [`compare_rays`]).
//!
//! `--wide` also times the 4-wide tree ([`WideTree`], made from the same binary
//! tree) per query, in the same interleaved rounds, and checks that its answers
//! equal the binary tree's. It also prints, for the wide tree per query and in
//! a batch, the median over the rounds of each round's own ratio to parry3d:
//! steadier than the ratio of best times when the load drifts between rounds.

use parry3d::shape::TriMesh;
use proxima::build::SplitMethod;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, LinearSearch, Mesh};
use proxima_bench::{Ray, aimed_rays, load_named, parry_distance, parry_input, parry_ray, parry_trimesh, ray_sets};
use std::time::Instant;

/// Runs `f`, returning its value and its time in seconds.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let v = f();
    (v, start.elapsed().as_secs_f64())
}

/// Runs `f` once untimed, then times a second run: every structure is
/// measured warm, as in a program that queries it over and over, and not
/// cold from the rounds of the other structures in between.
fn warm<T>(f: impl Fn() -> T) -> (T, f64) {
    std::hint::black_box(f());
    timed(f)
}

/// The median of `values` (sorted in place).
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn rate(n: usize, seconds: f64) -> f64 {
    n as f64 / seconds
}

fn compare(name: &str, mesh: &Mesh, n_queries: usize, n_linear: usize, config: &BuildConfig, with_wide: bool) {
    let diagonal = mesh.bounds().diagonal();
    println!(
        "\n## {name}: {} triangles, bbox diagonal {diagonal}, {config:?}",
        mesh.triangle_count()
    );
    let triangles = mesh.triangles();
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let (mut t_build, mut t_build_all, mut t_parry_build) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let (mut tree, mut trimesh) = (None, None);
    let (mut wide, mut t_wide_build, mut t_collapse) = (None, f64::INFINITY, f64::INFINITY);
    // Only the build calls are timed: each library's input (our triangles,
    // parry3d's vertices and index triples) is made before, untimed.
    for _ in 0..5 {
        let input = triangles.clone();
        let (t, s) = timed(|| one_thread.install(|| AabbTree::build_set(input, config).unwrap()));
        if with_wide {
            // The wide tree as its own build makes it, on one thread too:
            // the binary build (its leaves as large as the wide leaves it
            // merges) and the collapse.
            let input = triangles.clone();
            let (w, s) = timed(|| one_thread.install(|| WideTree::build_set(input, config).unwrap()));
            (wide, t_wide_build) = (Some(w), t_wide_build.min(s));
            let binary = t.clone();
            t_collapse = t_collapse.min(timed(|| one_thread.install(|| WideTree::from_tree(binary))).1);
        }
        (tree, t_build) = (Some(t), t_build.min(s));
        let input = triangles.clone();
        t_build_all = t_build_all.min(timed(|| AabbTree::build_set(input, config).unwrap()).1);
        let (vertices, indices) = parry_input(mesh);
        let (m, s) = timed(|| TriMesh::new(vertices, indices).expect("parry3d accepts the mesh"));
        (trimesh, t_parry_build) = (Some(m), t_parry_build.min(s));
    }
    let (tree, trimesh) = (tree.unwrap(), trimesh.unwrap());
    if let Some(wide) = &wide {
        println!(
            "wide tree: {} wide nodes (binary {}), depth {} (binary {}), the binary tree collapsed in {t_collapse:.3} s on 1 thread, best of 5, {:.1} MB on top of the binary tree's {:.1} MB; {:.1} MB of this process on huge pages",
            wide.node_count(),
            tree.node_count(),
            wide.depth(),
            tree.depth(),
            wide.extra_memory_bytes() as f64 / 1e6,
            tree.stats().memory_bytes as f64 / 1e6,
            proxima::memory::huge_page_bytes().unwrap_or(0) as f64 / 1e6,
        );
    }
    let mut wide_rows = Vec::new();
    let mut round_rows = Vec::new();
    println!(
        "build: proxima {t_build:.3} s on 1 thread ({:.2}x parry3d), {t_build_all:.3} s on all threads ({:.2}x); parry3d {t_parry_build:.3} s",
        t_parry_build / t_build,
        t_parry_build / t_build_all,
    );
    if with_wide {
        println!(
            "wide tree build (binary build to leaves of up to 8, and collapse), 1 thread: {t_wide_build:.3} s ({:.2}x parry3d); binary build of this config and collapse: {:.3} s ({:.2}x)",
            t_parry_build / t_wide_build,
            t_build + t_collapse,
            t_parry_build / (t_build + t_collapse)
        );
    }
    println!(
        "| query set | nodes/query | primitives/query | proxima q/s | proxima batch q/s | parry3d q/s | ours/parry | batch/parry | max diff / diag |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (set, points) in [
        ("near", proxima::sample::near_surface(mesh, n_queries, 0.01, 1)),
        ("uniform", proxima::sample::uniform_in_box(mesh, n_queries, 2)),
    ] {
        let (mut t_ours, mut t_batch, mut t_parry) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        let (mut t_wide, mut t_wide_batch, mut t_wide_all) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        // Each round's own ratios (to parry3d per query and in a batch; the
        // batch on all threads to the batch on one), whose median is steadier
        // than the ratio of best times when the machine's load drifts.
        let mut round_ratios = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..5 {
            let (mut round_wide, mut round_batch) = (f64::NAN, f64::NAN);
            let (o, t) = warm(|| {
                points
                    .iter()
                    .map(|&p| tree.closest(p).unwrap().distance)
                    .collect::<Vec<_>>()
            });
            (ours, t_ours) = (o, t_ours.min(t));
            let batch = || one_thread.install(|| tree.closest_batch_with(&points, BatchOptions::default()));
            t_batch = t_batch.min(warm(batch).1);
            if let Some(wide) = &wide {
                let (w, t) = warm(|| {
                    points
                        .iter()
                        .map(|&p| wide.closest(p).unwrap().distance)
                        .collect::<Vec<_>>()
                });
                assert_eq!(w, ours, "wide and binary trees disagree");
                t_wide = t_wide.min(t);
                round_wide = t;
                // The batch on one thread, in Morton order.
                let (b, t) = warm(|| one_thread.install(|| wide.closest_batch_with(&points, BatchOptions::default())));
                assert!(b.iter().zip(&ours).all(|(h, &d)| h.unwrap().distance == d));
                t_wide_batch = t_wide_batch.min(t);
                round_batch = t;
                let t = warm(|| wide.closest_batch(&points)).1;
                t_wide_all = t_wide_all.min(t);
                round_ratios.2.push(round_batch / t);
            }
            let (o, t) = warm(|| points.iter().map(|&p| parry_distance(&trimesh, p)).collect::<Vec<_>>());
            (theirs, t_parry) = (o, t_parry.min(t));
            round_ratios.0.push(t / round_wide);
            round_ratios.1.push(t / round_batch);
        }
        let worst = ours
            .iter()
            .zip(&theirs)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max)
            / diagonal;
        let (nodes, prims) = points.iter().fold((0, 0), |acc, &p| {
            let s = tree.closest_with_stats(p).1;
            (acc.0 + s.nodes_visited, acc.1 + s.primitives_tested)
        });
        let n = points.len();
        if let Some(wide) = &wide {
            let (nodes, prims) = points.iter().fold((0, 0), |acc, &p| {
                let s = wide.closest_with_stats(p).1;
                (acc.0 + s.nodes_visited, acc.1 + s.primitives_tested)
            });
            round_rows.push(format!(
                "| {set} | {:.2}x | {:.2}x | {:.2}x |",
                median(&mut round_ratios.0),
                median(&mut round_ratios.1),
                median(&mut round_ratios.2)
            ));
            wide_rows.push(format!(
                "| {set} | {:.1} | {:.1} | {:.1} | {:.0} | {:.0} | {:.0} | {:.2}x | {:.2}x | {:.0} | {:.2}x | {:.2}x |",
                nodes as f64 / n as f64,
                4.0 * nodes as f64 / n as f64,
                prims as f64 / n as f64,
                rate(n, t_ours),
                rate(n, t_wide),
                rate(n, t_parry),
                t_parry / t_wide,
                t_ours / t_wide,
                rate(n, t_wide_batch),
                t_parry / t_wide_batch,
                t_wide_batch / t_wide_all,
            ));
        }
        println!(
            "| {set} | {:.1} | {:.1} | {:.0} | {:.0} | {:.0} | {:.2}x | {:.2}x | {worst:.1e} |",
            nodes as f64 / n as f64,
            prims as f64 / n as f64,
            rate(n, t_ours),
            rate(n, t_batch),
            rate(n, t_parry),
            t_parry / t_ours,
            t_parry / t_batch,
        );
    }
    if !wide_rows.is_empty() {
        println!("\nwide tree, per query in input order (same rounds as above):");
        println!(
            "| query set | wide nodes/query | boxes/query | primitives/query | binary q/s | wide q/s | parry3d q/s | wide/parry | wide/binary | wide batch q/s | wide batch/parry | batch all threads/1 |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
        for row in wide_rows {
            println!("{row}");
        }
        println!("\nwide tree, median over the 5 rounds of each round's own ratio:");
        println!("| query set | wide/parry | wide batch/parry | batch all threads/1 |");
        println!("|---|---|---|---|");
        for row in round_rows {
            println!("{row}");
        }
    }
    if n_linear > 0 {
        let points = proxima::sample::near_surface(mesh, n_linear, 0.01, 3);
        let linear = LinearSearch::new(triangles);
        let (a, t_linear) = timed(|| {
            points
                .iter()
                .map(|&p| linear.closest(p).unwrap().distance)
                .collect::<Vec<_>>()
        });
        let (b, t_tree) = timed(|| {
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

/// Ray casting, single thread, in interleaved rounds (best of 5 kept): rays
/// per second of our first hit (binary tree; the wide tree with `--wide`) and
/// of parry3d's `cast_local_ray` (hollow triangles, first time of impact) on
/// the `outside` and `inside` ray sets of [`ray_sets`], with how often the two
/// disagree (hit against miss, or t off by more than 1e-5 of the diagonal).
/// Then `n_aimed` rays aimed exactly at shared edges and vertices
/// ([`aimed_rays`]): each must hit, and the misses of each library are counted.
fn compare_rays(name: &str, mesh: &Mesh, n_rays: usize, n_aimed: usize, config: &BuildConfig, with_wide: bool) {
    let diagonal = mesh.bounds().diagonal();
    println!(
        "\n## rays, {name}: {} triangles, bbox diagonal {diagonal}, {config:?}",
        mesh.triangle_count()
    );
    let tree = AabbTree::build_set(mesh.triangles(), config).unwrap();
    let trimesh = parry_trimesh(mesh);
    let wide = with_wide.then(|| WideTree::from_tree(tree.clone()));
    let ours = |rays: &[Ray]| -> Vec<Option<f32>> {
        rays.iter()
            .map(|&(o, d)| tree.first_hit(o, d, 0.0, f32::INFINITY).unwrap().map(|h| h.t))
            .collect()
    };
    let theirs = |rays: &[Ray]| -> Vec<Option<f32>> { rays.iter().map(|&r| parry_ray(&trimesh, r)).collect() };
    let wide_hits = |rays: &[Ray]| -> Vec<Option<f32>> {
        let wide = wide.as_ref().unwrap();
        rays.iter()
            .map(|&(o, d)| wide.first_hit(o, d, 0.0, f32::INFINITY).unwrap().map(|h| h.t))
            .collect()
    };
    println!(
        "| ray set | hits | nodes/ray | triangles/ray | proxima rays/s | wide rays/s | parry3d rays/s | ours/parry | wide/parry | disagree |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (set, rays) in ray_sets(mesh, n_rays, 5) {
        let (mut t_ours, mut t_wide, mut t_parry) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for _ in 0..5 {
            let (x, t) = warm(|| ours(&rays));
            (a, t_ours) = (x, t_ours.min(t));
            if wide.is_some() {
                let (w, t) = warm(|| wide_hits(&rays));
                assert_eq!(w, a, "wide and binary trees disagree");
                t_wide = t_wide.min(t);
            }
            let (y, t) = warm(|| theirs(&rays));
            (b, t_parry) = (y, t_parry.min(t));
        }
        let disagree = a
            .iter()
            .zip(&b)
            .filter(|(x, y)| match (x, y) {
                (Some(x), Some(y)) => (x - y).abs() > 1e-5 * diagonal,
                (None, None) => false,
                _ => true,
            })
            .count();
        let (nodes, prims) = rays.iter().fold((0, 0), |acc, &(o, d)| {
            let s = tree.first_hit_with_stats(o, d, 0.0, f32::INFINITY).unwrap().1;
            (acc.0 + s.nodes_visited, acc.1 + s.primitives_tested)
        });
        let n = rays.len();
        let wide_cells = if wide.is_some() {
            (format!("{:.0}", rate(n, t_wide)), format!("{:.2}x", t_parry / t_wide))
        } else {
            ("-".into(), "-".into())
        };
        println!(
            "| {set} | {:.1}% | {:.1} | {:.1} | {:.0} | {} | {:.0} | {:.2}x | {} | {disagree} |",
            100.0 * a.iter().flatten().count() as f64 / n as f64,
            nodes as f64 / n as f64,
            prims as f64 / n as f64,
            rate(n, t_ours),
            wide_cells.0,
            rate(n, t_parry),
            t_parry / t_ours,
            wide_cells.1,
        );
    }
    if n_aimed > 0 {
        let rays = aimed_rays(mesh, n_aimed, 6);
        let (a, t_ours) = timed(|| ours(&rays));
        let (b, t_parry) = timed(|| theirs(&rays));
        let misses = |hits: &[Option<f32>]| hits.iter().filter(|h| h.is_none()).count();
        println!(
            "aimed at edge midpoints and vertices: {} rays, misses: proxima {}, parry3d {} ({:.0} and {:.0} rays/s)",
            rays.len(),
            misses(&a),
            misses(&b),
            rate(rays.len(), t_ours),
            rate(rays.len(), t_parry),
        );
        if wide.is_some() {
            assert_eq!(wide_hits(&rays), a, "wide and binary trees disagree");
        }
    }
}

fn main() {
    let mut names = Vec::new();
    let mut n_queries = 20_000;
    let mut n_linear = 0;
    let mut config = BuildConfig::default();
    let mut with_wide = false;
    let mut rays = false;
    let mut n_aimed = 1_000_000;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut number = |flag: &str| {
            args.next()
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("{flag} N"))
        };
        match a.as_str() {
            "--queries" => n_queries = number("--queries"),
            "--linear" => n_linear = number("--linear"),
            "--leaf" => config.min_size = number("--leaf") as u32,
            "--sah" => config.split = SplitMethod::BinnedSah,
            "--median" => config.split = SplitMethod::Median,
            "--wide" => with_wide = true,
            "--rays" => rays = true,
            "--aimed" => n_aimed = number("--aimed"),
            _ => names.push(a),
        }
    }
    if names.is_empty() {
        names = vec!["dragon_vrip.ply.gz".into(), "ico1m".into()];
    }
    for name in names {
        match load_named(&name) {
            Ok(mesh) if rays => compare_rays(&name, &mesh, n_queries, n_aimed, &config, with_wide),
            Ok(mesh) => compare(&name, &mesh, n_queries, n_linear, &config, with_wide),
            Err(e) => eprintln!("{name}: {e}"),
        }
    }
}
