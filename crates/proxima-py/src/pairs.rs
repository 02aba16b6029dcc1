//! Queries between two meshes placed by rigid poses, and within one
//! (`proxima::pair`): `proxima.distance`, and the work of
//! `Mesh.intersects`, `Mesh.intersecting_pairs`, `Mesh.pairs_within` and
//! `Mesh.self_intersections` (whose `#[pymethods]` are in `mesh.rs`). Thin:
//! the arguments checked and named, the library called without the GIL on
//! the `threads=` pool, the answers laid out as numpy arrays.

use crate::arrays::{self, value_error};
use crate::poses::{self, Poses};
use crate::threads;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use proxima::pair::{self, DirectedHausdorff, FacePair, PairDistance, PairError, RigidPose};
use proxima::prelude::*;
use proxima::{DVec3, MeshIndex};
use pyo3::IntoPyObjectExt;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The nearest points of two placed meshes and where they lie; unpacks as
/// `(distance, point_a, point_b, face_a, face_b)`.
#[pyclass(module = "proxima", name = "PairDistance", frozen)]
pub struct PyPairDistance {
    inner: PairDistance,
}

#[pymethods]
impl PyPairDistance {
    /// The distance between the meshes (0 when their surfaces meet).
    #[getter]
    fn distance(&self) -> f64 {
        self.inner.distance
    }

    /// The point on the first mesh, in the world, (3,) float64.
    #[getter]
    fn point_a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.point_a.to_array().to_vec().into_pyarray(py)
    }

    /// The point on the second mesh, in the world, (3,) float64.
    #[getter]
    fn point_b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.point_b.to_array().to_vec().into_pyarray(py)
    }

    /// The face of the first mesh that holds `point_a`.
    #[getter]
    fn face_a(&self) -> i64 {
        self.inner.face_a.into()
    }

    /// The face of the second mesh that holds `point_b`.
    #[getter]
    fn face_b(&self) -> i64 {
        self.inner.face_b.into()
    }

    /// The triangle of the first mesh (fan triangles of its faces, in order)
    /// that holds `point_a`.
    #[getter]
    fn triangle_a(&self) -> i64 {
        self.inner.triangle_a.into()
    }

    /// The same for the second mesh.
    #[getter]
    fn triangle_b(&self) -> i64 {
        self.inner.triangle_b.into()
    }

    /// `point_a` in barycentric coordinates of `triangle_a`'s corners, (3,) float64.
    #[getter]
    fn barycentric_a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.barycentric_a.to_vec().into_pyarray(py)
    }

    /// `point_b` in barycentric coordinates of `triangle_b`'s corners, (3,) float64.
    #[getter]
    fn barycentric_b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.barycentric_b.to_vec().into_pyarray(py)
    }

    /// `(distance, point_a, point_b, face_a, face_b)`, so that the answer
    /// unpacks as a tuple.
    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let tuple = (
            self.distance(),
            self.point_a(py),
            self.point_b(py),
            self.face_a(),
            self.face_b(),
        );
        Ok(tuple.into_pyobject(py)?.as_any().try_iter()?.into_any())
    }

    fn __len__(&self) -> usize {
        5
    }

    fn __repr__(&self) -> String {
        let d = &self.inner;
        format!(
            "PairDistance(distance={}, point_a={:?}, point_b={:?}, face_a={}, face_b={})",
            d.distance,
            d.point_a.to_array(),
            d.point_b.to_array(),
            d.face_a,
            d.face_b
        )
    }
}

