//! The inputs of a run, read and checked as every `proxima` command reads and
//! checks them: meshes and points files within the loading limits of the
//! environment, the memory budget, the thread limit, one-line notes.

use anyhow::{Context, Result, anyhow, bail};
use proxima::prelude::*;
use std::path::Path;

/// The loading limits, with the environment's overrides.
fn load_options() -> Result<proxima::io::LoadOptions> {
    proxima::io::LoadOptions::from_env().map_err(|e| anyhow!(e))
}

/// Loads a mesh; the error names the file (and line).
pub fn load_mesh(path: &Path) -> Result<Mesh> {
    Ok(proxima::io::load_with(path, &load_options()?)?)
}

/// Reads a points file (see [`proxima::io::parse_points`]) within the same
/// limits as meshes.
pub fn read_points(path: &Path) -> Result<Vec<Vec3>> {
    Ok(proxima::io::load_points(path, &load_options()?)?)
}

/// The memory budget: `PROXIMA_MEMORY_BUDGET` or the library's default.
pub fn memory_budget() -> Result<u64> {
    proxima::budget::memory_budget_from_env().map_err(|e| anyhow!(e))
}

/// `requested` worker threads, refused beyond 4 per core (at least 8): more
/// would only cost memory and scheduling.
pub fn thread_count(requested: usize) -> Result<usize> {
    let cap = proxima::budget::max_threads();
    if requested > cap {
        bail!("--threads {requested} is more than the limit of {cap} (4 per core on this machine, at least 8)");
    }
    Ok(requested)
}

/// Fails when the mesh has no primitive of `kind` (no vertices, no edges, or no faces).
pub fn require_primitives(mesh: &Mesh, kind: PrimitiveKind, path: &Path) -> Result<()> {
    proxima::index::check_primitives(mesh, kind).with_context(|| path.display().to_string())
}

/// With `kind` polygons, prints on stderr how many faces of more than three
/// vertices were fan-triangulated, when any were.
pub fn note_polygons(mesh: &Mesh, kind: PrimitiveKind, path: &Path, planarity: f32) {
    if kind == PrimitiveKind::Polygons
        && let Some(line) = mesh.extract_polygons(planarity).fan_note(planarity)
    {
        note(&format!("{}: {line}", path.display()));
    }
}

/// Writes `proxima: {line}` on stderr. A stderr that cannot be written is
/// ignored: there is no one left to tell.
pub fn note(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "proxima: {line}");
}
