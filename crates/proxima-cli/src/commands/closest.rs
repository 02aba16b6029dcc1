//! `proxima closest MESH --primitives P (--point X,Y,Z | --points FILE) [-k K] [--method tree|linear]`.

use crate::common::{
    Primitives, Split, build_tree_planar, load_mesh, note_polygons, parse_planarity, parse_vec3, read_points,
    require_primitives,
};
use crate::with_tree;
use anyhow::{Context, bail};
use proxima::bvh::WideTree;
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
    let answers: Vec<Vec<ClosestHit>> = match args.method {
        Method::Tree => {
            let (tree, _) = build_tree_planar(&mesh, args.primitives, &args.split.config(), args.planarity)
                .with_context(|| args.mesh.display().to_string())?;
            // The 4-wide tree gives the same answers as the binary one, faster.
            with_tree!(tree, t => {
                let tree = WideTree::from_tree(t);
                let answers = tree.k_nearest_batch(&points, args.k);
                distinct_sources(answers, &points, args.k, tree.len(), |p, k| tree.k_nearest(p, k))
            })
        }
        Method::Linear => match args.primitives {
            Primitives::Vertices => linear(mesh.vertices(), &points, args.k),
            Primitives::Edges => linear(mesh.edges(), &points, args.k),
            Primitives::Faces => linear(mesh.triangles(), &points, args.k),
            Primitives::Polygons => linear(mesh.extract_polygons(args.planarity).set, &points, args.k),
        },
    };
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    writeln!(out, "query,rank,primitive,cx,cy,cz,distance")?;
    for (query, hits) in answers.iter().enumerate() {
        for (rank, hit) in hits.iter().enumerate() {
            writeln!(
                out,
                "{query},{rank},{},{},{},{},{}",
                hit.source, hit.point.x, hit.point.y, hit.point.z, hit.distance
            )?;
        }
    }
    out.flush()?;
    Ok(())
}

/// Brute-force answers, one list per query.
fn linear<T: ClosestPoint>(set: PrimitiveSet<T>, points: &[Vec3], k: usize) -> Vec<Vec<ClosestHit>> {
    let count = set.primitives.len();
    let scan = LinearSearch::new(set);
    let answers = points.iter().map(|&p| scan.k_nearest(p, k)).collect();
    distinct_sources(answers, points, k, count, |p, k| scan.k_nearest(p, k))
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