/// A library error as a `ValueError`; a refused distance bound names the
/// Python argument `distance_name`.
fn pair_error(error: PairError, distance_name: &str) -> PyErr {
    match error {
        PairError::BadDistance { value, .. } => value_error(distance_name, format!("must be at least 0 (got {value})")),
        PairError::BadTolerance { value, minimum } => value_error(
            "tolerance",
            format!("must be positive and at least {minimum:e} (1e-7 of the meshes' size; got {value})"),
        ),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// Fails unless `mesh` has faces, naming the argument.
fn require_faces(mesh: &MeshIndex, name: &str) -> PyResult<()> {
    mesh.require(PrimitiveKind::Faces).map_err(|e| value_error(name, e))
}

/// Refuses a stack of poses for `stack_name` with a non-identity
/// `fixed` pose (named `fixed_name`): a batch moves the second mesh with
/// the first unmoved.
fn require_unmoved(fixed: &RigidPose, fixed_name: &str, stack_name: &str) -> PyResult<()> {
    if fixed.is_identity() {
        return Ok(());
    }
    Err(value_error(
        fixed_name,
        format!(
            "a stack of poses in {stack_name} moves the second mesh with the first unmoved; give {fixed_name}=None \
             (or compose: inv({fixed_name}) @ {stack_name})"
        ),
    ))
}

/// The arrays of a batch of distances: distance (P,), point_a (P, 3),
/// point_b (P, 3), face_a (P,), face_b (P,).
type DistanceArrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
);

/// Bytes kept per pose of a batch of distances: the answer and its arrays.
const DISTANCE_BYTES: usize = size_of::<Option<PairDistance>>() + 8 * 9;

/// `proxima.distance` (its `#[pyfunction]` is in `mesh.rs`): the distance
/// between mesh `a` placed by `pose_a` and mesh `b` placed by `pose_b` (see
/// the stubs: one pose, or a (P, 4, 4) stack of poses of `b`).
pub fn distance<'py>(
    py: Python<'py>,
    a: &MeshIndex,
    b: &MeshIndex,
    pose_a: Option<&Bound<'py, PyAny>>,
    pose_b: Option<&Bound<'py, PyAny>>,
    max_distance: Option<f64>,
    threads: Option<i64>,
) -> PyResult<Py<PyAny>> {
    let pose_a = poses::one(pose_a, "pose_a")?;
    let pose_b = poses::poses(pose_b, "pose_b", DISTANCE_BYTES)?;
    require_faces(a, "a")?;
    require_faces(b, "b")?;
    let (ia, ib) = (a, b);
    let d_max = max_distance.unwrap_or(f64::INFINITY);
    match pose_b {
        Poses::One(pose_b) => {
            let found = threads::run(py, threads, || pair::distance_below(ia, &pose_a, ib, &pose_b, d_max))?
                .map_err(|e| pair_error(e, "max_distance"))?;
            match found {
                Some(inner) => PyPairDistance { inner }.into_py_any(py),
                None => Ok(py.None()),
            }
        }
        Poses::Many(poses) => {
            require_unmoved(&pose_a, "pose_a", "pose_b")?;
            let found = threads::run(py, threads, || pair::distance_below_batch(ia, ib, &poses, d_max))?
                .map_err(|e| pair_error(e, "max_distance"))?;
            distance_arrays(py, &found)?.into_py_any(py)
        }
    }
}

/// A batch's answers as arrays; beyond `max_distance`: distance `inf`,
/// points NaN, faces -1.
fn distance_arrays<'py>(py: Python<'py>, found: &[Option<PairDistance>]) -> PyResult<DistanceArrays<'py>> {
    let nan = [f64::NAN; 3];
    let distance: Vec<f64> = found.iter().map(|d| d.map_or(f64::INFINITY, |d| d.distance)).collect();
    let point = |f: fn(&PairDistance) -> [f64; 3]| -> Vec<f64> {
        found.iter().flat_map(|d| d.as_ref().map_or(nan, f)).collect()
    };
    let face = |f: fn(&PairDistance) -> u32| -> Vec<i64> {
        found.iter().map(|d| d.as_ref().map_or(-1, |d| f(d).into())).collect()
    };
    Ok((
        arrays::vector(py, distance),
        arrays::matrix(py, point(|d| d.point_a.to_array()), 3)?,
        arrays::matrix(py, point(|d| d.point_b.to_array()), 3)?,
        arrays::vector(py, face(|d| d.face_a)),
        arrays::vector(py, face(|d| d.face_b)),
    ))
}

