//! The Python `Mesh`: a mesh, the structures built on it, and every query.

use crate::arrays::{self, Check, value_error};
use crate::budget::check_budget;
use crate::closest;
use crate::pairs;
use crate::surface::{self, Answers, SurfaceColumns, SurfaceOptions};
use crate::threads;
use crate::voxels::VoxelGrid;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use proxima::index::{IndexError, MeshIndex};
use proxima::prelude::*;
use proxima::sdf::{SdfGrid, Sign, SignedDistanceField};
use proxima::{Aabb, SdfError};
use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use rayon::prelude::*;
use std::sync::Arc;

/// A polygon mesh and the structures that answer queries on it, each built
/// on first use and kept (see the package's type stubs for the full
/// contract of each method).
///
/// >>> import numpy as np, proxima
/// >>> mesh = proxima.Mesh(np.eye(3), [[0, 1, 2]])
/// >>> closest, distance, face = mesh.closest_points([[0, 0, 0]])
/// >>> face.tolist()
/// [0]
#[pyclass(module = "proxima", name = "Mesh")]
pub struct PyMesh {
    /// The mesh and the structures built on it so far (the library's index:
    /// the command line and the viewer ask the same one), shared with the
    /// scenes it is placed in.
    pub(crate) index: Arc<MeshIndex>,
}

/// Distances and indices, one row per point (`k_nearest`).
type NearestArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);
/// Ray origins and directions (`sample_rays`).
type RayArrays32<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<f32>>);
/// Training points and their signed distances (`training_samples`).
type SampleArrays<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray1<f32>>);

impl PyMesh {
    /// A mesh with nothing built yet.
    pub fn wrap(mesh: Mesh) -> Self {
        Self {
            index: Arc::new(MeshIndex::new(mesh)),
        }
    }

    /// The mesh.
    fn mesh(&self) -> &Mesh {
        self.index.mesh()
    }

    /// `work` on the index for `kind`, without the GIL on the pool
    /// `threads` names; nothing built and `empty` when there is no query
    /// to answer. An [`IndexError`] becomes a `ValueError` naming
    /// `primitives`.
    fn on_index<T: Send>(
        &self,
        py: Python<'_>,
        kind: PrimitiveKind,
        empty: Option<T>,
        threads: Option<i64>,
        work: impl FnOnce(&MeshIndex) -> Result<T, IndexError> + Send,
    ) -> PyResult<T> {
        if let Some(empty) = empty {
            return Ok(empty);
        }
        self.index.require(kind).map_err(|e| value_error("primitives", e))?;
        threads::run(py, threads, || work(&self.index))?.map_err(|e| value_error("primitives", e))
    }

    /// `answer` on the field signed by `sign`, for `points` checked as
    /// `check`, without the GIL on the pool `threads` names; `what` names
    /// the call in errors.
    #[allow(clippy::too_many_arguments)]
    fn on_field<T: Send>(
        &self,
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        check: Check,
        threads: Option<i64>,
        what: &str,
        sign: Sign,
        answer: impl Fn(&SignedDistanceField, &[Vec3]) -> Vec<T> + Send + Sync,
    ) -> PyResult<Vec<T>> {
        let points = arrays::points(points, "points", check)?;
        let points = points.as_slice();
        self.require_faces(what)?;
        threads::run(py, threads, || {
            Ok::<_, IndexError>(answer(self.index.field(sign)?, points))
        })?
        .map_err(|e| value_error(what, e))
    }

    /// Fails unless the mesh has faces (signed distances, rays).
    fn require_faces(&self, what: &str) -> PyResult<()> {
        self.index
            .require(PrimitiveKind::Faces)
            .map_err(|e| value_error(what, e))
    }
}

