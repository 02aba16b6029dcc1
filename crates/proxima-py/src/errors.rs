//! The library's typed errors as Python exceptions.

use proxima::{LoadError, LoadErrorKind};
use pyo3::PyErr;
use pyo3::exceptions::{PyOSError, PyValueError};

/// A mesh file that could not be read: `OSError` when reading failed,
/// `ValueError` when its content is malformed; the message is the command
/// line's (the file, the line where known, what is wrong).
pub fn load_error(error: LoadError) -> PyErr {
    let message = error.to_string();
    match &error.kind {
        // With errno, Python makes the matching subclass (FileNotFoundError,
        // PermissionError, ...), so callers can tell them apart.
        LoadErrorKind::Io(io) => match io.raw_os_error() {
            Some(code) => PyOSError::new_err((code, message)),
            None => PyOSError::new_err(message),
        },
        _ => PyValueError::new_err(message),
    }
}