/// `Mesh.intersects`: whether `this` placed by `pose_self` meets `other`
/// placed by `pose` (a bool), or at each pose of a (P, 4, 4) stack with
/// `this` unmoved ((P,) bool).
pub fn intersects(
    py: Python<'_>,
    this: &MeshIndex,
    other: &MeshIndex,
    pose: Option<&Bound<'_, PyAny>>,
    pose_self: Option<&Bound<'_, PyAny>>,
    threads: Option<i64>,
) -> PyResult<Py<PyAny>> {
    let pose_self = poses::one(pose_self, "pose_self")?;
    let pose = poses::poses(pose, "pose", 1)?;
    require_faces(this, "self")?;
    require_faces(other, "other")?;
    let (ia, ib) = (this, other);
    match pose {
        Poses::One(pose) => {
            let yes = threads::run(py, threads, || pair::intersects(ia, &pose_self, ib, &pose))?
                .map_err(|e| pair_error(e, "distance"))?;
            yes.into_py_any(py)
        }
        Poses::Many(poses) => {
            require_unmoved(&pose_self, "pose_self", "pose")?;
            let yes = threads::run(py, threads, || pair::intersects_batch(ia, ib, &poses))?
                .map_err(|e| pair_error(e, "distance"))?;
            yes.into_pyarray(py).into_py_any(py)
        }
    }
}

/// `Mesh.intersecting_pairs` (`within = None`) and `Mesh.pairs_within`: the
/// face pairs (face of `this`, face of `other`) that meet, or within
/// `within`, as a (K, 2) int64 array.
#[allow(clippy::too_many_arguments)]
pub fn pairs<'py>(
    py: Python<'py>,
    this: &MeshIndex,
    other: &MeshIndex,
    within: Option<f64>,
    pose: Option<&Bound<'py, PyAny>>,
    pose_self: Option<&Bound<'py, PyAny>>,
    threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    if let Some(d) = within
        && d.is_infinite()
    {
        // Every pair of faces: a list as long as the product of the face counts.
        return Err(value_error("distance", format!("must be finite (got {d})")));
    }
    let pose_self = poses::one(pose_self, "pose_self")?;
    let pose = poses::one(pose, "pose")?;
    require_faces(this, "self")?;
    require_faces(other, "other")?;
    let (ia, ib) = (this, other);
    let found = threads::run(py, threads, || match within {
        None => pair::intersecting_pairs(ia, &pose_self, ib, &pose),
        Some(d) => pair::pairs_within(ia, &pose_self, ib, &pose, d),
    })?
    .map_err(|e| pair_error(e, "distance"))?;
    face_pairs(py, &found)
}

/// `Mesh.self_intersections`: the face pairs of one mesh that meet beyond
/// what they share, (K, 2) int64, `face_a < face_b`, sorted.
pub fn self_intersections<'py>(
    py: Python<'py>,
    this: &MeshIndex,
    threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    require_faces(this, "self")?;
    let found = threads::run(py, threads, || pair::self_intersections(this))?.map_err(|e| pair_error(e, "distance"))?;
    face_pairs(py, &found)
}

/// Face pairs as a (K, 2) int64 array.
fn face_pairs<'py>(py: Python<'py>, pairs: &[FacePair]) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let flat: Vec<i64> = pairs.iter().flatten().map(|&f| f.into()).collect();
    arrays::matrix(py, flat, 2)
}

/// The Hausdorff distance between two meshes' surfaces, as bounds that meet
/// within the tolerance asked, and the pair of points that realizes the
/// lower bound.
#[pyclass(module = "proxima", name = "Hausdorff", frozen)]
pub struct PyHausdorff {
    lower: f64,
    /// The symmetric upper bound (both directions), or the one direction's
    /// when one-sided.
    upper: f64,
    /// The pair realizing `lower`: the point on `a` and its face, the same on `b`.
    a: (DVec3, u32),
    b: (DVec3, u32),
    /// `lower` is measured from `a` to `b` (else from `b` to `a`).
    from_a: bool,
}

