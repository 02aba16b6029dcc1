//! `proxima hausdorff A B [--tolerance T] [--one-sided] [--vertices]
//! [--threads T] [--json]`: the Hausdorff distance between two meshes'
//! surfaces (bounds within the tolerance, see
//! [`proxima::pair::hausdorff`]), or between two point sets (exact, see
//! [`proxima::points::chamfer`]) when either file is a points file (`.xyz`,
//! `.npy`, …) or `--vertices` asks for the meshes' vertices. CSV
//! `direction,lower,upper,px,py,pz,qx,qy,qz,index_p,index_q`, one row per
//! direction: `p` the farthest point found, on the side measured from, `q`
//! its nearest on the other side, the indices their faces (surfaces) or
//! points (point sets).

use crate::common::{load_cloud, load_mesh, note, require_primitives, thread_count};
use anyhow::{Context, Result, bail};
use proxima::index::MeshIndex;
use proxima::pair::{self, DirectedHausdorff};
use proxima::points::PointCloud;
use proxima::prelude::*;
use serde_json::json;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `proxima hausdorff`.
#[derive(clap::Args)]
pub struct Args {
    /// The first mesh or points file (A).
    a: PathBuf,
    /// The second mesh or points file (B).
    b: PathBuf,
    /// How far apart the bounds may end, in the meshes' units (default 1e-4
    /// of the larger bounding-box diagonal; at least 1e-7 of it). Surfaces
    /// only: between point sets the distance is exact.
    #[arg(long, value_name = "T", value_parser = parse_tolerance, allow_hyphen_values = true)]
    tolerance: Option<f64>,
    /// Only from A to B.
    #[arg(long)]
    one_sided: bool,
    /// Compare the meshes' vertices as point sets, not their surfaces.
    #[arg(long)]
    vertices: bool,
    /// Worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
    /// Print one JSON object instead of CSV and the summary line.
    #[arg(long)]
    json: bool,
}

/// The CSV header.
pub const CSV_HEADER: &str = "direction,lower,upper,px,py,pz,qx,qy,qz,index_p,index_q";

/// Parses `--tolerance`: a positive number (the meshes decide how small).
fn parse_tolerance(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(t) if t > 0.0 => Ok(t),
        _ => Err(format!("'{text}' is not a number > 0")),
    }
}

/// One direction's answer, whichever the inputs.
struct Row {
    direction: &'static str,
    lower: f64,
    upper: f64,
    p: [f64; 3],
    q: [f64; 3],
    index_p: u32,
    index_q: u32,
}

impl Row {
    fn of_surfaces(direction: &'static str, d: &DirectedHausdorff) -> Self {
        Self {
            direction,
            lower: d.lower,
            upper: d.upper,
            p: d.point.to_array(),
            q: d.closest.to_array(),
            index_p: d.face,
            index_q: d.closest_face,
        }
    }
}

