//! `proxima.Points`, `proxima.chamfer`, `proxima.hausdorff`: thin over
//! `proxima::points`.

use crate::arrays::{self, Check, value_error};
use crate::mesh::PyMesh;
use crate::threads;
use numpy::{PyArray1, PyArray2};
use proxima::Vec3;
use proxima::points::{PointCloud, PointsError};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::Arc;

/// The library's refusal as a `ValueError` (its message names the
/// argument, the radius as Python spells it: `r`).
fn points_error(error: PointsError) -> PyErr {
    let message = error.to_string();
    let message = match message.strip_prefix("radius") {
        Some(rest) => format!("r{rest}"),
        None => message,
    };
    PyValueError::new_err(message)
}

/// A point cloud and its tree, for neighbour queries.
#[pyclass(name = "Points", module = "proxima", frozen)]
pub struct PyPoints {
    cloud: Arc<PointCloud>,
}

/// (distance, index) rows of k-nearest.
type KRows<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<i64>>);

/// (offsets, index, distance) of compressed rows.
type Rows<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f32>>,
);

#[pymethods]
impl PyPoints {
    /// The cloud of `points` (N, 3), its tree built on the pool `threads`
    /// names.
    #[new]
    #[pyo3(signature = (points, threads = None))]
    fn new(py: Python<'_>, points: &Bound<'_, PyAny>, threads: Option<i64>) -> PyResult<Self> {
        let points = arrays::points(points, "points", Check::Finite)?;
        let points = points.as_slice();
        let cloud = threads::run(py, threads, || PointCloud::new(points))?.map_err(points_error)?;
        Ok(Self { cloud: Arc::new(cloud) })
    }

    fn __len__(&self) -> usize {
        self.cloud.len()
    }

    fn __repr__(&self) -> String {
        format!("proxima.Points({} points)", self.cloud.len())
    }

    /// The points, (N, 3) float32.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let flat: Vec<f32> = self.cloud.points().iter().flat_map(|p| p.to_array()).collect();
        arrays::matrix(py, flat, 3)
    }

    /// The `k` nearest points of each query: (distance, index), each
    /// (Q, k), nearest first, padded with inf and -1.
    #[pyo3(signature = (queries, k, threads = None))]
    fn k_nearest<'py>(
        &self,
        py: Python<'py>,
        queries: &Bound<'py, PyAny>,
        k: i64,
        threads: Option<i64>,
    ) -> PyResult<KRows<'py>> {
        let k = usize::try_from(k).map_err(|_| value_error("k", format!("{k} is less than 1")))?;
        let queries = arrays::points(queries, "queries", Check::QueryPoint)?;
        let queries = queries.as_slice();
        let cloud = &self.cloud;
        let found = threads::run(py, threads, || cloud.k_nearest_batch(queries, k))?.map_err(points_error)?;
        let index = found
            .indices
            .iter()
            .map(|&i| if i == u32::MAX { -1 } else { i64::from(i) })
            .collect();
        Ok((arrays::matrix(py, found.distances, k)?, arrays::matrix(py, index, k)?))
    }

    /// The points within `r` of each query (exactly: on the sphere counts),
    /// nearest first, at most `max_neighbors` of them, in compressed rows:
    /// (offsets (Q + 1,), index, distance); query i's are
    /// ``index[offsets[i]:offsets[i + 1]]``.
    #[pyo3(signature = (queries, r, max_neighbors = None, threads = None))]
    fn within<'py>(
        &self,
        py: Python<'py>,
        queries: &Bound<'py, PyAny>,
        r: f64,
        max_neighbors: Option<i64>,
        threads: Option<i64>,
    ) -> PyResult<Rows<'py>> {
        let most = match max_neighbors {
            None => None,
            Some(m) => {
                Some(usize::try_from(m).map_err(|_| value_error("max_neighbors", format!("{m} is less than 1")))?)
            }
        };
        let queries = arrays::points(queries, "queries", Check::QueryPoint)?;
        let queries = queries.as_slice();
        let cloud = &self.cloud;
        let rows = threads::run(py, threads, || cloud.within_batch(queries, r, most))?.map_err(points_error)?;
        let offsets = rows.offsets.iter().map(|&o| o as i64).collect();
        let index = rows.indices.iter().map(|&i| i64::from(i)).collect();
        Ok((
            arrays::vector(py, offsets),
            arrays::vector(py, index),
            arrays::vector(py, rows.distances),
        ))
    }

    /// How many points lie within `r` of each query (exactly), (Q,).
    #[pyo3(signature = (queries, r, threads = None))]
    fn count_within<'py>(
        &self,
        py: Python<'py>,
        queries: &Bound<'py, PyAny>,
        r: f64,
        threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let queries = arrays::points(queries, "queries", Check::QueryPoint)?;
        let queries = queries.as_slice();
        let cloud = &self.cloud;
        let counts = threads::run(py, threads, || cloud.count_within_batch(queries, r))?.map_err(points_error)?;
        Ok(arrays::vector(py, counts.into_iter().map(i64::from).collect()))
    }

    /// Every pair (i, j), i < j, of points within `r` of each other
    /// (exactly), sorted: (K, 2).
    #[pyo3(signature = (r, threads = None))]
    fn pairs_within<'py>(&self, py: Python<'py>, r: f64, threads: Option<i64>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let cloud = &self.cloud;
        let pairs = threads::run(py, threads, || cloud.pairs_within(r))?.map_err(points_error)?;
        arrays::matrix(py, pairs.iter().flat_map(|p| p.map(i64::from)).collect(), 2)
    }
}

