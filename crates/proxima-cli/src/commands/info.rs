//! `proxima info MESH [--json]`: counts, bounding box, tree statistics.

use crate::common::{DEFAULT_KINDS, load_mesh, run_kind};
use anyhow::Context;
use proxima::prelude::*;
use proxima::primitive::polygon::DEFAULT_PLANARITY_TOLERANCE;
use proxima::{BuildError, TreeStats};
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `proxima info`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz).
    mesh: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Prints the mesh's counts, bounding box, and for each primitive type the
/// statistics and build time of its AABB tree.
pub fn run(args: Args) -> anyhow::Result<()> {
    let mesh = load_mesh(&args.mesh)?;
    // A mesh of vertices only is reported (its vertex tree), an empty one is an error.
    crate::common::require_vertices(&mesh, &args.mesh)?;
    let bounds = mesh.bounds();
    let edges = mesh.edge_indices().len();
    let mut trees = Vec::new();
    // Polygons too when there are faces of more than three vertices.
    let polygons = (mesh.polygon_count() > 0).then_some(PrimitiveKind::Polygons);
    for kind in DEFAULT_KINDS.into_iter().chain(polygons) {
        if crate::common::require_primitives(&mesh, kind, &args.mesh).is_err() {
            continue; // info reports what there is; nothing to build for this kind
        }
        let (stats, seconds) = run_kind(&mesh, kind, &args.mesh, DEFAULT_PLANARITY_TOLERANCE, TreeFigures)
            .with_context(|| args.mesh.display().to_string())?;
        trees.push((kind, stats, seconds));
    }
    if args.json {
        let trees: Vec<_> = trees
            .iter()
            .map(|(kind, s, seconds)| {
                json!({
                    "primitives": kind.name(), "count": s.primitives, "nodes": s.nodes, "leaves": s.leaves,
                    "depth": s.depth, "min_leaf_size": s.min_leaf_size, "max_leaf_size": s.max_leaf_size,
                    "mean_leaf_size": s.mean_leaf_size, "memory_bytes": s.memory_bytes, "build_seconds": seconds,
                })
            })
            .collect();
        let out = json!({
            "mesh": args.mesh.display().to_string(),
            "vertices": mesh.vertex_count(), "edges": edges, "faces": mesh.face_count(),
            "triangles": mesh.triangle_count(), "polygons": mesh.polygon_count(),
            "bbox": {"min": bounds.min.to_array(), "max": bounds.max.to_array()},
            "trees": trees,
        });
        crate::outln!("{out:#}");
        return Ok(());
    }
    crate::outln!("mesh       {}", args.mesh.display());
    crate::outln!("vertices   {}", mesh.vertex_count());
    crate::outln!("edges      {edges}");
    crate::outln!(
        "faces      {} ({} with more than 3 vertices)",
        mesh.face_count(),
        mesh.polygon_count()
    );
    crate::outln!("triangles  {}", mesh.triangle_count());
    if bounds.is_empty() {
        crate::outln!("bbox       empty");
    } else {
        crate::outln!(
            "bbox       min {:?}  max {:?}  diagonal {}",
            bounds.min.to_array(),
            bounds.max.to_array(),
            bounds.diagonal()
        );
    }
    crate::outln!();
    crate::outln!(
        "{:<10} {:>9} {:>9} {:>9} {:>6} {:>14} {:>11}",
        "tree",
        "count",
        "nodes",
        "leaves",
        "depth",
        "leaf min/mean/max",
        "build ms"
    );
    for (kind, s, seconds) in &trees {
        crate::outln!(
            "{:<10} {:>9} {:>9} {:>9} {:>6} {:>6}/{:.2}/{:<4} {:>11.3}",
            kind.name(),
            s.primitives,
            s.nodes,
            s.leaves,
            s.depth,
            s.min_leaf_size,
            s.mean_leaf_size,
            s.max_leaf_size,
            seconds * 1e3
        );
    }
    Ok(())
}

/// The statistics of the tree built with the default configuration, and its
/// build time in seconds.
struct TreeFigures;

impl KindTask for TreeFigures {
    type Output = Result<(TreeStats, f64), BuildError>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> Self::Output {
        let start = Instant::now();
        let tree = AabbTree::build_set(set, &BuildConfig::default())?;
        Ok((tree.stats(), start.elapsed().as_secs_f64()))
    }
}
