//! `proxima sdf MESH (--point X,Y,Z | --points FILE | --grid N | --sample N) [--sign winding|pseudonormal]
//! [--exact] [--beta B] [--gradient] [--threads T] [--json]`: signed distances (negative inside) at query points as
//! CSV, on a dense grid as a `.npy`, or at training samples as a `.npz`.

use crate::common::{load_mesh, note, parse_vec3, query_points, thread_count};
use crate::npy;
use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use proxima::budget::check_fits;
use proxima::sample::training_sample_counts;
use proxima::sdf::{DEFAULT_BETA, Pseudonormals, SdfGrid, certificate_pays, signed_distance_gradients};
use proxima::{Aabb, Mesh, SdfConfig, SdfError, Sign, SignedDistance, SignedDistanceField, Vec3};
use rayon::prelude::*;
use serde_json::{Value, json};
use std::borrow::Cow;
use std::convert::Infallible;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// How the side of a point is decided, on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SignMethod {
    /// The generalized winding number (inside above ½): right on open,
    /// non-manifold and self-crossing meshes.
    Winding,
    /// The angle-weighted pseudonormal of the closest feature: faster, right
    /// on closed, consistently oriented meshes that do not cross themselves.
    Pseudonormal,
}

impl SignMethod {
    /// The library's sign.
    pub fn sign(self) -> Sign {
        match self {
            SignMethod::Winding => Sign::WindingNumber,
            SignMethod::Pseudonormal => Sign::Pseudonormal,
        }
    }

    /// The name the command line and the JSON output use.
    pub fn name(self) -> &'static str {
        match self {
            SignMethod::Winding => "winding",
            SignMethod::Pseudonormal => "pseudonormal",
        }
    }
}

/// Arguments of `proxima sdf`.
#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("what").required(true).args(["point", "points", "grid", "sample"])))]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz).
    mesh: PathBuf,
    /// One query point.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    point: Option<Vec3>,
    /// A file of query points, with the rules of `proxima closest --points`:
    /// one per line, three numbers separated by commas or white space; `#`
    /// comments and blank lines are skipped.
    #[arg(long, value_name = "FILE")]
    points: Option<PathBuf>,
    /// The signed distances at the centres of N³ cells over the bounding box
    /// grown by 5% on every side (or the --cube), as a float32 .npy of shape
    /// (N, N, N), index [i, j, k] = x, y, z. Written to --out, or to standard
    /// output when it is redirected (never to a terminal).
    #[arg(long, value_name = "N")]
    grid: Option<usize>,
    /// N training samples, near the surface first, then (--uniform-fraction of
    /// them) uniform in the bounding box grown by 5% (or the --cube), written
    /// to --out as a .npz with `points` (N, 3) and `sdf` (N,) float32 arrays
    /// (the DeepSDF layout). The recipe of `proxima.dataset`: the same mesh,
    /// options and seed give the same samples.
    #[arg(long, value_name = "N", requires = "out")]
    sample: Option<usize>,
    /// With --sample: the standard deviation of the near samples' offsets
    /// from the surface, per axis, an absolute length in the mesh's units
    /// (as `proxima.dataset`'s near_sigma in its normalized units; default 1%
    /// of the bounding box diagonal).
    #[arg(long, value_name = "S", requires = "sample", allow_hyphen_values = true)]
    near_sigma: Option<f32>,
    /// With --sample: the share of the samples drawn uniform in the box, the
    /// rest near the surface (the nearest whole number, halves rounded down).
    #[arg(
        long,
        value_name = "F",
        requires = "sample",
        default_value_t = 0.5,
        allow_hyphen_values = true
    )]
    uniform_fraction: f64,
    /// With --sample or --grid: the box is the cube [-H, H]³ (as
    /// `proxima.dataset`'s volume) instead of the bounding box grown by 5%.
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    cube: Option<f32>,
    /// With --sample: the seed (the same seed gives the same samples on every machine).
    #[arg(long, value_name = "K", default_value_t = 1)]
    seed: u64,
    /// The output file of --grid (.npy) or --sample (.npz).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["point", "points"])]
    out: Option<PathBuf>,
    /// How the side (the sign) is decided.
    #[arg(long, value_enum, default_value = "winding")]
    sign: SignMethod,
    /// With --sign winding: sum the solid angles of every triangle in f64
    /// (the exact winding number; linear in the triangles per query).
    #[arg(long)]
    exact: bool,
    /// With --sign winding: the accuracy parameter β of the winding numbers'
    /// far field (at least 1; larger is more accurate and slower).
    #[arg(long, value_name = "B", value_parser = parse_beta, default_value_t = DEFAULT_BETA)]
    beta: f32,
    /// Worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T")]
    threads: Option<usize>,
    /// With --point or --points: add the gradient of the signed distance
    /// with respect to the point, columns gx,gy,gz (unit length, outward:
    /// sign·(p − c)/|p − c| from the closest point c located again in f64;
    /// the closest feature's unit pseudonormal for points on the surface).
    #[arg(long, conflicts_with_all = ["grid", "sample"])]
    gradient: bool,
    /// Print one JSON object (the answers, or the grid's or samples' summary)
    /// instead of CSV and notes.
    #[arg(long)]
    json: bool,
}