/// A `Points` as it is, or (N, 3) points made into one.
fn cloud(object: &Bound<'_, PyAny>, name: &str, threads: Option<i64>) -> PyResult<Arc<PointCloud>> {
    if let Ok(points) = object.cast::<PyPoints>() {
        return Ok(points.get().cloud.clone());
    }
    let points = arrays::points(object, name, Check::Finite)?;
    let points: &[Vec3] = points.as_slice();
    let built = threads::run(object.py(), threads, || PointCloud::new(points))?
        .map_err(|e| PyValueError::new_err(e.to_string().replacen("points", name, 1)))?;
    Ok(Arc::new(built))
}

/// The nearest distances from `a` to `b` and back ([`proxima::points::chamfer`]).
fn both_ways(
    py: Python<'_>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    threads: Option<i64>,
) -> PyResult<proxima::points::Chamfer> {
    let (a, b) = (cloud(a, "a", threads)?, cloud(b, "b", threads)?);
    threads::run(py, threads, || proxima::points::chamfer(&a, &b))
}

/// The Chamfer distance between point sets `a` and `b` (arrays (N, 3) or
/// `Points`): with `squared`, mean of squared nearest distances from a to b
/// plus from b to a (pytorch3d's `chamfer_distance`); without, the same of
/// plain distances (point-cloud-utils').
#[pyfunction]
#[pyo3(signature = (a, b, squared = true, threads = None))]
pub fn chamfer(
    py: Python<'_>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    squared: bool,
    threads: Option<i64>,
) -> PyResult<f64> {
    let c = both_ways(py, a, b, threads)?;
    Ok(if squared {
        c.forward.mean_squared + c.backward.mean_squared
    } else {
        c.forward.mean + c.backward.mean
    })
}

/// The Hausdorff distance between point sets `a` and `b`: the largest
/// distance from a point of either to the other set, or with `one_sided`
/// only from `a` to `b`. Between two `Mesh`es, the distance between their
/// surfaces as a `Hausdorff` (bounds within `tolerance`, by default 1e-4 of
/// the larger bounding-box diagonal).
#[pyfunction]
#[pyo3(signature = (a, b, one_sided = false, *, tolerance = None, threads = None))]
pub fn hausdorff<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    one_sided: bool,
    tolerance: Option<f64>,
    threads: Option<i64>,
) -> PyResult<Py<PyAny>> {
    match (a.cast::<PyMesh>(), b.cast::<PyMesh>()) {
        (Ok(a), Ok(b)) => {
            let (a, b) = (a.borrow(), b.borrow());
            return Ok(
                crate::pairs::hausdorff(py, &a.index, &b.index, one_sided, tolerance, threads)?
                    .into_any()
                    .unbind(),
            );
        }
        (Ok(_), Err(_)) => return Err(value_error("b", "a is a Mesh, so b must be a Mesh too")),
        (Err(_), Ok(_)) => return Err(value_error("a", "b is a Mesh, so a must be a Mesh too")),
        (Err(_), Err(_)) => {}
    }
    if tolerance.is_some() {
        return Err(value_error(
            "tolerance",
            "applies to meshes; between point sets the distance is exact",
        ));
    }
    let c = both_ways(py, a, b, threads)?;
    let h = if one_sided { c.forward.max } else { c.hausdorff() };
    Ok(h.into_pyobject(py)?.into_any().unbind())
}
