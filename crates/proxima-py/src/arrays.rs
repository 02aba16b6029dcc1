//! numpy arrays in and out: shape, dtype and value checks that name the
//! argument, and points read without a copy when they are already
//! contiguous float32.

use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyReadonlyArray2, PyUntypedArray,
    PyUntypedArrayMethods,
};
use proxima::Vec3;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `ValueError("{name}: {message}")`.
pub fn value_error(name: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{name}: {message}"))
}

/// `object` as a numpy array (no copy when it is one), refused unless its
/// values are real numbers (integers or floats).
pub fn real_array<'py>(object: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let py = object.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (object,))
        .map_err(|e| value_error(name, format!("not an array of numbers ({e})")))?;
    let array = array
        .cast_into::<PyUntypedArray>()
        .map_err(|_| value_error(name, "not an array"))?;
    let kind = array.dtype().kind();
    if !matches!(kind, b'i' | b'u' | b'f') {
        let dtype = array.dtype().str().map(|s| s.to_string()).unwrap_or_default();
        return Err(value_error(
            name,
            format!("dtype {dtype} is not a real number type (expected float32 or float64)"),
        ));
    }
    Ok(array)
}

/// `array` converted to a C-contiguous array of `dtype` (the same array
/// when it already is one).
fn contiguous<'py>(array: &Bound<'py, PyUntypedArray>, dtype: &str) -> PyResult<Bound<'py, PyAny>> {
    let numpy = array.py().import("numpy")?;
    numpy.call_method1("ascontiguousarray", (array, dtype))
}

/// The values of `array` converted to `dtype` (a numpy name matching `T`),
/// in C order.
pub fn values<T: numpy::Element + Copy>(
    array: &Bound<'_, PyUntypedArray>,
    dtype: &str,
    name: &str,
) -> PyResult<Vec<T>> {
    let array = contiguous(array, dtype)?;
    let array = array
        .cast_into::<numpy::PyArrayDyn<T>>()
        .map_err(|_| value_error(name, format!("not a {dtype} array")))?;
    let readonly = array.try_readonly().map_err(|e| value_error(name, e))?;
    Ok(readonly.as_slice().map_err(|e| value_error(name, e))?.to_vec())
}

/// Points of shape (N, 3): borrowed from a C-contiguous float32 array, or
/// converted once (float64 and integers, other layouts) to float32.
pub enum Points<'py> {
    /// The caller's own float32 array.
    Borrowed(PyReadonlyArray2<'py, f32>),
    /// A converted copy.
    Owned(Vec<Vec3>),
}

impl Points<'_> {
    /// The points.
    pub fn as_slice(&self) -> &[Vec3] {
        match self {
            Self::Borrowed(array) => bytemuck::cast_slice(array.as_slice().expect("checked C-contiguous")),
            Self::Owned(points) => points,
        }
    }
}

/// What a coordinate array's values must be.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Check {
    /// Finite, and within the range the trees answer in
    /// ([`proxima::check_query_point`]).
    QueryPoint,
    /// Finite (also after rounding to float32).
    Finite,
}

/// `object` as (N, 3) points named `name` in messages; every point
/// checked as `check` says, the first bad one named by its row.
pub fn points<'py>(object: &Bound<'py, PyAny>, name: &str, check: Check) -> PyResult<Points<'py>> {
    let array = real_array(object, name)?;
    let shape = array.shape();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(value_error(name, format!("expected shape (N, 3), got {shape:?}")));
    }
    let is_f32 = array.dtype().is_equiv_to(&numpy::dtype::<f32>(object.py()));
    let points = if is_f32 && array.is_c_contiguous() {
        let array = array
            .cast_into::<PyArray2<f32>>()
            .map_err(|_| value_error(name, "not a float32 array"))?;
        Points::Borrowed(array.try_readonly().map_err(|e| value_error(name, e))?)
    } else {
        // float64 (or integers, or another layout): read once into float32.
        let array = contiguous(&array, "float64")?;
        let array = array
            .cast_into::<PyArray2<f64>>()
            .map_err(|_| value_error(name, "not a float64 array"))?;
        let array = array.try_readonly().map_err(|e| value_error(name, e))?;
        let values = array.as_slice().map_err(|e| value_error(name, e))?;
        Points::Owned(
            values
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
                .collect(),
        )
    };
    check_points(points.as_slice(), name, check)?;
    Ok(points)
}