impl PyHausdorff {
    /// The answer of `d`, measured from `a` (`from_a`) or from `b`, with the
    /// upper bound `upper`.
    fn new(d: &DirectedHausdorff, from_a: bool, upper: f64) -> Self {
        let (far, near) = ((d.point, d.face), (d.closest, d.closest_face));
        let (a, b) = if from_a { (far, near) } else { (near, far) };
        Self {
            lower: d.lower,
            upper,
            a,
            b,
            from_a,
        }
    }
}

#[pymethods]
impl PyHausdorff {
    /// A lower bound: the distance between `point_a` and `point_b`.
    #[getter]
    fn lower(&self) -> f64 {
        self.lower
    }

    /// An upper bound: no point of either surface (of `a`, one-sided) lies
    /// farther from the other.
    #[getter]
    fn upper(&self) -> f64 {
        self.upper
    }

    /// The point of mesh `a` of the pair that realizes `lower`, (3,) float64.
    #[getter]
    fn point_a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.a.0.to_array().to_vec().into_pyarray(py)
    }

    /// The point of mesh `b` of that pair, (3,) float64.
    #[getter]
    fn point_b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.b.0.to_array().to_vec().into_pyarray(py)
    }

    /// The face of `a` that holds `point_a`.
    #[getter]
    fn face_a(&self) -> i64 {
        self.a.1.into()
    }

    /// The face of `b` that holds `point_b`.
    #[getter]
    fn face_b(&self) -> i64 {
        self.b.1.into()
    }

    /// Whether `lower` is measured from `a`'s surface to `b`'s (`point_a` is
    /// the far point, `point_b` its nearest on `b`), else from `b`'s to `a`'s.
    #[getter(from_a)]
    fn measured_from_a(&self) -> bool {
        self.from_a
    }

    /// The upper bound, so that `float(h)` never understates the distance.
    fn __float__(&self) -> f64 {
        self.upper
    }

    fn __repr__(&self) -> String {
        format!(
            "Hausdorff(lower={}, upper={}, from_a={})",
            self.lower,
            self.upper,
            if self.from_a { "True" } else { "False" }
        )
    }
}

/// The tolerance of a mesh Hausdorff distance when none is given: this
/// fraction of the larger bounding-box diagonal.
const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-4;

/// `proxima.hausdorff` on two meshes (its `#[pyfunction]` is in
/// `points.rs`, which answers point sets too).
pub fn hausdorff<'py>(
    py: Python<'py>,
    a: &MeshIndex,
    b: &MeshIndex,
    one_sided: bool,
    tolerance: Option<f64>,
    threads: Option<i64>,
) -> PyResult<Bound<'py, PyHausdorff>> {
    require_faces(a, "a")?;
    require_faces(b, "b")?;
    let diagonal = |m: &MeshIndex| f64::from(m.mesh().bounds().diagonal());
    let tolerance = tolerance.unwrap_or(DEFAULT_RELATIVE_TOLERANCE * diagonal(a).max(diagonal(b)));
    let answer = if one_sided {
        let inner = threads::run(py, threads, || pair::directed_hausdorff(a, b, tolerance))?
            .map_err(|e| pair_error(e, "tolerance"))?;
        PyHausdorff::new(&inner, true, inner.upper)
    } else {
        let both =
            threads::run(py, threads, || pair::hausdorff(a, b, tolerance))?.map_err(|e| pair_error(e, "tolerance"))?;
        let from_a = both.forward.lower >= both.backward.lower;
        PyHausdorff::new(both.larger(), from_a, both.upper())
    };
    Bound::new(py, answer)
}
