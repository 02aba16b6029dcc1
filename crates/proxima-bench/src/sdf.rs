//! `proxima bench MESH --query sdf`: signed distances per second, with the
//! winding-number sign and the pseudonormal sign, one query at a time and in
//! batches, against the plain closest query and against linear search
//! (the closest triangle and the exact winding number) on a subset.

use crate::args::QuerySet;
use crate::input::{load_mesh, memory_budget, read_points};
use crate::report::{Record, bar, print_table, timed};
use anyhow::{Context, Result, bail};
use proxima::prelude::*;
use proxima::sdf::winding_number_exact;
use proxima::{SdfConfig, Sign, SignedDistanceField};
use rayon::prelude::*;
use serde_json::json;
use std::path::Path;

/// What `proxima bench --query sdf` was asked.
pub struct Options<'a> {
    /// The mesh file.
    pub mesh: &'a Path,
    /// Generated queries per set.
    pub queries: usize,
    /// A points file instead of generated sets.
    pub points: Option<&'a Path>,
    /// The generated sets measured.
    pub sets: Vec<QuerySet>,
    /// Their seed.
    pub seed: u64,
    /// Worker threads of the query loops.
    pub threads: usize,
    /// The trees' build.
    pub build: BuildConfig,
    /// The build's name in the JSON output.
    pub split: String,
    /// One JSON object instead of tables.
    pub json: bool,
}

/// Memory per query point, counted generously: the point (12 bytes), six
/// per-query answers (8 each), the batch's closest hits and signed answers
/// (28 + 40) and the batch distances kept (8 each).
pub const BYTES_PER_QUERY: u64 = 192;

/// Triangle visits the linear reference may spend per set: each visit is a
/// closest-point test and an `f64` solid angle (about 60 ns in all), so about
/// 1.5 s on one core.
const LINEAR_BUDGET: usize = 25_000_000;

/// A winding number this close to ½ decides no side: the approximation's
/// documented accuracy.
const SIGN_MARGIN: f64 = 0.01;

/// How the signs of the subset checked by linear search compare with the
/// exact winding number's.
struct SignCheck {
    /// Queries checked.
    checked: usize,
    /// Those whose exact winding number is farther than [`SIGN_MARGIN`] from ½.
    decisive: usize,
    /// Decisive queries the winding-number sign puts on the exact side.
    winding: usize,
    /// Decisive queries the pseudonormal sign puts on the exact side.
    pseudonormal: usize,
}

/// The measurements of one query set.
struct SetResult {
    name: String,
    queries: usize,
    records: Vec<Record>,
    signs: SignCheck,
}

/// Runs `proxima bench --query sdf`.
pub fn run(options: &Options) -> Result<()> {
    let budget = memory_budget()?;
    let asked = options.queries as u128 * BYTES_PER_QUERY as u128;
    if options.points.is_none() && asked > budget as u128 {
        bail!(
            "--queries {}: the query points and answers need about {} ({BYTES_PER_QUERY} bytes per query), more than the memory budget of {}",
            options.queries,
            proxima::budget::human_bytes(asked),
            proxima::budget::human_bytes(budget.into())
        );
    }
    let mesh = load_mesh(options.mesh)?;
    let name = || options.mesh.display().to_string();
    let sets: Vec<(String, Vec<Vec3>)> = match options.points {
        Some(file) => vec![(file.display().to_string(), read_points(file)?)],
        None => options
            .sets
            .iter()
            .map(|set| match set {
                QuerySet::Near => (
                    "near".to_string(),
                    proxima::sample::near_surface(&mesh, options.queries, 0.01, options.seed),
                ),
                QuerySet::Uniform => (
                    "uniform".to_string(),
                    proxima::sample::uniform_in_box(&mesh, options.queries, options.seed),
                ),
            })
            .collect(),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads.max(1))
        .build()
        .context("thread pool")?;
    let results = pool.install(|| -> Result<Vec<SetResult>> {
        let field = |sign| {
            let config = SdfConfig {
                sign,
                build: options.build,
                ..SdfConfig::default()
            };
            timed(|| SignedDistanceField::new(&mesh, &config))
        };
        let (winding, winding_build) = field(Sign::WindingNumber);
        let winding = winding.with_context(name)?;
        let (pseudonormal, pseudonormal_build) = field(Sign::Pseudonormal);
        let pseudonormal = pseudonormal.with_context(name)?;
        let fields = Fields {
            winding: &winding,
            winding_build,
            pseudonormal: &pseudonormal,
            pseudonormal_build,
        };
        let mut results = Vec::new();
        for (set, points) in &sets {
            if points.is_empty() {
                bail!("{}: no query points in the {set} set", options.mesh.display());
            }
            results.push(measure_set(&mesh, &fields, set, points, !options.json));
        }
        Ok(results)
    })?;
    if options.json {
        print_json(options, &mesh, &results)?;
    } else {
        print_tables(options, &mesh, &results)?;
    }
    for result in &results {
        if let Some(r) = result.records.iter().find(|r| !r.agree) {
            bail!(
                "{}: {} set: {} disagrees with its reference (linear search, the exact winding number where \
                 |w - 1/2| > {SIGN_MARGIN}, or the single queries): this is a bug, please report it",
                options.mesh.display(),
                result.name,
                r.method
            );
        }
    }
    Ok(())
}

