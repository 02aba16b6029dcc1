//! Closest-point benchmarks (`proxima bench MESH [--primitives P]`): linear
//! search against the AABB tree (binary, 4-wide, batch) and the sphere tree
//! on the same queries, per primitive type, with parry3d's row on faces when
//! asked ([`Peers`]).

use crate::args::{Args, Peers, QuerySet};
use crate::input::{load_mesh, note_polygons, read_points, require_primitives};
use crate::report::{Record, bar, linear_budget, linear_queries, print_notes, print_table, timed};
use anyhow::Context;
use proxima::prelude::*;
use rayon::prelude::*;
use serde_json::json;
use std::time::Instant;

/// The kinds measured when none is asked for.
const DEFAULT_KINDS: [PrimitiveKind; 3] = [PrimitiveKind::Vertices, PrimitiveKind::Edges, PrimitiveKind::Faces];

/// Memory per query point of a benchmark, counted generously: the point (12
/// bytes), the distances of the tree, wide tree, sphere tree, linear and peer
/// answers (8 bytes each) and the batch answers (32 bytes).
pub const BYTES_PER_QUERY: u64 = 96;

/// Queries whose work is counted before a structure's row is timed.
const PROBE: usize = 20;

/// The queries a structure's row answers: all, unless its first [`PROBE`]
/// queries tested half the primitives or more each, as a linear scan does
/// (faces all on one point are all at the same distance: a tie that leaves
/// nothing to prune, so each query costs a scan of the mesh). Such a row
/// answers what the linear row answers (`n_linear`), within the same budget
/// of tests, and says so in its note. Counted work, not time: the same input
/// caps the same rows.
fn row_queries<S: NearestQuery<T>, T: MeshPrimitive>(
    structure: &S,
    method: &str,
    points: &[Vec3],
    n_linear: usize,
) -> (usize, Option<String>) {
    let primitives = structure.leaves().len() as u64;
    if n_linear >= points.len() {
        return (points.len(), None);
    }
    let probe = &points[..PROBE.min(points.len())];
    let tested: u64 = probe
        .iter()
        .map(|&p| structure.closest_with_stats(p).1.primitives_tested)
        .sum();
    if 2 * tested < probe.len() as u64 * primitives {
        return (points.len(), None);
    }
    let note = format!(
        "{method} ran on the first {n_linear} queries only, as linear search does: its first {} queries tested {} \
         of the {primitives} primitives each on average (equal distances leave it nothing to prune)",
        probe.len(),
        tested / probe.len() as u64
    );
    (n_linear, Some(note))
}

/// Benchmarks one primitive type: tree build, linear and tree queries, and
/// for faces the peer library.
struct BenchKind<'a> {
    mesh: &'a Mesh,
    points: &'a [Vec3],
    config: &'a BuildConfig,
    progress: bool,
    peers: Peers,
}

impl KindTask for BenchKind<'_> {
    type Output = anyhow::Result<Vec<Record>>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> Self::Output {
        let Self {
            mesh,
            points,
            config,
            progress,
            peers,
        } = self;
        bench_set(set, points, config, progress, |expected, budget| {
            match (peers, T::KIND) {
                #[cfg(feature = "peers")]
                (Peers::Parry3d, PrimitiveKind::Faces) => crate::peers::parry3d_faces(mesh, points, expected, budget),
                _ => {
                    // Without peers, the distances and the budget go unused.
                    let _ = (mesh, expected, budget);
                    None
                }
            }
        })
    }
}

