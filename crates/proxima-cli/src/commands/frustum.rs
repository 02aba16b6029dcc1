//! `proxima frustum MESH --primitives P (--view-proj M | --look-at EYE,TARGET,UP
//! --fov DEG --aspect A --near N --far F) [--json] [--bench]`: the mesh
//! elements a camera sees (every vertex, edge or face sharing a point with its
//! view frustum).

use super::closest::Method;
use crate::common::{Split, kind_parser, load_mesh, parse_planarity, require_primitives, run_kind};
use anyhow::{Context, Result};
use proxima::prelude::*;
use serde_json::json;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Arguments of `proxima frustum`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz).
    mesh: PathBuf,
    /// Which primitives to test.
    #[arg(long, value_parser = kind_parser(), default_value = "faces")]
    primitives: PrimitiveKind,
    /// The view-projection matrix: 16 numbers, column-major (OpenGL clip space -w..w).
    #[arg(long, value_name = "M00,M10,..", value_parser = parse_matrix, allow_hyphen_values = true,
          conflicts_with = "look_at", required_unless_present = "look_at")]
    view_proj: Option<Mat4>,
    /// A perspective camera: eye, target and up vector (9 numbers).
    #[arg(long, value_name = "EYE,TARGET,UP", value_parser = parse_look_at, allow_hyphen_values = true,
          requires_all = ["near", "far"])]
    look_at: Option<[Vec3; 3]>,
    /// Vertical field of view in degrees (with --look-at).
    #[arg(long, default_value_t = 60.0, allow_hyphen_values = true)]
    fov: f32,
    /// Width / height (with --look-at).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    aspect: f32,
    /// Near plane distance (with --look-at).
    #[arg(long, allow_hyphen_values = true)]
    near: Option<f32>,
    /// Far plane distance (with --look-at).
    #[arg(long, allow_hyphen_values = true)]
    far: Option<f32>,
    /// Bounding volume of the tree (same answer either way).
    #[arg(long, value_enum, default_value = "aabb")]
    tree: TreeKind,
    /// Search method (same answer either way).
    #[arg(long, value_enum, default_value = "tree")]
    method: Method,
    /// How the tree is split (same answer either way).
    #[arg(long, value_enum, default_value = "median")]
    split: Split,
    /// Faces farther from planar than this (relative to their size) are fan-triangulated (polygons only).
    #[arg(long, value_parser = parse_planarity, default_value = "1e-5")]
    planarity: f32,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Also time the tree query against brute force (repeated for about a
    /// second each) and report nodes visited and primitives tested.
    #[arg(long)]
    bench: bool,
}

/// Parses `n` numbers separated by commas and/or white space.
fn parse_numbers<const N: usize>(text: &str, what: &str) -> Result<[f32; N], String> {
    let parts: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    if parts.len() != N {
        return Err(format!("expected {N} numbers ({what}), got {}", parts.len()));
    }
    let mut out = [0f32; N];
    for (slot, s) in out.iter_mut().zip(&parts) {
        *slot = s.parse::<f32>().map_err(|_| format!("'{s}' is not a number"))?;
        if !slot.is_finite() {
            return Err(format!("'{s}' is not a finite number"));
        }
    }
    Ok(out)
}

fn parse_matrix(text: &str) -> Result<Mat4, String> {
    parse_numbers::<16>(text, "a column-major 4x4 matrix").map(|m| Mat4::from_cols_array(&m))
}

fn parse_look_at(text: &str) -> Result<[Vec3; 3], String> {
    let v = parse_numbers::<9>(text, "EYE,TARGET,UP")?;
    Ok([
        Vec3::new(v[0], v[1], v[2]),
        Vec3::new(v[3], v[4], v[5]),
        Vec3::new(v[6], v[7], v[8]),
    ])
}

/// What one run found.
struct Outcome {
    /// Source indices (vertex, edge or face), ascending, without repeats.
    sources: Vec<u32>,
    /// Primitives found (a face split into triangles counts each).
    primitives: usize,
    /// Work of the tree query, when the tree answered.
    stats: Option<QueryStats>,
    /// Seconds per query (tree, brute force), with `--bench`.
    timing: Option<(f64, f64)>,
    build_seconds: f64,
    total: usize,
}

/// Which tree answers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum TreeKind {
    /// The AABB tree.
    Aabb,
    /// The bounding-sphere tree (same hierarchy, spheres instead of boxes).
    Sphere,
}

/// A built tree of either kind.
enum AnyVolumeTree<T> {
    Aabb(AabbTree<T>),
    Sphere(SphereTree<T>),
}

impl<T: FrustumOverlap> AnyVolumeTree<T> {
    fn frustum_with_stats(&self, frustum: &Frustum) -> (Vec<u32>, QueryStats) {
        match self {
            Self::Aabb(tree) => tree.frustum_with_stats(frustum),
            Self::Sphere(tree) => tree.frustum_with_stats(frustum),
        }
    }

    fn frustum_into(&self, frustum: &Frustum, out: &mut Vec<u32>) {
        match self {
            Self::Aabb(tree) => tree.frustum_into(frustum, out),
            Self::Sphere(tree) => tree.frustum_into(frustum, out),
        }
    }
}

