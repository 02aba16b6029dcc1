//! The Python `Scene`: meshes placed by rigid poses, asked as one (the
//! library's `proxima::scene`).

use crate::arrays::{self, Check, value_error};
use crate::mesh::PyMesh;
use crate::{poses, threads};
use numpy::{PyArray1, PyArray2};
use proxima::scene::Scene;
use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use rayon::prelude::*;

/// Meshes placed by rigid poses, asked as one (see the type stubs).
#[pyclass(module = "proxima", name = "Scene")]
pub struct PyScene {
    scene: Scene,
}

/// A (4, 4) pose as its rows.
fn pose_rows<'py>(py: Python<'py>, pose: &proxima::pair::RigidPose) -> PyResult<Bound<'py, PyArray2<f64>>> {
    arrays::matrix(py, pose.to_rows().into_iter().flatten().collect(), 4)
}

impl PyScene {
    /// The instance `index` names, or a ValueError naming `index`.
    fn instance(&self, index: i64) -> PyResult<usize> {
        let count = self.scene.len();
        usize::try_from(index).ok().filter(|&i| i < count).ok_or_else(|| {
            value_error(
                "index",
                format!("{index} is out of range: the scene has {count} instances"),
            )
        })
    }
}

#[pymethods]
impl PyScene {
    /// A scene of ``instances``: (mesh, pose) pairs, pose a (4, 4) rigid
    /// matrix or None for the identity.
    #[new]
    fn new(py: Python<'_>, instances: &Bound<'_, PyAny>) -> PyResult<Self> {
        let mut placed = Vec::new();
        for (i, item) in instances.try_iter()?.enumerate() {
            let item = item?;
            let name = format!("instances[{i}]");
            let pair = item
                .cast::<PyTuple>()
                .map_err(|_| value_error(&name, "expected a (mesh, pose) pair"))?;
            if pair.len() != 2 {
                return Err(value_error(
                    &name,
                    format!("expected a (mesh, pose) pair, got {} items", pair.len()),
                ));
            }
            let mesh = pair
                .get_item(0)?
                .cast::<PyMesh>()
                .map_err(|_| value_error(&name, "the first item is not a proxima.Mesh"))?
                .borrow()
                .index
                .clone();
            let pose = pair.get_item(1)?;
            let pose = poses::one((!pose.is_none()).then_some(&pose), &format!("{name}[1]"))?;
            placed.push((mesh, pose));
        }
        let scene = py
            .detach(|| Scene::new(placed))
            .map_err(|e| value_error("instances", e))?;
        Ok(Self { scene })
    }

    /// Number of instances.
    fn __len__(&self) -> usize {
        self.scene.len()
    }

