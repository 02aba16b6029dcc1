//! What several commands share: argument parsers, mesh loading, primitive choice.

use anyhow::{Context, Result, anyhow, bail};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use proxima::prelude::*;
use std::path::{Path, PathBuf};

/// The error chain on one line (`outer: inner: root`), without repeats.
pub fn one_line(error: &anyhow::Error) -> String {
    let mut parts: Vec<String> = Vec::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if !parts.iter().any(|p| p.contains(&text)) {
            parts.push(text);
        }
    }
    // File names and echoed file content reach the terminal: no escape sequences.
    proxima::io::escape_for_terminal(&parts.join(": ").replace('\n', " "), usize::MAX)
}

/// Parses `X,Y,Z` (commas and/or spaces) into a finite point.
pub fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let numbers: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    if numbers.len() != 3 {
        return Err(format!("expected three numbers X,Y,Z, got '{text}'"));
    }
    let mut v = [0f32; 3];
    for (slot, s) in v.iter_mut().zip(&numbers) {
        *slot = s.parse::<f32>().map_err(|_| format!("'{s}' is not a number"))?;
        if !slot.is_finite() {
            return Err(format!("'{s}' is not a finite number"));
        }
    }
    Ok(Vec3::from_array(v))
}

/// `direction` scaled to unit length in `f64`, where its squared length can
/// neither overflow (`0,0,-3e38`) nor underflow (`1e-30,0,0`) as it does in
/// `f32`. A zero direction is returned as it is, for the library to refuse.
pub fn unit_direction(direction: Vec3) -> Vec3 {
    let d = direction.to_array().map(|x| x as f64);
    let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if length == 0.0 || !length.is_finite() {
        return direction;
    }
    Vec3::from_array(d.map(|x| (x / length) as f32))
}

/// Reads a points file (see [`proxima::io::parse_points`]): one point per
/// line, three numbers separated by commas or white space; `#` comments and
/// blank lines are skipped. Read within the same limits as meshes.
pub fn read_points(path: &Path) -> Result<Vec<Vec3>> {
    Ok(proxima::io::load_points(path, &load_options()?)?)
}

/// Reads a rays file (see [`proxima::io::parse_rays`]): one ray per line,
/// `ox oy oz dx dy dz`, with the limits and the line-numbered errors of
/// points files.
pub fn read_rays(path: &Path) -> Result<Vec<(Vec3, Vec3)>> {
    Ok(proxima::io::load_rays(path, &load_options()?)?)
}

/// The query points of `--point X,Y,Z` (checked against the trees' range,
/// see [`check_query_point`]) or `--points FILE` (see [`read_points`]),
/// whichever was given.
pub fn query_points(point: Option<Vec3>, points: Option<&Path>) -> Result<Vec<Vec3>> {
    match (point, points) {
        (Some(p), _) => {
            check_query_point(p, "--point")?;
            Ok(vec![p])
        }
        (None, Some(file)) => read_points(file),
        (None, None) => bail!("give --point X,Y,Z or --points FILE"),
    }
}

/// The loading limits, with the environment's overrides.
fn load_options() -> Result<proxima::io::LoadOptions> {
    proxima::io::LoadOptions::from_env().map_err(|e| anyhow!(e))
}

/// Loads a mesh; the error names the file (and line).
pub fn load_mesh(path: &Path) -> Result<Mesh> {
    Ok(proxima::io::load_with(path, &load_options()?)?)
}

/// Fails when the mesh has no vertices at all: there is nothing any command
/// could work on.
pub fn require_vertices(mesh: &Mesh, path: &Path) -> Result<()> {
    proxima::index::check_not_empty(mesh).with_context(|| path.display().to_string())
}

/// Fails with the point's line (or `--point`) when a query point lies beyond
/// the range the trees answer in; see [`proxima::check_query_point`].
pub fn check_query_point(p: Vec3, what: &str) -> Result<()> {
    proxima::check_query_point(p).map_err(|e| anyhow::anyhow!("{what}: {e}"))
}

/// The kinds commands report when none is asked for: polygons only on request
/// (or, in `info`, when the mesh has faces of more than three vertices).
pub const DEFAULT_KINDS: [PrimitiveKind; 3] = [PrimitiveKind::Vertices, PrimitiveKind::Edges, PrimitiveKind::Faces];

/// The values `--primitives` takes, each with its help, as `--help` lists them.
pub fn kind_values() -> impl Iterator<Item = PossibleValue> {
    PrimitiveKind::ALL
        .into_iter()
        .map(|kind| PossibleValue::new(kind.name()).help(kind.description()))
}

/// The parser of `--primitives`: one of [`PrimitiveKind::NAMES`].
pub fn kind_parser() -> impl TypedValueParser<Value = PrimitiveKind> {
    PossibleValuesParser::new(kind_values()).map(|name| name.parse().expect("clap passes only the names it lists"))
}

/// How trees are split, on the command line (the benchmarks' option, shared).
pub use proxima_bench::Split;

/// The embedded default model (see `assets/README.md` for source and licence).
pub const DEFAULT_MODEL_NAME: &str = "bunny-npm.obj (embedded)";
const DEFAULT_MODEL: &[u8] = include_bytes!("../assets/bunny-npm.obj");

/// Loads `path`, or the embedded default model when `None`.
pub fn load_or_default(path: Option<&PathBuf>) -> Result<(Mesh, String)> {
    match path {
        Some(p) => Ok((load_mesh(p)?, p.display().to_string())),
        None => Ok((
            proxima::io::parse(DEFAULT_MODEL, proxima::io::Format::Obj, Path::new(DEFAULT_MODEL_NAME))?,
            DEFAULT_MODEL_NAME.to_string(),
        )),
    }
}

