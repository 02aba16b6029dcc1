//! `proxima.traverse`: the Amanatides & Woo walk of a ray through a grid.

use crate::arrays::{self, value_error};
use crate::budget::check_budget;
use numpy::{PyArray1, PyArray2};
use proxima::prelude::*;
use proxima::{GridTraversal, TraversalConfig};
use pyo3::prelude::*;

/// What `traverse` returns: cells, entry and exit parameters.
type Walk<'py> = (
    Bound<'py, PyArray2<i64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// The first ``steps`` cells that the ray ``origin + t * direction`` (t >= 0)
/// crosses in a grid of cells of ``cell_size`` (one number, or three) with a
/// corner at the origin: ``(cells (n, 3) int64, t_enter (n,), t_exit (n,))``.
///
/// >>> cells, t0, t1 = proxima.traverse([0.5, 0.5, 0.5], [1, 0, 0], 1.0, 3)
/// >>> cells.tolist()
/// [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
#[pyfunction]
pub fn traverse<'py>(
    py: Python<'py>,
    origin: &Bound<'py, PyAny>,
    direction: &Bound<'py, PyAny>,
    cell_size: &Bound<'py, PyAny>,
    steps: i64,
) -> PyResult<Walk<'py>> {
    let origin = arrays::vec3(origin, "origin")?;
    let direction = arrays::vec3(direction, "direction")?;
    let size = match cell_size.extract::<f64>() {
        Ok(size) => Vec3::splat(size as f32),
        Err(_) => arrays::vec3(cell_size, "cell_size")?,
    };
    if steps < 0 {
        return Err(value_error("steps", format!("{steps} is negative")));
    }
    // Cells (24 bytes) and two parameters (16 bytes) per step.
    check_budget("steps", steps, steps as u128, 40)?;
    let config = TraversalConfig {
        max_steps: steps as u64,
        ..TraversalConfig::new(size)
    };
    let walk = GridTraversal::new(origin, direction, &config).map_err(|e| {
        let name = match e {
            proxima::GridError::Ray(proxima::RayError::Direction) => "direction",
            proxima::GridError::Ray(proxima::RayError::Origin) => "origin",
            _ => "cell_size",
        };
        value_error(name, e)
    })?;
    let (mut cells, mut t_enter, mut t_exit) = (Vec::new(), Vec::new(), Vec::new());
    py.detach(|| {
        for step in walk {
            cells.extend(step.cell);
            t_enter.push(step.t_enter as f64);
            t_exit.push(step.t_exit as f64);
        }
    });
    Ok((
        arrays::matrix(py, cells, 3)?,
        arrays::vector(py, t_enter),
        arrays::vector(py, t_exit),
    ))
}
