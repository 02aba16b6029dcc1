//! `proxima closest MESH --primitives P (--point X,Y,Z | --points FILE) [-k K] [--method tree|linear] [--attributes]`.

use crate::common::{
    Split, kind_parser, load_mesh, note_polygons, parse_planarity, parse_vec3, query_points, require_primitives,
    run_kind,
};
use crate::surface_columns::{self, SurfaceColumns};
use proxima::index::{IndexConfig, MeshIndex};
use proxima::prelude::*;
use proxima::query::NearestAnswers;
use proxima::surface::SurfacePoint;
use rayon::prelude::*;
use std::io::{BufWriter, StdoutLock, Write};
use std::path::PathBuf;

/// How the answer is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// The AABB tree.
    Tree,
    /// Brute force over every primitive.
    Linear,
}

/// Arguments of `proxima closest`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file.
    mesh: PathBuf,
    /// Which primitives to search.
    #[arg(long, value_parser = kind_parser(), default_value = "faces")]
    primitives: PrimitiveKind,
    /// One query point, X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, conflicts_with = "points", required_unless_present = "points")]
    point: Option<Vec3>,
    /// A file of query points: one per line, three numbers separated by commas
    /// or white space; `#` comments and blank lines are skipped.
    #[arg(long)]
    points: Option<PathBuf>,
    /// How many nearest primitives per query; a face of more than three
    /// vertices is listed once, at its nearest triangle's distance.
    #[arg(short, long, default_value_t = 1)]
    k: usize,
    /// Search method.
    #[arg(long, value_enum, default_value = "tree")]
    method: Method,
    /// How the tree is split (same answers either way).
    #[arg(long, value_enum, default_value = "median")]
    split: Split,
    /// With `--primitives polygons`: how far from planar a face may be and
    /// stay one polygon (its vertices' extent along the normal, relative to its
    /// bounding box diagonal); other faces are fan-triangulated.
    #[arg(long, value_parser = parse_planarity, default_value = "1e-5")]
    planarity: f32,
    /// With --primitives faces: add where each closest point lies, columns
    /// triangle,u,v,feature,fa,fb,nx,ny,nz,fnx,fny,fnz,tu,tv: the face's fan
    /// triangle (v0, vi, vi+1) holding it, numbered over all faces' fans; its
    /// barycentric weights u, v of the triangle's second and third corners
    /// (located again in f64); the smallest feature holding it (face, edge or
    /// vertex) and that feature's vertices fa, fb (empty where it has fewer);
    /// the shading normal interpolated there (the file's normals, else
    /// angle-weighted vertex normals; unit length); the triangle's unit
    /// normal; the file's texture coordinates interpolated there (empty when
    /// it has none).
    #[arg(long)]
    attributes: bool,
}

/// Prints CSV `query,rank,primitive,cx,cy,cz,distance`, k rows per query
/// (with `--attributes`, the surface columns after them).
pub fn run(args: Args) -> anyhow::Result<()> {
    if args.attributes && args.primitives != PrimitiveKind::Faces {
        anyhow::bail!(
            "--attributes: the surface columns are those of faces, not of --primitives {}",
            args.primitives
        );
    }
    let mesh = load_mesh(&args.mesh)?;
    let points = query_points(args.point, args.points.as_deref())?;
    require_primitives(&mesh, args.primitives, &args.mesh)?;
    let (kind, k) = (args.primitives, args.k);
    if args.method == Method::Tree {
        note_polygons(&mesh, kind, &args.mesh, args.planarity);
    }
    let config = IndexConfig {
        build: args.split.config(),
        planarity: args.planarity,
        ..IndexConfig::default()
    };
    // Structures are built on first use: the linear scan builds none.
    let index = MeshIndex::with_config(mesh, config);
    let surface = args.attributes.then(|| SurfaceColumns {
        mesh: index.mesh(),
        normals: index.vertex_normals(),
    });
    let mut rows = Rows::new(surface.as_ref(), &points);
    let columns = if args.attributes { surface_columns::HEADER } else { "" };
    writeln!(rows.out, "query,rank,primitive,cx,cy,cz,distance{columns}")?;
    match args.method {
        Method::Tree => {
            let path = args.mesh.display();
            index
                .k_nearest_chunks(kind, &points, k, |answers| -> anyhow::Result<()> {
                    Ok(rows.write(answers)?)
                })
                .map_err(|e| e.context(path.to_string()))?;
        }
        Method::Linear => run_kind(
            index.mesh(),
            kind,
            &args.mesh,
            args.planarity,
            Linear {
                points: &points,
                k,
                rows: &mut rows,
            },
        )?,
    }
    rows.out.flush()?;
    Ok(())
}

