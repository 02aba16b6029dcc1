//! The options of a benchmark run, as `proxima bench` and the `bench` binary
//! take them: what is measured, on which queries, with which build.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use proxima::prelude::*;
use std::path::PathBuf;

/// The query sets of BENCHMARKS.md.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum QuerySet {
    /// Surface samples plus a gaussian offset of 1% of the bbox diagonal.
    Near,
    /// Uniform in the bounding box enlarged by 10% per side.
    Uniform,
}

/// What is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum QueryKind {
    /// Closest-point queries, per primitive type.
    Closest,
    /// Signed distances on the faces: winding-number and pseudonormal signs,
    /// single queries and batches, against the plain closest query and linear
    /// search (the exact winding number); the near and uniform sets unless
    /// --set or --points chooses one.
    Sdf,
    /// First-hit rays on the faces (--queries rays of the BENCHMARKS rays
    /// set): linear search, the 4-wide tree, the ray tree one ray at a time
    /// and in batches (and parry3d in the `bench` binary of proxima-bench).
    Rays,
}

/// How trees are split, on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Split {
    /// Classic median split (fastest build).
    Median,
    /// Binned surface area heuristic (fewer nodes visited per query).
    Sah,
}

impl Split {
    /// The build configuration this names.
    pub fn config(self) -> BuildConfig {
        match self {
            Split::Median => BuildConfig::fast_build(),
            Split::Sah => BuildConfig::fast_queries(),
        }
    }

    /// The name the JSON output gives it (`median`, `sah`).
    pub fn name(self) -> &'static str {
        match self {
            Split::Median => "median",
            Split::Sah => "sah",
        }
    }
}

/// Which peer libraries' rows a run adds to proxima's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Peers {
    /// proxima's rows only: the shipped `proxima bench`, built without peers.
    None,
    /// parry3d's row too, on faces (closest points and rays): the `bench`
    /// binary of proxima-bench.
    #[cfg(feature = "peers")]
    Parry3d,
}

/// Arguments of `proxima bench` (and of proxima-bench's `bench` binary).
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file.
    pub mesh: PathBuf,
    /// Benchmark only this primitive type (default: vertices, edges and faces).
    #[arg(long, value_parser = kind_parser())]
    pub primitives: Option<PrimitiveKind>,
    /// Number of generated query points (rays with --query rays).
    #[arg(long, default_value_t = 10_000, conflicts_with = "points")]
    pub queries: usize,
    /// Query points from a file instead of generated ones.
    #[arg(long)]
    pub points: Option<PathBuf>,
    /// Which generated query set (default: near; with --query sdf, both).
    #[arg(long, value_enum)]
    pub set: Option<QuerySet>,
    /// What is measured.
    #[arg(long, value_enum, default_value = "closest")]
    pub query: QueryKind,
    /// Seed of the generated query set.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads for the query loops (1 = single-thread figures; at
    /// most 4 per core, at least 8).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// How the tree is split.
    #[arg(long, value_enum, default_value = "median")]
    pub split: Split,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// With `--primitives polygons`: the relative planarity tolerance of
    /// faces kept as polygons (see `proxima closest --help`).
    #[arg(long, value_parser = parse_planarity, default_value = "1e-5")]
    pub planarity: f32,
}

/// The parser of `--primitives`: one of [`PrimitiveKind::NAMES`], each
/// listed with its help.
fn kind_parser() -> impl TypedValueParser<Value = PrimitiveKind> {
    let values = PrimitiveKind::ALL
        .into_iter()
        .map(|kind| PossibleValue::new(kind.name()).help(kind.description()));
    PossibleValuesParser::new(values).map(|name| name.parse().expect("clap passes only the names it lists"))
}

/// Parses a relative planarity tolerance (finite, not negative).
fn parse_planarity(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{text}' is not a finite tolerance >= 0")),
    }
}