/// Parses β: a finite number of at least 1.
fn parse_beta(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(beta) if beta.is_finite() && beta >= 1.0 => Ok(beta),
        _ => Err(format!("'{text}' is not a finite number >= 1")),
    }
}

/// Bytes per grid cell: its `f32` value; the `.npy` is written from it in blocks.
const BYTES_PER_CELL: u128 = 4;

/// Bytes per training sample, counted generously: the point and its value
/// (16), the closest hits and signed answers of the batch (28 + 40), and the
/// arrays written (16).
const BYTES_PER_SAMPLE: u128 = 128;

/// Queries answered and written at a time: memory holds one chunk's answers
/// (about 40 MiB), whatever the size of the points file.
const CHUNK: usize = 1 << 20;

/// The margin of grids and uniform samples around the bounding box, per side,
/// as a fraction of its size (the library's, which Python's use too).
const MARGIN: f32 = SdfGrid::DEFAULT_MARGIN;

/// Runs `proxima sdf`.
pub fn run(args: Args) -> Result<()> {
    let threads = match args.threads {
        Some(t) => thread_count(t)?,
        None => 0,
    };
    // Everything that sizes work is checked before the mesh is read.
    check_sizes(&args)?;
    let points = match (args.point, &args.points) {
        (None, None) => None,
        (point, points) => Some(query_points(point, points.as_deref())?),
    };
    let mesh = load_mesh(&args.mesh)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("thread pool")?;
    // The sign certificate is made when the queries pay for it.
    let queries = match (&points, args.grid, args.sample) {
        (Some(points), _, _) => points.len(),
        (None, Some(n), _) => n.saturating_pow(3),
        (None, None, n) => n.unwrap_or(0),
    };
    pool.install(|| {
        let config = SdfConfig {
            sign: args.sign.sign(),
            beta: args.beta,
            exact: args.exact,
            certify: certificate_pays(queries, mesh.triangle_count()),
            ..SdfConfig::default()
        };
        let start = Instant::now();
        let field = SignedDistanceField::new(&mesh, &config).with_context(|| args.mesh.display().to_string())?;
        let summary = Summary {
            args: &args,
            triangles: mesh.triangle_count(),
            threads: rayon::current_num_threads(),
            build_seconds: start.elapsed().as_secs_f64(),
        };
        match (points, args.grid, args.sample) {
            (Some(points), _, _) => answer_points(&field, &mesh, &points, &summary),
            (None, Some(n), _) => write_grid(&field, n, &summary),
            (None, None, Some(n)) => write_samples(&field, n, &summary),
            (None, None, None) => unreachable!("clap requires one of --point, --points, --grid, --sample"),
        }
    })
}

