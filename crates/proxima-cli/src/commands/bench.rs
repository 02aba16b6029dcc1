//! `proxima bench MESH [--query closest|sdf|rays] [--primitives P] [--queries N | --points FILE] [--threads T] [--json]`:
//! linear search against the AABB tree (binary, 4-wide, batch) and the
//! sphere tree on the same queries; with `--query sdf`, signed distances
//! (`bench_sdf.rs`); with `--query rays`, first-hit rays (`bench_rays.rs`).

use crate::common::{DEFAULT_KINDS, Split, kind_parser, load_mesh, parse_planarity, read_points};
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use proxima::prelude::*;
use rayon::prelude::*;
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// The query sets of BENCHMARKS.md.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum QuerySet {
    /// Surface samples plus a gaussian offset of 1% of the bbox diagonal.
    Near,
    /// Uniform in the bounding box enlarged by 10% per side.
    Uniform,
}

/// What is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum QueryKind {
    /// Closest-point queries, per primitive type.
    Closest,
    /// Signed distances on the faces: winding-number and pseudonormal signs,
    /// single queries and batches, against the plain closest query and linear
    /// search (the exact winding number); the near and uniform sets unless
    /// --set or --points chooses one.
    Sdf,
    /// First-hit rays on the faces (--queries rays of the BENCHMARKS rays
    /// set): linear search, the 4-wide tree, the ray tree one ray at a time
    /// and in batches, and parry3d.
    Rays,
}

/// Arguments of `proxima bench`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file.
    mesh: PathBuf,
    /// Benchmark only this primitive type (default: vertices, edges and faces).
    #[arg(long, value_parser = kind_parser())]
    primitives: Option<PrimitiveKind>,
    /// Number of generated query points (rays with --query rays).
    #[arg(long, default_value_t = 10_000, conflicts_with = "points")]
    queries: usize,
    /// Query points from a file instead of generated ones.
    #[arg(long)]
    points: Option<PathBuf>,
    /// Which generated query set (default: near; with --query sdf, both).
    #[arg(long, value_enum)]
    set: Option<QuerySet>,
    /// What is measured.
    #[arg(long, value_enum, default_value = "closest")]
    query: QueryKind,
    /// Seed of the generated query set.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Worker threads for the query loops (1 = single-thread figures; at
    /// most 4 per core, at least 8).
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// How the tree is split.
    #[arg(long, value_enum, default_value = "median")]
    split: Split,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
    /// With `--primitives polygons`: the relative planarity tolerance of
    /// faces kept as polygons (see `proxima closest --help`).
    #[arg(long, value_parser = parse_planarity, default_value = "1e-5")]
    planarity: f32,
}

/// One measured row.
pub struct Record {
    /// Primitive type.
    pub primitives: &'static str,
    /// `linear`, `tree` (binary tree, per query in input order), `tree-wide`
    /// (4-wide SIMD tree, per query), `tree-batch` (4-wide tree, Morton-ordered
    /// batch), `sphere-tree` (bounding spheres, per query in input order) or,
    /// for faces, `parry3d` (the peer library, per query in input order).
    pub method: &'static str,
    /// Build time of the structure (0 for linear).
    pub build_seconds: f64,
    /// Number of queries answered.
    pub queries: usize,
    /// Time for all of them.
    pub seconds: f64,
    /// `true` when the distances equal the reference's: for linear search and
    /// the binary tree, each other's on the shared queries; for the other
    /// structures of proxima, the binary tree's; for the peer, ours within
    /// its tolerance.
    pub agree: bool,
    /// Why the row answered fewer queries than the set, when it did for a
    /// reason of its own (the linear row's budget is said once, after the
    /// table): a structure that searched like a linear scan, a peer that
    /// spent its time budget.
    pub note: Option<String>,
}

impl Record {
    /// Queries answered per second.
    pub fn queries_per_second(&self) -> f64 {
        self.queries as f64 / self.seconds.max(1e-12)
    }
}

/// Memory per query point of a benchmark, counted generously: the point (12
/// bytes), the distances of the tree, wide tree, sphere tree, linear and peer
/// answers (8 bytes each) and the batch answers (32 bytes).
const BYTES_PER_QUERY: u64 = 96;

/// Primitive tests the linear scan may spend, so big meshes still finish
/// quickly ([`LINEAR_BUDGET_ENV`] sets it).
const LINEAR_BUDGET: u64 = 100_000_000;

/// The environment variable that sets the linear row's budget of primitive
/// tests (a positive whole number), which also bounds the rows of
/// structures that search like a linear scan.
pub const LINEAR_BUDGET_ENV: &str = "PROXIMA_BENCH_LINEAR_BUDGET";

/// The primitive tests the linear row may spend: [`LINEAR_BUDGET_ENV`] or
/// [`LINEAR_BUDGET`].
pub fn linear_budget() -> anyhow::Result<u64> {
    match std::env::var_os(LINEAR_BUDGET_ENV) {
        None => Ok(LINEAR_BUDGET),
        Some(value) => {
            let text = value.to_string_lossy();
            text.trim()
                .parse::<u64>()
                .ok()
                .filter(|&budget| budget > 0)
                .ok_or_else(|| {
                    anyhow::anyhow!("{LINEAR_BUDGET_ENV}: '{text}' is not a positive whole number of primitive tests")
                })
        }
    }
}

/// The queries of a row that the linear row's budget allows on `primitives`
/// primitives: at least 20 (when there are that many), at most all.
pub fn linear_queries(budget: u64, primitives: usize, total: usize) -> usize {
    usize::try_from(budget / primitives.max(1) as u64)
        .unwrap_or(usize::MAX)
        .max(20)
        .min(total)
}

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
}