/// Fails when the mesh has no primitive of `kind` (no vertices, no edges, or no faces).
pub fn require_primitives(mesh: &Mesh, kind: PrimitiveKind, path: &Path) -> Result<()> {
    proxima::index::check_primitives(mesh, kind).with_context(|| path.display().to_string())
}

/// Parses a relative planarity tolerance (finite, not negative).
pub fn parse_planarity(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{text}' is not a finite tolerance >= 0")),
    }
}

/// The faces as convex polygons; prints on stderr how many faces of more than
/// three vertices were fan-triangulated, when any were.
pub fn polygons(mesh: &Mesh, path: &Path, planarity: f32) -> PrimitiveSet<ConvexPolygon> {
    let extraction = mesh.extract_polygons(planarity);
    if let Some(line) = extraction.fan_note(planarity) {
        note(&format!("{}: {line}", path.display()));
    }
    extraction.set
}

/// Prints the note of [`polygons`] when `kind` is polygons.
pub fn note_polygons(mesh: &Mesh, kind: PrimitiveKind, path: &Path, planarity: f32) {
    if kind == PrimitiveKind::Polygons {
        polygons(mesh, path, planarity);
    }
}

/// Runs `task` on `kind`'s primitives of `mesh` ([`PrimitiveKind::run`]);
/// polygons come with the note of [`polygons`], from the one extraction.
pub fn run_kind<F: KindTask>(mesh: &Mesh, kind: PrimitiveKind, path: &Path, planarity: f32, task: F) -> F::Output {
    match kind {
        PrimitiveKind::Polygons => task.run(polygons(mesh, path, planarity)),
        _ => kind.run(mesh, planarity, task),
    }
}

/// `println!` that returns an error instead of panicking when standard output
/// is closed (`proxima info MESH | head -1`); `main` ends quietly on it.
#[macro_export]
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}

/// `true` when the error is a write to a closed pipe: the reader is gone, so
/// there is no one to tell and nothing went wrong.
pub fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause
            .downcast_ref::<std::io::Error>()
            .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Writes `proxima: {line}` on stderr. A stderr that cannot be written (closed,
/// or a full device: `2>/dev/full`) is ignored: there is no one left to tell.
pub fn note(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "proxima: {line}");
}

/// The memory budget: `PROXIMA_MEMORY_BUDGET` or the library's default (the
/// sizes known before a command starts are checked with
/// [`proxima::budget::check_fits`], which reads the same).
pub fn memory_budget() -> Result<u64> {
    proxima::budget::memory_budget_from_env().map_err(|e| anyhow!(e))
}

/// The cell-test limit: [`MAX_CELL_TESTS_ENV`] or the library's default.
pub fn max_cell_tests() -> Result<u64> {
    proxima::budget::max_cell_tests_from_env().map_err(|e| anyhow!(e))
}

/// `requested` worker threads, refused beyond the library's cap
/// ([`proxima::budget::max_threads`], Python's too) with a one-line error (a
/// note and a cap would make a second stderr line when the command then
/// fails).
pub fn thread_count(requested: usize) -> Result<usize> {
    let cap = proxima::budget::max_threads();
    if requested > cap {
        bail!("--threads {requested} is more than the limit of {cap} (4 per core on this machine, at least 8)");
    }
    Ok(requested)
}

/// A grid's budget error with the option that sized it (`--cell 0.001`,
/// `--res 65536`) in front; other errors unchanged.
pub fn name_option(error: anyhow::Error, option: impl FnOnce() -> String) -> anyhow::Error {
    match error.downcast_ref::<proxima::GridError>() {
        Some(proxima::GridError::CellTests { .. } | proxima::GridError::MemoryBudget { .. }) => error.context(option()),
        _ => error,
    }
}

/// `--cell W` for cubic cells, `--cell W,H,D` otherwise.
pub fn cell_option(cell: Vec3) -> String {
    if cell.x == cell.y && cell.y == cell.z {
        format!("--cell {}", cell.x)
    } else {
        format!("--cell {},{},{}", cell.x, cell.y, cell.z)
    }
}

/// The point cloud of `path`: a mesh file's vertices (by its extension,
/// see [`proxima::io::Format::from_path`]) or a points file (see
/// [`read_points`]); an empty or unusable cloud names the file.
pub fn load_cloud(path: &Path) -> Result<proxima::points::PointCloud> {
    let points = match proxima::io::Format::from_path(path) {
        Some(_) => load_mesh(path)?.positions().to_vec(),
        None => read_points(path)?,
    };
    proxima::points::PointCloud::new(&points)
        .map_err(|e| anyhow!("{}: {}", path.display(), e.to_string().trim_start_matches("points: ")))
}

/// What `proxima knn` and `proxima radius` start from: the cloud of
/// `points` (see [`load_cloud`]), the query points of `queries` (see
/// [`read_points`]) and the pool of `--threads`.
pub fn cloud_queries_pool(
    points: &Path,
    queries: &Path,
    threads: Option<usize>,
) -> Result<(proxima::points::PointCloud, Vec<Vec3>, rayon::ThreadPool)> {
    let threads = threads.map_or(Ok(0), thread_count)?;
    let cloud = load_cloud(points)?;
    let queries = read_points(queries)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("thread pool")?;
    Ok((cloud, queries, pool))
}