/// Refuses zero counts, a spread that is negative or not finite, and grids
/// and sample sets beyond the memory budget, before anything is read or
/// allocated; and a grid bound for a terminal.
fn check_sizes(args: &Args) -> Result<()> {
    if let Some(n) = args.grid {
        if n == 0 {
            return Err(SdfError::Zero { option: "--grid" }.into());
        }
        check_fits("--grid", n, (n as u128).pow(3), BYTES_PER_CELL)?;
        // Any other name is taken as given (`/dev/stdout`, a pipe), as for --sample.
        if let Some(path) = args.out.as_deref().filter(|path| extension_is(path, "npz")) {
            bail!(
                "{}: --grid writes one .npy array, not a .npz archive: give --out FILE.npy",
                path.display()
            );
        }
        if args.out.is_none() {
            if args.json {
                bail!("--grid with --json prints the summary on standard output: give --out FILE.npy for the values");
            }
            if std::io::stdout().is_terminal() {
                bail!("--grid writes binary .npy data: give --out FILE.npy, or redirect standard output to a file");
            }
        }
    }
    if let Some(n) = args.sample {
        if n == 0 {
            return Err(SdfError::Zero { option: "--sample" }.into());
        }
        if let Some(path) = args.out.as_deref().filter(|path| extension_is(path, "npy")) {
            bail!(
                "{}: --sample writes a .npz archive (arrays points and sdf), not a .npy array: give --out FILE.npz",
                path.display()
            );
        }
        check_fits("--sample", n, n as u128, BYTES_PER_SAMPLE)?;
        if !(0.0..=1.0).contains(&args.uniform_fraction) {
            bail!(
                "--uniform-fraction must be between 0 and 1, got {}",
                args.uniform_fraction
            );
        }
    }
    if let Some(half) = args.cube {
        if args.grid.is_none() && args.sample.is_none() {
            bail!("--cube sets the box of --grid or --sample: give one of them");
        }
        if !(half.is_finite() && half > 0.0) {
            bail!("--cube must be a finite number above 0, got {half}");
        }
    }
    if let Some(sigma) = args.near_sigma
        && !(sigma.is_finite() && sigma >= 0.0)
    {
        return Err(SdfError::Parameter {
            option: "--near-sigma",
            value: sigma,
        }
        .into());
    }
    Ok(())
}

/// What every output says of the run.
struct Summary<'a> {
    args: &'a Args,
    triangles: usize,
    threads: usize,
    build_seconds: f64,
}

impl Summary<'_> {
    /// The JSON keys every output shares.
    fn json(&self) -> serde_json::Map<String, Value> {
        let args = self.args;
        let mut out = serde_json::Map::new();
        out.insert("mesh".into(), json!(args.mesh.display().to_string()));
        out.insert("triangles".into(), json!(self.triangles));
        out.insert("sign".into(), json!(args.sign.name()));
        out.insert("exact".into(), json!(args.exact));
        out.insert("beta".into(), json!(args.beta));
        out.insert("threads".into(), json!(self.threads));
        out.insert("build_seconds".into(), json!(self.build_seconds));
        out
    }
}

/// The CSV header of the answers at query points.
pub const CSV_HEADER: &str = "query,signed_distance,winding_number,primitive,cx,cy,cz";

