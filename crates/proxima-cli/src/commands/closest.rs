//! `proxima closest MESH --primitives P (--point X,Y,Z | --points FILE) [-k K] [--method tree|linear]`.

use crate::common::{
    Primitives, Split, build_tree_planar, load_mesh, note_polygons, parse_planarity, parse_vec3, read_points,
    require_primitives,
};
use crate::with_tree;
use anyhow::{Context, bail};
use proxima::prelude::*;
use proxima::{ClosestHit, ClosestPoint, LinearSearch, PrimitiveSet, Vec3};
use std::io::{BufWriter, Write};
use std::path::PathBuf;

/// How the answer is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// The AABB tree.
    Tree,
    /// Brute force over every primitive.
    Linear,
}

/// Arguments of `proxima closest`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file.
    mesh: PathBuf,
    /// Which primitives to search.
    #[arg(long, value_enum, default_value = "faces")]
    primitives: Primitives,
    /// One query point, X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, conflicts_with = "points", required_unless_present = "points")]
    point: Option<Vec3>,
    /// A file of query points: one per line, three numbers separated by commas
    /// or white space; `#` comments and blank lines are skipped.
    #[arg(long)]
    points: Option<PathBuf>,
    /// How many nearest primitives per query; a face of more than three
    /// vertices is listed once, at its nearest triangle's distance.
    #[arg(short, long, default_value_t = 1)]
    k: usize,
    /// Search method.
    #[arg(long, value_enum, default_value = "tree")]
    method: Method,
    /// How the tree is split (same answers either way).
    #[arg(long, value_enum, default_value = "median")]
    split: Split,
    /// With `--primitives polygons`: how far from planar a face may be and
    /// stay one polygon (its vertices' extent along the normal, relative to its
    /// bounding box diagonal); other faces are fan-triangulated.
    #[arg(long, value_parser = parse_planarity, default_value = "1e-5")]
    planarity: f32,
}

/// Prints CSV `query,rank,primitive,cx,cy,cz,distance`, k rows per query.
pub fn run(args: Args) -> anyhow::Result<()> {
    let mesh = load_mesh(&args.mesh)?;
    let points = match (&args.point, &args.points) {
        (Some(p), _) => {
            crate::common::check_query_point(*p, "--point")?;
            vec![*p]
        }
        (None, Some(file)) => read_points(file)?,
        (None, None) => bail!("give --point X,Y,Z or --points FILE"),
    };
    require_primitives(&mesh, args.primitives, &args.mesh)?;
    note_polygons(&mesh, args.primitives, &args.mesh, args.planarity);
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    writeln!(out, "query,rank,primitive,cx,cy,cz,distance")?;
    // The answers are written chunk by chunk, in input order, so that memory
    // holds one chunk's answers: at most CHUNK_HITS hits, whatever -k.
    let mut first = 0usize;
    let mut write = |hits: Vec<Vec<ClosestHit>>| -> std::io::Result<()> {
        for (offset, hits) in hits.iter().enumerate() {
            for (rank, hit) in hits.iter().enumerate() {
                writeln!(
                    out,
                    "{},{rank},{},{},{},{},{}",
                    first + offset,
                    hit.source,
                    hit.point.x,
                    hit.point.y,
                    hit.point.z,
                    hit.distance
                )?;
            }
        }
        first += hits.len();
        Ok(())
    };
    match args.method {
        Method::Tree => {
            let (tree, _) = build_tree_planar(&mesh, args.primitives, &args.split.config(), args.planarity)
                .with_context(|| args.mesh.display().to_string())?;
            // The 4-wide tree gives the same answers as the binary one, faster.
            with_tree!(tree, t => {
                let wide = WideTree::from_tree(t);
                for chunk in points.chunks(chunk_len(args.k, wide.len())) {
                    let answers = wide.k_nearest_batch(chunk, args.k);
                    write(distinct_sources(answers, chunk, args.k, wide.len(), |p, k| wide.k_nearest(p, k)))?;
                }
            })
        }
        Method::Linear => match args.primitives {
            Primitives::Vertices => linear(mesh.vertices(), &points, args.k, &mut write)?,
            Primitives::Edges => linear(mesh.edges(), &points, args.k, &mut write)?,
            Primitives::Faces => linear(mesh.triangles(), &points, args.k, &mut write)?,
            Primitives::Polygons => linear(mesh.extract_polygons(args.planarity).set, &points, args.k, &mut write)?,
        },
    }
    out.flush()?;
    Ok(())
}

/// Answers held in memory at once: 2^20 hits (about 32 MiB).
const CHUNK_HITS: usize = 1 << 20;

/// Queries answered per chunk: at most 65,536, and at most [`CHUNK_HITS`]
/// hits of `min(k, primitives)` each (at least one query).
fn chunk_len(k: usize, primitives: usize) -> usize {
    (CHUNK_HITS / k.min(primitives).max(1)).clamp(1, 1 << 16)
}

/// Brute-force answers, chunk by chunk, handed to `write`.
fn linear<T: ClosestPoint>(
    set: PrimitiveSet<T>,
    points: &[Vec3],
    k: usize,
    write: &mut impl FnMut(Vec<Vec<ClosestHit>>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let len = set.len();
    let scan = LinearSearch::new(set);
    for chunk in points.chunks(chunk_len(k, len)) {
        let answers = chunk.iter().map(|&p| scan.k_nearest(p, k)).collect();
        write(distinct_sources(answers, chunk, k, len, |p, k| scan.k_nearest(p, k)))?;
    }
    Ok(())
}

/// The `k` nearest primitives as the user counts them: a face split into
/// several triangles (a fan) or polygons is one face, listed once, at its
/// nearest part's distance.
///
/// `answers` holds the `k` nearest parts per query, nearest first (ties by
/// part index, and the parts of a face are consecutive, so ties go to the
/// lower face). The first occurrence of each source in that order is the
/// source at its own distance, so keeping first occurrences gives the nearest
/// sources in order; when that leaves fewer than `k`, the query is asked
/// again for twice as many parts, until `k` sources are found or every part
/// has been seen.
fn distinct_sources(
    mut answers: Vec<Vec<ClosestHit>>,
    points: &[Vec3],
    k: usize,
    parts: usize,
    k_nearest: impl Fn(Vec3, usize) -> Vec<ClosestHit>,
) -> Vec<Vec<ClosestHit>> {
    let first_occurrences = |hits: &mut Vec<ClosestHit>| {
        let mut seen = std::collections::HashSet::with_capacity(hits.len());
        hits.retain(|h| seen.insert(h.source));
    };
    for (hits, &p) in answers.iter_mut().zip(points) {
        let mut asked = k;
        first_occurrences(hits);
        while hits.len() < k && asked < parts {
            asked = asked.saturating_mul(2).min(parts);
            *hits = k_nearest(p, asked);
            first_occurrences(hits);
        }
        hits.truncate(k);
    }
    answers
}
