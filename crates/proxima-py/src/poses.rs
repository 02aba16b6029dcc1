//! Rigid poses from numpy: a (4, 4) matrix `[R t; 0 0 0 1]` (row-major, as
//! numpy writes it) or a (P, 4, 4) stack, float64 or float32, checked by the
//! library ([`RigidPose::from_rows`], [`check_pose`]) and refused with a
//! `ValueError` naming the argument (and the pose of a stack by its index).

use crate::arrays::{real_array, value_error, values};
use crate::budget::check_budget;
use numpy::PyUntypedArrayMethods;
use proxima::pair::{RigidPose, check_pose};
use pyo3::prelude::*;

/// One pose or a stack of them.
pub enum Poses {
    /// A (4, 4) argument (or `None`: the identity).
    One(RigidPose),
    /// A (P, 4, 4) argument, in order.
    Many(Vec<RigidPose>),
}

/// `object` as one pose (`None` is the identity), refusing a stack.
pub fn one(object: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<RigidPose> {
    match poses(object, name, 0)? {
        Poses::One(pose) => Ok(pose),
        Poses::Many(_) => Err(value_error(
            name,
            "expected one pose of shape (4, 4); a stack of poses is answered by proxima.distance and Mesh.intersects",
        )),
    }
}

/// `object` as one pose or a stack; `None` is the identity. A stack is
/// counted against the memory budget at `bytes_each` bytes per pose (what
/// the caller keeps per pose besides the pose) before it is read.
pub fn poses(object: Option<&Bound<'_, PyAny>>, name: &str, bytes_each: usize) -> PyResult<Poses> {
    let Some(object) = object.filter(|o| !o.is_none()) else {
        return Ok(Poses::One(RigidPose::IDENTITY));
    };
    let array = real_array(object, name)?;
    let shape = array.shape().to_vec();
    match shape.as_slice() {
        [4, 4] => {
            let v: Vec<f64> = values(&array, "float64", name)?;
            Ok(Poses::One(pose(&v, name)?))
        }
        [count, 4, 4] => {
            let bytes = size_of::<RigidPose>() + 16 * size_of::<f64>() + bytes_each;
            check_budget(name, count, *count as u128, bytes as u128)?;
            let v: Vec<f64> = values(&array, "float64", name)?;
            let poses = v
                .chunks_exact(16)
                .enumerate()
                .map(|(i, m)| pose(m, &format!("{name}[{i}]")))
                .collect::<PyResult<Vec<_>>>()?;
            Ok(Poses::Many(poses))
        }
        _ => Err(value_error(
            name,
            format!("expected shape (4, 4) or (P, 4, 4), got {shape:?}"),
        )),
    }
}

/// The pose of 16 row-major values, or a `ValueError` naming `name`.
fn pose(m: &[f64], name: &str) -> PyResult<RigidPose> {
    let rows = [0, 1, 2, 3].map(|i| [m[4 * i], m[4 * i + 1], m[4 * i + 2], m[4 * i + 3]]);
    let pose = RigidPose::from_rows(rows).map_err(|e| value_error(name, e))?;
    check_pose(&pose, || name.to_string()).map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    Ok(pose)
}