/// Answers the query points chunk by chunk in input order, as CSV rows or a
/// JSON object whose answers are written as they come; with `--gradient`,
/// each with its gradient.
fn answer_points(field: &SignedDistanceField, mesh: &Mesh, points: &[Vec3], summary: &Summary) -> Result<()> {
    let json = summary.args.json;
    // Built once, for the first point found right on the surface.
    let pseudonormals = OnceLock::new();
    let normals = || {
        let built = || {
            field
                .pseudonormals()
                .cloned()
                .unwrap_or_else(|| Pseudonormals::new(mesh))
        };
        Ok::<_, Infallible>(Cow::Borrowed(pseudonormals.get_or_init(built)))
    };
    let mut out = BufWriter::new(std::io::stdout().lock());
    if json {
        // The summary first and the answers streamed after it; the totals,
        // known at the end, close the object.
        let head = serde_json::to_string_pretty(&Value::Object(summary.json()))?;
        write!(out, "{},\n  \"answers\": [", head.trim_end_matches('}').trim_end())?;
    } else {
        let gradient = if summary.args.gradient { ",gx,gy,gz" } else { "" };
        writeln!(out, "{CSV_HEADER}{gradient}")?;
    }
    let (mut seconds, mut inside) = (0.0, 0usize);
    for (chunk_index, chunk) in points.chunks(CHUNK).enumerate() {
        let start = Instant::now();
        let answers = field.signed_distance_batch(chunk);
        let gradients = match summary.args.gradient {
            true => {
                let Ok(gradients) = signed_distance_gradients(mesh, chunk, &answers, normals);
                gradients.into_iter().map(|g| g.map(|g| g.gradient)).collect()
            }
            false => Vec::new(),
        };
        seconds += start.elapsed().as_secs_f64();
        inside += answers.iter().flatten().filter(|a| a.is_inside()).count();
        let first = chunk_index * CHUNK;
        // Formatting is spread over the cores too: on one thread it took
        // about as long as the queries.
        let texts: Vec<Vec<u8>> = answers
            .par_chunks(4096)
            .enumerate()
            .map(|(block, answers)| {
                let mut text = Vec::with_capacity(96 * answers.len());
                for (offset, answer) in answers.iter().enumerate() {
                    let row = block * 4096 + offset;
                    let query = first + row;
                    let gradient = gradients.get(row).map(|g| g.map(|g| g.to_array()));
                    if json {
                        let separator = if query == 0 { "" } else { "," };
                        let object = answer_json(query, answer.as_ref(), gradient);
                        write!(text, "{separator}\n    {object}").expect("writing to memory does not fail");
                    } else {
                        csv_row(&mut text, query, answer.as_ref(), gradient);
                    }
                }
                text
            })
            .collect();
        for text in &texts {
            out.write_all(text)?;
        }
    }
    if json {
        let totals = json!({
            "queries": points.len(),
            "inside": inside,
            "seconds": seconds,
            "queries_per_second": points.len() as f64 / seconds.max(1e-12),
        });
        let totals = serde_json::to_string_pretty(&totals)?;
        writeln!(out, "\n  ],{}", totals.trim_start_matches('{'))?;
    }
    out.flush()?;
    Ok(())
}

/// One CSV row: `query,signed_distance,winding_number,primitive,cx,cy,cz`,
/// the primitive being the face (as `closest` prints it); the winding number
/// empty when the sign came from pseudonormals, every field but the first
/// empty for a point without an answer. `gradient` (with `--gradient`) adds
/// `gx,gy,gz`.
fn csv_row(text: &mut Vec<u8>, query: usize, answer: Option<&SignedDistance>, gradient: Option<Option<[f64; 3]>>) {
    let result = match answer {
        Some(a) => {
            let winding = a.winding_number.map(|w| w.to_string()).unwrap_or_default();
            let hit = &a.closest;
            write!(
                text,
                "{query},{},{winding},{},{},{},{}",
                a.distance, hit.source, hit.point.x, hit.point.y, hit.point.z
            )
        }
        None => write!(text, "{query},,,,,,"),
    };
    let result = result.and_then(|()| match gradient {
        Some(Some([x, y, z])) => writeln!(text, ",{x},{y},{z}"),
        Some(None) => writeln!(text, ",,,"),
        None => writeln!(text),
    });
    result.expect("writing to memory does not fail");
}

