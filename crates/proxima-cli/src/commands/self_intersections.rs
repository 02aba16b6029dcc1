//! `proxima self-intersections MESH [--out pairs.csv] [--json] [--threads T]`:
//! the pairs of faces of one mesh that meet beyond the vertices and edges
//! they share (see [`proxima::pair::self_intersections`]), as CSV
//! `face_a,face_b` (`face_a < face_b`, sorted) on standard output or to
//! `--out`, or JSON; the count on the summary line.

use crate::common::{load_mesh, note, require_primitives, thread_count};
use anyhow::{Context, Result};
use proxima::index::MeshIndex;
use proxima::pair;
use proxima::prelude::*;
use serde_json::json;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `proxima self-intersections`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file.
    mesh: PathBuf,
    /// Write the pairs as CSV to this file instead of standard output.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Print one JSON object (with the pairs, unless --out takes them)
    /// instead of CSV and the summary line.
    #[arg(long)]
    json: bool,
    /// Worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
}

/// Runs `proxima self-intersections`.
pub fn run(args: Args) -> Result<()> {
    let threads = args.threads.map_or(Ok(0), thread_count)?;
    let mesh = load_mesh(&args.mesh)?;
    require_primitives(&mesh, PrimitiveKind::Faces, &args.mesh)?;
    let index = MeshIndex::new(mesh);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("thread pool")?;
    let start = Instant::now();
    let pairs = pool
        .install(|| pair::self_intersections(&index))
        .with_context(|| args.mesh.display().to_string())?;
    let seconds = start.elapsed().as_secs_f64();

    if let Some(path) = &args.out {
        let file = std::fs::File::create(path).with_context(|| path.display().to_string())?;
        let mut file = BufWriter::new(file);
        write_csv(&mut file, &pairs).with_context(|| path.display().to_string())?;
    }
    let mut out = BufWriter::new(std::io::stdout().lock());
    if args.json {
        let summary = json!({
            "mesh": args.mesh.display().to_string(),
            "faces": index.mesh().face_count(),
            "count": pairs.len(),
            "threads": pool.current_num_threads(),
            "seconds": seconds,
            "out": args.out.as_ref().map(|p| p.display().to_string()),
        });
        let summary = serde_json::to_string_pretty(&summary)?;
        if args.out.is_some() {
            writeln!(out, "{summary}")?;
        } else {
            // The pairs, one per line, after the summary's keys.
            write!(
                out,
                "{},\n  \"pairs\": [",
                summary.trim_end().trim_end_matches('}').trim_end()
            )?;
            for (i, pair) in pairs.iter().enumerate() {
                let separator = if i == 0 { "" } else { "," };
                write!(out, "{separator}\n    {}", json!(pair))?;
            }
            writeln!(out, "\n  ]\n}}")?;
        }
    } else if args.out.is_none() {
        write_csv(&mut out, &pairs)?;
    }
    out.flush()?;
    if !args.json {
        let to = args
            .out
            .as_ref()
            .map_or("standard output".to_string(), |p| p.display().to_string());
        note(&format!(
            "{}: {} faces, {} self-intersecting face pairs; {seconds:.3} s; written to {to}",
            args.mesh.display(),
            index.mesh().face_count(),
            pairs.len()
        ));
    }
    Ok(())
}

/// The pairs as CSV `face_a,face_b`, header first.
fn write_csv(out: &mut impl Write, pairs: &[pair::FacePair]) -> std::io::Result<()> {
    writeln!(out, "face_a,face_b")?;
    for [a, b] in pairs {
        writeln!(out, "{a},{b}")?;
    }
    out.flush()
}
