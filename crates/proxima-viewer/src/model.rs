//! What the viewer knows about a loaded mesh: the mesh, its draw buffers, and
//! per primitive kind an AABB tree, brute force and (built on first use) a
//! sphere tree, with the queries the panel asks of them. Built off the UI
//! thread; no GL, no egui.
//!
//! The per-kind work is written once, generic over the primitive type
//! ([`KindModel`]), held typed per kind in the library's [`PerKind`], and
//! reached by a kind chosen at run time through the object-safe
//! [`KindQueries`]: one virtual call per UI action, none per primitive.

use crate::scene::{self, MeshBuffers, Overlay, Shape, colors};
use proxima::kind::{KindFamily, KindGeneric, PerKind};
use proxima::prelude::*;
use proxima::primitive::polygon::DEFAULT_PLANARITY_TOLERANCE;
use proxima::{Sphere, TreeStats};
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};
use std::time::Instant;

/// Where a model comes from.
#[derive(Debug)]
pub enum ModelSource {
    /// A mesh file, loaded (off the UI thread) with [`proxima::io::load`].
    File(PathBuf),
    /// A mesh already in memory (the embedded default model), with its display name.
    Mesh {
        /// The mesh.
        mesh: Mesh,
        /// The name shown in the window.
        name: String,
    },
}

/// A stage of loading a model, reported to the progress indicator.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// What is being done.
    pub stage: String,
    /// Fraction of the whole job done, 0 to 1.
    pub fraction: f32,
}

/// Seconds spent on each step of loading a model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Reading and parsing the file (0 for an in-memory mesh).
    pub load: f64,
    /// Vertex normals and draw buffers.
    pub buffers: f64,
    /// Tree build per kind (vertices, edges, faces, polygons).
    pub build: [f64; 4],
}

/// What the viewer asks of the structures over one kind of primitive, with
/// the primitive type erased.
trait KindQueries: Send + Sync {
    /// Number of primitives (build inputs).
    fn len(&self) -> usize;
    /// Statistics of the AABB tree.
    fn stats(&self) -> TreeStats;
    /// Boxes of the AABB tree's nodes at `depth`.
    fn nodes_at_depth(&self, depth: u32) -> Vec<Aabb>;
    /// Spheres of the sphere tree's nodes at `depth` (the tree is built on first use).
    fn sphere_nodes_at_depth(&self, depth: u32) -> Vec<Sphere>;
    /// Fills the answers of `result` for its point (see [`Model::query`]).
    fn closest(&self, result: &mut QueryResult, k: usize, with_linear: bool);
    /// Closest primitive by brute force.
    fn linear_closest(&self, p: Vec3) -> Option<ClosestHit>;
    /// The tree's frustum selection into `out`, and the mean seconds per query.
    fn frustum(&self, frustum: &Frustum, out: &mut Vec<u32>) -> f64;
    /// The frustum selection by brute force.
    fn frustum_linear(&self, frustum: &Frustum) -> Vec<u32>;
    /// The mesh element build input `input` came from.
    fn source(&self, input: u32) -> Option<u32>;
    /// The geometry of build input `input`.
    fn input_shape(&self, input: u32) -> Option<Shape>;
}

/// The viewer's structures for each primitive type (`None` when the mesh
/// gives no primitive of that kind).
struct Models;

impl KindFamily for Models {
    type Of<T: MeshPrimitive> = Option<KindModel<T>>;
}

/// Trees and brute-force searches over one kind of primitive.
struct KindModel<T> {
    tree: AabbTree<T>,
    linear: LinearSearch<T>,
    /// `sources[i]`: the mesh element build input `i` came from.
    sources: Vec<u32>,
    /// Computed once: it walks every node.
    stats: TreeStats,
    /// The sphere tree over the same inputs, built when first shown.
    spheres: OnceLock<Option<SphereTree<T>>>,
}

/// Builds a kind's [`KindModel`] into `kinds`, returning its build time.
struct BuildKind<'a> {
    mesh: &'a Mesh,
    kinds: &'a mut PerKind<Models>,
}