/// Fails on the first point that is not finite (or, for query points,
/// beyond the trees' range), naming it by row.
fn check_points(points: &[Vec3], name: &str, check: Check) -> PyResult<()> {
    let bad = match check {
        Check::Finite => points.iter().position(|p| !p.is_finite()).map(|row| (row, None)),
        Check::QueryPoint => points
            .iter()
            .enumerate()
            .find_map(|(row, &p)| proxima::check_query_point(p).err().map(|e| (row, Some(e.to_string())))),
    };
    match bad {
        None => Ok(()),
        Some((row, reason)) => {
            let p = points[row];
            let reason = reason.unwrap_or_else(|| "not finite as float32".into());
            Err(PyValueError::new_err(format!(
                "{name}[{row}] = ({}, {}, {}): {reason}",
                p.x, p.y, p.z
            )))
        }
    }
}

/// `object` as one 3-vector named `name` (a sequence or array of three
/// real numbers, finite).
pub fn vec3(object: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec3> {
    let array = real_array(object, name)?;
    if array.shape() != [3] {
        return Err(value_error(
            name,
            format!("expected 3 numbers, got shape {:?}", array.shape()),
        ));
    }
    let values: Vec<f64> = values(&array, "float64", name)?;
    let v = Vec3::new(values[0] as f32, values[1] as f32, values[2] as f32);
    if !v.is_finite() {
        return Err(value_error(
            name,
            format!("({}, {}, {}) is not finite as float32", values[0], values[1], values[2]),
        ));
    }
    Ok(v)
}

/// `object` as a float64 array of `shape`, C-contiguous, as a flat vector.
pub fn floats(object: &Bound<'_, PyAny>, name: &str, shape: &[usize]) -> PyResult<Vec<f64>> {
    let array = real_array(object, name)?;
    if array.shape() != shape {
        return Err(value_error(
            name,
            format!("expected shape {shape:?}, got {:?}", array.shape()),
        ));
    }
    values(&array, "float64", name)
}

/// `object` as a 2-D integer array (rows of equal length) or `None` when
/// it is not an integer array of two dimensions; refuses floats.
pub fn index_rows(object: &Bound<'_, PyAny>, name: &str) -> PyResult<Option<(Vec<i64>, usize)>> {
    let py = object.py();
    let numpy = py.import("numpy")?;
    let Ok(array) = numpy.call_method1("asarray", (object,)) else {
        return Ok(None); // ragged lists: the caller reads them face by face
    };
    let Ok(array) = array.cast_into::<PyUntypedArray>() else {
        return Ok(None);
    };
    let kind = array.dtype().kind();
    if kind == b'O' {
        return Ok(None);
    }
    if !matches!(kind, b'i' | b'u') {
        let dtype = array.dtype().str().map(|s| s.to_string()).unwrap_or_default();
        return Err(value_error(name, format!("dtype {dtype} is not an integer type")));
    }
    let shape = array.shape().to_vec();
    if shape.len() != 2 {
        if shape.len() == 1 && shape[0] == 0 {
            return Ok(Some((Vec::new(), 3))); // an empty list: no faces
        }
        return Err(value_error(
            name,
            format!("expected shape (F, k) or a list of index sequences, got {shape:?}"),
        ));
    }
    let values: Vec<i64> = values(&array, "int64", name)?;
    Ok(Some((values, shape[1])))
}

/// `object` as one face: a 1-D sequence of integers.
pub fn index_list(object: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<i64>> {
    let array = real_array(object, name)?;
    if !matches!(array.dtype().kind(), b'i' | b'u') {
        return Err(value_error(name, "face indices must be integers"));
    }
    if array.shape().len() != 1 {
        return Err(value_error(
            name,
            format!("expected a sequence of indices, got shape {:?}", array.shape()),
        ));
    }
    values(&array, "int64", name)
}

/// A flat vector of `rows * columns` values as a (rows, columns) array.
pub fn matrix<'py, T: numpy::Element>(
    py: Python<'py>,
    values: Vec<T>,
    columns: usize,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let rows = values.len().checked_div(columns).unwrap_or(0);
    values.into_pyarray(py).reshape([rows, columns])
}

/// A vector as a 1-D array.
pub fn vector<T: numpy::Element>(py: Python<'_>, values: Vec<T>) -> Bound<'_, PyArray1<T>> {
    values.into_pyarray(py)
}
