//! Helpers shared by the command-line tests.
#![allow(dead_code)]

use std::path::Path;

/// A fresh directory in the system temp folder, removed when dropped
/// (`tempfile`); reads as a `Path`.
pub struct TempDir(tempfile::TempDir);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

/// A fresh temporary directory for the test `name`.
pub fn temp_dir(name: &str) -> TempDir {
    TempDir(
        tempfile::Builder::new()
            .prefix(&format!("proxima-cli-{name}-"))
            .tempdir()
            .unwrap(),
    )
}