impl KindGeneric for BuildKind<'_> {
    type Output = Result<f64, String>;

    fn call<T: MeshPrimitive>(self) -> Self::Output {
        let set = T::extract(self.mesh, DEFAULT_PLANARITY_TOLERANCE);
        let start = Instant::now();
        let tree = AabbTree::build_set(set.clone(), &BuildConfig::default()).map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        *self.kinds.get_mut::<T>() = Some(KindModel {
            sources: set.sources.clone(),
            spheres: OnceLock::new(),
            stats: tree.stats(),
            tree,
            linear: LinearSearch::new(set),
        });
        Ok(seconds)
    }
}

/// The structures of one kind as [`KindQueries`], for [`PrimitiveKind::dispatch`].
struct AsQueries<'a>(&'a PerKind<Models>);

impl<'a> KindGeneric for AsQueries<'a> {
    type Output = Option<&'a dyn KindQueries>;

    fn call<T: MeshPrimitive>(self) -> Self::Output {
        self.0.get::<T>().as_ref().map(|model| model as &dyn KindQueries)
    }
}

impl<T: MeshPrimitive> KindQueries for KindModel<T> {
    fn len(&self) -> usize {
        self.tree.len()
    }

    fn stats(&self) -> TreeStats {
        self.stats
    }

    fn nodes_at_depth(&self, depth: u32) -> Vec<Aabb> {
        scene::nodes_at_depth(&self.tree, depth)
    }

    fn sphere_nodes_at_depth(&self, depth: u32) -> Vec<Sphere> {
        // The same inputs built the AABB tree, so the build does not fail.
        let tree = self.spheres.get_or_init(|| {
            SphereTree::build_with_sources(
                self.linear.primitives().to_vec(),
                self.sources.clone(),
                &BuildConfig::default(),
            )
            .ok()
        });
        tree.as_ref()
            .map(|t| crate::spheres::sphere_nodes_at_depth(t, depth))
            .unwrap_or_default()
    }

    fn closest(&self, result: &mut QueryResult, k: usize, with_linear: bool) {
        let p = result.point;
        (result.tree, result.tree_seconds) = timed(|| self.tree.closest(p));
        if with_linear {
            let start = Instant::now();
            result.linear = self.linear.closest(p);
            result.linear_seconds = start.elapsed().as_secs_f64();
        }
        if k > 0 {
            result.nearest = self.tree.k_nearest(p, k);
        }
    }

    fn linear_closest(&self, p: Vec3) -> Option<ClosestHit> {
        self.linear.closest(p)
    }

    fn frustum(&self, frustum: &Frustum, out: &mut Vec<u32>) -> f64 {
        timed(|| self.tree.frustum_into(frustum, out)).1
    }

    fn frustum_linear(&self, frustum: &Frustum) -> Vec<u32> {
        self.linear.frustum(frustum)
    }

    fn source(&self, input: u32) -> Option<u32> {
        self.sources.get(input as usize).copied()
    }

    fn input_shape(&self, input: u32) -> Option<Shape> {
        self.linear.primitives().get(input as usize).map(shape_of)
    }
}

/// The geometry of one primitive, for highlighting: its hull points (a
/// point's one, a segment's two, a triangle's or convex polygon's corners
/// in order), drawn as the shape of its kind.
fn shape_of<T: MeshPrimitive>(primitive: &T) -> Shape {
    let mut points = Vec::new();
    primitive.push_bounding_points(&mut points);
    match (T::KIND, points.as_slice()) {
        (PrimitiveKind::Vertices, &[p]) => Shape::Point(p),
        (PrimitiveKind::Edges, &[a, b]) => Shape::Segment(a, b),
        _ => Shape::Polygon(points),
    }
}

