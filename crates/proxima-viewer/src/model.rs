//! What the viewer knows about a loaded mesh: the mesh, its draw buffers, the
//! three AABB trees and brute-force searches (vertices, edges, faces), and the
//! queries the panel asks of them. Built off the UI thread; no GL, no egui.

use crate::scene::{self, MeshBuffers};
use proxima::frustum::Frustum;
use proxima::math::Vec3;
use proxima::prelude::*;
use proxima::{
    Aabb, AabbTree, BuildConfig, ClosestHit, ConvexPolygon, LineSegment, LinearSearch, Mesh, Point, PrimitiveSet,
    Sphere, SphereTree, TreeStats, Triangle,
};
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};
use std::time::Instant;

/// Which primitives of the mesh the queries run on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PrimitiveKind {
    /// Mesh vertices as points.
    Vertices,
    /// Unique undirected edges as segments.
    Edges,
    /// Faces (fan-triangulated; the source is the face).
    #[default]
    Faces,
    /// Faces as convex polygons (`Mesh::polygons`: convex planar faces kept
    /// whole, others fan-triangulated; the source is the face).
    Polygons,
}

impl PrimitiveKind {
    /// All kinds, in display order.
    pub const ALL: [PrimitiveKind; 4] = [
        PrimitiveKind::Vertices,
        PrimitiveKind::Edges,
        PrimitiveKind::Faces,
        PrimitiveKind::Polygons,
    ];

    /// Lowercase name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PrimitiveKind::Vertices => "vertices",
            PrimitiveKind::Edges => "edges",
            PrimitiveKind::Faces => "faces",
            PrimitiveKind::Polygons => "polygons",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

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

/// Trees and brute-force searches over one kind of primitive.
struct Index<T> {
    tree: AabbTree<T>,
    linear: LinearSearch<T>,
    /// `sources[i]`: the mesh element build input `i` came from.
    sources: Vec<u32>,
    /// Computed once: it walks every node.
    stats: TreeStats,
    /// The sphere tree over the same inputs, built when first shown.
    spheres: OnceLock<Option<SphereTree<T>>>,
}

impl<T: proxima::ClosestPoint + proxima::FrustumOverlap + Copy + Send + Sync> Index<T> {
    fn build(set: PrimitiveSet<T>) -> Result<(Self, f64), String> {
        let start = Instant::now();
        let tree = AabbTree::build_set(set.clone(), &BuildConfig::default()).map_err(|e| e.to_string())?;
        let seconds = start.elapsed().as_secs_f64();
        Ok((
            Self {
                sources: set.sources.clone(),
                spheres: OnceLock::new(),
                stats: tree.stats(),
                tree,
                linear: LinearSearch::new(set),
            },
            seconds,
        ))
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
    vertices: Index<Point>,
    edge_index: Index<LineSegment>,
    faces: Option<Index<Triangle>>,
    polygons: Option<Index<ConvexPolygon>>,
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
        let buffer_seconds = start.elapsed().as_secs_f64();
        report("tree over vertices", 0.45);
        let (vertices, t_vertices) = Index::build(mesh.vertices())?;
        report("tree over edges", 0.6);
        let (edge_index, t_edges) = Index::build(mesh.edges())?;
        report("tree over faces", 0.8);
        let (faces, t_faces) = if mesh.face_count() > 0 {
            let (index, t) = Index::build(mesh.triangles())?;
            (Some(index), t)
        } else {
            (None, 0.0)
        };
        report("tree over convex polygons", 0.9);
        let (polygons, t_polygons) = if mesh.face_count() > 0 {
            let (index, t) = Index::build(mesh.polygons())?;
            (Some(index), t)
        } else {
            (None, 0.0)
        };
        report("done", 1.0);
        Ok(Model {
            name,
            bounds: mesh.bounds(),
            edges,
            buffers,
            buffers_lod,
            timings: Timings {
                load,
                buffers: buffer_seconds,
                build: [t_vertices, t_edges, t_faces, t_polygons],
            },
            mesh,
            vertices,
            edge_index,
            faces,
            polygons,
        })
    }

    /// `true` when primitives of `kind` exist (a point cloud has no faces, a
    /// mesh without faces no edges).
    pub fn has(&self, kind: PrimitiveKind) -> bool {
        self.count(kind) > 0
    }

    /// Number of primitives of `kind`.
    pub fn count(&self, kind: PrimitiveKind) -> usize {
        match kind {
            PrimitiveKind::Vertices => self.vertices.tree.len(),
            PrimitiveKind::Edges => self.edge_index.tree.len(),
            PrimitiveKind::Faces => self.faces.as_ref().map_or(0, |f| f.tree.len()),
            PrimitiveKind::Polygons => self.polygons.as_ref().map_or(0, |f| f.tree.len()),
        }
    }

    /// Statistics of the tree over `kind`.
    pub fn tree_stats(&self, kind: PrimitiveKind) -> TreeStats {
        match kind {
            PrimitiveKind::Vertices => self.vertices.stats,
            PrimitiveKind::Edges => self.edge_index.stats,
            PrimitiveKind::Faces => self.faces.as_ref().map(|f| f.stats).unwrap_or_default(),
            PrimitiveKind::Polygons => self.polygons.as_ref().map(|f| f.stats).unwrap_or_default(),
        }
    }

