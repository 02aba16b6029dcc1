//! `proxima raycast MESH --origin X,Y,Z --dir X,Y,Z [--cell W]`: the first face
//! a ray hits, found by walking a hash grid of the faces.

use super::grid::parse_cell;
use crate::common::{load_mesh, parse_vec3};
use anyhow::{Context, Result, bail};
use proxima::grid::{FastHash, GridConfig, HashGrid};
use proxima::{GridError, Triangle, Vec3};
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `proxima raycast`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, optionally .gz).
    mesh: PathBuf,
    /// Ray origin.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    origin: Vec3,
    /// Ray direction (normalized here, so t is a distance).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    dir: Vec3,
    /// Cell extents (W or W,H,D); by default about one cell per triangle
    /// along the bounding box (longest side / cube root of the triangle count).
    #[arg(long, value_name = "W[,H,D]", value_parser = parse_cell, allow_hyphen_values = true)]
    cell: Option<Vec3>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Prints the hit face, t and point, or "no hit".
pub fn run(args: Args) -> Result<()> {
    if args.dir == Vec3::ZERO {
        return Err(GridError::RayDirection.into());
    }
    let mesh = load_mesh(&args.mesh)?;
    if mesh.face_count() == 0 {
        bail!("{}: the mesh has no faces to hit", args.mesh.display());
    }
    let triangles = mesh.triangles();
    let cell = args.cell.unwrap_or_else(|| {
        let side = mesh.bounds().size().max_element();
        Vec3::splat(side / (triangles.len() as f32).cbrt().max(1.0))
    });
    let start = Instant::now();
    let grid: HashGrid<Triangle, FastHash> =
        HashGrid::build(triangles, &GridConfig::new(cell)).with_context(|| args.mesh.display().to_string())?;
    let build = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let hit = grid.first_hit(args.origin, args.dir.normalize(), 0.0, f32::INFINITY)?;
    let query = start.elapsed().as_secs_f64();
    if args.json {
        let hit = hit.map(
            |h| json!({"face": h.source, "t": h.t, "point": h.point.to_array(), "cells_visited": h.cells_visited}),
        );
        let out = json!({"hit": hit, "cell": cell.to_array(), "build_seconds": build, "query_seconds": query});
        println!("{out:#}");
        return Ok(());
    }
    match hit {
        Some(h) => println!(
            "hit face {} at t = {} point {} {} {} ({} cells visited, grid cell {:?})",
            h.source,
            h.t,
            h.point.x,
            h.point.y,
            h.point.z,
            h.cells_visited,
            cell.to_array()
        ),
        None => println!("no hit"),
    }
    Ok(())
}
