//! `proxima raycast MESH --origin X,Y,Z --dir X,Y,Z [--method tree|grid] [--cell W] [--any]`:
//! the first face a ray hits, found with the AABB tree (default) or by walking
//! a hash grid of the faces; with `--any`, only whether it hits one.
//! `proxima raycast MESH --rays FILE [--threads T] [--any] [--attributes] [--json]`: a file
//! of rays on all cores (`raycast_batch.rs`).

use super::grid::parse_cell;
use crate::common::{load_mesh, parse_vec3};
use anyhow::{Context, Result, bail};
use proxima::grid::{FastHash, GridConfig, HashGrid};
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, RayError, Triangle, Vec3};
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// How the ray is cast.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum RayMethod {
    /// The AABB tree of the faces.
    Tree,
    /// A hash grid of the faces, walked cell by cell along the ray.
    Grid,
}

/// Arguments of `proxima raycast`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz).
    mesh: PathBuf,
    /// Ray origin.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true,
          required_unless_present = "rays", conflicts_with = "rays")]
    origin: Option<Vec3>,
    /// Ray direction (normalized here, so t is a distance).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true,
          required_unless_present = "rays", conflicts_with = "rays")]
    dir: Option<Vec3>,
    /// A file of rays, one per line: `ox oy oz dx dy dz` separated by commas
    /// or white space (`#` comments and blank lines skipped). Prints CSV
    /// `ray,t,face` in input order (`inf,-1` for a miss; with `--any`,
    /// `ray,hit` with 1 or 0), cast on all cores with the 4-wide tree.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["method", "cell"])]
    rays: Option<PathBuf>,
    /// With --rays: worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T", requires = "rays")]
    threads: Option<usize>,
    /// Search structure; default `tree`, or `grid` when `--cell` is given.
    #[arg(long, value_enum)]
    method: Option<RayMethod>,
    /// Grid cell extents (W or W,H,D); by default about one cell per triangle
    /// along the bounding box (longest side / cube root of the triangle
    /// count). Implies `--method grid`.
    #[arg(long, value_name = "W[,H,D]", value_parser = parse_cell, allow_hyphen_values = true)]
    cell: Option<Vec3>,
    /// Only say whether the ray hits a face (occlusion test; stops at the first
    /// hit found).
    #[arg(long)]
    any: bool,
    /// With --rays: add where each hit lies, the columns of `closest
    /// --attributes` (triangle,u,v,feature,fa,fb,nx,ny,nz,fnx,fny,fnz,tu,tv; u, v
    /// the ray test's own), empty for a miss.
    #[arg(long, requires = "rays", conflicts_with_all = ["any", "json"])]
    attributes: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// What was found, in the terms both methods share.
struct Found {
    face: u32,
    t: f32,
    point: Vec3,
    /// Nodes (tree) or cells (grid) visited.
    visited: u64,
}

