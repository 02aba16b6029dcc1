//! `proxima raycast MESH --rays FILE [--threads T] [--any] [--json]`: every
//! ray of a file cast on all cores with the 8-wide ray tree ([`RayTree`]), answers in input
//! order as CSV `ray,t,face` (`inf,-1` for a miss) or `ray,hit` with `--any`.

use crate::common::{load_mesh, read_rays, thread_count, unit_direction};
use crate::surface_columns::{self, SurfaceColumns};
use anyhow::{Context, Result, bail};
use proxima::prelude::*;
use proxima::surface::{SurfacePoint, vertex_normals};
use proxima::{RayHit, RayTree};
use serde_json::json;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::Instant;

/// Rays answered and written at a time, so memory holds one chunk's answers
/// whatever the size of the file.
const CHUNK: usize = 1 << 20;

/// What `raycast --rays FILE` was asked (`raycast.rs` owns the options).
pub struct Batch<'a> {
    /// The mesh file.
    pub mesh: &'a Path,
    /// The rays file.
    pub rays: &'a Path,
    /// Worker threads; all cores when `None`.
    pub threads: Option<usize>,
    /// Only whether each ray hits (`ray,hit`).
    pub any: bool,
    /// A JSON summary instead of rows.
    pub json: bool,
    /// The surface columns of each hit (`--attributes`).
    pub attributes: bool,
}

/// Casts the rays of `args.rays` and prints one row per ray, or a JSON summary.
pub fn run(args: &Batch) -> Result<()> {
    let file = args.rays;
    let threads = match args.threads {
        Some(t) => thread_count(t)?,
        None => 0,
    };
    let rays = read_rays(file)?;
    let mesh = load_mesh(args.mesh)?;
    if mesh.face_count() == 0 {
        bail!("{}: the mesh has no faces to hit", args.mesh.display());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("thread pool")?;
    let start = Instant::now();
    let tree = pool
        .install(|| RayTree::build(&mesh))
        .with_context(|| args.mesh.display().to_string())?;
    let build_seconds = start.elapsed().as_secs_f64();
    // Unit directions, so that t is a distance; the file's rays were checked
    // by the reader, and a unit direction passes the same checks.
    let rays: Vec<(Vec3, Vec3)> = rays.into_iter().map(|(o, d)| (o, unit_direction(d))).collect();

    let normals = if args.attributes {
        vertex_normals(&mesh)
    } else {
        Vec::new()
    };
    let surface = args.attributes.then(|| SurfaceColumns {
        mesh: &mesh,
        normals: &normals,
    });
    let mut out = BufWriter::new(std::io::stdout().lock());
    let header = match (args.any, args.attributes) {
        (true, _) => "ray,hit".to_string(),
        (false, attributes) => {
            let columns = if attributes { surface_columns::HEADER } else { "" };
            format!("ray,t,face{columns}")
        }
    };
    // Written with the first rows, once they are known to be answers (an
    // error leaves standard output empty).
    let mut header_due = !args.json;
    let (mut hits, mut seconds) = (0usize, 0f64);
    for (chunk_index, chunk) in rays.chunks(CHUNK).enumerate() {
        let first = chunk_index * CHUNK;
        let start = Instant::now();
        // Whether each ray hits, and (without --any) the first hit.
        let answers: Vec<Result<(bool, Option<RayHit>), proxima::RayError>> = if args.any {
            let any = pool.install(|| tree.any_hit_batch(chunk, 0.0, f32::INFINITY));
            any.into_iter().map(|r| r.map(|hit| (hit, None))).collect()
        } else {
            let first_hits = pool.install(|| tree.first_hit_batch(chunk, 0.0, f32::INFINITY));
            first_hits
                .into_iter()
                .map(|r| r.map(|hit| (hit.is_some(), hit)))
                .collect()
        };
        // The reader checked every ray; what is left is an origin too far
        // from this mesh for its hits to be told apart.
        if let Some((i, Err(e))) = answers.iter().enumerate().find(|(_, a)| a.is_err()) {
            bail!("{}: ray {} (counting from 0): {e}", file.display(), first + i);
        }
        let answers: Vec<(bool, Option<RayHit>)> = answers.into_iter().flatten().collect();
        seconds += start.elapsed().as_secs_f64();
        hits += answers.iter().filter(|a| a.0).count();
        if args.json {
            continue;
        }
        let mut text = Vec::with_capacity(answers.len() * 24);
        if std::mem::take(&mut header_due) {
            writeln!(text, "{header}")?;
        }
        for (i, &(hit, answer)) in answers.iter().enumerate() {
            let ray = first + i;
            match (args.any, &answer) {
                (true, _) => write!(text, "{ray},{}", u8::from(hit))?,
                (false, Some(hit)) => write!(text, "{ray},{},{}", hit.t, hit.source)?,
                (false, None) => write!(text, "{ray},inf,-1")?,
            }
            match (&surface, &answer) {
                (Some(surface), Some(hit)) => surface.write(&mut text, &SurfacePoint::of_ray_hit(&mesh, hit))?,
                (Some(_), None) => text.extend_from_slice(surface_columns::EMPTY.as_bytes()),
                (None, _) => {}
            }
            writeln!(text)?;
        }
        out.write_all(&text)?;
    }
    if header_due {
        writeln!(out, "{header}")?;
    }
    if args.json {
        let summary = json!({
            "rays": rays.len(),
            "hits": hits,
            "seconds": seconds,
            "rays_per_second": if seconds > 0.0 { rays.len() as f64 / seconds } else { 0.0 },
            "threads": pool.current_num_threads(),
            "build_seconds": build_seconds,
            "any": args.any,
            "triangles": tree.len(),
        });
        writeln!(out, "{summary:#}")?;
    }
    out.flush()?;
    Ok(())
}