    /// Seconds the tree over `kind` took to build.
    pub fn build_seconds(&self, kind: PrimitiveKind) -> f64 {
        self.timings.build[kind.index()]
    }

    /// The tree over faces (for picking), if the mesh has faces.
    pub fn face_tree(&self) -> Option<&AabbTree<Triangle>> {
        self.faces.as_ref().map(|f| &f.tree)
    }

    /// Spheres of the sphere tree's nodes of `kind` at exactly `depth` (root
    /// = 0). The sphere tree is built on first use (same inputs as the AABB
    /// tree, same hierarchy).
    pub fn sphere_nodes_at_depth(&self, kind: PrimitiveKind, depth: u32) -> Vec<Sphere> {
        fn at<T: Copy + proxima::ClosestPoint + proxima::primitive::BoundingPoints + Send + Sync>(
            index: &Index<T>,
            depth: u32,
        ) -> Vec<Sphere> {
            // The same inputs built the AABB tree, so the build does not fail.
            let tree = index.spheres.get_or_init(|| {
                SphereTree::build_with_sources(
                    index.linear.primitives().to_vec(),
                    index.sources.clone(),
                    &BuildConfig::default(),
                )
                .ok()
            });
            tree.as_ref()
                .map(|t| crate::spheres::sphere_nodes_at_depth(t, depth))
                .unwrap_or_default()
        }
        match kind {
            PrimitiveKind::Vertices => at(&self.vertices, depth),
            PrimitiveKind::Edges => at(&self.edge_index, depth),
            PrimitiveKind::Faces => self.faces.as_ref().map(|f| at(f, depth)).unwrap_or_default(),
            PrimitiveKind::Polygons => self.polygons.as_ref().map(|f| at(f, depth)).unwrap_or_default(),
        }
    }

    /// Boxes of the tree nodes of `kind` at exactly `depth` (root = 0).
    pub fn nodes_at_depth(&self, kind: PrimitiveKind, depth: u32) -> Vec<Aabb> {
        match kind {
            PrimitiveKind::Vertices => scene::nodes_at_depth(&self.vertices.tree, depth),
            PrimitiveKind::Edges => scene::nodes_at_depth(&self.edge_index.tree, depth),
            PrimitiveKind::Faces => self
                .faces
                .as_ref()
                .map(|f| scene::nodes_at_depth(&f.tree, depth))
                .unwrap_or_default(),
            PrimitiveKind::Polygons => self
                .polygons
                .as_ref()
                .map(|f| scene::nodes_at_depth(&f.tree, depth))
                .unwrap_or_default(),
        }
    }

    /// Closest primitive of `kind` to `p` by the tree (and by brute force when
    /// `with_linear`), with timings, and the `k` nearest.
    pub fn query(&self, kind: PrimitiveKind, p: Vec3, k: usize, with_linear: bool) -> QueryResult {
        fn run<T: proxima::ClosestPoint>(
            index: &Index<T>,
            p: Vec3,
            k: usize,
            with_linear: bool,
        ) -> (Option<ClosestHit>, f64, Option<ClosestHit>, f64, Vec<ClosestHit>) {
            let (tree, tree_seconds) = timed(|| index.tree.closest(p));
            let (linear, linear_seconds) = if with_linear {
                let start = Instant::now();
                let hit = index.linear.closest(p);
                (hit, start.elapsed().as_secs_f64())
            } else {
                (None, 0.0)
            };
            let nearest = if k > 0 { index.tree.k_nearest(p, k) } else { Vec::new() };
            (tree, tree_seconds, linear, linear_seconds, nearest)
        }
        let answer = match kind {
            PrimitiveKind::Vertices => run(&self.vertices, p, k, with_linear),
            PrimitiveKind::Edges => run(&self.edge_index, p, k, with_linear),
            PrimitiveKind::Faces => match &self.faces {
                Some(index) => run(index, p, k, with_linear),
                None => (None, 0.0, None, 0.0, Vec::new()),
            },
            PrimitiveKind::Polygons => match &self.polygons {
                Some(index) => run(index, p, k, with_linear),
                None => (None, 0.0, None, 0.0, Vec::new()),
            },
        };
        let (tree, tree_seconds, linear, linear_seconds, nearest) = answer;
        QueryResult {
            point: p,
            kind,
            tree,
            linear,
            tree_seconds,
            linear_seconds,
            nearest,
        }
    }

