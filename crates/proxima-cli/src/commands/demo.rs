//! `proxima demo`: the main job on the embedded model, no arguments needed.

use crate::common::{DEFAULT_KINDS, load_or_default};
use proxima::BuildError;
use proxima::prelude::*;
use proxima::primitive::polygon::DEFAULT_PLANARITY_TOLERANCE;
use std::time::Instant;

/// Arguments of `proxima demo`.
#[derive(clap::Args)]
pub struct Args {
    /// Number of queries for the benchmark table.
    #[arg(long, default_value_t = 2_000)]
    queries: usize,
}

/// Loads the embedded bunny, builds the three trees, answers a few queries and
/// prints the linear-versus-tree table.
pub fn run(args: Args) -> anyhow::Result<()> {
    let (mesh, name) = load_or_default(None)?;
    let b = mesh.bounds();
    crate::outln!(
        "{name}: {} vertices, {} edges, {} triangles; bbox {:?} .. {:?}",
        mesh.vertex_count(),
        mesh.edge_indices().len(),
        mesh.triangle_count(),
        b.min.to_array(),
        b.max.to_array()
    );
    let queries = [
        b.center(),
        b.max + b.size() * 0.25,
        Vec3::new(b.min.x, b.center().y, b.max.z),
    ];
    crate::outln!("\nclosest primitive to a few points:");
    crate::outln!(
        "{:<10} {:<28} {:>8} {:<28} {:>10}",
        "type",
        "query",
        "index",
        "closest point",
        "distance"
    );
    for kind in DEFAULT_KINDS {
        let (hits, seconds) = kind.run(&mesh, DEFAULT_PLANARITY_TOLERANCE, ClosestTo(queries))?;
        for (q, hit) in queries.into_iter().zip(hits) {
            let hit = hit.ok_or_else(|| anyhow::anyhow!("empty tree"))?;
            crate::outln!(
                "{:<10} {:<28} {:>8} {:<28} {:>10.5}",
                kind.name(),
                format!("({:.3}, {:.3}, {:.3})", q.x, q.y, q.z),
                hit.source,
                format!("({:.3}, {:.3}, {:.3})", hit.point.x, hit.point.y, hit.point.z),
                hit.distance
            );
        }
        crate::outln!("{:<10} tree built in {:.3} ms", "", seconds * 1e3);
    }
    let points = proxima::sample::near_surface(&mesh, args.queries, 0.01, 1);
    crate::outln!(
        "\nlinear search vs AABB tree, {} near-surface queries, 1 thread:",
        points.len()
    );
    let records = super::bench::measure(
        &mesh,
        &DEFAULT_KINDS,
        &points,
        1,
        &BuildConfig::default(),
        false,
        DEFAULT_PLANARITY_TOLERANCE,
    )?;
    super::bench::print_table(&records)?;
    Ok(())
}

/// The closest primitive to each point, through a tree built with the
/// default configuration, and the tree's build time in seconds.
struct ClosestTo<const N: usize>([Vec3; N]);

impl<const N: usize> KindTask for ClosestTo<N> {
    type Output = Result<([Option<ClosestHit>; N], f64), BuildError>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> Self::Output {
        let start = Instant::now();
        let tree = AabbTree::build_set(set, &BuildConfig::default())?;
        let seconds = start.elapsed().as_secs_f64();
        Ok((self.0.map(|q| tree.closest(q)), seconds))
    }
}
