//! `proxima voxelize MESH --res N`: the cells of an N³ grid over the mesh's
//! bounding box that the surface touches.

use super::grid::{Insert, check_extension, write_binvox, write_boxes};
use crate::common::load_mesh;
use anyhow::{Context, Result, bail};
use proxima::grid::{VoxelConfig, VoxelGrid, voxelize};
use serde_json::json;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `proxima voxelize`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz).
    mesh: PathBuf,
    /// Cells along the longest side of the bounding box.
    #[arg(long, value_name = "N")]
    res: u32,
    /// Worker threads (0: one per core; at most 4 per core, at least 8).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Insertion method (both give the same cells).
    #[arg(long, value_enum, default_value = "scanline")]
    insert: Insert,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Write the occupied cells: .csv (`i,j,k`), .ply (boxes) or .binvox.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
}

/// The largest `--res` written as .binvox: the format lists every voxel, so
/// its writing time grows as N³ (1024³ voxels take a few seconds).
const MAX_BINVOX_RES: u32 = 1024;

/// `true` when `path` ends in `.ext` (any case).
fn extension_is(path: &Path, ext: &str) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// Voxelizes the mesh and prints the occupied-cell count and the time.
pub fn run(args: Args) -> Result<()> {
    if let Some(path) = &args.out {
        check_extension(path, &["csv", "ply", "binvox"], "voxelize --out")?;
        if extension_is(path, "binvox") && args.res > MAX_BINVOX_RES {
            bail!(
                "{}: --res {}: a .binvox file is written voxel by voxel ({} voxels); it is limited to --res {MAX_BINVOX_RES}",
                path.display(),
                args.res,
                (args.res as u128).pow(3)
            );
        }
    }
    let threads = crate::common::thread_count(args.threads)?;
    let mesh = load_mesh(&args.mesh)?;
    crate::common::require_primitives(&mesh, proxima::PrimitiveKind::Faces, &args.mesh)?;
    let triangles = mesh.triangles().primitives;
    let bounds = mesh.bounds();
    let config = VoxelConfig {
        insert: args.insert.method(),
        parallel: args.threads != 1,
        memory_budget: crate::common::memory_budget()?,
        max_cell_tests: crate::common::max_cell_tests()?,
        ..VoxelConfig::new(args.res)
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    let threads = pool.current_num_threads();
    let start = Instant::now();
    let voxels = pool
        .install(|| voxelize(&triangles, &bounds, &config))
        .map_err(|e| crate::common::name_option(e.into(), || format!("--res {}", args.res)))
        .with_context(|| args.mesh.display().to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.out {
        write_voxels(path, &voxels)?;
    }
    if args.json {
        let out = json!({
            "res": args.res, "cell": voxels.cell_size(), "origin": voxels.origin().to_array(),
            "occupied": voxels.occupied(), "seconds": seconds, "threads": if config.parallel { threads } else { 1 },
            "dense": voxels.is_dense(), "triangles": triangles.len(),
        });
        crate::outln!("{out:#}");
    } else {
        crate::outln!(
            "{} occupied cells of {}³ (cell {}, origin {:?}) in {:.2} ms, {} triangles, {} thread(s)",
            voxels.occupied(),
            args.res,
            voxels.cell_size(),
            voxels.origin().to_array(),
            seconds * 1e3,
            triangles.len(),
            if config.parallel { threads } else { 1 }
        );
    }
    Ok(())
}

fn write_voxels(path: &Path, voxels: &VoxelGrid) -> Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let n = voxels.resolution();
    match ext.as_str() {
        "binvox" => write_binvox(path, n, voxels.origin(), voxels.cell_size() * n as f32, |c| {
            voxels.contains(c)
        }),
        _ => {
            let file = std::fs::File::create(path).with_context(|| format!("{}", path.display()))?;
            let mut out = BufWriter::new(file);
            // Streamed from the storage: no second copy of the cells.
            let result = if ext == "ply" {
                write_boxes(&mut out, voxels.layout(), voxels.iter(), voxels.occupied() as usize)
            } else {
                (|| {
                    writeln!(out, "i,j,k")?;
                    for c in voxels.iter() {
                        writeln!(out, "{},{},{}", c[0], c[1], c[2])?;
                    }
                    out.flush()
                })()
            };
            result.with_context(|| format!("{}", path.display()))
        }
    }
}