/// The two fields measured, with their build times.
struct Fields<'a> {
    winding: &'a SignedDistanceField,
    winding_build: f64,
    pseudonormal: &'a SignedDistanceField,
    pseudonormal_build: f64,
}

/// Measures every method on one query set.
fn measure_set(mesh: &Mesh, fields: &Fields, set: &str, points: &[Vec3], progress: bool) -> SetResult {
    let triangles = mesh.triangles();
    // At least 20 queries (when there are that many), at most all of them.
    let n_linear = (LINEAR_BUDGET / triangles.len().max(1)).max(20).min(points.len());
    let primitives = triangles.primitives.clone();
    let linear = LinearSearch::new(triangles);
    let bar = bar(progress, n_linear, &format!("{set} linear"));
    let (expected, linear_seconds): (Vec<(Option<f32>, f64)>, f64) = timed(|| {
        points[..n_linear]
            .par_iter()
            .map(|&p| {
                bar.inc(1);
                (
                    linear.closest(p).map(|h| h.distance),
                    winding_number_exact(&primitives, p),
                )
            })
            .collect()
    });
    bar.finish_and_clear();
    drop((linear, primitives));

    let tree = fields.winding.tree();
    let per_query = |f: &(dyn Fn(Vec3) -> Option<f32> + Sync)| -> (Vec<Option<f32>>, f64) {
        timed(|| points.par_iter().map(|&p| f(p)).collect())
    };
    let (closest, closest_seconds) = per_query(&|p| tree.closest(p).map(|h| h.distance));
    let (closest_batch, closest_batch_seconds) = timed(|| tree.closest_batch(points));
    let (winding, winding_seconds) = per_query(&|p| fields.winding.signed_distance(p).map(|s| s.distance));
    let (winding_batch, winding_batch_seconds) = timed(|| fields.winding.signed_distance_batch(points));
    let (pseudonormal, pseudonormal_seconds) =
        per_query(&|p| fields.pseudonormal.signed_distance(p).map(|s| s.distance));
    let (pseudonormal_batch, pseudonormal_batch_seconds) = timed(|| fields.pseudonormal.signed_distance_batch(points));

    // Linear search against the tree; each signed distance's size against
    // the tree's distance, its sign against the exact winding number where
    // that decides; each batch against its single queries.
    let linear_agrees = expected.iter().zip(&closest).all(|((d, _), c)| d == c);
    let unsigned_equal = |signed: &[Option<f32>]| signed.iter().zip(&closest).all(|(s, c)| s.map(f32::abs) == *c);
    let mut signs = SignCheck {
        checked: n_linear,
        decisive: 0,
        winding: 0,
        pseudonormal: 0,
    };
    for (i, &(_, w)) in expected.iter().enumerate() {
        if (w - 0.5).abs() <= SIGN_MARGIN {
            continue;
        }
        signs.decisive += 1;
        let exact_inside = w > 0.5;
        signs.winding += usize::from(winding[i].is_some_and(|d| (d < 0.0) == exact_inside));
        signs.pseudonormal += usize::from(pseudonormal[i].is_some_and(|d| (d < 0.0) == exact_inside));
    }
    let batch_equal = |batch: &[Option<proxima::SignedDistance>], single: &[Option<f32>]| {
        batch.iter().zip(single).all(|(b, s)| b.map(|b| b.distance) == *s)
    };
    let closest_batch_equal = closest_batch
        .iter()
        .zip(&closest)
        .all(|(b, s)| b.map(|b| b.distance) == *s);
    let row = |method, build_seconds, queries, seconds, agree| Record {
        primitives: "faces",
        method,
        build_seconds,
        queries,
        seconds,
        agree,
        note: None,
    };
    let n = points.len();
    let records = vec![
        row("linear", 0.0, n_linear, linear_seconds, linear_agrees),
        row("closest", fields.winding_build, n, closest_seconds, linear_agrees),
        row(
            "closest-batch",
            fields.winding_build,
            n,
            closest_batch_seconds,
            closest_batch_equal,
        ),
        row(
            "winding",
            fields.winding_build,
            n,
            winding_seconds,
            unsigned_equal(&winding) && signs.winding == signs.decisive,
        ),
        row(
            "winding-batch",
            fields.winding_build,
            n,
            winding_batch_seconds,
            batch_equal(&winding_batch, &winding),
        ),
        // The pseudonormal sign is right only on closed oriented meshes:
        // its disagreements are counted, not failed.
        row(
            "pseudonormal",
            fields.pseudonormal_build,
            n,
            pseudonormal_seconds,
            unsigned_equal(&pseudonormal),
        ),
        row(
            "pseudonormal-batch",
            fields.pseudonormal_build,
            n,
            pseudonormal_batch_seconds,
            batch_equal(&pseudonormal_batch, &pseudonormal),
        ),
    ];
    SetResult {
        name: set.to_string(),
        queries: n,
        records,
        signs,
    }
}

