//! The sphere tree against the AABB tree it shares its hierarchy with, in one
//! run, single thread.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin spheres -- [MESH|ico1m|ico100k ...] [--queries N] [--leaf N] [--sah]
//! ```
//!
//! For each mesh: build time of both trees on one thread (best of 3; the
//! sphere tree's includes the AABB build whose topology it takes), then for
//! the `near` and `uniform` query sets the nodes and triangles visited per
//! closest-face query and the queries per second of each tree, timed in
//! interleaved rounds (best of 5) so that load from other processes hits both
//! alike. The answers of the two trees are checked equal.

use proxima::build::SplitMethod;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, ClosestHit, Mesh, SphereTree, Vec3};
use proxima_bench::load_named;
use std::time::Instant;

fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let v = f();
    (v, start.elapsed().as_secs_f64())
}

/// Mean nodes and primitives visited per query.
fn visits(points: &[Vec3], query: impl Fn(Vec3) -> proxima::QueryStats) -> (f64, f64) {
    let (nodes, primitives) = points.iter().fold((0, 0), |acc, &p| {
        let s = query(p);
        (acc.0 + s.nodes_visited, acc.1 + s.primitives_tested)
    });
    let n = points.len().max(1) as f64;
    (nodes as f64 / n, primitives as f64 / n)
}

fn compare(name: &str, mesh: &Mesh, n_queries: usize, config: &BuildConfig) {
    println!("\n## {name}: {} triangles, {config:?}", mesh.triangle_count());
    let triangles = mesh.triangles();
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let (mut t_boxes, mut t_spheres) = (f64::INFINITY, f64::INFINITY);
    let (mut boxes, mut spheres) = (None, None);
    for _ in 0..3 {
        let (t, s) = timed(|| one_thread.install(|| AabbTree::build_set(triangles.clone(), config).unwrap()));
        (boxes, t_boxes) = (Some(t), t_boxes.min(s));
        let (t, s) = timed(|| one_thread.install(|| SphereTree::build_set(triangles.clone(), config).unwrap()));
        (spheres, t_spheres) = (Some(t), t_spheres.min(s));
    }
    let (boxes, spheres) = (boxes.unwrap(), spheres.unwrap());
    println!(
        "build, 1 thread: AABB tree {t_boxes:.3} s, sphere tree {t_spheres:.3} s ({:.2}x the AABB time)",
        t_spheres / t_boxes
    );
    println!(
        "| query set | AABB nodes/query | AABB tris/query | sphere nodes/query | sphere tris/query | AABB q/s | sphere q/s | sphere/AABB |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (set, points) in [
        ("near", proxima::sample::near_surface(mesh, n_queries, 0.01, 1)),
        ("uniform", proxima::sample::uniform_in_box(mesh, n_queries, 2)),
    ] {
        let (mut tb, mut ts) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..5 {
            let (a, t) = timed(|| {
                points
                    .iter()
                    .map(|&p| boxes.closest(p))
                    .collect::<Vec<Option<ClosestHit>>>()
            });
            tb = tb.min(t);
            let (b, t) = timed(|| {
                points
                    .iter()
                    .map(|&p| spheres.closest(p))
                    .collect::<Vec<Option<ClosestHit>>>()
            });
            ts = ts.min(t);
            assert_eq!(a, b, "the sphere tree and the AABB tree disagree");
        }
        let (bn, bp) = visits(&points, |p| boxes.closest_with_stats(p).1);
        let (sn, sp) = visits(&points, |p| spheres.closest_with_stats(p).1);
        let n = points.len() as f64;
        println!(
            "| {set} | {bn:.1} | {bp:.1} | {sn:.1} | {sp:.1} | {:.0} | {:.0} | {:.2}x |",
            n / tb,
            n / ts,
            tb / ts
        );
    }
}

fn main() {
    let mut names = Vec::new();
    let mut n_queries = 20_000;
    let mut config = BuildConfig::default();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut number = |flag: &str| {
            args.next()
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("{flag} N"))
        };
        match a.as_str() {
            "--queries" => n_queries = number("--queries"),
            "--leaf" => config.min_size = number("--leaf") as u32,
            "--sah" => config.split = SplitMethod::BinnedSah,
            _ => names.push(a),
        }
    }
    if names.is_empty() {
        names = vec!["nefertiti.obj".into(), "dragon_vrip.ply.gz".into()];
    }
    for name in names {
        match load_named(&name) {
            Ok(mesh) => compare(&name, &mesh, n_queries, &config),
            Err(e) => eprintln!("{name}: {e}"),
        }
    }
}
