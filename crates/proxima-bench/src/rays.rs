//! `proxima bench MESH --query rays [--queries N] [--seed S] [--threads T] [--json]`:
//! first-hit rays of the BENCHMARKS.md `rays` set, cast by linear search,
//! the 4-wide tree, the ray tree one ray at a time and in batches, and
//! parry3d (when asked, [`Peers`]), on the same rays; every proxima answer
//! must be linear search's.

use crate::args::Peers;
use crate::input::load_mesh;
use crate::report::{Record, bar, linear_budget, linear_queries, print_notes, print_table, timed};
use anyhow::{Context, bail};
use proxima::prelude::*;
use rayon::prelude::*;
use serde_json::json;
use std::path::Path;

/// What `bench --query rays` is given.
pub struct Options<'a> {
    /// The mesh file.
    pub mesh: &'a Path,
    /// Rays of the generated set.
    pub rays: usize,
    /// Their seed.
    pub seed: u64,
    /// Worker threads of the casting loops.
    pub threads: usize,
    /// One JSON object instead of a table.
    pub json: bool,
}

/// A ray's answer as compared: `t` and input index of the triangle hit.
type Answer = Option<(f32, u32)>;

fn answer(hit: Result<Option<RayHit>, proxima::RayError>) -> anyhow::Result<Answer> {
    Ok(hit?.map(|h| (h.t, h.primitive)))
}

/// Runs `proxima bench --query rays`, with the rows of `peers`.
pub fn run(options: &Options<'_>, peers: Peers) -> anyhow::Result<()> {
    let mesh = load_mesh(options.mesh)?;
    if mesh.face_count() == 0 {
        bail!("{}: the mesh has no faces to hit", options.mesh.display());
    }
    let rays = proxima::sample::rays_at_box(&mesh.bounds(), options.rays, options.seed);
    if rays.is_empty() {
        bail!(
            "{}: no rays (the mesh's bounding box is a point)",
            options.mesh.display()
        );
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()
        .context("thread pool")?;
    let records = pool
        .install(|| measure(&mesh, &rays, !options.json, peers))
        .with_context(|| options.mesh.display().to_string())?;
    if options.json {
        let results: Vec<_> = records
            .iter()
            .map(|r| {
                json!({
                    "method": r.method, "build_seconds": r.build_seconds, "rays": r.queries,
                    "seconds": r.seconds, "rays_per_second": r.queries_per_second(), "agree": r.agree,
                    "capped": r.queries < rays.len(), "note": r.note,
                })
            })
            .collect();
        let out = json!({
            "mesh": options.mesh.display().to_string(), "triangles": mesh.triangle_count(), "query": "rays",
            "threads": options.threads, "results": results,
        });
        outln!("{out:#}");
    } else {
        outln!(
            "{}: {} triangles; {} rays of the BENCHMARKS rays set; {} thread(s)",
            options.mesh.display(),
            mesh.triangle_count(),
            rays.len(),
            options.threads
        );
        print_table(&records)?;
        print_notes(&records)?;
        if let Some(peer) = records.iter().find(|r| r.method == "parry3d") {
            for r in records.iter().filter(|r| r.method.starts_with("ray-tree")) {
                outln!(
                    "{} casts {:.2}x as many rays per second as parry3d",
                    r.method,
                    r.queries_per_second() / peer.queries_per_second()
                );
            }
        }
    }
    if let Some(r) = records.iter().find(|r| !r.agree && r.method != "parry3d") {
        bail!(
            "{}: {} disagrees with linear search: this is a bug, please report it",
            options.mesh.display(),
            r.method
        );
    }
    if records.iter().any(|r| !r.agree && r.method == "parry3d") {
        eprintln!(
            "proxima: note: {}: parry3d's hits differ from proxima's on some rays (proxima's structures and linear \
             search agree); parry3d's ray/triangle test is not watertight, and rays through shared edges can pass \
             through it",
            options.mesh.display()
        );
    }
    Ok(())
}

/// Every method's row, on the current pool.
fn measure(mesh: &Mesh, rays: &[(Vec3, Vec3)], progress: bool, peers: Peers) -> anyhow::Result<Vec<Record>> {
    let row = |method, build_seconds, queries, seconds, agree| Record {
        primitives: "faces",
        method,
        build_seconds,
        queries,
        seconds,
        agree,
        note: None,
    };
    // The linear scan's budget of triangle tests, as for closest points.
    let n_linear = linear_queries(linear_budget()?, mesh.triangle_count(), rays.len());
    let linear = LinearSearch::new(mesh.triangles());
    let progress_bar = bar(progress, n_linear, "faces linear");
    let (expected, linear_seconds) = timed(|| {
        rays[..n_linear]
            .par_iter()
            .map(|&(o, d)| {
                progress_bar.inc(1);
                answer(linear.first_hit(o, d, 0.0, f32::INFINITY))
            })
            .collect::<anyhow::Result<Vec<Answer>>>()
    });
    progress_bar.finish_and_clear();
    let expected = expected?;
    drop(linear);

    let (wide, wide_build) = timed(|| WideTree::build_set(mesh.triangles(), &BuildConfig::default()));
    let wide = wide?;
    let (wide_answers, wide_seconds) = timed(|| per_ray(&wide, rays));
    drop(wide);
    let (tree, tree_build) = timed(|| RayTree::build(mesh));
    let tree = tree?;
    let (single, single_seconds) = timed(|| per_ray(&tree, rays));
    let (batch, batch_seconds) = timed(|| tree.first_hit_batch(rays, 0.0, f32::INFINITY));
    let batch: Vec<Answer> = batch.into_iter().map(answer).collect::<anyhow::Result<_>>()?;
    let (wide_answers, single) = (wide_answers?, single?);
    // The ray tree against linear search, the others against the ray tree.
    let single_agrees = single[..n_linear] == expected[..];
    let n = rays.len();
    let records = vec![
        row("linear", 0.0, n_linear, linear_seconds, single_agrees),
        row("tree-wide", wide_build, n, wide_seconds, wide_answers == single),
        row("ray-tree", tree_build, n, single_seconds, single_agrees),
        row("ray-tree-batch", tree_build, n, batch_seconds, batch == single),
    ];
    let peer = match peers {
        Peers::None => None,
        #[cfg(feature = "peers")]
        Peers::Parry3d => {
            // The peer may take ten times our slowest row, and at least 10 s.
            let slowest = [wide_seconds, single_seconds, batch_seconds]
                .into_iter()
                .fold(0.0, f64::max);
            let budget = std::time::Duration::from_secs_f64((10.0 * slowest).max(10.0));
            crate::peers::parry3d_rays(mesh, rays, &single, budget)
        }
    };
    Ok(records.into_iter().chain(peer).collect())
}

/// `first_hit` of every ray, one at a time, on the current pool.
fn per_ray<S: RayQuery<Triangle> + Sync>(structure: &S, rays: &[(Vec3, Vec3)]) -> anyhow::Result<Vec<Answer>> {
    rays.par_iter()
        .map(|&(o, d)| answer(structure.first_hit(o, d, 0.0, f32::INFINITY)))
        .collect()
}
