//! The meshes the benchmark binaries take by name: generated icospheres or
//! files of the shared data folder.

use proxima::Mesh;
use std::path::PathBuf;

/// The shared data folder: `PROXIMA_DATA_DIR` when set, else `../shared/data`
/// beside the checkout; `None` when absent.
pub fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("PROXIMA_DATA_DIR").map_or_else(
        || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
        PathBuf::from,
    );
    dir.is_dir().then_some(dir)
}

/// A mesh by name: `ico1m` (the seeded 1,003,520-triangle bumpy icosphere),
/// `ico100k` (101,120 triangles), or a file path (absolute, or relative to the
/// shared data folder).
pub fn load_named(name: &str) -> Result<Mesh, String> {
    match name {
        "ico1m" => Ok(proxima::mesh::generate::noisy_icosphere(224, 1)),
        "ico100k" => Ok(proxima::mesh::generate::noisy_icosphere(71, 1)),
        _ => {
            let path = PathBuf::from(name);
            let path = if path.exists() {
                path
            } else {
                data_dir().map(|d| d.join(name)).unwrap_or(path)
            };
            proxima::io::load(&path).map_err(|e| e.to_string())
        }
    }
}