/// Benchmarks one primitive type: tree build, linear and tree queries.
/// `peer` is given the binary tree's distances and a time budget.
fn bench_set<T: MeshPrimitive>(
    set: PrimitiveSet<T>,
    points: &[Vec3],
    config: &BuildConfig,
    progress: bool,
    peer: impl FnOnce(&[Option<f32>], std::time::Duration) -> Option<Record>,
) -> anyhow::Result<Vec<Record>> {
    let kind = T::KIND;
    // The build alone is timed, not the copy of its input (nor parry3d's).
    let input = set.clone();
    let start = Instant::now();
    let tree = AabbTree::build_set(input, config)?;
    let build_seconds = start.elapsed().as_secs_f64();

    let n_linear = linear_queries(linear_budget()?, set.len(), points.len());
    let set_for_spheres = set.clone();
    let set_for_wide = set.clone();
    let linear = LinearSearch::new(set);
    let bar = bar(progress, n_linear, &format!("{} linear", kind.name()));
    let start = Instant::now();
    let expected: Vec<Option<f32>> = points[..n_linear]
        .par_iter()
        .map(|&p| {
            bar.inc(1);
            linear.closest(p).map(|h| h.distance)
        })
        .collect();
    let linear_seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();

    // Per query, in input order: the binary tree, then the 4-wide tree
    // (same answers, SIMD nodes), built by its own build. Each answers the
    // first `n_*` queries: all of them unless it searches like linear search.
    let (n_tree, tree_note) = row_queries(&tree, "tree", points, n_linear);
    let (per_query, tree_seconds): (Vec<Option<f32>>, f64) = timed(|| {
        points[..n_tree]
            .par_iter()
            .map(|&p| tree.closest(p).map(|h| h.distance))
            .collect()
    });
    drop(tree);
    let (wide, wide_build_seconds) = timed(|| WideTree::build_set(set_for_wide, config));
    let wide = wide?;
    let (n_wide, wide_note) = row_queries(&wide, "tree-wide and tree-batch", points, n_linear);
    let (per_query_wide, wide_seconds): (Vec<Option<f32>>, f64) = timed(|| {
        points[..n_wide]
            .par_iter()
            .map(|&p| wide.closest(p).map(|h| h.distance))
            .collect()
    });
    let (batch, batch_seconds) = timed(|| wide.closest_batch(&points[..n_wide]));
    drop(wide);
    // The sphere tree: the same hierarchy with spheres (its build includes
    // the AABB tree's, whose topology it takes).
    let (spheres, sphere_build_seconds) = timed(|| SphereTree::build_set(set_for_spheres, config));
    let spheres = spheres?;
    let (n_spheres, spheres_note) = row_queries(&spheres, "sphere-tree", points, n_linear);
    let (per_query_spheres, sphere_seconds): (Vec<Option<f32>>, f64) = timed(|| {
        points[..n_spheres]
            .par_iter()
            .map(|&p| spheres.closest(p).map(|h| h.distance))
            .collect()
    });

    // Each structure against the binary tree, and the tree against linear
    // search, on the queries both answered, so a disagreement names the
    // structure that differs.
    let same = |a: &[Option<f32>], b: &[Option<f32>]| a.iter().zip(b).all(|(a, b)| a == b);
    let tree_agrees = same(&expected, &per_query);
    let wide_agrees = same(&per_query_wide, &per_query);
    let spheres_agree = same(&per_query_spheres, &per_query);
    let batch_agrees = batch.iter().zip(&per_query).all(|(a, b)| a.map(|h| h.distance) == *b);
    let row = |method, build_seconds, queries, seconds, agree, note| Record {
        primitives: kind.name(),
        method,
        build_seconds,
        queries,
        seconds,
        agree,
        note,
    };
    // The peer may take ten times our slowest row, and at least 10 s.
    let slowest = [tree_seconds, wide_seconds, batch_seconds, sphere_seconds]
        .into_iter()
        .fold(0.0, f64::max);
    let peer = peer(
        &per_query,
        std::time::Duration::from_secs_f64((10.0 * slowest).max(10.0)),
    );
    Ok([
        row("linear", 0.0, n_linear, linear_seconds, tree_agrees, None),
        row("tree", build_seconds, n_tree, tree_seconds, tree_agrees, tree_note),
        row(
            "tree-wide",
            wide_build_seconds,
            n_wide,
            wide_seconds,
            wide_agrees,
            wide_note.clone(),
        ),
        row(
            "tree-batch",
            wide_build_seconds,
            n_wide,
            batch_seconds,
            batch_agrees,
            wide_note,
        ),
        row(
            "sphere-tree",
            sphere_build_seconds,
            n_spheres,
            sphere_seconds,
            spheres_agree,
            spheres_note,
        ),
    ]
    .into_iter()
    .chain(peer)
    .collect())
}

/// Measures every requested primitive type on `points`, on a pool of
/// `threads` workers: one row per method (linear, tree, tree-wide,
/// tree-batch, sphere-tree) and type, and on faces the rows of `peers`.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    mesh: &Mesh,
    kinds: &[PrimitiveKind],
    points: &[Vec3],
    threads: usize,
    config: &BuildConfig,
    progress: bool,
    planarity: f32,
    peers: Peers,
) -> anyhow::Result<Vec<Record>> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .context("thread pool")?;
    pool.install(|| {
        let mut records = Vec::new();
        for &kind in kinds {
            let task = BenchKind {
                mesh,
                points,
                config,
                progress,
                peers,
            };
            records.extend(kind.run(mesh, planarity, task)?);
        }
        Ok(records)
    })
}