/// One answer as a JSON object on one line, with `"gradient"` when asked.
fn answer_json(query: usize, answer: Option<&SignedDistance>, gradient: Option<Option<[f64; 3]>>) -> Value {
    let mut object = match answer {
        Some(a) => json!({
            "query": query,
            "signed_distance": a.distance,
            "winding_number": a.winding_number,
            "inside": a.is_inside(),
            "primitive": a.closest.source,
            "closest": a.closest.point.to_array(),
        }),
        None => json!({"query": query, "signed_distance": null}),
    };
    if let Some(gradient) = gradient {
        object["gradient"] = json!(gradient);
    }
    object
}

/// Evaluates the `n`³ grid and writes it as a `.npy` (x fastest, so in
/// Fortran order for numpy's `[i, j, k]` = x, y, z).
fn write_grid(field: &SignedDistanceField, n: usize, summary: &Summary) -> Result<()> {
    let args = summary.args;
    let grid = match args.cube {
        Some(half) => SdfGrid::over(&cube(half), [n; 3]),
        None => SdfGrid::around(&field.bounds(), n, MARGIN),
    }
    .with_context(|| args.mesh.display().to_string())?;
    let start = Instant::now();
    let mut bar = LateBar::new("sdf grid");
    let values = field
        .sdf_grid(&grid, |done, total| bar.update(done, total))
        .with_context(|| format!("--grid {n}"))?;
    bar.finish();
    let seconds = start.elapsed().as_secs_f64();
    let shape = [n; 3];
    match &args.out {
        Some(path) => write_file(path, |out| npy::write(out, &shape, true, &values))?,
        None => {
            let mut out = BufWriter::new(std::io::stdout().lock());
            npy::write(&mut out, &shape, true, &values)?;
            out.flush()?;
        }
    }
    let inside = values.par_iter().filter(|&&v| v < 0.0).count();
    let (origin, cell) = (grid.origin(), grid.cell);
    if args.json {
        let mut out = summary.json();
        out.insert("grid".into(), json!(n));
        out.insert("shape".into(), json!(shape));
        out.insert("cells".into(), json!(values.len()));
        out.insert("origin".into(), json!(origin.to_array()));
        out.insert("cell".into(), json!(cell.to_array()));
        out.insert("inside".into(), json!(inside));
        out.insert("seconds".into(), json!(seconds));
        out.insert(
            "cells_per_second".into(),
            json!(values.len() as f64 / seconds.max(1e-12)),
        );
        out.insert("out".into(), json!(args.out.as_ref().map(|p| p.display().to_string())));
        crate::outln!("{:#}", Value::Object(out));
    } else {
        let to = args
            .out
            .as_ref()
            .map_or("standard output".to_string(), |p| p.display().to_string());
        note(&format!(
            "{n}x{n}x{n} grid (index [i,j,k] = x,y,z): origin {},{},{} (the first cell's centre), cell {},{},{}; \
             {inside} of {} cells inside; {seconds:.3} s; written to {to}",
            origin.x,
            origin.y,
            origin.z,
            cell.x,
            cell.y,
            cell.z,
            values.len()
        ));
    }
    Ok(())
}