/// Prints the hit face, t and point, or "no hit" (or, with `--rays`, a row per ray).
pub fn run(args: Args) -> Result<()> {
    let (Some(origin), Some(dir)) = (args.origin, args.dir) else {
        let rays = args
            .rays
            .as_deref()
            .context("give --origin and --dir, or --rays FILE")?;
        return super::raycast_batch::run(&super::raycast_batch::Batch {
            mesh: &args.mesh,
            rays,
            threads: args.threads,
            any: args.any,
            json: args.json,
            attributes: args.attributes,
        });
    };
    let method = match (args.method, args.cell) {
        (Some(RayMethod::Tree), Some(_)) => {
            use clap::CommandFactory;
            crate::Cli::command()
                .error(
                    clap::error::ErrorKind::ArgumentConflict,
                    "--cell sets the grid's cells; it cannot be used with --method tree",
                )
                .exit()
        }
        (Some(m), _) => m,
        (None, Some(_)) => RayMethod::Grid,
        (None, None) => RayMethod::Tree,
    };
    if !dir.is_finite() || dir == Vec3::ZERO {
        return Err(RayError::Direction.into());
    }
    let mesh = load_mesh(&args.mesh)?;
    if mesh.face_count() == 0 {
        bail!("{}: the mesh has no faces to hit", args.mesh.display());
    }
    let triangles = mesh.triangles();
    let direction = crate::common::unit_direction(dir);
    let (found, any, build, query, structure, label) = match method {
        RayMethod::Tree => {
            let start = Instant::now();
            let tree = AabbTree::build_set(triangles, &BuildConfig::default())
                .with_context(|| args.mesh.display().to_string())?;
            let build = start.elapsed().as_secs_f64();
            let start = Instant::now();
            let (found, any) = if args.any {
                (None, tree.any_hit(origin, direction, 0.0, f32::INFINITY)?)
            } else {
                let (hit, stats) = tree.first_hit_with_stats(origin, direction, 0.0, f32::INFINITY)?;
                let found = hit.map(|h| Found {
                    face: h.source,
                    t: h.t,
                    point: h.point,
                    visited: stats.nodes_visited,
                });
                let any = found.is_some();
                (found, any)
            };
            let query = start.elapsed().as_secs_f64();
            let nodes = tree.node_count();
            let label = format!("tree of {nodes} nodes");
            (
                found,
                any,
                build,
                query,
                json!({"method": "tree", "nodes": nodes}),
                label,
            )
        }
        RayMethod::Grid => {
            let cell = match args.cell {
                Some(cell) => cell,
                None => {
                    let side = mesh.bounds().size().max_element();
                    let cell = side / (triangles.len() as f32).cbrt().max(1.0);
                    // No extent to size cells by: say so, not "cell size 0" the user never gave.
                    if !(cell > 0.0 && cell.is_finite()) {
                        return Err(anyhow::Error::new(proxima::GridError::DegenerateBounds)
                            .context(format!("{} (give --cell)", args.mesh.display())));
                    }
                    Vec3::splat(cell)
                }
            };
            let start = Instant::now();
            let config = GridConfig {
                memory_budget: crate::common::memory_budget()?,
                max_cell_tests: crate::common::max_cell_tests()?,
                ..GridConfig::new(cell)
            };
            let grid: HashGrid<Triangle, FastHash> = HashGrid::build(triangles, &config)
                .map_err(|e| {
                    crate::common::name_option(e.into(), || match args.cell {
                        Some(_) => crate::common::cell_option(cell),
                        None => format!("the default cell size {}", cell.x),
                    })
                })
                .with_context(|| args.mesh.display().to_string())?;
            let build = start.elapsed().as_secs_f64();
            let start = Instant::now();
            let (hit, stats) = grid.first_hit_with_stats(origin, direction, 0.0, f32::INFINITY)?;
            let query = start.elapsed().as_secs_f64();
            let found = hit.map(|h| Found {
                face: h.source,
                t: h.t,
                point: h.point,
                visited: stats.nodes_visited,
            });
            let any = found.is_some();
            let label = format!("grid cell {:?}", cell.to_array());
            (
                found,
                any,
                build,
                query,
                json!({"method": "grid", "cell": cell.to_array()}),
                label,
            )
        }
    };
    let visited_key = match method {
        RayMethod::Tree => "nodes_visited",
        RayMethod::Grid => "cells_visited",
    };
    if args.json {
        let mut out = json!({"build_seconds": build, "query_seconds": query});
        if args.any {
            out["any_hit"] = json!(any);
        } else {
            out["hit"] = json!(
                found.map(|h| json!({"face": h.face, "t": h.t, "point": h.point.to_array(), visited_key: h.visited}))
            );
        }
        for (key, value) in structure.as_object().into_iter().flatten() {
            out[key] = value.clone();
        }
        crate::outln!("{out:#}");
        return Ok(());
    }
    if args.any {
        crate::outln!("{}", if any { "hit" } else { "no hit" });
        return Ok(());
    }
    match found {
        Some(h) => {
            let visited = visited_key.replace('_', " ");
            crate::outln!(
                "hit face {} at t = {} point {} {} {} ({} {visited}, {label})",
                h.face,
                h.t,
                h.point.x,
                h.point.y,
                h.point.z,
                h.visited
            )
        }
        None => crate::outln!("no hit"),
    }
    Ok(())
}
