//! `proxima traverse --origin X,Y,Z --dir X,Y,Z --cell W[,H,D]`: the cells a ray
//! walks through (Amanatides & Woo), as CSV.

use super::grid::parse_cell;
use crate::common::parse_vec3;
use anyhow::{Result, bail};
use proxima::grid::{GridTraversal, TraversalConfig};
use proxima::{GridError, RayError, Vec3};
use std::io::{BufWriter, Write};

/// Arguments of `proxima traverse`.
#[derive(clap::Args)]
pub struct Args {
    /// Ray origin.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    origin: Vec3,
    /// Ray direction (normalized here, so t is a distance).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    dir: Vec3,
    /// Cell extents: one number for cubic cells, or W,H,D. Cell 0,0,0 starts at the world origin.
    #[arg(long, value_name = "W[,H,D]", value_parser = parse_cell, allow_hyphen_values = true)]
    cell: Vec3,
    /// Number of cells to print (at most 10,000,000; the walk also ends
    /// where t no longer fits a float).
    #[arg(long, default_value_t = 16)]
    steps: u64,
}

/// The most rows `--steps` may ask for: about 500 MB of CSV, a few seconds.
pub const MAX_STEPS: u64 = 10_000_000;

/// Prints `step,i,j,k,t_enter,t_exit` for each cell.
pub fn run(args: Args) -> Result<()> {
    if args.dir == Vec3::ZERO {
        return Err(GridError::Ray(RayError::Direction).into());
    }
    if args.steps > MAX_STEPS {
        bail!("--steps {} is more than the limit of {MAX_STEPS} cells", args.steps);
    }
    let config = TraversalConfig {
        max_steps: args.steps,
        ..TraversalConfig::new(args.cell)
    };
    let walk = GridTraversal::new(args.origin, crate::common::unit_direction(args.dir), &config)?;
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    writeln!(out, "step,i,j,k,t_enter,t_exit")?;
    for (n, s) in walk.enumerate() {
        writeln!(
            out,
            "{n},{},{},{},{},{}",
            s.cell[0], s.cell[1], s.cell[2], s.t_enter, s.t_exit
        )?;
    }
    out.flush()?;
    Ok(())
}
