//! `proxima grid MESH --cell W[,H,D]`: hash grid statistics per primitive type,
//! optionally the occupied cells as CSV or as a PLY of boxes. Also the cell
//! parser and the cell writers that `voxelize` shares.

use crate::common::{DEFAULT_KINDS, load_mesh, run_kind};
use anyhow::{Context, Result, bail};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use proxima::grid::{ClassicHash, FastHash, GridLayout, GridStats, InsertMethod};
use proxima::prelude::*;
use serde_json::json;
use std::hash::BuildHasher;
use std::io::{BufWriter, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Which primitives go into grids: one kind, or (`None`, named `all`) one
/// grid for each of [`DEFAULT_KINDS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GridKinds(Option<PrimitiveKind>);

/// The parser of `--primitives`: a kind's name or `all`.
fn grid_kinds_parser() -> impl TypedValueParser<Value = GridKinds> {
    let values = crate::common::kind_values().map(|value| match value.get_name() {
        "polygons" => value.help(
            "Faces as convex polygons where convex and planar within tolerance \
             (the others fan-triangulated; a note on stderr says how many)",
        ),
        _ => value,
    });
    let all = PossibleValue::new("all").help("One grid for each of vertices, edges and faces");
    PossibleValuesParser::new(values.chain([all])).map(|name| GridKinds(name.parse().ok()))
}

/// Insertion method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Insert {
    /// Every cell of the primitive's box, tested exactly.
    Classic,
    /// Slab-by-slab clipping, then the same exact test (same cells, fewer tests).
    Scanline,
}

impl Insert {
    /// The library's method.
    pub fn method(self) -> InsertMethod {
        match self {
            Insert::Classic => InsertMethod::Classic,
            Insert::Scanline => InsertMethod::Scanline,
        }
    }
}

/// Hash function of the cell keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Hasher {
    /// 131071·i + 524287·j + 8191·k (the classic design).
    Classic,
    /// The same sum through a multiply–xorshift finalizer.
    Fast,
}

/// Arguments of `proxima grid`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz).
    mesh: PathBuf,
    /// Cell extents: one number for cubic cells, or W,H,D.
    #[arg(long, value_name = "W[,H,D]", value_parser = parse_cell, allow_hyphen_values = true)]
    cell: Vec3,
    /// Grid origin (minimum corner of cell 0,0,0); the world origin by default.
    #[arg(long, value_name = "X,Y,Z", value_parser = crate::common::parse_vec3, allow_hyphen_values = true)]
    origin: Option<Vec3>,
    /// Primitives put into grids.
    #[arg(long, value_parser = grid_kinds_parser(), default_value = "all")]
    primitives: GridKinds,
    /// Insertion method (both give the same cells).
    #[arg(long, value_enum, default_value = "classic")]
    insert: Insert,
    /// Hash function of the cell keys. The classic hash is the library's
    /// default, for compatibility; with std's hash table (which picks buckets
    /// from the low bits) it measured 7-35x slower, so the tool uses the fast one.
    #[arg(long, value_enum, default_value = "fast")]
    hasher: Hasher,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// With `--primitives polygons`: the relative planarity tolerance of
    /// faces kept as polygons (see `proxima closest --help`).
    #[arg(long, value_parser = crate::common::parse_planarity, default_value = "1e-5")]
    planarity: f32,
    /// Write the occupied cells: CSV `i,j,k,count`, or a PLY of boxes when the
    /// name ends in .ply. With `--primitives all`, the cells of the face grid.
    #[arg(long, value_name = "FILE")]
    cells_out: Option<PathBuf>,
}

/// One built grid's figures, and its cells when asked for.
struct Built {
    kind: &'static str,
    stats: GridStats,
    seconds: f64,
    cells: Vec<([i64; 3], usize)>,
}

/// Builds the grid of one kind of primitive with the hash `S`, timed; its
/// cells are kept when `keep_cells`.
struct BuildGrid<'a, S> {
    config: &'a GridConfig,
    keep_cells: bool,
    hasher: PhantomData<S>,
}

impl<S: BuildHasher + Default> KindTask for BuildGrid<'_, S> {
    type Output = Result<Built>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> Result<Built> {
        let start = Instant::now();
        let grid: HashGrid<T, S> = HashGrid::build(set, self.config)?;
        let seconds = start.elapsed().as_secs_f64();
        let cells = if self.keep_cells {
            grid.occupied().map(|(c, p)| (c, p.len())).collect()
        } else {
            Vec::new()
        };
        Ok(Built {
            kind: T::KIND.name(),
            stats: grid.stats(),
            seconds,
            cells,
        })
    }
}