/// Prints the count and the source indices.
pub fn run(args: Args) -> Result<()> {
    let frustum = match (args.view_proj, args.look_at) {
        (Some(m), _) => Frustum::from_view_projection(m).context("invalid --view-proj")?,
        (None, Some([eye, target, up])) => {
            let (near, far) = (args.near.unwrap_or(f32::NAN), args.far.unwrap_or(f32::NAN));
            Frustum::look_at(eye, target, up, args.fov, args.aspect, near, far).context("invalid camera")?
        }
        (None, None) => anyhow::bail!("give --view-proj or --look-at"),
    };
    let mesh = load_mesh(&args.mesh)?;
    require_primitives(&mesh, args.primitives, &args.mesh)?;
    let task = Search {
        frustum: &frustum,
        args: &args,
    };
    let outcome = run_kind(&mesh, args.primitives, &args.mesh, args.planarity, task)?;
    let kind = args.primitives.name();
    if args.json {
        let mut out = json!({
            "mesh": args.mesh.display().to_string(),
            "primitives": kind,
            "count": outcome.sources.len(),
            "indices": outcome.sources,
        });
        if let Some(stats) = outcome.stats {
            out["nodes_visited"] = json!(stats.nodes_visited);
            out["primitives_tested"] = json!(stats.primitives_tested);
        }
        if let Some((tree, linear)) = outcome.timing {
            out["bench"] = json!({
                "primitives": outcome.total,
                "primitives_found": outcome.primitives,
                "build_seconds": outcome.build_seconds,
                "tree_seconds_per_query": tree,
                "linear_seconds_per_query": linear,
                "speedup": linear / tree,
            });
        }
        // Written, not printed: a closed pipe is then an error, not a panic.
        writeln!(std::io::stdout().lock(), "{out}")?;
        return Ok(());
    }
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    writeln!(out, "{} {kind} in the frustum", outcome.sources.len())?;
    if let Some((tree, linear)) = outcome.timing {
        let stats = outcome.stats.unwrap_or_default();
        writeln!(
            out,
            "# {} of {} primitives found; tree build {:.1} ms; query: tree {:.3} ms ({} nodes visited, {} primitives tested), brute force {:.3} ms, {:.1}x",
            outcome.primitives,
            outcome.total,
            outcome.build_seconds * 1e3,
            tree * 1e3,
            stats.nodes_visited,
            stats.primitives_tested,
            linear * 1e3,
            linear / tree
        )?;
    }
    for s in &outcome.sources {
        writeln!(out, "{s}")?;
    }
    out.flush()?;
    Ok(())
}

/// The frustum query on one kind of primitive, as `args` ask.
struct Search<'a> {
    frustum: &'a Frustum,
    args: &'a Args,
}

impl KindTask for Search<'_> {
    type Output = Result<Outcome>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> Result<Outcome> {
        search(set, self.frustum, self.args, &self.args.split.config())
    }
}

fn search<T: MeshPrimitive>(
    set: PrimitiveSet<T>,
    frustum: &Frustum,
    args: &Args,
    config: &BuildConfig,
) -> Result<Outcome> {
    let total = set.len();
    let needs_tree = args.method == Method::Tree || args.bench;
    let start = Instant::now();
    let tree = needs_tree
        .then(|| -> Result<AnyVolumeTree<T>, proxima::BuildError> {
            Ok(match args.tree {
                TreeKind::Aabb => AnyVolumeTree::Aabb(AabbTree::build_set(set.clone(), config)?),
                TreeKind::Sphere => AnyVolumeTree::Sphere(SphereTree::build_set(set.clone(), config)?),
            })
        })
        .transpose()?;
    let build_seconds = start.elapsed().as_secs_f64();
    let linear = LinearSearch::new(set);
    let (found, stats) = match (&tree, args.method) {
        (Some(tree), Method::Tree) => {
            let (found, stats) = tree.frustum_with_stats(frustum);
            (found, Some(stats))
        }
        _ => (linear.frustum(frustum), None),
    };
    let timing = match (&tree, args.bench) {
        (Some(tree), true) => {
            let mut buffer = Vec::with_capacity(found.len());
            let tree_time = time_per_call(|| tree.frustum_into(frustum, &mut buffer));
            let linear_time = time_per_call(|| linear.frustum_into(frustum, &mut buffer));
            Some((tree_time, linear_time))
        }
        _ => None,
    };
    let stats = stats.or_else(|| tree.as_ref().map(|t| t.frustum_with_stats(frustum).1));
    Ok(Outcome {
        sources: linear.leaves().sources_of_inputs(&found),
        primitives: found.len(),
        stats,
        timing,
        build_seconds,
        total,
    })
}

/// Mean seconds per call of `f`, repeated for about a second (at least 3 calls).
fn time_per_call(mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    let mut calls = 0u32;
    while calls < 3 || start.elapsed() < Duration::from_secs(1) {
        f();
        calls += 1;
    }
    start.elapsed().as_secs_f64() / calls as f64
}