    /// The pose of instance ``index``, (4, 4) float64.
    fn pose<'py>(&self, py: Python<'py>, index: i64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        pose_rows(py, self.scene.instances()[self.instance(index)?].pose())
    }

    /// Moves instance ``index`` to ``pose``; only the top level is refit.
    fn set_pose(&mut self, index: i64, pose: &Bound<'_, PyAny>) -> PyResult<()> {
        let i = self.instance(index)?;
        let pose = poses::one(Some(pose), "pose")?;
        self.scene.set_pose(i, pose).map_err(|e| value_error("pose", e))
    }

    /// Moves the vertices of instance ``index``'s mesh to ``positions`` (V,
    /// 3), deforming every instance of that mesh (see the type stubs).
    fn update_vertices<'py>(
        &mut self,
        py: Python<'py>,
        index: i64,
        positions: &Bound<'py, PyAny>,
    ) -> PyResult<Vec<(&'static str, bool, f64)>> {
        let i = self.instance(index)?;
        let positions = arrays::points(positions, "positions", Check::Finite)?;
        let positions = positions.as_slice();
        let updated = py
            .detach(|| self.scene.update_vertices(i, positions))
            .map_err(|e| value_error("positions", e))?;
        Ok(updated
            .into_iter()
            .map(|u| (u.structure, u.rebuilt, u.cost_ratio))
            .collect())
    }

    /// The closest point of any instance to each point: ``(closest (N, 3)
    /// float64, distance (N,) float64, instance (N,) int64, face (N,) int64)``.
    #[pyo3(signature = (points, threads = None))]
    fn closest_points<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        threads: Option<i64>,
    ) -> PyResult<Py<PyAny>> {
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        let hits = threads::run(py, threads, || self.scene.closest_batch(points))?;
        let (mut closest, mut distance, mut instance, mut face) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for hit in &hits {
            match hit {
                Some(h) => {
                    closest.extend(h.point.to_array());
                    distance.push(h.distance as f64);
                    instance.push(h.instance as i64);
                    face.push(h.face as i64);
                }
                None => {
                    closest.extend([f64::NAN; 3]);
                    distance.push(f64::INFINITY);
                    instance.push(-1);
                    face.push(-1);
                }
            }
        }
        PyTuple::new(
            py,
            [
                arrays::matrix(py, closest, 3)?.into_py_any(py)?,
                arrays::vector(py, distance).into_py_any(py)?,
                arrays::vector(py, instance).into_py_any(py)?,
                arrays::vector(py, face).into_py_any(py)?,
            ],
        )?
        .into_py_any(py)
    }

    /// The ``k`` faces of any instances nearest to each point: ``(distance
    /// (N, k) float64, instance (N, k) int64, face (N, k) int64)``, nearest
    /// first, padded with inf and -1.
    #[pyo3(signature = (points, k, threads = None))]
    fn k_nearest<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        k: i64,
        threads: Option<i64>,
    ) -> PyResult<Py<PyAny>> {
        if k < 1 {
            return Err(value_error("k", format!("{k} is less than 1")));
        }
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        crate::budget::check_budget("k", k, points.len() as u128 * k as u128, 64)?;
        let k = k as usize;
        let answers = threads::run(py, threads, || self.scene.k_nearest_batch(points, k))?;
        let n = points.len() * k;
        let (mut distance, mut instance, mut face) = (vec![f64::INFINITY; n], vec![-1i64; n], vec![-1i64; n]);
        for (row, hits) in answers.iter().enumerate() {
            for (j, h) in hits.iter().enumerate() {
                distance[row * k + j] = h.distance as f64;
                instance[row * k + j] = h.instance as i64;
                face[row * k + j] = h.face as i64;
            }
        }
        PyTuple::new(
            py,
            [
                arrays::matrix(py, distance, k)?.into_py_any(py)?,
                arrays::matrix(py, instance, k)?.into_py_any(py)?,
                arrays::matrix(py, face, k)?.into_py_any(py)?,
            ],
        )?
        .into_py_any(py)
    }

    /// The scene's signed distance at each point: negative inside any
    /// instance, (N,) float64.
    #[pyo3(signature = (points, sign = "winding", threads = None))]
    fn signed_distance<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        sign: &str,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let sign = crate::mesh::sign(sign)?;
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        let values = threads::run(py, threads, || {
            self.scene
                .signed_distance_batch(points, sign)
                .into_par_iter()
                .map(|s| s.map_or(f64::INFINITY, |s| s.distance as f64))
                .collect::<Vec<_>>()
        })?;
        Ok(arrays::vector(py, values))
    }

    /// Whether each point is inside some instance, (N,) bool.
    #[pyo3(signature = (points, sign = "winding", threads = None))]
    fn contains<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        sign: &str,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let sign = crate::mesh::sign(sign)?;
        let points = arrays::points(points, "points", Check::QueryPoint)?;
        let points = points.as_slice();
        let values = threads::run(py, threads, || {
            points
                .par_iter()
                .with_min_len(64)
                .map(|&p| self.scene.contains(p, sign))
                .collect::<Vec<_>>()
        })?;
        Ok(arrays::vector(py, values))
    }

    /// The first hit of each ray on any instance (or, with ``any_hit``,
    /// some hit): ``(t (N,) float64, instance (N,) int64, face (N,) int64)``,
    /// ``inf`` and -1 for a miss; directions normalized, so ``t`` is a distance.
    #[pyo3(signature = (origins, directions, any_hit = false, threads = None))]
    fn cast_rays<'py>(
        &self,
        py: Python<'py>,
        origins: &Bound<'py, PyAny>,
        directions: &Bound<'py, PyAny>,
        any_hit: bool,
        threads: Option<i64>,
    ) -> PyResult<Py<PyAny>> {
        let (origins, directions) = crate::rays::ray_arrays(origins, directions)?;
        let rays = crate::rays::rays(origins.as_slice(), directions.as_slice());
        let hits = threads::run(py, threads, || {
            rays.par_iter()
                .with_min_len(64)
                .map(|&(o, d)| {
                    let hit = if any_hit {
                        self.scene.some_hit(o, d, 0.0, f32::INFINITY)
                    } else {
                        self.scene.first_hit(o, d, 0.0, f32::INFINITY)
                    };
                    hit.map(|hit| hit.map(|h| (h.t, h.instance as i64, h.face as i64)))
                })
                .collect::<Vec<_>>()
        })?;
        let (mut t, mut instance, mut face) = (Vec::new(), Vec::new(), Vec::new());
        for (row, hit) in hits.into_iter().enumerate() {
            match hit.map_err(|e| value_error(&format!("rays[{row}]"), e))? {
                Some((tt, i, f)) => {
                    t.push(tt as f64);
                    instance.push(i);
                    face.push(f);
                }
                None => {
                    t.push(f64::INFINITY);
                    instance.push(-1);
                    face.push(-1);
                }
            }
        }
        PyTuple::new(
            py,
            [
                arrays::vector(py, t).into_py_any(py)?,
                arrays::vector(py, instance).into_py_any(py)?,
                arrays::vector(py, face).into_py_any(py)?,
            ],
        )?
        .into_py_any(py)
    }
}
