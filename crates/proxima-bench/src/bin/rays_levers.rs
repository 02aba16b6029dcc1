//! What each lever of the ray traversal gives, measured in one run on one
//! thread: the 4-wide tree (median and SAH builds) against the 8-wide
//! [`RayTree`] (with and without AVX2), one ray at a time and as a batch
//! (`first_hit_batch`: rays in Morton order), on the same rays.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin rays_levers -- MESH [RAYS] [--rays N] [--rounds R] [--only TEXT]
//! ```
//!
//! `MESH` as [`load_named`] takes it (a file, `ico1m`, `ico100k`); `RAYS` a
//! rays file ([`proxima::io::load_rays`]), else `N` rays (default 200,000) of
//! the BENCHMARKS.md `rays` set: origins on a sphere of radius 0.75 × the
//! box diagonal around the box centre, aimed at uniform points of the box.
//! Rounds alternate between the variants, the best of `R` (default 5) kept;
//! every variant's answers must equal the first's. Prints one markdown
//! table: rays/s, ratio to the first variant, nodes and triangles tested per
//! ray, build seconds.

use proxima::prelude::*;
use proxima::{BuildConfig, RayTree};
use proxima_bench::load_named;
use std::time::Instant;

type Caster<'a> = Box<dyn Fn(&[(Vec3, Vec3)]) -> Vec<Option<(f32, u32)>> + 'a>;

fn cast_all<T: RayIntersect, S: RayQuery<T>>(tree: &S, rays: &[(Vec3, Vec3)]) -> Vec<Option<(f32, u32)>> {
    rays.iter()
        .map(|&(o, d)| {
            tree.first_hit(o, d, 0.0, f32::INFINITY)
                .expect("valid ray")
                .map(|h| (h.t, h.primitive))
        })
        .collect()
}

/// The batch call: rays in Morton order of their point nearest the centre.
fn batch<T: RayIntersect, S: RayQuery<T> + Sync>(tree: &S, rays: &[(Vec3, Vec3)]) -> Vec<Option<(f32, u32)>> {
    tree.first_hit_batch(rays, 0.0, f32::INFINITY)
        .into_iter()
        .map(|r| r.expect("valid ray").map(|h| (h.t, h.primitive)))
        .collect()
}

fn stats<T: RayIntersect, S: RayQuery<T>>(tree: &S, rays: &[(Vec3, Vec3)]) -> (f64, f64) {
    let (mut nodes, mut primitives) = (0u64, 0u64);
    for &(o, d) in rays {
        let (_, s) = tree.first_hit_with_stats(o, d, 0.0, f32::INFINITY).expect("valid ray");
        nodes += s.nodes_visited;
        primitives += s.primitives_tested;
    }
    let n = rays.len() as f64;
    (nodes as f64 / n, primitives as f64 / n)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .map(|i| args[i + 1].parse::<usize>().expect(flag))
    };
    let positional: Vec<&String> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| !a.starts_with("--") && (*i == 0 || !args[i - 1].starts_with("--")))
        .map(|(_, a)| a)
        .collect();
    let mesh = load_named(positional.first().expect("a mesh")).expect("mesh");
    let rays = match positional.get(1) {
        Some(path) => {
            proxima::io::load_rays(std::path::Path::new(path.as_str()), &Default::default()).expect("rays file")
        }
        None => proxima::sample::rays_at_box(&mesh.bounds(), value("--rays").unwrap_or(200_000), 1),
    };
    let rays: Vec<(Vec3, Vec3)> = rays.into_iter().map(|(o, d)| (o, d.normalize())).collect();
    let rounds = value("--rounds").unwrap_or(5);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    pool.install(|| {
        let timed = |f: &dyn Fn()| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        };
        let mut built: Vec<(&str, f64, Caster, (f64, f64))> = Vec::new();
        let t = Instant::now();
        let wide = WideTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
        let b = t.elapsed().as_secs_f64();
        let s = stats(&wide, &rays[..20_000.min(rays.len())]);
        let batched = wide.clone();
        built.push(("wide4 median", b, Box::new(move |r| cast_all(&wide, r)), s));
        built.push(("wide4 median, batch", b, Box::new(move |r| batch(&batched, r)), s));
        let t = Instant::now();
        let wide = WideTree::build_set(mesh.triangles(), &BuildConfig::fast_queries()).unwrap();
        let b = t.elapsed().as_secs_f64();
        let s = stats(&wide, &rays[..20_000.min(rays.len())]);
        built.push(("wide4 SAH", b, Box::new(move |r| cast_all(&wide, r)), s));
        let t = Instant::now();
        let ray = RayTree::build(&mesh).unwrap();
        let b = t.elapsed().as_secs_f64();
        let s = stats(&ray, &rays[..20_000.min(rays.len())]);
        let leaves: Vec<usize> = (0..ray.node_count())
            .flat_map(|n| (0..8).map(move |l| (n, l)))
            .filter_map(|(n, l)| match ray.child(n, l) {
                proxima::ray_tree::RayChild::Leaf(r) => Some(r.len()),
                _ => None,
            })
            .collect();
        println!(
            "ray tree: {} nodes, depth {}, {} leaves of {:.2} triangles on average, {:.1} MB",
            ray.node_count(),
            ray.depth(),
            leaves.len(),
            leaves.iter().sum::<usize>() as f64 / leaves.len() as f64,
            ray.memory_bytes() as f64 / 1e6
        );
        let batched = ray.clone();
        built.push((
            "ray8 SAH, AVX2, batch (interleaved)",
            b,
            Box::new(move |r| batch(&batched, r)),
            s,
        ));
        let mut portable = ray.clone();
        portable.set_avx2(false);
        built.push(("ray8 SAH, AVX2", b, Box::new(move |r| cast_all(&ray, r)), s));
        built.push(("ray8 SAH, portable", b, Box::new(move |r| cast_all(&portable, r)), s));
        // `--only TEXT`: just the variants whose name holds TEXT (to profile one).
        if let Some(i) = args.iter().position(|a| a == "--only") {
            built.retain(|(name, ..)| name.contains(args[i + 1].as_str()));
        }
        let reference = (built[0].2)(&rays);
        let mut best = vec![f64::INFINITY; built.len()];
        for _ in 0..rounds {
            for (k, (name, _, cast, _)) in built.iter().enumerate() {
                let seconds = timed(&|| {
                    std::hint::black_box(cast(&rays));
                });
                best[k] = best[k].min(seconds);
                let answers = cast(&rays);
                assert_eq!(answers.len(), reference.len());
                let differ = answers.iter().zip(&reference).filter(|(a, b)| a != b).count();
                assert!(differ == 0, "{name}: {differ} answers differ from the first variant's");
            }
        }
        println!(
            "{} triangles, {} rays, hits {}",
            mesh.triangle_count(),
            rays.len(),
            reference.iter().flatten().count()
        );
        println!("| variant | rays/s | vs first | nodes/ray | triangles/ray | build s |");
        println!("|---|---|---|---|---|---|");
        for (k, (name, build, _, (nodes, tris))) in built.iter().enumerate() {
            let rate = rays.len() as f64 / best[k];
            println!(
                "| {name} | {rate:.0} | {:.2}x | {nodes:.1} | {tris:.1} | {build:.2} |",
                best[0] / best[k]
            );
        }
    });
}