/// Builds the grid of `kind` over `mesh` with the hash `S`.
fn build_grid<S: BuildHasher + Default>(
    mesh: &Mesh,
    kind: PrimitiveKind,
    args: &Args,
    config: &GridConfig,
    keep_cells: bool,
) -> Result<Built> {
    let task = BuildGrid::<S> {
        config,
        keep_cells,
        hasher: PhantomData,
    };
    run_kind(mesh, kind, &args.mesh, args.planarity, task)
}

/// Builds the grids and prints their statistics.
pub fn run(args: Args) -> Result<()> {
    let mesh = load_mesh(&args.mesh)?;
    // `all` reports each kind there is; one kind must be there.
    match args.primitives.0 {
        Some(kind) => crate::common::require_primitives(&mesh, kind, &args.mesh)?,
        None => crate::common::require_vertices(&mesh, &args.mesh)?,
    }
    let config = GridConfig {
        origin: args.origin.unwrap_or(Vec3::ZERO),
        insert: args.insert.method(),
        memory_budget: crate::common::memory_budget()?,
        max_cell_tests: crate::common::max_cell_tests()?,
        ..GridConfig::new(args.cell)
    };
    config.layout()?;
    let kinds = match args.primitives.0 {
        None => DEFAULT_KINDS.to_vec(),
        Some(kind) => vec![kind],
    };
    let mut built = Vec::new();
    for (n, &kind) in kinds.iter().enumerate() {
        let keep_cells = args.cells_out.is_some() && n + 1 == kinds.len();
        let result = match args.hasher {
            Hasher::Classic => build_grid::<ClassicHash>(&mesh, kind, &args, &config, keep_cells),
            Hasher::Fast => build_grid::<FastHash>(&mesh, kind, &args, &config, keep_cells),
        };
        built.push(
            result
                .map_err(|e| crate::common::name_option(e, || crate::common::cell_option(args.cell)))
                .with_context(|| args.mesh.display().to_string())?,
        );
    }
    if let (Some(path), Some(last)) = (&args.cells_out, built.last()) {
        let layout = config.layout()?;
        write_cells(path, &layout, &last.cells)?;
    }
    let name = |v: clap::builder::PossibleValue| v.get_name().to_string();
    let insert = name(clap::ValueEnum::to_possible_value(&args.insert).expect("named"));
    let hasher = name(clap::ValueEnum::to_possible_value(&args.hasher).expect("named"));
    if args.json {
        let grids: Vec<_> = built
            .iter()
            .map(|b| {
                json!({
                    "primitives": b.kind, "count": b.stats.primitives, "occupied_cells": b.stats.occupied_cells,
                    "entries": b.stats.entries, "max_per_cell": b.stats.max_per_cell,
                    "mean_per_cell": b.stats.mean_per_cell, "memory_bytes": b.stats.memory_bytes,
                    "build_seconds": b.seconds,
                })
            })
            .collect();
        let out = json!({
            "mesh": args.mesh.display().to_string(), "cell": args.cell.to_array(),
            "origin": config.origin.to_array(), "insert": insert, "hasher": hasher, "grids": grids,
        });
        crate::outln!("{out:#}");
        return Ok(());
    }
    crate::outln!("mesh    {}", args.mesh.display());
    crate::outln!(
        "cell    {:?}  origin {:?}  insert {insert}  hasher {hasher}",
        args.cell.to_array(),
        config.origin.to_array()
    );
    crate::outln!();
    crate::outln!(
        "{:<10} {:>10} {:>10} {:>11} {:>9} {:>10} {:>10}",
        "grid",
        "count",
        "occupied",
        "entries",
        "max/cell",
        "mean/cell",
        "build ms"
    );
    for b in &built {
        let s = &b.stats;
        crate::outln!(
            "{:<10} {:>10} {:>10} {:>11} {:>9} {:>10.2} {:>10.2}",
            b.kind,
            s.primitives,
            s.occupied_cells,
            s.entries,
            s.max_per_cell,
            s.mean_per_cell,
            b.seconds * 1e3
        );
    }
    Ok(())
}

// ------------------------------------------------ shared with voxelize ---

