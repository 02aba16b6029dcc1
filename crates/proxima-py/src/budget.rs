//! The library's one limits policy on the Python side: sizes checked with
//! [`proxima::budget::check_fits`] (`PROXIMA_MEMORY_BUDGET` or the default),
//! the thread cap, the training-sample split and the mesh file suffixes, as
//! `Mesh`, `VoxelGrid` and `proxima.dataset` use them.

use proxima::budget::BudgetError;
use proxima::io::Format;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Fails with a `ValueError` starting with `name` unless `count` values of
/// `bytes_each` bytes fit the memory budget; a malformed
/// `PROXIMA_MEMORY_BUDGET` is a `ValueError` naming the variable.
pub fn check_budget(name: &str, value: impl std::fmt::Display, count: u128, bytes_each: u128) -> PyResult<()> {
    proxima::budget::check_fits(name, value, count, bytes_each).map_err(budget_error)
}

/// The library's message as a `ValueError` (it starts with the argument, or
/// with the variable for [`BudgetError::Environment`]).
fn budget_error(error: BudgetError) -> PyErr {
    PyValueError::new_err(error.to_string())
}

/// Raises ``ValueError`` (``"OPTION VALUE: needs about ..., more than the
/// memory budget of ... (set PROXIMA_MEMORY_BUDGET to change it)"``) unless
/// ``count`` items of ``bytes_each`` bytes fit the memory budget; what every
/// call of the package checks before allocating, for Python code that sizes
/// work of its own (``proxima.dataset``).
#[pyfunction]
#[pyo3(name = "check_fits")]
pub fn check_fits_py(option: &str, value: &Bound<'_, PyAny>, count: u128, bytes_each: u128) -> PyResult<()> {
    check_budget(option, value.str()?, count, bytes_each)
}

/// The memory budget in bytes that every size is checked against before
/// anything is allocated: `PROXIMA_MEMORY_BUDGET` (bytes, or with a K, M or G
/// suffix) or the library's default (three quarters of the available
/// memory, at most 2 GiB); `ValueError` when the variable is malformed.
#[pyfunction]
pub fn memory_budget() -> PyResult<u64> {
    proxima::budget::memory_budget_from_env().map_err(PyValueError::new_err)
}

/// The largest `threads=` a batch call accepts: 4 per core, at least 8 (the
/// command line's `--threads` cap).
#[pyfunction]
pub fn max_threads() -> usize {
    proxima::budget::max_threads()
}

/// ``(near, uniform)``: how many of ``total`` training samples
/// ``Mesh.training_samples`` draws near the surface and uniform in the box
/// when ``uniform_fraction`` of them are uniform (the nearest whole number,
/// halves rounded down; as ``proxima sdf --sample N --uniform-fraction F``).
#[pyfunction]
pub fn training_sample_counts(total: usize, uniform_fraction: f64) -> PyResult<(usize, usize)> {
    if !(0.0..=1.0).contains(&uniform_fraction) {
        return Err(crate::arrays::value_error(
            "uniform_fraction",
            format!("{uniform_fraction} is not in [0, 1]"),
        ));
    }
    Ok(proxima::sample::training_sample_counts(total, uniform_fraction))
}

/// Every format `load` reads, in the library's order.
const FORMATS: [Format; 5] = [Format::Obj, Format::Ply, Format::Stl, Format::Off, Format::Glb];

/// The suffixes of the files ``load`` reads (``".obj"``, ...), each also
/// read with ``.gz`` after it: the library's formats.
#[pyfunction]
pub fn mesh_suffixes() -> Vec<String> {
    // A format added to the library fails to compile here until it is listed above.
    for format in FORMATS {
        match format {
            Format::Obj | Format::Ply | Format::Stl | Format::Off | Format::Glb => {}
        }
    }
    FORMATS.iter().map(|f| format!(".{}", f.extension())).collect()
}