/// Runs `proxima hausdorff`.
pub fn run(args: Args) -> Result<()> {
    let threads = args.threads.map_or(Ok(0), thread_count)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("thread pool")?;
    let is_mesh = |p: &Path| proxima::io::Format::from_path(p).is_some();
    let surfaces = !args.vertices && is_mesh(&args.a) && is_mesh(&args.b);
    if !surfaces && args.tolerance.is_some() {
        bail!("--tolerance: between point sets the distance is exact; the tolerance is for two meshes' surfaces");
    }
    let start = Instant::now();
    let (rows, tolerance) = if surfaces {
        surface_rows(&args, &pool)?
    } else {
        (point_rows(&args, &pool)?, 0.0)
    };
    let seconds = start.elapsed().as_secs_f64();
    let lower = rows.iter().map(|r| r.lower).fold(0.0, f64::max);
    let upper = rows.iter().map(|r| r.upper).fold(0.0, f64::max);

    let mut out = BufWriter::new(std::io::stdout().lock());
    if args.json {
        let directions: Vec<_> = rows
            .iter()
            .map(|r| {
                json!({
                    "direction": r.direction,
                    "lower": r.lower,
                    "upper": r.upper,
                    "point": r.p,
                    "nearest": r.q,
                    "index": r.index_p,
                    "nearest_index": r.index_q,
                })
            })
            .collect();
        let answer = json!({
            "a": args.a.display().to_string(),
            "b": args.b.display().to_string(),
            "compared": if surfaces { "surfaces" } else { "points" },
            "tolerance": tolerance,
            "lower": lower,
            "upper": upper,
            "directions": directions,
            "threads": pool.current_num_threads(),
            "seconds": seconds,
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&answer)?)?;
    } else {
        writeln!(out, "{CSV_HEADER}")?;
        for r in &rows {
            writeln!(
                out,
                "{},{},{},{},{},{},{},{},{},{},{}",
                r.direction, r.lower, r.upper, r.p[0], r.p[1], r.p[2], r.q[0], r.q[1], r.q[2], r.index_p, r.index_q
            )?;
        }
    }
    out.flush()?;
    if !args.json {
        let what = if surfaces {
            format!("surfaces, tolerance {tolerance:e}")
        } else {
            "point sets, exact".into()
        };
        note(&format!("hausdorff in [{lower}, {upper}] ({what}); {seconds:.3} s"));
    }
    Ok(())
}

/// Both surfaces' bounds, and the tolerance used.
fn surface_rows(args: &Args, pool: &rayon::ThreadPool) -> Result<(Vec<Row>, f64)> {
    let load = |path: &Path| -> Result<MeshIndex> {
        let mesh = load_mesh(path)?;
        require_primitives(&mesh, PrimitiveKind::Faces, path)?;
        Ok(MeshIndex::new(mesh))
    };
    let (a, b) = (load(&args.a)?, load(&args.b)?);
    let diagonal = |m: &MeshIndex| f64::from(m.mesh().bounds().diagonal());
    let tolerance = args.tolerance.unwrap_or(1e-4 * diagonal(&a).max(diagonal(&b)));
    let name = |e: pair::PairError| match e {
        pair::PairError::BadTolerance { value, minimum } => {
            anyhow::anyhow!("--tolerance {value:e}: must be at least {minimum:e} (1e-7 of the meshes' size)")
        }
        other => other.into(),
    };
    pool.install(|| {
        if args.one_sided {
            let d = pair::directed_hausdorff(&a, &b, tolerance).map_err(name)?;
            Ok((vec![Row::of_surfaces("a_to_b", &d)], tolerance))
        } else {
            let h = pair::hausdorff(&a, &b, tolerance).map_err(name)?;
            Ok((
                vec![
                    Row::of_surfaces("a_to_b", &h.forward),
                    Row::of_surfaces("b_to_a", &h.backward),
                ],
                tolerance,
            ))
        }
    })
}

/// Both point sets' exact distances.
fn point_rows(args: &Args, pool: &rayon::ThreadPool) -> Result<Vec<Row>> {
    let (a, b) = (load_cloud(&args.a)?, load_cloud(&args.b)?);
    pool.install(|| {
        let c = proxima::points::chamfer(&a, &b);
        let row = |direction, from: &PointCloud, to: &PointCloud, d: &proxima::points::Directed| {
            let p = from.points()[d.argmax as usize];
            let nearest = to
                .k_nearest(p, 1)
                .expect("a point of a cloud is a valid query")
                .first()
                .copied()
                .expect("the other cloud is not empty");
            let q = to.points()[nearest.index as usize];
            Row {
                direction,
                lower: d.max,
                upper: d.max,
                p: p.as_dvec3().to_array(),
                q: q.as_dvec3().to_array(),
                index_p: d.argmax,
                index_q: nearest.index,
            }
        };
        let mut rows = vec![row("a_to_b", &a, &b, &c.forward)];
        if !args.one_sided {
            rows.push(row("b_to_a", &b, &a, &c.backward));
        }
        Ok(rows)
    })
}