/// Parses `W` (cubic cells) or `W,H,D`. Validity (finite, positive) is the
/// library's to check, so its message is the one shown.
pub fn parse_cell(text: &str) -> Result<Vec3, String> {
    let numbers: Vec<&str> = text.split([',', ' ']).filter(|s| !s.is_empty()).collect();
    let parse = |s: &str| s.parse::<f32>().map_err(|_| format!("'{s}' is not a number"));
    match numbers.as_slice() {
        [w] => Ok(Vec3::splat(parse(w)?)),
        [w, h, d] => Ok(Vec3::new(parse(w)?, parse(h)?, parse(d)?)),
        _ => Err(format!("expected W or W,H,D, got '{text}'")),
    }
}

/// The lower-case extension of `path`.
fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// Writes `(cell, count)` pairs: `.ply` as boxes, anything else as CSV
/// `i,j,k,count`.
pub fn write_cells(path: &Path, layout: &GridLayout, cells: &[([i64; 3], usize)]) -> Result<()> {
    let file = std::fs::File::create(path).with_context(|| format!("{}", path.display()))?;
    let mut out = BufWriter::new(file);
    let context = || format!("{}", path.display());
    if extension(path) == "ply" {
        write_boxes(&mut out, layout, cells.iter().map(|c| c.0), cells.len()).with_context(context)?;
    } else {
        (|| -> std::io::Result<()> {
            writeln!(out, "i,j,k,count")?;
            for (c, n) in cells {
                writeln!(out, "{},{},{},{n}", c[0], c[1], c[2])?;
            }
            out.flush()
        })()
        .with_context(context)?;
    }
    Ok(())
}

/// An ascii PLY with one box (8 vertices, 6 quads) per cell.
pub fn write_boxes(
    out: &mut impl Write,
    layout: &GridLayout,
    cells: impl Iterator<Item = [i64; 3]>,
    count: usize,
) -> std::io::Result<()> {
    writeln!(out, "ply\nformat ascii 1.0\ncomment proxima grid cells")?;
    writeln!(
        out,
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z",
        count * 8
    )?;
    writeln!(
        out,
        "element face {}\nproperty list uchar int vertex_indices\nend_header",
        count * 6
    )?;
    for c in cells {
        for p in layout.cell_box(c).corners() {
            writeln!(out, "{} {} {}", p.x, p.y, p.z)?;
        }
    }
    // The faces of box `b` use its corners 8b..8b+8, so they are written from
    // the count alone (no list held in memory). Corner bit 0 = max x, bit 1 =
    // max y, bit 2 = max z; outward quads.
    for b in 0..count {
        let n = 8 * b;
        for q in [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ] {
            writeln!(out, "4 {} {} {} {}", n + q[0], n + q[1], n + q[2], n + q[3])?;
        }
    }
    out.flush()
}

/// A binvox volume (`#binvox 1`, run-length encoded, y fastest, then z, then x)
/// of `res³` voxels; `contains` says which are occupied.
pub fn write_binvox(path: &Path, res: u32, origin: Vec3, side: f32, contains: impl Fn([i64; 3]) -> bool) -> Result<()> {
    let file = std::fs::File::create(path).with_context(|| format!("{}", path.display()))?;
    let mut out = BufWriter::new(file);
    let n = res as i64;
    (|| -> std::io::Result<()> {
        writeln!(
            out,
            "#binvox 1\ndim {res} {res} {res}\ntranslate {} {} {}\nscale {side}\ndata",
            origin.x, origin.y, origin.z
        )?;
        let (mut value, mut run) = (false, 0u8);
        for x in 0..n {
            for z in 0..n {
                for y in 0..n {
                    let v = contains([x, y, z]);
                    if run > 0 && (v != value || run == u8::MAX) {
                        out.write_all(&[value as u8, run])?;
                        run = 0;
                    }
                    value = v;
                    run += 1;
                }
            }
        }
        if run > 0 {
            out.write_all(&[value as u8, run])?;
        }
        out.flush()
    })()
    .with_context(|| format!("{}", path.display()))
}

/// Refuses an output extension `what` cannot write.
pub fn check_extension(path: &Path, allowed: &[&str], what: &str) -> Result<()> {
    let ext = extension(path);
    if !allowed.contains(&ext.as_str()) {
        bail!(
            "{}: {what} writes {}",
            path.display(),
            allowed.iter().map(|e| format!(".{e}")).collect::<Vec<_>>().join(", ")
        );
    }
    Ok(())
}
