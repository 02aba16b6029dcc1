//! `Mesh.voxelize` and the `VoxelGrid` it returns.

use crate::arrays::{self, value_error};
use crate::budget::check_budget;
use crate::threads;
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use proxima::grid::{Cell, VoxelConfig, voxelize};
use proxima::prelude::*;
use pyo3::prelude::*;

/// The cells of a cubic grid that a mesh's triangles overlap (exact
/// triangle/box test), with the grid's origin and cell size.
#[pyclass(module = "proxima", name = "VoxelGrid", frozen)]
pub struct VoxelGrid {
    resolution: u32,
    origin: Vec3,
    cell_size: f32,
    cells: Vec<Cell>,
}

impl VoxelGrid {
    /// The voxelization of `mesh`'s faces at `resolution` cells along the
    /// bounding box's longest side.
    pub fn of_mesh(py: Python<'_>, mesh: &Mesh, resolution: i64, threads: Option<i64>) -> PyResult<Self> {
        let resolution = u32::try_from(resolution)
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| value_error("resolution", format!("{resolution} is not between 1 and 2^32 - 1")))?;
        if mesh.triangle_count() == 0 {
            return Err(value_error("voxelize", "the mesh has no faces"));
        }
        let budget = proxima::budget::memory_budget_from_env().map_err(pyo3::exceptions::PyValueError::new_err)?;
        let max_cell_tests =
            proxima::budget::max_cell_tests_from_env().map_err(pyo3::exceptions::PyValueError::new_err)?;
        let config = VoxelConfig {
            memory_budget: budget,
            max_cell_tests,
            parallel: threads != Some(1),
            ..VoxelConfig::new(resolution)
        };
        let triangles = mesh.triangles().primitives;
        let bounds = mesh.bounds();
        let grid = threads::run(py, threads, || voxelize(&triangles, &bounds, &config))?
            .map_err(|e| value_error("resolution", format!("{resolution}: {e}")))?;
        // The cells as an array: 24 bytes each.
        check_budget("resolution", resolution, grid.occupied() as u128, 24)?;
        Ok(Self {
            resolution,
            origin: grid.origin(),
            cell_size: grid.cell_size(),
            cells: grid.cells(),
        })
    }
}

#[pymethods]
impl VoxelGrid {
    /// Cells per side.
    #[getter]
    fn resolution(&self) -> u32 {
        self.resolution
    }

    /// The corner of cell (0, 0, 0), shape (3,).
    #[getter]
    fn origin<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arrays::vector(py, self.origin.to_array().map(f64::from).to_vec())
    }

    /// The side of a cell.
    #[getter]
    fn cell_size(&self) -> f64 {
        self.cell_size as f64
    }

    /// The occupied cells' indices, shape (M, 3).
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        arrays::matrix(py, self.cells.iter().flatten().copied().collect(), 3)
    }

    /// A (N, N, N) bool array, true where cell (i, j, k) is occupied.
    fn dense<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<bool>>> {
        let n = self.resolution as usize;
        check_budget("resolution", self.resolution, (n as u128).pow(3), 1)?;
        let mut values = vec![false; n * n * n];
        for c in &self.cells {
            let [i, j, k] = c.map(|x| x as usize);
            if i < n && j < n && k < n {
                values[(i * n + j) * n + k] = true;
            }
        }
        arrays::vector(py, values).reshape([n, n, n])
    }

    fn __len__(&self) -> usize {
        self.cells.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "VoxelGrid(resolution={}, occupied={}, cell_size={})",
            self.resolution,
            self.cells.len(),
            self.cell_size
        )
    }
}