/// The plain arrays `leading` as a tuple, or with `columns` (the
/// `return_*` options' arrays) as [`Answers`].
fn answers_or_tuple(
    py: Python<'_>,
    leading: Vec<(&'static str, Py<PyAny>)>,
    columns: Option<SurfaceColumns>,
) -> PyResult<Py<PyAny>> {
    match columns {
        Some(columns) => Answers::new(leading, columns.into_fields(py)?).into_py_any(py),
        None => PyTuple::new(py, leading.into_iter().map(|(_, v)| v))?.into_py_any(py),
    }
}

/// `primitives=` as a kind.
fn kind(primitives: &str) -> PyResult<PrimitiveKind> {
    primitives.parse().map_err(|e| value_error("primitives", e))
}

/// `sign=` as a sign method.
pub(crate) fn sign(text: &str) -> PyResult<Sign> {
    match text {
        "winding" => Ok(Sign::WindingNumber),
        "pseudonormal" => Ok(Sign::Pseudonormal),
        _ => Err(value_error(
            "sign",
            format!("'{text}' is not 'winding' or 'pseudonormal'"),
        )),
    }
}

/// The cube `[-half, half]³` of a `cube=` argument.
fn cube_bounds(half: f64) -> PyResult<Aabb> {
    let h = half as f32;
    if !(h.is_finite() && h > 0.0) {
        return Err(value_error("cube", format!("{half} is not a finite number > 0")));
    }
    Ok(Aabb::new(Vec3::splat(-h), Vec3::splat(h)))
}

/// Face index lists from `faces` (an integer (F, k) array or a list of
/// index sequences), checked non-negative and 32-bit.
fn face_lists(faces: &Bound<'_, PyAny>) -> PyResult<(Vec<u32>, Vec<u32>)> {
    let mut offsets = vec![0u32];
    let mut indices = Vec::new();
    let mut push = |face: usize, values: &[i64]| -> PyResult<()> {
        if values.len() < 3 {
            return Err(value_error(
                "faces",
                format!("face {face} has {} vertices; a face needs at least 3", values.len()),
            ));
        }
        for &v in values {
            let v = u32::try_from(v)
                .map_err(|_| value_error("faces", format!("face {face} refers to vertex {v}, not a vertex index")))?;
            indices.push(v);
        }
        let end = u32::try_from(indices.len()).map_err(|_| value_error("faces", "more than 2^32 - 1 indices"))?;
        offsets.push(end);
        Ok(())
    };
    match arrays::index_rows(faces, "faces")? {
        Some((values, k)) => {
            for (face, row) in values.chunks(k.max(1)).enumerate() {
                push(face, row)?;
            }
        }
        None => {
            for (face, item) in faces.try_iter().map_err(|e| value_error("faces", e))?.enumerate() {
                let values = arrays::index_list(&item?, &format!("faces[{face}]"))?;
                push(face, &values)?;
            }
        }
    }
    Ok((offsets, indices))
}

#[pymethods]
impl PyMesh {
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<Self> {
        let positions = arrays::points(vertices, "vertices", Check::Finite)?.as_slice().to_vec();
        let (offsets, indices) = face_lists(faces)?;
        let mesh = Mesh::from_compact(positions, offsets, indices).map_err(|e| value_error("faces", e))?;
        Ok(Self::wrap(mesh))
    }

    /// The mesh of a ``trimesh.Trimesh`` (its ``vertices`` and ``faces``).
    #[staticmethod]
    fn from_trimesh(mesh: &Bound<'_, PyAny>) -> PyResult<Self> {
        let vertices = mesh.getattr("vertices").map_err(|e| value_error("mesh", e))?;
        let faces = mesh.getattr("faces").map_err(|e| value_error("mesh", e))?;
        Self::new(&vertices, &faces)
    }

    /// The vertices, (V, 3) float32 (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = self.mesh().positions().iter().flat_map(|p| p.to_array()).collect();
        arrays::matrix(py, flat, 3)
    }

    /// Moves the vertices to ``positions`` ((V, 3), one row per vertex, in
    /// order; the faces unchanged) and refits every structure built so far
    /// (see the type stubs); returns what was done to each.
    fn update_vertices<'py>(
        &mut self,
        py: Python<'py>,
        positions: &Bound<'py, PyAny>,
    ) -> PyResult<Vec<(&'static str, bool, f64)>> {
        let positions = arrays::points(positions, "positions", Check::Finite)?;
        let positions = positions.as_slice();
        let Some(index) = Arc::get_mut(&mut self.index) else {
            return Err(value_error(
                "positions",
                "the mesh is placed in a Scene, which shares its structures: deform it there with \
                 Scene.update_vertices (or move it with Scene.set_pose), or deform a copy \
                 (proxima.Mesh(mesh.vertices, mesh.faces))",
            ));
        };
        let updated = py
            .detach(|| index.update_vertices(positions))
            .map_err(|e| value_error("positions", e))?;
        Ok(updated
            .into_iter()
            .map(|u| (u.structure, u.rebuilt, u.cost_ratio))
            .collect())
    }

    /// Every vertex's unit normal, angle-weighted from its faces, (V, 3)
    /// float32 (computed once and kept; zero for a vertex no face uses).
    #[getter]
    fn vertex_normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = self.index.vertex_normals().iter().flat_map(|n| n.to_array()).collect();
        arrays::matrix(py, flat, 3)
    }

    /// The texture coordinates per face corner (C, 2) float32, in the order
    /// of the faces' vertices, or None when the file had none.
    #[getter]
    fn corner_uvs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        let Some(uvs) = self.mesh().corner_uvs() else {
            return Ok(None);
        };
        arrays::matrix(py, uvs.iter().flatten().copied().collect(), 2).map(Some)
    }

    /// The shading normals per face corner (C, 3) float32, or None when the
    /// file had none.
    #[getter]
    fn corner_normals<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray2<f32>>>> {
        let Some(normals) = self.mesh().corner_normals() else {
            return Ok(None);
        };
        arrays::matrix(py, normals.iter().flat_map(|n| n.to_array()).collect(), 3).map(Some)
    }

    /// The faces: an (F, k) int64 array when every face has k vertices,
    /// otherwise a list of F int64 arrays.
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sizes: Vec<usize> = self.mesh().faces().map(<[u32]>::len).collect();
        let uniform = sizes.windows(2).all(|w| w[0] == w[1]);
        if uniform {
            let k = sizes.first().copied().unwrap_or(3);
            let flat: Vec<i64> = self.mesh().faces().flatten().map(|&v| v as i64).collect();
            return arrays::matrix(py, flat, k)?.into_bound_py_any(py);
        }
        let faces: Vec<Bound<'py, PyArray1<i64>>> = self
            .mesh()
            .faces()
            .map(|f| arrays::vector(py, f.iter().map(|&v| v as i64).collect()))
            .collect();
        PyList::new(py, faces)?.into_bound_py_any(py)
    }

    /// Whether a face uses each vertex, (V,) bool: without making
    /// :attr:`faces`' arrays, which for a mesh of mixed polygons is a list
    /// of one array per face.
    #[getter]
    fn used_vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let mesh = self.mesh();
        let mut used = vec![false; mesh.positions().len()];
        for &v in mesh.faces().flatten() {
            used[v as usize] = true;
        }
        arrays::vector(py, used)
    }

    /// The bounding box, [[min x, min y, min z], [max x, max y, max z]].
    #[getter]
    fn bounds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let b = self.mesh().bounds();
        let flat = [b.min, b.max]
            .iter()
            .flat_map(|v| v.to_array().map(f64::from))
            .collect();
        arrays::matrix(py, flat, 3)
    }

    fn __len__(&self) -> usize {
        self.mesh().face_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(vertices={}, faces={})",
            self.mesh().vertex_count(),
            self.mesh().face_count()
        )
    }

    /// The names of the structures built so far, in a fixed order
    /// (``"vertices"``, ``"edges"``, ``"faces"``, ``"polygons"``,
    /// ``"winding"``, ``"pseudonormal"``, ``"rays"``).
    fn built_structures(&self) -> Vec<&'static str> {
        self.index.built()
    }

    /// For each of ``points`` (N, 3), the closest point of the mesh's
    /// ``primitives``: ``(closest (N, 3) float64, distance (N,) float64,
    /// index (N,) int64)``.
    #[pyo3(signature = (
        points,
        primitives = "faces",
        threads = None,
        *,
        return_barycentric = false,
        return_feature = false,
        return_normal = false,
        return_uv = false
    ))]
    #[allow(clippy::too_many_arguments)]
    fn closest_points<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        primitives: &str,
        threads: Option<i64>,
        return_barycentric: bool,
        return_feature: bool,
        return_normal: bool,
        return_uv: bool,
    ) -> PyResult<Py<PyAny>> {
        let kind = kind(primitives)?;
        let asked = [return_barycentric, return_feature, return_normal, return_uv];
        let options = SurfaceOptions::asked(self.mesh(), asked)?;
        surface::require_faces(options, primitives)?;
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        let empty = points.is_empty().then(|| (Vec::new(), None));
        let (hits, columns) = self.on_index(py, kind, empty, threads, |index| {
            let hits = index.closest(kind, points)?;
            let columns = options
                .any()
                .then(|| SurfaceColumns::new(&index.closest_surface(points, &hits, options.attributes()), options));
            Ok((hits, columns))
        })?;
        let answers = closest::arrays(&hits);
        let leading = vec![
            ("closest", arrays::matrix(py, answers.closest, 3)?.into_py_any(py)?),
            ("distance", arrays::vector(py, answers.distance).into_py_any(py)?),
            ("index", arrays::vector(py, answers.index).into_py_any(py)?),
        ];
        answers_or_tuple(
            py,
            leading,
            columns.or_else(|| options.any().then(|| SurfaceColumns::empty(0, options))),
        )
    }

    /// The ``k`` nearest source elements of each point, nearest first:
    /// ``(distance (N, k) float64, index (N, k) int64)``.
    #[pyo3(signature = (points, k, primitives = "faces", threads = None))]
    fn k_nearest<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        k: i64,
        primitives: &str,
        threads: Option<i64>,
    ) -> PyResult<NearestArrays<'py>> {
        let kind = kind(primitives)?;
        if k < 1 {
            return Err(value_error("k", format!("{k} is less than 1")));
        }
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        // The answers: 16 bytes per (point, rank), and the hits behind them.
        check_budget("k", k, points.len() as u128 * k as u128, 48)?;
        let k = k as usize;
        let empty = points.is_empty().then(Default::default);
        let (distance, index) = self.on_index(py, kind, empty, threads, |index| {
            let mut rows = closest::NearestRows::with_capacity(points.len(), k);
            index.k_nearest_chunks::<IndexError>(kind, points, k, |answers| {
                rows.extend(answers);
                Ok(())
            })?;
            Ok(rows.into_arrays())
        })?;
        Ok((arrays::matrix(py, distance, k)?, arrays::matrix(py, index, k)?))
    }

    /// The signed distance of each point to the faces, negative inside;
    /// with ``return_gradient``, its gradient too.
    #[pyo3(signature = (points, sign = "winding", threads = None, *, return_gradient = false))]
    fn signed_distance<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        sign: &str,
        threads: Option<i64>,
        return_gradient: bool,
    ) -> PyResult<Py<PyAny>> {
        let sign = self::sign(sign)?;
        if return_gradient {
            let points = arrays::points(points, "points", Check::QueryPoint)?;
            let points = points.as_slice();
            self.require_faces("signed_distance")?;
            let answers = threads::run(py, threads, || self.index.signed_distance_gradients(sign, points))?
                .map_err(|e| value_error("signed_distance", e))?;
            let distance = answers
                .iter()
                .map(|a| a.map_or(f64::NAN, |a| f64::from(a.distance.distance)))
                .collect();
            let gradient = answers
                .iter()
                .flat_map(|a| a.map_or([f64::NAN; 3], |a| a.gradient.to_array()))
                .collect();
            let arrays = (arrays::vector(py, distance), arrays::matrix(py, gradient, 3)?);
            return arrays.into_py_any(py);
        }
        let values = self.on_field(
            py,
            points,
            Check::QueryPoint,
            threads,
            "signed_distance",
            sign,
            |field, points| {
                let answers = field.signed_distance_batch(points);
                answers
                    .iter()
                    .map(|d| d.map_or(f64::NAN, |d| d.distance as f64))
                    .collect()
            },
        )?;
        arrays::vector(py, values).into_py_any(py)
    }

    /// The generalized winding number at each point, shape (N,).
    #[pyo3(signature = (points, threads = None))]
    fn winding_number<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let values = self.on_field(
            py,
            points,
            Check::Finite,
            threads,
            "winding_number",
            Sign::WindingNumber,
            |field, points| field.winding_number_batch(points).into_iter().map(f64::from).collect(),
        )?;
        Ok(arrays::vector(py, values))
    }

    /// Whether each point is inside (winding number above 1/2), shape (N,).
    #[pyo3(signature = (points, threads = None))]
    fn contains<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let values = self.on_field(
            py,
            points,
            Check::Finite,
            threads,
            "contains",
            Sign::WindingNumber,
            |field, points| field.contains_batch(points),
        )?;
        Ok(arrays::vector(py, values))
    }

    /// The first face each ray hits: ``(t (N,) float64, index (N,) int64)``,
    /// t along the normalized direction, ``inf`` and -1 for a miss.
    #[pyo3(signature = (
        origins,
        directions,
        any_hit = false,
        threads = None,
        *,
        return_barycentric = false,
        return_feature = false,
        return_normal = false,
        return_uv = false
    ))]
    #[allow(clippy::too_many_arguments)]
    fn cast_rays<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        any_hit: bool,
        threads: Option<i64>,
        return_barycentric: bool,
        return_feature: bool,
        return_normal: bool,
        return_uv: bool,
    ) -> PyResult<Py<PyAny>> {
        let asked = [return_barycentric, return_feature, return_normal, return_uv];
        let options = SurfaceOptions::asked(self.mesh(), asked)?;
        let (origins, directions) = crate::rays::ray_arrays(origins, directions)?;
        let (origins, directions) = (origins.as_slice(), directions.as_slice());
        self.require_faces("cast_rays")?;
        let (t, index, columns) = threads::run(py, threads, || {
            let tree = self.index.ray_tree().map_err(|e| value_error("cast_rays", e))?;
            let hits = crate::rays::cast(tree, &crate::rays::rays(origins, directions), any_hit)?;
            let columns = options
                .any()
                .then(|| SurfaceColumns::new(&self.index.ray_surface(&hits, options.attributes()), options));
            let (t, index) = crate::rays::columns(&hits);
            Ok::<_, PyErr>((t, index, columns))
        })??;
        let leading = vec![
            ("t", arrays::vector(py, t).into_py_any(py)?),
            ("index", arrays::vector(py, index).into_py_any(py)?),
        ];
        answers_or_tuple(py, leading, columns)
    }

    /// The cells of a ``resolution``-cubed grid around the mesh that its
    /// faces overlap.
    #[pyo3(signature = (resolution, threads = None))]
    fn voxelize(&self, py: Python<'_>, resolution: i64, threads: Option<i64>) -> PyResult<VoxelGrid> {
        VoxelGrid::of_mesh(py, self.mesh(), resolution, threads)
    }

    /// The source indices (increasing) of the ``primitives`` that share a
    /// point with the frustum of an OpenGL view-projection matrix (4, 4).
    #[pyo3(signature = (view_projection, primitives = "faces"))]
    fn frustum<'py>(
        &self,
        py: Python<'py>,
        view_projection: &Bound<'py, PyAny>,
        primitives: &str,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let kind = kind(primitives)?;
        let m = arrays::floats(view_projection, "view_projection", &[4, 4])?;
        // numpy's rows; glam takes columns.
        let m: Vec<f32> = m.iter().map(|&x| x as f32).collect();
        let matrix = Mat4::from_cols_slice(&m).transpose();
        let frustum = Frustum::from_view_projection(matrix).map_err(|e| value_error("view_projection", e))?;
        // A mesh without that kind of element sees nothing: not an error.
        let nothing = (kind.available(self.mesh()) == 0).then(Vec::new);
        let found = self.on_index(py, kind, nothing, None, |index| index.frustum(kind, &frustum))?;
        Ok(arrays::vector(py, found.into_iter().map(i64::from).collect()))
    }

    /// For benchmarks: the seconds that the library's batch of ``query``
    /// (``"closest_points"``, ``"signed_distance"`` or ``"cast_rays"``, on
    /// faces, default options) takes on ``points`` (for rays: the origins,
    /// with ``directions``), timed inside the call: structures built first,
    /// no array conversion. The Python call's overhead is its own time over
    /// this one, measured in one process.
    #[pyo3(signature = (points, query, directions = None, threads = None))]
    fn _batch_seconds(
        &self,
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        query: &str,
        directions: Option<&Bound<'_, PyAny>>,
        threads: Option<i64>,
    ) -> PyResult<f64> {
        let rays = match directions {
            Some(directions) => {
                let (origins, directions) = crate::rays::ray_arrays(points, directions)?;
                crate::rays::rays(origins.as_slice(), directions.as_slice())
            }
            None => Vec::new(),
        };
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        self.require_faces(query)?;
        let timed = |work: &dyn Fn()| {
            let start = std::time::Instant::now();
            work();
            start.elapsed().as_secs_f64()
        };
        threads::run(py, threads, || -> PyResult<f64> {
            let built = |e: IndexError| value_error(query, e);
            match query {
                "closest_points" => {
                    let tree = self.index.tree::<Triangle>().map_err(built)?;
                    Ok(timed(&|| drop(tree.closest_batch(points))))
                }
                "signed_distance" => {
                    let field = self.index.field(Sign::WindingNumber).map_err(built)?;
                    Ok(timed(&|| drop(field.signed_distance_batch(points))))
                }
                "cast_rays" => {
                    let tree = self.index.ray_tree().map_err(built)?;
                    Ok(timed(&|| drop(tree.first_hit_batch(&rays, 0.0, f32::INFINITY))))
                }
                _ => Err(value_error(
                    "query",
                    format!("'{query}' is not closest_points, signed_distance or cast_rays"),
                )),
            }
        })?
    }

    /// ``n`` points uniform on the faces plus a gaussian offset per axis of
    /// ``sigma`` times the bounding-box diagonal, (n, 3) float32.
    #[pyo3(signature = (n, sigma = 0.01, seed = 0))]
    fn sample_near_surface<'py>(
        &self,
        py: Python<'py>,
        n: usize,
        sigma: f64,
        seed: u64,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        if !(0.0..=1e6).contains(&sigma) {
            return Err(value_error(
                "sigma",
                format!("{sigma} is not a finite number in [0, 1e6]"),
            ));
        }
        check_budget("n", n, n as u128, 12)?;
        self.require_faces("sample_near_surface")?;
        let points = py.detach(|| proxima::sample::near_surface(self.mesh(), n, sigma as f32, seed));
        if points.len() != n {
            return Err(value_error("sample_near_surface", "the faces have no area"));
        }
        arrays::matrix(py, points.iter().flat_map(|p| p.to_array()).collect(), 3)
    }

    /// ``n`` rays: origins uniform on the sphere of radius 0.75 times the
    /// bounding-box diagonal around its centre, aimed at points uniform in
    /// the box, unit directions (the benchmarks' ``rays`` set):
    /// ``(origins (n, 3), directions (n, 3))`` float32.
    #[pyo3(signature = (n, seed = 0))]
    fn sample_rays<'py>(&self, py: Python<'py>, n: usize, seed: u64) -> PyResult<RayArrays32<'py>> {
        check_budget("n", n, n as u128, 24)?;
        let bounds = self.mesh().bounds();
        let rays = py.detach(|| proxima::sample::rays_at_box(&bounds, n, seed));
        if rays.len() != n {
            return Err(value_error("sample_rays", "the bounding box is empty or a point"));
        }
        let origins = rays.iter().flat_map(|r| r.0.to_array()).collect();
        let directions = rays.iter().flat_map(|r| r.1.to_array()).collect();
        Ok((arrays::matrix(py, origins, 3)?, arrays::matrix(py, directions, 3)?))
    }

    /// ``n`` points uniform in the bounding box enlarged by 10% per side,
    /// (n, 3) float32.
    #[pyo3(signature = (n, seed = 0))]
    fn sample_uniform<'py>(&self, py: Python<'py>, n: usize, seed: u64) -> PyResult<Bound<'py, PyArray2<f32>>> {
        check_budget("n", n, n as u128, 12)?;
        if self.mesh().vertex_count() == 0 {
            return Err(value_error("sample_uniform", "the mesh has no vertices"));
        }
        let points = py.detach(|| proxima::sample::uniform_in_box(self.mesh(), n, seed));
        arrays::matrix(py, points.iter().flat_map(|p| p.to_array()).collect(), 3)
    }

    /// Training samples, the recipe of ``proxima sdf --sample`` and
    /// ``proxima.dataset``: ``n`` points, the first ``near`` of
    /// ``training_sample_counts(n, uniform_fraction)`` near the surface
    /// (uniform on the faces by area plus a gaussian offset per axis of
    /// standard deviation ``near_sigma``, an absolute length in the mesh's
    /// units), the rest uniform in the cube ``[-cube, cube]^3`` (or, when
    /// ``cube`` is None, the bounding box grown by 5% per side), with their
    /// signed distances: ``(points (n, 3) float32, sdf (n,) float32)``. The
    /// same arguments give the same arrays on every machine and thread count.
    #[pyo3(signature = (n, near_sigma, uniform_fraction = 0.5, cube = None, seed = 0, sign = "winding", threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn training_samples<'py>(
        &self,
        py: Python<'py>,
        n: usize,
        near_sigma: f64,
        uniform_fraction: f64,
        cube: Option<f64>,
        seed: u64,
        sign: &str,
        threads: Option<i64>,
    ) -> PyResult<SampleArrays<'py>> {
        let sign = self::sign(sign)?;
        let (near, uniform) = crate::budget::training_sample_counts(n, uniform_fraction)?;
        if !(near_sigma.is_finite() && near_sigma >= 0.0) {
            return Err(value_error(
                "near_sigma",
                format!("{near_sigma} is not a finite number >= 0"),
            ));
        }
        let cube = cube.map(cube_bounds).transpose()?;
        // The samples and their arrays: 16 bytes each, twice, and the batch's answers.
        check_budget("n", n, n as u128, 128)?;
        self.require_faces("training_samples")?;
        if n == 0 {
            return Ok((arrays::matrix(py, Vec::new(), 3)?, arrays::vector(py, Vec::new())));
        }
        let samples = threads::run(py, threads, || {
            let field = self
                .index
                .field_for(sign, n)
                .map_err(|e| value_error("training_samples", e))?;
            let uniform_box = cube.unwrap_or_else(|| {
                let b = field.bounds();
                let grow = b.size() * SdfGrid::DEFAULT_MARGIN;
                Aabb::new(b.min - grow, b.max + grow)
            });
            field
                .training_samples(near, near_sigma as f32, uniform, &uniform_box, seed)
                .map_err(|e| match e {
                    SdfError::Parameter { option: "sigma", .. } | SdfError::TooFar { option: "sigma", .. } => {
                        value_error("near_sigma", e)
                    }
                    SdfError::Parameter { option: "bounds", .. } | SdfError::TooFar { option: "bounds", .. } => {
                        value_error("cube", e)
                    }
                    e => value_error("n", e),
                })
        })??;
        if samples.points.len() != n {
            return Err(value_error("training_samples", "the faces have no area"));
        }
        let points = samples.points.iter().flat_map(|p| p.to_array()).collect();
        Ok((
            arrays::matrix(py, points, 3)?,
            arrays::vector(py, samples.signed_distances),
        ))
    }

    /// The signed distances at the centres of ``resolution``^3 cells dividing
    /// the cube ``[-cube, cube]^3`` (or, when ``cube`` is None, the bounding
    /// box grown by 5% per side), as ``proxima sdf --grid`` computes them:
    /// (N, N, N) float32, ``[i, j, k]`` at ``(x_i, y_j, z_k)``,
    /// ``x_i = lo + cell * (i + 0.5)`` in float32 (``cell = (hi - lo) / N``).
    #[pyo3(signature = (resolution, cube = None, sign = "winding", threads = None))]
    fn sdf_grid<'py>(
        &self,
        py: Python<'py>,
        resolution: i64,
        cube: Option<f64>,
        sign: &str,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray3<f32>>> {
        let sign = self::sign(sign)?;
        let n = usize::try_from(resolution)
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| value_error("resolution", format!("{resolution} is less than 1")))?;
        let cube = cube.map(cube_bounds).transpose()?;
        // The values in the library's order (x fastest) and in numpy's (C order).
        check_budget("resolution", n, (n as u128).pow(3), 8)?;
        self.require_faces("sdf_grid")?;
        let values = threads::run(py, threads, || {
            let field = self
                .index
                .field_for(sign, n.saturating_pow(3))
                .map_err(|e| value_error("sdf_grid", e))?;
            let grid = match cube {
                Some(cube) => SdfGrid::over(&cube, [n; 3]),
                None => SdfGrid::around(&field.bounds(), n, SdfGrid::DEFAULT_MARGIN),
            }
            .map_err(|e| value_error("sdf_grid", e))?;
            let values = field
                .sdf_grid(&grid, |_, _| {})
                .map_err(|e| value_error("resolution", e))?;
            // [i, j, k] in C order from x fastest.
            let mut out = vec![0f32; values.len()];
            out.par_chunks_mut(n * n).enumerate().for_each(|(i, plane)| {
                for (jk, value) in plane.iter_mut().enumerate() {
                    let (j, k) = (jk / n, jk % n);
                    *value = values[i + n * (j + n * k)];
                }
            });
            Ok::<_, PyErr>(out)
        })??;
        arrays::vector(py, values).reshape([n, n, n])
    }

    /// Whether this mesh's surface meets `other`'s (closed triangles:
    /// touching counts; decided exactly): `other` placed by `pose`, this
    /// mesh by `pose_self` ((4, 4) matrices, `None` the identity). A
    /// (P, 4, 4) `pose` answers each pose with this mesh unmoved: (P,) bool.
    #[pyo3(signature = (other, pose = None, *, pose_self = None, threads = None))]
    fn intersects(
        &self,
        py: Python<'_>,
        other: &Bound<'_, PyMesh>,
        pose: Option<&Bound<'_, PyAny>>,
        pose_self: Option<&Bound<'_, PyAny>>,
        threads: Option<i64>,
    ) -> PyResult<Py<PyAny>> {
        pairs::intersects(py, &self.index, &other.borrow().index, pose, pose_self, threads)
    }

    /// The pairs of faces (face of this mesh, face of `other`) that meet,
    /// decided exactly: (K, 2) int64, sorted.
    #[pyo3(signature = (other, pose = None, *, pose_self = None, threads = None))]
    fn intersecting_pairs<'py>(
        &self,
        py: Python<'py>,
        other: &Bound<'py, PyMesh>,
        pose: Option<&Bound<'py, PyAny>>,
        pose_self: Option<&Bound<'py, PyAny>>,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray2<i64>>> {
        pairs::pairs(py, &self.index, &other.borrow().index, None, pose, pose_self, threads)
    }

    /// The pairs of faces at distance at most `distance`: (K, 2) int64, sorted.
    #[pyo3(signature = (other, distance, pose = None, *, pose_self = None, threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn pairs_within<'py>(
        &self,
        py: Python<'py>,
        other: &Bound<'py, PyMesh>,
        distance: f64,
        pose: Option<&Bound<'py, PyAny>>,
        pose_self: Option<&Bound<'py, PyAny>>,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray2<i64>>> {
        pairs::pairs(
            py,
            &self.index,
            &other.borrow().index,
            Some(distance),
            pose,
            pose_self,
            threads,
        )
    }

    /// The pairs of faces of this mesh that meet beyond the vertices and
    /// edges they share: (K, 2) int64, `face_a < face_b`, sorted.
    #[pyo3(signature = (threads = None))]
    fn self_intersections<'py>(&self, py: Python<'py>, threads: Option<i64>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        pairs::self_intersections(py, &self.index, threads)
    }
}

/// `proxima.distance(a, b, pose_a=None, pose_b=None, *, max_distance=None,
/// threads=None)`: the distance between mesh `a` placed by `pose_a` and
/// mesh `b` placed by `pose_b` (see the stubs; the work is `pairs::distance`).
#[pyfunction]
#[pyo3(signature = (a, b, pose_a = None, pose_b = None, *, max_distance = None, threads = None))]
pub fn distance<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyMesh>,
    b: &Bound<'py, PyMesh>,
    pose_a: Option<&Bound<'py, PyAny>>,
    pose_b: Option<&Bound<'py, PyAny>>,
    max_distance: Option<f64>,
    threads: Option<i64>,
) -> PyResult<Py<PyAny>> {
    pairs::distance(
        py,
        &a.borrow().index,
        &b.borrow().index,
        pose_a,
        pose_b,
        max_distance,
        threads,
    )
}