/// The CSV rows on standard output, numbered by query in input order.
struct Rows<'a> {
    out: BufWriter<StdoutLock<'static>>,
    /// The number of the next query written.
    first: usize,
    /// With `--attributes`: the surface and the query points.
    surface: Option<(&'a SurfaceColumns<'a>, &'a [Vec3])>,
}

impl<'a> Rows<'a> {
    fn new(surface: Option<&'a SurfaceColumns<'a>>, points: &'a [Vec3]) -> Self {
        Self {
            out: BufWriter::new(std::io::stdout().lock()),
            first: 0,
            surface: surface.map(|s| (s, points)),
        }
    }

    /// Writes the answers of the next queries, each one's hits nearest
    /// first.
    ///
    /// The rows are formatted in parallel, in blocks of about [`BLOCK_HITS`]
    /// hits, and written in order (formatting all on one thread kept the
    /// others waiting). At most 64 blocks' text is held at once.
    fn write(&mut self, answers: &NearestAnswers) -> std::io::Result<()> {
        let most = (0..answers.len()).map(|i| answers.hits(i).len()).max().unwrap_or(0);
        let block = (BLOCK_HITS / most.max(1)).max(1);
        for window in (0..answers.len()).step_by(64 * block) {
            let end = (window + 64 * block).min(answers.len());
            let (first, surface) = (self.first, self.surface);
            let texts: Vec<Vec<u8>> = (window..end)
                .step_by(block)
                .collect::<Vec<_>>()
                .into_par_iter()
                .map(|start| {
                    let mut text = Vec::with_capacity(80 * BLOCK_HITS); // rows of up to about 80 bytes
                    for i in start..(start + block).min(end) {
                        let query = first + i - window;
                        for (rank, hit) in answers.hits(i).iter().enumerate() {
                            write!(
                                text,
                                "{query},{rank},{},{},{},{},{}",
                                hit.source, hit.point.x, hit.point.y, hit.point.z, hit.distance
                            )
                            .and_then(|()| match surface {
                                Some((surface, points)) => {
                                    let at = SurfacePoint::closest(surface.mesh, hit, points[query]);
                                    surface.write(&mut text, &at)
                                }
                                None => Ok(()),
                            })
                            .and_then(|()| writeln!(text))
                            .expect("writing to memory does not fail");
                        }
                    }
                    text
                })
                .collect();
            for text in &texts {
                self.out.write_all(text)?;
            }
            self.first += end - window;
        }
        Ok(())
    }
}

/// Hits per block of rows formatted at once by [`Rows::write`].
const BLOCK_HITS: usize = 4096;

/// Brute force on one kind of primitive: the same chunked answers as the
/// tree's ([`NearestQuery::k_nearest_sources_chunks`] is written once for
/// every structure), written as they come.
struct Linear<'a, 'r> {
    points: &'a [Vec3],
    k: usize,
    rows: &'a mut Rows<'r>,
}

impl KindTask for Linear<'_, '_> {
    type Output = anyhow::Result<()>;

    fn run<T: MeshPrimitive>(self, set: PrimitiveSet<T>) -> anyhow::Result<()> {
        let Self { points, k, rows } = self;
        LinearSearch::new(set).k_nearest_sources_chunks(points, k, |answers| rows.write(answers))?;
        Ok(())
    }
}
