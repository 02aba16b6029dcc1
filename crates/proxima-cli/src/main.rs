//! `proxima`: closest points, frustum queries, rays, signed distances, hash
//! grids, voxelization, grid walks, distances and collisions between two
//! meshes, self-intersections, tree statistics, benchmarks and the
//! viewer on meshes, from the command line.
//!
//! Every failure on user input prints one line (`proxima: <file>:<line>: what`)
//! and exits with status 1; usage errors exit with status 2.

mod commands;
mod common;
mod npy;
mod poses;
mod surface_columns;
mod two_meshes;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Spatial acceleration structures for 3D meshes.
#[derive(Parser)]
#[command(name = "proxima", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the main job on the embedded model: load, build, query, benchmark.
    Demo(commands::demo::Args),
    /// Mesh counts, bounding box and tree statistics.
    Info(commands::info::Args),
    /// Closest vertices, edges or faces to query points, as CSV.
    Closest(commands::closest::Args),
    /// The k nearest points of a point cloud to query points, as CSV.
    Knn(commands::knn::Args),
    /// Every point of a point cloud within a radius of query points (exactly), as CSV.
    Radius(commands::radius::Args),
    /// The vertices, edges or faces a camera sees (overlapping its view frustum).
    Frustum(commands::frustum::Args),
    /// Linear search against the trees on the same queries (closest points, signed distances or rays).
    #[command(after_help = commands::bench::PEER_ROWS)]
    Bench(commands::bench::Args),
    /// Hash grid statistics per primitive type (occupied cells, primitives per cell, build time).
    Grid(commands::grid::Args),
    /// Surface voxelization at N³ over the bounding box: occupied cells and time.
    Voxelize(commands::voxelize::Args),
    /// The cells a ray walks through (Amanatides & Woo), as CSV.
    Traverse(commands::traverse::Args),
    /// The first face a ray hits: the AABB tree (default) or a hash grid (`--method grid`); `--rays FILE` casts a file with the 8-wide ray tree.
    Raycast(commands::raycast::Args),
    /// Signed distances (negative inside) at points as CSV, on an N³ grid as .npy, or at training samples as .npz.
    Sdf(commands::sdf::Args),
    /// The distance between two meshes placed by rigid poses, with the nearest points and faces, as CSV.
    Distance(commands::distance::Args),
    /// Whether two meshes placed by rigid poses meet, or which of their faces meet (`--pairs`), as CSV.
    Collide(commands::collide::Args),
    /// The Hausdorff distance between two meshes' surfaces (bounds within a tolerance) or two point sets, as CSV.
    Hausdorff(commands::hausdorff::Args),
    /// The pairs of faces of one mesh that cross or touch beyond what they share, as CSV.
    SelfIntersections(commands::self_intersections::Args),
    /// Interactive viewer (needs a display); `--screenshot` renders one frame to a PNG.
    View(commands::view::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(args) => commands::demo::run(args),
        Command::Info(args) => commands::info::run(args),
        Command::Closest(args) => commands::closest::run(args),
        Command::Knn(args) => commands::knn::run(args),
        Command::Radius(args) => commands::radius::run(args),
        Command::Bench(args) => commands::bench::run(args),
        Command::View(args) => commands::view::run(args),
        Command::Frustum(args) => commands::frustum::run(args),
        Command::Grid(args) => commands::grid::run(args),
        Command::Voxelize(args) => commands::voxelize::run(args),
        Command::Traverse(args) => commands::traverse::run(args),
        Command::Raycast(args) => commands::raycast::run(args),
        Command::Sdf(args) => commands::sdf::run(args),
        Command::Distance(args) => commands::distance::run(args),
        Command::Hausdorff(args) => commands::hausdorff::run(args),
        Command::Collide(args) => commands::collide::run(args),
        Command::SelfIntersections(args) => commands::self_intersections::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) if common::is_broken_pipe(&error) => ExitCode::SUCCESS,
        Err(error) => {
            // One line: the chain of causes joined, no backtrace.
            common::note(&common::one_line(&error));
            ExitCode::FAILURE
        }
    }
}