impl KindTask for BenchKind<'_> {
    type Output = anyhow::Result<Vec<Record>>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> Self::Output {
        let Self {
            mesh,
            points,
            config,
            progress,
        } = self;
        bench_set(set, points, config, progress, |expected, budget| match T::KIND {
            PrimitiveKind::Faces => super::bench_peer::parry3d_faces(mesh, points, expected, budget),
            _ => None,
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

/// Runs `f`, returning its value and its time in seconds.
pub fn timed<R>(f: impl FnOnce() -> R) -> (R, f64) {
    let start = Instant::now();
    let value = f();
    (value, start.elapsed().as_secs_f64())
}

/// A progress bar on standard error, or a hidden one when not `enabled`.
pub fn bar(enabled: bool, len: usize, message: &str) -> ProgressBar {
    if !enabled {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg:>16} {wide_bar} {pos}/{len} {eta}").unwrap_or(ProgressStyle::default_bar()),
    );
    bar.set_message(message.to_string());
    bar
}

/// Measures every requested primitive type on `points`.
pub fn measure(
    mesh: &Mesh,
    kinds: &[PrimitiveKind],
    points: &[Vec3],
    threads: usize,
    config: &BuildConfig,
    progress: bool,
    planarity: f32,
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
            };
            records.extend(kind.run(mesh, planarity, task)?);
        }
        Ok(records)
    })
}

/// Prints each row's note once (the wide tree's rows share theirs), in
/// parentheses after the table, naming the primitive type.
pub fn print_notes(records: &[Record]) -> std::io::Result<()> {
    let mut printed: Vec<(&str, &str)> = Vec::new();
    for r in records {
        if let Some(note) = &r.note
            && !printed.contains(&(r.primitives, note.as_str()))
        {
            printed.push((r.primitives, note));
            crate::outln!("({}: {note})", r.primitives);
        }
    }
    Ok(())
}

/// Prints the records as a table.
pub fn print_table(records: &[Record]) -> std::io::Result<()> {
    crate::outln!(
        "{:<10} {:<14} {:>10} {:>8} {:>10} {:>12} {:>10} {:>9}",
        "primitives",
        "method",
        "build ms",
        "queries",
        "seconds",
        "queries/s",
        "vs linear",
        "agree"
    );
    for r in records {
        let linear = records
            .iter()
            .find(|l| l.primitives == r.primitives && l.method == "linear");
        let speedup = linear.map_or(1.0, |l| r.queries_per_second() / l.queries_per_second());
        crate::outln!(
            "{:<10} {:<14} {:>10.3} {:>8} {:>10.4} {:>12.0} {:>9.1}x {:>9}",
            r.primitives,
            r.method,
            r.build_seconds * 1e3,
            r.queries,
            r.seconds,
            r.queries_per_second(),
            speedup,
            if r.agree { "yes" } else { "NO" }
        );
    }
    Ok(())
}

/// Runs `proxima bench`.
pub fn run(args: Args) -> anyhow::Result<()> {
    crate::common::thread_count(args.threads)?;
    // Zero generated queries would leave every set empty and be reported as
    // a property of the mesh (no area, a point-sized box), not of the option.
    if args.points.is_none() && args.queries == 0 {
        anyhow::bail!("--queries must be at least 1");
    }
    if args.query == QueryKind::Sdf {
        if args.primitives.is_some_and(|kind| kind != PrimitiveKind::Faces) {
            anyhow::bail!("--query sdf measures signed distances to the faces; --primitives cannot change that");
        }
        return super::bench_sdf::run(&super::bench_sdf::Options {
            mesh: &args.mesh,
            queries: args.queries,
            points: args.points.as_deref(),
            sets: args
                .set
                .map_or(vec![QuerySet::Near, QuerySet::Uniform], |set| vec![set]),
            seed: args.seed,
            threads: args.threads,
            build: args.split.config(),
            split: format!("{:?}", args.split).to_lowercase(),
            json: args.json,
        });
    }
    if args.query == QueryKind::Rays {
        if args.primitives.is_some_and(|kind| kind != PrimitiveKind::Faces) {
            anyhow::bail!("--query rays casts rays at the faces; --primitives cannot change that");
        }
        if args.points.is_some() || args.set.is_some() {
            anyhow::bail!("--query rays casts the BENCHMARKS rays set; --points and --set choose query points");
        }
    }
    let budget = crate::common::memory_budget()?;
    if args.points.is_none() && args.queries as u128 * BYTES_PER_QUERY as u128 > budget as u128 {
        anyhow::bail!(
            "--queries {}: the query points and answers need about {} ({BYTES_PER_QUERY} bytes per query), more than the memory budget of {}",
            args.queries,
            proxima::budget::human_bytes(args.queries as u128 * BYTES_PER_QUERY as u128),
            proxima::budget::human_bytes(budget.into())
        );
    }
    if args.query == QueryKind::Rays {
        return super::bench_rays::run(&super::bench_rays::Options {
            mesh: &args.mesh,
            rays: args.queries,
            seed: args.seed,
            threads: args.threads,
            json: args.json,
        });
    }
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
        crate::common::require_primitives(&mesh, kind, &args.mesh)?;
        crate::common::note_polygons(&mesh, kind, &args.mesh, args.planarity);
    }
    let records = measure(
        &mesh,
        &kinds,
        &points,
        args.threads,
        &args.split.config(),
        !args.json,
        args.planarity,
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
            "query_set": set_name, "threads": args.threads, "split": format!("{:?}", args.split).to_lowercase(),
            "huge_page_bytes": proxima::memory::huge_page_bytes(),
            "results": results,
        });
        crate::outln!("{out:#}");
    } else {
        crate::outln!(
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
                    crate::outln!(
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
            crate::outln!(
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