/// A loaded mesh with everything the viewer draws and asks of it.
pub struct Model {
    /// Display name (the path, or the embedded model's name).
    pub name: String,
    /// The mesh.
    pub mesh: Mesh,
    /// Vertex pairs of the unique edges, in edge-source order.
    pub edges: Vec<[u32; 2]>,
    /// Bounding box of the positions.
    pub bounds: Aabb,
    /// Vertex and index buffers for drawing the shaded mesh.
    pub buffers: Arc<MeshBuffers>,
    /// A coarse copy drawn while the camera moves (meshes of more than
    /// [`scene::INTERACTIVE_TRIANGLE_LIMIT`] triangles).
    pub buffers_lod: Option<Arc<MeshBuffers>>,
    /// How long each step took.
    pub timings: Timings,
    /// Per kind (indexed by `PrimitiveKind as usize`); `None` when the mesh
    /// gives no primitive of that kind.
    kinds: PerKind<Models>,
}

/// The answer to one closest-point question, by tree and by brute force.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QueryResult {
    /// The query point.
    pub point: Vec3,
    /// Primitive kind asked.
    pub kind: PrimitiveKind,
    /// The tree's answer.
    pub tree: Option<ClosestHit>,
    /// Brute force's answer (`None` when not run or empty).
    pub linear: Option<ClosestHit>,
    /// Seconds per tree query (averaged over repeats when fast).
    pub tree_seconds: f64,
    /// Seconds for the brute-force query.
    pub linear_seconds: f64,
    /// The k nearest primitives by the tree, nearest first (empty when k = 0).
    pub nearest: Vec<ClosestHit>,
}

/// Runs `f` once, and again until about a millisecond has passed when it is
/// fast, returning the last result and the mean seconds per call.
fn timed<R>(mut f: impl FnMut() -> R) -> (R, f64) {
    let start = Instant::now();
    let mut result = f();
    let mut runs = 1u32;
    while start.elapsed().as_secs_f64() < 1e-3 && runs < 10_000 {
        result = f();
        runs += 1;
    }
    (result, start.elapsed().as_secs_f64() / runs as f64)
}

impl Model {
    /// Loads (if needed) and indexes a model, reporting each stage to
    /// `progress`. The error is one line naming the file.
    pub fn load(source: ModelSource, progress: &dyn Fn(Progress)) -> Result<Model, String> {
        let report = |stage: &str, fraction: f32| {
            progress(Progress {
                stage: stage.to_string(),
                fraction,
            })
        };
        let start = Instant::now();
        let (mesh, name) = match source {
            ModelSource::File(path) => {
                report(&format!("reading {}", path.display()), 0.0);
                (
                    proxima::io::load(&path).map_err(|e| e.to_string())?,
                    path.display().to_string(),
                )
            }
            ModelSource::Mesh { mesh, name } => (mesh, name),
        };
        let load = start.elapsed().as_secs_f64();
        Self::index(mesh, name, load, &report)
    }

    /// Builds draw buffers, trees and brute-force searches over `mesh`.
    fn index(mesh: Mesh, name: String, load: f64, report: &dyn Fn(&str, f32)) -> Result<Model, String> {
        if mesh.vertex_count() == 0 {
            return Err(format!("{name}: the mesh has no vertices"));
        }
        report("normals and draw buffers", 0.3);
        let start = Instant::now();
        let buffers = Arc::new(scene::mesh_buffers(&mesh));
        let buffers_lod = (mesh.triangle_count() > scene::INTERACTIVE_TRIANGLE_LIMIT)
            .then(|| Arc::new(scene::decimate(&buffers, 160)));
        let edges = mesh.edge_indices();
        let mut timings = Timings {
            load,
            buffers: start.elapsed().as_secs_f64(),
            build: [0.0; 4],
        };
        let mut kinds = PerKind::<Models>::default();
        for (i, kind) in PrimitiveKind::ALL.into_iter().enumerate() {
            report(&format!("tree over {}", kind.name()), 0.45 + 0.15 * i as f32);
            if kind.available(&mesh) > 0 {
                let build = BuildKind {
                    mesh: &mesh,
                    kinds: &mut kinds,
                };
                timings.build[kind as usize] = kind.dispatch(build)?;
            }
        }
        report("done", 1.0);
        Ok(Model {
            name,
            bounds: mesh.bounds(),
            edges,
            buffers,
            buffers_lod,
            timings,
            mesh,
            kinds,
        })
    }