    /// Build-input indices of the primitives of `kind` overlapping `frustum`
    /// by the tree (ascending), with the mean seconds per query.
    pub fn frustum_query(&self, kind: PrimitiveKind, frustum: &Frustum) -> (Vec<u32>, f64) {
        let mut out = Vec::new();
        let seconds = match kind {
            PrimitiveKind::Vertices => timed(|| self.vertices.tree.frustum_into(frustum, &mut out)).1,
            PrimitiveKind::Edges => timed(|| self.edge_index.tree.frustum_into(frustum, &mut out)).1,
            PrimitiveKind::Faces => match &self.faces {
                Some(f) => timed(|| f.tree.frustum_into(frustum, &mut out)).1,
                None => 0.0,
            },
            PrimitiveKind::Polygons => match &self.polygons {
                Some(f) => timed(|| f.tree.frustum_into(frustum, &mut out)).1,
                None => 0.0,
            },
        };
        (out, seconds)
    }

    /// [`frustum_query`](Self::frustum_query) by brute force (every
    /// primitive tested), with the seconds it took.
    pub fn frustum_linear(&self, kind: PrimitiveKind, frustum: &Frustum) -> (Vec<u32>, f64) {
        let start = Instant::now();
        let out = match kind {
            PrimitiveKind::Vertices => self.vertices.linear.frustum(frustum),
            PrimitiveKind::Edges => self.edge_index.linear.frustum(frustum),
            PrimitiveKind::Faces => self
                .faces
                .as_ref()
                .map(|f| f.linear.frustum(frustum))
                .unwrap_or_default(),
            PrimitiveKind::Polygons => self
                .polygons
                .as_ref()
                .map(|f| f.linear.frustum(frustum))
                .unwrap_or_default(),
        };
        (out, start.elapsed().as_secs_f64())
    }

    /// The mesh element (vertex, edge or face) that build input `input` of
    /// `kind` came from.
    pub fn input_source(&self, kind: PrimitiveKind, input: u32) -> Option<u32> {
        let sources = match kind {
            PrimitiveKind::Vertices => &self.vertices.sources,
            PrimitiveKind::Edges => &self.edge_index.sources,
            PrimitiveKind::Faces => &self.faces.as_ref()?.sources,
            PrimitiveKind::Polygons => &self.polygons.as_ref()?.sources,
        };
        sources.get(input as usize).copied()
    }

    /// The geometry of build input `input` of `kind` (a face's fan triangle,
    /// not the whole face), for highlighting query answers given as inputs.
    pub fn input_shape(&self, kind: PrimitiveKind, input: u32) -> Option<scene::Shape> {
        let i = input as usize;
        match kind {
            PrimitiveKind::Vertices => self
                .vertices
                .linear
                .primitives()
                .get(i)
                .map(|p| scene::Shape::Point(p.0)),
            PrimitiveKind::Edges => self
                .edge_index
                .linear
                .primitives()
                .get(i)
                .map(|e| scene::Shape::Segment(e.a, e.b)),
            PrimitiveKind::Faces => self
                .faces
                .as_ref()?
                .linear
                .primitives()
                .get(i)
                .map(|t| scene::Shape::Polygon(vec![t.a, t.b, t.c])),
            PrimitiveKind::Polygons => self
                .polygons
                .as_ref()?
                .linear
                .primitives()
                .get(i)
                .map(|polygon| scene::Shape::Polygon(polygon.vertices().to_vec())),
        }
    }

    /// Closest primitive of `kind` to `p` by brute force, with the seconds it
    /// took (run on a worker thread by the viewer: on the dragon it takes
    /// tens of milliseconds).
    pub fn linear_closest(&self, kind: PrimitiveKind, p: Vec3) -> (Option<ClosestHit>, f64) {
        let start = Instant::now();
        let hit = match kind {
            PrimitiveKind::Vertices => self.vertices.linear.closest(p),
            PrimitiveKind::Edges => self.edge_index.linear.closest(p),
            PrimitiveKind::Faces => self.faces.as_ref().and_then(|f| f.linear.closest(p)),
            PrimitiveKind::Polygons => self.polygons.as_ref().and_then(|f| f.linear.closest(p)),
        };
        (hit, start.elapsed().as_secs_f64())
    }

    /// The geometry of primitive `source` of `kind` (vertex, edge or face
    /// index), for highlighting; `None` for an index out of range.
    pub fn primitive_shape(&self, kind: PrimitiveKind, source: u32) -> Option<scene::Shape> {
        let p = self.mesh.positions();
        let s = source as usize;
        match kind {
            PrimitiveKind::Vertices => p.get(s).map(|&v| scene::Shape::Point(v)),
            PrimitiveKind::Edges => self
                .edges
                .get(s)
                .map(|&[a, b]| scene::Shape::Segment(p[a as usize], p[b as usize])),
            PrimitiveKind::Faces => (s < self.mesh.face_count())
                .then(|| scene::Shape::Polygon(self.mesh.face(s).iter().map(|&i| p[i as usize]).collect())),
            PrimitiveKind::Polygons => (s < self.mesh.face_count())
                .then(|| scene::Shape::Polygon(self.mesh.face(s).iter().map(|&i| p[i as usize]).collect())),
        }
    }
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
        assert!(m.face_tree().is_none());
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
        let positions: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let faces = vec![
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
        ];
        let m = Model::load(
            ModelSource::Mesh {
                mesh: Mesh::from_faces(positions, &faces).unwrap(),
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
}
