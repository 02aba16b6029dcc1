//! `proxima radius POINTS --queries FILE --radius R [--max N] [--threads T]`:
//! every point of a cloud within `R` of each query, exactly (see
//! [`proxima::points::PointCloud::within_batch`]), as CSV
//! `query,index,distance`, nearest first (ties by index).

use crate::common::cloud_queries_pool;
use anyhow::{Result, bail};
use std::io::{BufWriter, Write};
use std::path::PathBuf;

/// Arguments of `proxima radius`.
#[derive(clap::Args)]
pub struct Args {
    /// The cloud: a points file (three numbers per line) or a mesh file,
    /// whose vertices are the points.
    points: PathBuf,
    /// A file of query points, three numbers per line.
    #[arg(long, value_name = "FILE")]
    queries: PathBuf,
    /// The radius: points at distance at most R (exactly) are listed.
    #[arg(short, long, value_name = "R", allow_hyphen_values = true)]
    radius: f64,
    /// At most this many per query, the nearest (the ball query).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    max: Option<u64>,
    /// Worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
}

/// Runs `proxima radius`.
pub fn run(args: Args) -> Result<()> {
    if args.radius.is_nan() || args.radius < 0.0 {
        bail!("--radius {}: must be a non-negative number", args.radius);
    }
    let (cloud, queries, pool) = cloud_queries_pool(&args.points, &args.queries, args.threads)?;
    let most = args.max.map(|m| usize::try_from(m).unwrap_or(usize::MAX));
    let rows = pool
        .install(|| cloud.within_batch(&queries, args.radius, most))
        .map_err(|e| anyhow::anyhow!("{}", e.to_string().replacen("radius ", "--radius ", 1)))?;
    let mut out = BufWriter::new(std::io::stdout().lock());
    writeln!(out, "query,index,distance")?;
    for q in 0..rows.len() {
        let (indices, distances) = rows.of(q);
        for (index, distance) in indices.iter().zip(distances) {
            writeln!(out, "{q},{index},{distance}")?;
        }
    }
    out.flush()?;
    Ok(())
}