    /// The structures over `kind`, if the mesh gives primitives of it.
    fn kind(&self, kind: PrimitiveKind) -> Option<&dyn KindQueries> {
        kind.dispatch(AsQueries(&self.kinds))
    }

    /// `true` when primitives of `kind` exist (a point cloud has no faces, a
    /// mesh without faces no edges).
    pub fn has(&self, kind: PrimitiveKind) -> bool {
        self.count(kind) > 0
    }

    /// Number of primitives of `kind`.
    pub fn count(&self, kind: PrimitiveKind) -> usize {
        self.kind(kind).map_or(0, |k| k.len())
    }

    /// Statistics of the tree over `kind`.
    pub fn tree_stats(&self, kind: PrimitiveKind) -> TreeStats {
        self.kind(kind).map(|k| k.stats()).unwrap_or_default()
    }

    /// Seconds the tree over `kind` took to build.
    pub fn build_seconds(&self, kind: PrimitiveKind) -> f64 {
        self.timings.build[kind as usize]
    }

    /// The first face the ray `origin + t · direction` (t ≥ 0) meets, by
    /// the library's ray query on the faces' tree; `None` for a miss, a
    /// mesh without faces or a ray the library refuses.
    pub fn pick(&self, origin: Vec3, direction: Vec3) -> Option<scene::Pick> {
        let faces = self.kinds.faces.as_ref()?;
        scene::pick(&faces.tree, faces.linear.primitives(), origin, direction)
    }

    /// `true` when the mesh has faces to pick.
    pub fn can_pick(&self) -> bool {
        self.kinds.faces.is_some()
    }

    /// Spheres of the sphere tree's nodes of `kind` at exactly `depth` (root
    /// = 0). The sphere tree is built on first use (same inputs as the AABB
    /// tree, same hierarchy).
    pub fn sphere_nodes_at_depth(&self, kind: PrimitiveKind, depth: u32) -> Vec<Sphere> {
        self.kind(kind)
            .map(|k| k.sphere_nodes_at_depth(depth))
            .unwrap_or_default()
    }

    /// Boxes of the tree nodes of `kind` at exactly `depth` (root = 0).
    pub fn nodes_at_depth(&self, kind: PrimitiveKind, depth: u32) -> Vec<Aabb> {
        self.kind(kind).map(|k| k.nodes_at_depth(depth)).unwrap_or_default()
    }

    /// Closest primitive of `kind` to `p` by the tree (and by brute force when
    /// `with_linear`), with timings, and the `k` nearest.
    pub fn query(&self, kind: PrimitiveKind, p: Vec3, k: usize, with_linear: bool) -> QueryResult {
        let mut result = QueryResult {
            point: p,
            kind,
            ..QueryResult::default()
        };
        if let Some(structures) = self.kind(kind) {
            structures.closest(&mut result, k, with_linear);
        }
        result
    }

    /// Build-input indices of the primitives of `kind` overlapping `frustum`
    /// by the tree (ascending), with the mean seconds per query.
    pub fn frustum_query(&self, kind: PrimitiveKind, frustum: &Frustum) -> (Vec<u32>, f64) {
        let mut out = Vec::new();
        let seconds = self.kind(kind).map_or(0.0, |k| k.frustum(frustum, &mut out));
        (out, seconds)
    }

    /// [`frustum_query`](Self::frustum_query) by brute force (every
    /// primitive tested), with the seconds it took.
    pub fn frustum_linear(&self, kind: PrimitiveKind, frustum: &Frustum) -> (Vec<u32>, f64) {
        let start = Instant::now();
        let out = self.kind(kind).map(|k| k.frustum_linear(frustum)).unwrap_or_default();
        (out, start.elapsed().as_secs_f64())
    }

    /// The mesh element (vertex, edge or face) that build input `input` of
    /// `kind` came from.
    pub fn input_source(&self, kind: PrimitiveKind, input: u32) -> Option<u32> {
        self.kind(kind)?.source(input)
    }

