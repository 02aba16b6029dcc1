//! `proxima closest MESH --primitives P (--point X,Y,Z | --points FILE) [-k K] [--method tree|linear]`.

use crate::common::{
    Split, kind_parser, load_mesh, parse_planarity, parse_vec3, query_points, require_primitives, run_kind,
};
use anyhow::Context;
use proxima::prelude::*;
use proxima::query::distinct_sources;
use rayon::prelude::*;
use std::io::{BufWriter, StdoutLock, Write};
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
    #[arg(long, value_parser = kind_parser(), default_value = "faces")]
    primitives: PrimitiveKind,
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
    let points = query_points(args.point, args.points.as_deref())?;
    require_primitives(&mesh, args.primitives, &args.mesh)?;
    let mut rows = Rows::new();
    writeln!(rows.out, "query,rank,primitive,cx,cy,cz,distance")?;
    let task = Answer {
        points: &points,
        args: &args,
        rows: &mut rows,
    };
    run_kind(&mesh, args.primitives, &args.mesh, args.planarity, task)?;
    rows.out.flush()?;
    Ok(())
}

/// The CSV rows on standard output, numbered by query in input order.
struct Rows {
    out: BufWriter<StdoutLock<'static>>,
    /// The number of the next query written.
    first: usize,
}

impl Rows {
    fn new() -> Self {
        Self {
            out: BufWriter::new(std::io::stdout().lock()),
            first: 0,
        }
    }

    /// Writes the answers of the next queries, `hits` giving each one's
    /// hits, nearest first.
    ///
    /// The rows are formatted in parallel, in blocks of about [`BLOCK_HITS`]
    /// hits, and written in order: formatting took about 30% of the CPU
    /// time of `-k 8` (dragon, 1M points), all of it on one thread while
    /// the others waited. At most 64 blocks' text is held at once.
    fn write<A: Sync>(&mut self, answers: &[A], hits: impl Fn(&A) -> &[ClosestHit] + Sync) -> std::io::Result<()> {
        let most = answers.iter().map(|a| hits(a).len()).max().unwrap_or(0);
        let block = (BLOCK_HITS / most.max(1)).max(1);
        for window in answers.chunks(64 * block) {
            let first = self.first;
            let texts: Vec<Vec<u8>> = window
                .par_chunks(block)
                .enumerate()
                .map(|(n, answers)| {
                    let mut text = Vec::with_capacity(80 * BLOCK_HITS); // rows of up to about 80 bytes
                    for (offset, answer) in answers.iter().enumerate() {
                        let query = first + n * block + offset;
                        for (rank, hit) in hits(answer).iter().enumerate() {
                            writeln!(
                                text,
                                "{query},{rank},{},{},{},{},{}",
                                hit.source, hit.point.x, hit.point.y, hit.point.z, hit.distance
                            )
                            .expect("writing to memory does not fail");
                        }
                    }
                    text
                })
                .collect();
            for text in &texts {
                self.out.write_all(text)?;
            }
            self.first += window.len();
        }
        Ok(())
    }
}

/// Hits per block of rows formatted at once by [`Rows::write`].
const BLOCK_HITS: usize = 4096;

/// Answers the queries on one kind of primitive and writes them, chunk by
/// chunk in input order, so that memory holds one chunk's answers: at most
/// [`CHUNK_HITS`] hits, whatever `-k`.
struct Answer<'a> {
    points: &'a [Vec3],
    args: &'a Args,
    rows: &'a mut Rows,
}

impl KindTask for Answer<'_> {
    type Output = anyhow::Result<()>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> anyhow::Result<()> {
        let Self { points, args, rows } = self;
        let k = args.k;
        // Each source one part (vertices, edges, triangles): the k nearest
        // parts are the k nearest sources already.
        let one_part_each = set.sources.windows(2).all(|pair| pair[0] < pair[1]);
        match args.method {
            Method::Tree => {
                // The wide tree built by its own build (leaves sized for its
                // collapse), rather than a binary tree converted: the same
                // tree, and the same answers as the binary one, faster.
                let tree =
                    WideTree::build_set(set, &args.split.config()).with_context(|| args.mesh.display().to_string())?;
                for chunk in points.chunks(chunk_len(k, tree.len())) {
                    if k == 1 {
                        // The closest-point batch, seeded by each previous
                        // answer, rather than the k-nearest heap: the same
                        // hit (ties to the lowest input index), faster; one
                        // hit has no repeated source to remove.
                        rows.write(&tree.closest_batch(chunk), Option::as_slice)?;
                    } else {
                        let mut answers = tree.k_nearest_batch(chunk, k);
                        if !one_part_each {
                            answers = distinct_sources(answers, chunk, k, tree.len(), &|p, k| tree.k_nearest(p, k));
                        }
                        rows.write(&answers, Vec::as_slice)?;
                    }
                }
            }
            Method::Linear => {
                let len = set.len();
                let scan = LinearSearch::new(set);
                for chunk in points.chunks(chunk_len(k, len)) {
                    let mut answers = chunk.iter().map(|&p| scan.k_nearest(p, k)).collect();
                    if !one_part_each {
                        answers = distinct_sources(answers, chunk, k, len, &|p, k| scan.k_nearest(p, k));
                    }
                    rows.write(&answers, Vec::as_slice)?;
                }
            }
        }
        Ok(())
    }
}

/// Answers held in memory at once: 2^20 hits (about 32 MiB).
const CHUNK_HITS: usize = 1 << 20;

/// Queries answered per chunk: at most [`CHUNK_HITS`] hits of
/// `min(k, primitives)` each (at least one query). Against chunks of at most
/// 65,536 queries, `-k 1` took 0.89x the CPU time on the dragon with 1M
/// points (the closest-point batch seeds each query with its Morton-order
/// neighbour's answer, nearer in a bigger batch).
fn chunk_len(k: usize, primitives: usize) -> usize {
    (CHUNK_HITS / k.min(primitives).max(1)).max(1)
}
