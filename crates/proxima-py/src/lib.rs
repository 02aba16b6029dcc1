//! proxima's Python package: every query of the library on numpy arrays.
//!
//! The module `proxima._proxima`, re-exported by the pure-Python package
//! `proxima` (python/proxima). Each batch call releases the GIL while it
//! works, runs on the pool that `threads=` names, and reads C-contiguous
//! float32 points without a copy. Bad input raises `ValueError` naming the
//! argument (`OSError` for files that cannot be read); no Rust panic is
//! expected to reach Python. The type stubs (`_proxima.pyi`) are the
//! contract.
#![forbid(unsafe_code)]

mod arrays;
mod budget;
mod closest;
mod errors;
mod mesh;
mod pairs;
mod points;
mod poses;
mod rays;
mod scene;
mod surface;
mod threads;
mod traverse;
mod voxels;

use mesh::PyMesh;
use pyo3::prelude::*;
use std::path::PathBuf;

/// Reads a mesh file (OBJ, PLY, STL, OFF, binary glTF, optionally gzip-compressed), as
/// the command line does; `OSError` when it cannot be read, `ValueError`
/// when it is malformed.
#[pyfunction]
fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyMesh> {
    let options = proxima::io::LoadOptions::from_env().map_err(pyo3::exceptions::PyValueError::new_err)?;
    let mesh = py
        .detach(|| proxima::io::load_with(&path, &options))
        .map_err(errors::load_error)?;
    // As the command line refuses it: no query could be answered on it (an
    // empty OBJ parses; an empty PLY, OFF or STL is already malformed).
    proxima::index::check_not_empty(&mesh)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("{}: {e}", path.display())))?;
    Ok(PyMesh::wrap(mesh))
}

/// A closed sphere of radius about 1 with smooth noise, ``20 * frequency**2``
/// triangles (``noisy_icosphere(224)`` is the benchmarks' ``ico1m``).
#[pyfunction]
#[pyo3(signature = (frequency, seed = 1))]
fn noisy_icosphere(py: Python<'_>, frequency: u32, seed: u64) -> PyResult<PyMesh> {
    if frequency == 0 {
        return Err(arrays::value_error("frequency", "0 is less than 1"));
    }
    // 20 f² triangles of 12 bytes of indices, f² vertices of 12 bytes, and the working copies.
    budget::check_budget("frequency", frequency, 20 * (frequency as u128).pow(2), 64)?;
    Ok(PyMesh::wrap(
        py.detach(|| proxima::mesh::generate::noisy_icosphere(frequency, seed)),
    ))
}

/// The native module.
#[pymodule]
fn _proxima(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<PyMesh>()?;
    m.add_class::<voxels::VoxelGrid>()?;
    m.add_class::<pairs::PyPairDistance>()?;
    m.add_class::<pairs::PyHausdorff>()?;
    m.add_class::<surface::Answers>()?;
    m.add_class::<points::PyPoints>()?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(points::chamfer, m)?)?;
    m.add_function(wrap_pyfunction!(points::hausdorff, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(noisy_icosphere, m)?)?;
    m.add_function(wrap_pyfunction!(traverse::traverse, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::distance, m)?)?;
    m.add_function(wrap_pyfunction!(budget::memory_budget, m)?)?;
    m.add_function(wrap_pyfunction!(budget::max_threads, m)?)?;
    m.add_function(wrap_pyfunction!(budget::check_fits_py, m)?)?;
    m.add_function(wrap_pyfunction!(budget::training_sample_counts, m)?)?;
    m.add_function(wrap_pyfunction!(budget::mesh_suffixes, m)?)?;
    Ok(())
}