    /// The geometry of build input `input` of `kind` (a face's fan triangle,
    /// not the whole face), for highlighting query answers given as inputs.
    pub fn input_shape(&self, kind: PrimitiveKind, input: u32) -> Option<Shape> {
        self.kind(kind)?.input_shape(input)
    }

    /// Closest primitive of `kind` to `p` by brute force, with the seconds it
    /// took (run on a worker thread by the viewer: on the dragon it takes
    /// tens of milliseconds).
    pub fn linear_closest(&self, kind: PrimitiveKind, p: Vec3) -> (Option<ClosestHit>, f64) {
        let start = Instant::now();
        let hit = self.kind(kind).and_then(|k| k.linear_closest(p));
        (hit, start.elapsed().as_secs_f64())
    }

    /// The geometry of primitive `source` of `kind` (vertex, edge or face
    /// index), for highlighting; `None` for an index out of range. Answers
    /// name mesh elements, so this reads the mesh, not the primitives.
    pub fn primitive_shape(&self, kind: PrimitiveKind, source: u32) -> Option<Shape> {
        let p = self.mesh.positions();
        let s = source as usize;
        match kind {
            PrimitiveKind::Vertices => p.get(s).map(|&v| Shape::Point(v)),
            PrimitiveKind::Edges => self
                .edges
                .get(s)
                .map(|&[a, b]| Shape::Segment(p[a as usize], p[b as usize])),
            PrimitiveKind::Faces | PrimitiveKind::Polygons => (s < self.mesh.face_count())
                .then(|| Shape::Polygon(self.mesh.face(s).iter().map(|&i| p[i as usize]).collect())),
        }
    }
}