/// The per-query time of `method` over the plain closest query's.
fn time_ratio(records: &[Record], method: &str, reference: &str) -> Option<f64> {
    let find = |m: &str| records.iter().find(|r| r.method == m);
    let (r, reference) = (find(method)?, find(reference)?);
    Some((r.seconds / r.queries as f64) / (reference.seconds / reference.queries as f64).max(1e-18))
}

fn print_tables(options: &Options, mesh: &Mesh, results: &[SetResult]) -> std::io::Result<()> {
    outln!(
        "{}: {} vertices, {} triangles; signed distances; {} thread(s)",
        options.mesh.display(),
        mesh.vertex_count(),
        mesh.triangle_count(),
        options.threads
    );
    for result in results {
        outln!("");
        outln!("{} queries of the {} set:", result.queries, result.name);
        print_table(&result.records)?;
        for (method, reference) in [
            ("pseudonormal", "closest"),
            ("winding", "closest"),
            ("pseudonormal-batch", "closest-batch"),
            ("winding-batch", "closest-batch"),
        ] {
            if let Some(ratio) = time_ratio(&result.records, method, reference) {
                outln!("{}: {method} takes {ratio:.2}x the time of {reference}", result.name);
            }
        }
        let s = &result.signs;
        outln!(
            "{}: signs on the {} linear-checked queries, {} with |w - 1/2| > {SIGN_MARGIN} (exact): winding number \
             agrees on {}, pseudonormal on {}",
            result.name,
            s.checked,
            s.decisive,
            s.winding,
            s.pseudonormal
        );
    }
    Ok(())
}

fn print_json(options: &Options, mesh: &Mesh, results: &[SetResult]) -> std::io::Result<()> {
    let mut rows = Vec::new();
    let mut signs = Vec::new();
    for result in results {
        for r in &result.records {
            rows.push(json!({
                "query_set": result.name, "primitives": r.primitives, "method": r.method,
                "build_seconds": r.build_seconds, "queries": r.queries, "seconds": r.seconds,
                "queries_per_second": r.queries_per_second(), "agree": r.agree,
            }));
        }
        let s = &result.signs;
        signs.push(json!({
            "query_set": result.name, "checked": s.checked, "decisive": s.decisive,
            "winding_agrees": s.winding, "pseudonormal_agrees": s.pseudonormal,
        }));
    }
    let out = json!({
        "mesh": options.mesh.display().to_string(), "triangles": mesh.triangle_count(), "query": "sdf",
        "query_sets": results.iter().map(|r| r.name.clone()).collect::<Vec<_>>(),
        "threads": options.threads, "split": options.split, "seed": options.seed,
        "results": rows, "signs": signs,
    });
    outln!("{out:#}");
    Ok(())
}