/// Draws `n` training samples (the near ones first, then the uniform ones)
/// and writes them as a `.npz`.
fn write_samples(field: &SignedDistanceField, n: usize, summary: &Summary) -> Result<()> {
    let args = summary.args;
    let path = args.out.as_ref().expect("clap requires --out with --sample");
    let (near_count, uniform_count) = training_sample_counts(n, args.uniform_fraction);
    let sigma = args.near_sigma.unwrap_or(0.01 * field.bounds().size().length());
    let uniform_box = match args.cube {
        Some(half) => cube(half),
        None => {
            let b = field.bounds();
            let grow = b.size() * MARGIN;
            Aabb::new(b.min - grow, b.max + grow)
        }
    };
    let start = Instant::now();
    let samples = field
        .training_samples(near_count, sigma, uniform_count, &uniform_box, args.seed)
        .map_err(|e| match e {
            SdfError::TooFar { value, bound, .. } => SdfError::TooFar {
                option: "--near-sigma",
                value,
                bound,
            },
            e => e,
        })
        .with_context(|| args.mesh.display().to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    let points: Vec<f32> = samples.points.iter().flat_map(|p| p.to_array()).collect();
    let sdf = samples.signed_distances;
    drop(samples.points);
    let inside = sdf.iter().filter(|&&v| v < 0.0).count();
    let archive = npy::npz(&[("points", &[n, 3], &points), ("sdf", &[n], &sdf)])
        .with_context(|| format!("{}: the .npz archive", path.display()))?;
    drop((points, sdf));
    write_file(path, |out| out.write_all(&archive))?;
    if args.json {
        let mut out = summary.json();
        out.insert("samples".into(), json!(n));
        out.insert("near".into(), json!(near_count));
        out.insert("uniform".into(), json!(uniform_count));
        out.insert("near_sigma".into(), json!(sigma));
        out.insert("uniform_fraction".into(), json!(args.uniform_fraction));
        out.insert("margin".into(), json!(args.cube.map_or(Some(MARGIN), |_| None)));
        out.insert("cube".into(), json!(args.cube));
        out.insert("seed".into(), json!(args.seed));
        out.insert("inside".into(), json!(inside));
        out.insert("seconds".into(), json!(seconds));
        out.insert("out".into(), json!(path.display().to_string()));
        crate::outln!("{:#}", Value::Object(out));
    } else {
        note(&format!(
            "{n} samples ({near_count} near the surface, sigma {sigma}; {uniform_count} uniform in {}), \
             {inside} inside; {seconds:.3} s; written to {}",
            args.cube
                .map_or("the box grown by 5%".to_string(), |h| format!("the cube [-{h}, {h}]³")),
            path.display()
        ));
    }
    Ok(())
}

/// The cube `[-half, half]³` of `--cube`.
fn cube(half: f32) -> Aabb {
    Aabb::new(Vec3::splat(-half), Vec3::splat(half))
}

/// `true` when `path` ends in `.ext` (any case).
fn extension_is(path: &Path, ext: &str) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext))
}

/// Creates `path` and writes it through a buffer; errors name the file.
fn write_file(path: &Path, write: impl FnOnce(&mut BufWriter<std::fs::File>) -> std::io::Result<()>) -> Result<()> {
    let name = || path.display().to_string();
    let mut out = BufWriter::new(std::fs::File::create(path).with_context(name)?);
    write(&mut out).with_context(name)?;
    out.flush().with_context(name)?;
    Ok(())
}

/// A progress bar on standard error that appears only once the work has
/// taken a second, and only on a terminal: short runs and redirected
/// output stay clean.
struct LateBar {
    start: Instant,
    message: &'static str,
    terminal: bool,
    bar: Option<ProgressBar>,
}

impl LateBar {
    fn new(message: &'static str) -> Self {
        Self {
            start: Instant::now(),
            message,
            terminal: std::io::stderr().is_terminal(),
            bar: None,
        }
    }

    fn update(&mut self, done: u64, total: u64) {
        if self.bar.is_none() && self.terminal && self.start.elapsed() > Duration::from_secs(1) && done < total {
            let bar = ProgressBar::new(total);
            bar.set_style(
                ProgressStyle::with_template("{msg} {wide_bar} {percent}% {eta}")
                    .unwrap_or(ProgressStyle::default_bar()),
            );
            bar.set_message(self.message);
            self.bar = Some(bar);
        }
        if let Some(bar) = &self.bar {
            bar.set_position(done);
        }
    }

    fn finish(self) {
        if let Some(bar) = self.bar {
            bar.finish_and_clear();
        }
    }
}