/// The overlay of a closest-point answer: the query point, the line to the
/// closest point, the closest primitive filled, the other k-nearest
/// primitives outlined, and the closest-point marker on top. The query
/// marker is blue ([`colors::QUERY_INSIDE`]) when `inside` says the point is
/// inside the mesh, orange otherwise (outside or not known).
pub fn query_overlay(model: &Model, result: &QueryResult, inside: Option<bool>) -> Overlay {
    let mut overlay = Overlay::default();
    for hit in result.nearest.iter().skip(1) {
        if let Some(shape) = model.primitive_shape(result.kind, hit.source) {
            overlay.shape(&shape, colors::NEAREST, false);
        }
    }
    if let Some(hit) = result.tree {
        if let Some(shape) = model.primitive_shape(result.kind, hit.source) {
            overlay.shape(&shape, colors::CLOSEST_PRIMITIVE, true);
        }
        overlay.line(result.point, hit.point, colors::QUERY_LINE);
    }
    let query_color = if inside == Some(true) {
        colors::QUERY_INSIDE
    } else {
        colors::QUERY
    };
    overlay.marker(result.point, query_color, scene::MARKER_SIZE);
    if let Some(hit) = result.tree {
        overlay.marker(hit.point, colors::CLOSEST, scene::MARKER_SIZE);
    }
    overlay
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> Mesh {
        Mesh::from_triangles(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
        .unwrap()
    }

    use crate::scene::tests::cube_mesh;

    fn model() -> Model {
        Model::load(
            ModelSource::Mesh {
                mesh: tetra(),
                name: "tetra".into(),
            },
            &|_| {},
        )
        .unwrap()
    }

    #[test]
    fn loading_reports_progress_and_counts() {
        let stages = std::cell::RefCell::new(Vec::new());
        let m = Model::load(
            ModelSource::Mesh {
                mesh: tetra(),
                name: "tetra".into(),
            },
            &|p| stages.borrow_mut().push(p),
        )
        .unwrap();
        let stages = stages.into_inner();
        assert!(stages.windows(2).all(|w| w[0].fraction <= w[1].fraction));
        assert_eq!(stages.last().unwrap().fraction, 1.0);
        assert_eq!(
            (
                m.count(PrimitiveKind::Vertices),
                m.count(PrimitiveKind::Edges),
                m.count(PrimitiveKind::Faces)
            ),
            (4, 6, 4)
        );
        assert_eq!(m.tree_stats(PrimitiveKind::Faces).primitives, 4);
    }

    #[test]
    fn a_broken_file_is_an_error_naming_it() {
        let temp = tempfile::Builder::new()
            .prefix("proxima-viewer-model-")
            .tempdir()
            .unwrap();
        let dir = temp.path();
        let path = dir.join("broken.obj");
        std::fs::write(&path, "v 0 0 0\nf 1 2 3\n").unwrap();
        let error = Model::load(ModelSource::File(path.clone()), &|_| {}).err().unwrap();
        assert!(error.contains("broken.obj"), "{error}");
        let missing = Model::load(ModelSource::File(dir.join("missing.ply")), &|_| {})
            .err()
            .unwrap();
        assert!(missing.contains("missing.ply"), "{missing}");
    }

    #[test]
    fn tree_and_linear_agree_and_shapes_match_sources() {
        let m = model();
        let p = Vec3::new(0.3, 0.3, 1.0);
        for kind in PrimitiveKind::ALL {
            let r = m.query(kind, p, 3, true);
            assert_eq!(r.tree, r.linear, "{kind:?}");
            assert_eq!(m.linear_closest(kind, p).0, r.tree);
            assert_eq!(r.nearest.len(), 3);
            assert_eq!(r.nearest[0], r.tree.unwrap());
            assert!(r.tree_seconds > 0.0);
            let hit = r.tree.unwrap();
            let shape = m.primitive_shape(kind, hit.source).unwrap();
            // The closest point lies on the highlighted primitive.
            assert!(shape.distance_to(hit.point) < 1e-5, "{kind:?} {shape:?} {hit:?}");
        }
        assert!(m.primitive_shape(PrimitiveKind::Faces, 99).is_none());
        let r = m.query(PrimitiveKind::Faces, p, 0, false);
        assert!(r.nearest.is_empty() && r.linear.is_none());
    }

    #[test]
    fn picking_asks_the_faces_tree_and_names_the_face() {
        let mesh = crate::scene::tests::cube_mesh();
        let m = Model::load(
            ModelSource::Mesh {
                mesh,
                name: "cube".into(),
            },
            &|_| {},
        )
        .unwrap();
        assert!(m.can_pick());
        let hit = m.pick(Vec3::new(0.25, 0.5, 5.0), -Vec3::Z).unwrap();
        assert_eq!((hit.face, hit.t, hit.normal), (1, 4.0, Vec3::Z));
        assert!(m.pick(Vec3::new(3.0, 3.0, 3.0), Vec3::Z).is_none());
        assert!(m.pick(Vec3::ZERO, Vec3::ZERO).is_none());
    }

    #[test]
    fn a_point_cloud_has_no_faces_to_query() {
        let mesh = Mesh::from_compact(vec![Vec3::ZERO, Vec3::X], vec![0], vec![]).unwrap();
        let m = Model::load(
            ModelSource::Mesh {
                mesh,
                name: "points".into(),
            },
            &|_| {},
        )
        .unwrap();
        assert!(!m.has(PrimitiveKind::Faces) && m.has(PrimitiveKind::Vertices));
        assert!(!m.can_pick() && m.pick(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z).is_none());
        assert!(m.query(PrimitiveKind::Faces, Vec3::ONE, 2, true).tree.is_none());
        assert_eq!(
            m.query(PrimitiveKind::Vertices, Vec3::ONE, 1, true)
                .tree
                .unwrap()
                .source,
            1
        );
        assert!(m.nodes_at_depth(PrimitiveKind::Faces, 0).is_empty());
        assert!(m.sphere_nodes_at_depth(PrimitiveKind::Faces, 0).is_empty());
        assert_eq!(m.sphere_nodes_at_depth(PrimitiveKind::Vertices, 0).len(), 1);
    }

    #[test]
    fn polygons_are_whole_faces_queried_like_triangles() {
        // A cube of six quads: six polygons, twelve triangles.
        let m = Model::load(
            ModelSource::Mesh {
                mesh: cube_mesh(),
                name: "cube".into(),
            },
            &|_| {},
        )
        .unwrap();
        assert_eq!(m.count(PrimitiveKind::Polygons), 6);
        assert_eq!(m.count(PrimitiveKind::Faces), 12);
        assert_eq!(m.tree_stats(PrimitiveKind::Polygons).primitives, 6);
        assert_eq!(m.nodes_at_depth(PrimitiveKind::Polygons, 0).len(), 1);
        assert_eq!(m.sphere_nodes_at_depth(PrimitiveKind::Polygons, 0).len(), 1);
        for p in [
            Vec3::new(0.3, 0.6, 2.0),
            Vec3::new(-1.0, 0.5, 0.5),
            Vec3::new(0.45, 0.2, 0.4),
        ] {
            let polygons = m.query(PrimitiveKind::Polygons, p, 2, true);
            let faces = m.query(PrimitiveKind::Faces, p, 0, false);
            assert_eq!(polygons.tree, polygons.linear);
            // Same surface, same closest face and distance as over triangles.
            let (a, b) = (polygons.tree.unwrap(), faces.tree.unwrap());
            assert_eq!(a.source, b.source);
            assert!((a.distance - b.distance).abs() < 1e-6);
            // The polygon's own shape is the whole quad.
            match m.input_shape(PrimitiveKind::Polygons, 0).unwrap() {
                scene::Shape::Polygon(v) => assert_eq!(v.len(), 4),
                other => panic!("{other:?}"),
            }
        }
        let grid = crate::cells::CellGrid::build(&m, PrimitiveKind::Polygons, 0.25).unwrap();
        assert!(grid.occupied_count() > 0);
    }

    #[test]
    fn the_query_overlay_connects_query_and_closest_and_highlights() {
        let model = Model::load(
            ModelSource::Mesh {
                mesh: cube_mesh(),
                name: "cube".into(),
            },
            &|_| {},
        )
        .unwrap();
        let q = Vec3::new(0.25, 0.5, 2.0);
        let result = model.query(PrimitiveKind::Faces, q, 3, false);
        let overlay = query_overlay(&model, &result, None);
        assert_eq!(overlay.markers[0].color, colors::QUERY);
        assert_eq!(query_overlay(&model, &result, Some(false)), overlay);
        let inside = query_overlay(&model, &result, Some(true));
        assert_eq!(inside.markers[0].color, colors::QUERY_INSIDE);
        assert_eq!(inside.markers[1], overlay.markers[1]);
        let hit = result.tree.unwrap();
        assert_eq!(hit.point, Vec3::new(0.25, 0.5, 1.0));
        // The query line runs from the query point to the closest point.
        let line = overlay
            .lines
            .chunks(2)
            .find(|l| l[0].color == colors::QUERY_LINE)
            .unwrap();
        assert_eq!(
            (line[0].position, line[1].position),
            (q.to_array(), hit.point.to_array())
        );
        // Markers: query, then the closest point on top.
        assert_eq!(overlay.markers.len(), 2);
        assert_eq!(overlay.markers[1].position, hit.point.to_array());
        assert_eq!(overlay.markers[1].color, colors::CLOSEST);
        // The closest face (a quad) is filled with 2 triangles and outlined.
        assert_eq!(overlay.triangles.len(), 6);
        let outline = overlay
            .lines
            .iter()
            .filter(|v| v.color == colors::CLOSEST_PRIMITIVE)
            .count();
        assert_eq!(outline, 8);
        // The two other nearest faces are outlined only.
        let others = overlay.lines.iter().filter(|v| v.color == colors::NEAREST).count();
        assert_eq!(others, 16);

        let vertices = model.query(PrimitiveKind::Vertices, q, 1, false);
        let overlay = query_overlay(&model, &vertices, None);
        assert_eq!(overlay.points.len(), 1);
        assert!(overlay.triangles.is_empty());
    }
}