/// Runs the closest-point benchmark of `args` (checked by
/// [`crate::run`]) and prints its table or JSON.
pub fn run(args: &Args, peers: Peers) -> anyhow::Result<()> {
    let mesh = load_mesh(&args.mesh)?;
    let (points, set_name) = match &args.points {
        Some(file) => (read_points(file)?, file.display().to_string()),
        None => match args.set.unwrap_or(QuerySet::Near) {
            QuerySet::Near => (
                proxima::sample::near_surface(&mesh, args.queries, 0.01, args.seed),
                "near".to_string(),
            ),
            QuerySet::Uniform => (
                proxima::sample::uniform_in_box(&mesh, args.queries, args.seed),
                "uniform".to_string(),
            ),
        },
    };
    if points.is_empty() {
        anyhow::bail!(
            "{}: no query points (the mesh has no area, or the points file is empty)",
            args.mesh.display()
        );
    }
    let kinds: Vec<PrimitiveKind> = match args.primitives {
        Some(kind) => vec![kind],
        None if mesh.face_count() == 0 => vec![PrimitiveKind::Vertices, PrimitiveKind::Edges],
        None => DEFAULT_KINDS.to_vec(),
    };
    for &kind in &kinds {
        require_primitives(&mesh, kind, &args.mesh)?;
        note_polygons(&mesh, kind, &args.mesh, args.planarity);
    }
    let records = measure(
        &mesh,
        &kinds,
        &points,
        args.threads,
        &args.split.config(),
        !args.json,
        args.planarity,
        peers,
    )
    .with_context(|| args.mesh.display().to_string())?;
    if args.json {
        let results: Vec<_> = records
            .iter()
            .map(|r| {
                json!({
                    "primitives": r.primitives, "method": r.method, "build_seconds": r.build_seconds,
                    "queries": r.queries, "seconds": r.seconds, "queries_per_second": r.queries_per_second(),
                    "agree": r.agree, "capped": r.queries < points.len(), "note": r.note,
                })
            })
            .collect();
        let out = json!({
            "mesh": args.mesh.display().to_string(), "triangles": mesh.triangle_count(),
            "query_set": set_name, "threads": args.threads, "split": args.split.name(),
            "huge_page_bytes": proxima::memory::huge_page_bytes(),
            "results": results,
        });
        outln!("{out:#}");
    } else {
        outln!(
            "{}: {} vertices, {} triangles; {} {set_name} queries; {} thread(s)",
            args.mesh.display(),
            mesh.vertex_count(),
            mesh.triangle_count(),
            points.len(),
            args.threads
        );
        print_table(&records)?;
        if let Some(peer) = records.iter().find(|r| r.method == "parry3d") {
            for method in ["tree-wide", "tree-batch"] {
                if let Some(r) = records.iter().find(|r| r.primitives == "faces" && r.method == method) {
                    outln!(
                        "faces: {method} answers {:.2}x as many queries per second as parry3d",
                        r.queries_per_second() / peer.queries_per_second()
                    );
                }
            }
        }
        if let Some(r) = records
            .iter()
            .find(|r| r.method == "linear" && r.queries < points.len())
        {
            outln!(
                "(linear search ran on the first {} queries only, to bound its time)",
                r.queries
            );
        }
        print_notes(&records)?;
    }
    // Our structures must agree exactly; the peer computes in its own f32
    // arithmetic, and its rounding at large coordinates is not our bug.
    if let Some(r) = records.iter().find(|r| !r.agree && r.method != "parry3d") {
        if matches!(r.method, "linear" | "tree") {
            anyhow::bail!(
                "{}: the tree and linear search disagree: this is a bug, please report it",
                r.primitives
            );
        }
        anyhow::bail!(
            "{}: {} disagrees with the binary tree (which agrees with linear search): this is a bug, please report it",
            r.primitives,
            r.method
        );
    }
    if records.iter().any(|r| !r.agree && r.method == "parry3d") {
        eprintln!(
            "proxima: note: {}: parry3d's distances differ from proxima's by more than 1e-5 of the bounding box \
             diagonal on some queries (proxima's tree and linear search agree); parry3d's own rounding, not an error",
            args.mesh.display()
        );
    }
    Ok(())
}
