//! `proxima knn POINTS --queries FILE [-k K] [--threads T]`: the `k`
//! nearest points of a cloud to each query (see
//! [`proxima::points::PointCloud::k_nearest_batch`]), as CSV
//! `query,rank,index,distance`, nearest first (ties by index).

use crate::common::cloud_queries_pool;
use anyhow::Result;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

/// Arguments of `proxima knn`.
#[derive(clap::Args)]
pub struct Args {
    /// The cloud: a points file (three numbers per line) or a mesh file,
    /// whose vertices are the points.
    points: PathBuf,
    /// A file of query points, three numbers per line.
    #[arg(long, value_name = "FILE")]
    queries: PathBuf,
    /// How many nearest points per query (fewer when the cloud has fewer).
    #[arg(short, long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1 << 31))]
    k: u32,
    /// Worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
}

/// Runs `proxima knn`.
pub fn run(args: Args) -> Result<()> {
    let (cloud, queries, pool) = cloud_queries_pool(&args.points, &args.queries, args.threads)?;
    let k = args.k as usize;
    let found = pool
        .install(|| cloud.k_nearest_batch(&queries, k))
        .map_err(|e| anyhow::anyhow!("{}", e.to_string().replacen("k ", "-k ", 1)))?;
    let mut out = BufWriter::new(std::io::stdout().lock());
    writeln!(out, "query,rank,index,distance")?;
    for q in 0..queries.len() {
        for rank in 0..k {
            let index = found.indices[q * k + rank];
            if index == u32::MAX {
                break;
            }
            writeln!(out, "{q},{rank},{index},{}", found.distances[q * k + rank])?;
        }
    }
    out.flush()?;
    Ok(())
}
