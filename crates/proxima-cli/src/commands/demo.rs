//! `proxima demo`: the main job on the embedded model, no arguments needed.

use crate::common::{Primitives, build_tree, load_or_default};
use crate::with_tree;
use proxima::prelude::*;
use proxima::{BuildConfig, Vec3};

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
    for kind in Primitives::ALL {
        let (tree, seconds) = build_tree(&mesh, kind, &BuildConfig::default())?;
        for q in queries {
            let hit = with_tree!(&tree, t => t.closest(q)).ok_or_else(|| anyhow::anyhow!("empty tree"))?;
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
        &Primitives::ALL,
        &points,
        1,
        &BuildConfig::default(),
        false,
        proxima::primitive::polygon::DEFAULT_PLANARITY_TOLERANCE,
    )?;
    super::bench::print_table(&records)?;
    Ok(())
}
