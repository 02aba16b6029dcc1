//! Helpers shared by the integration tests: seeded meshes, query sets, and the
//! real meshes of ../shared/data (skipped with a note when absent).
#![allow(dead_code)]

pub mod degenerate;
pub mod exact;
pub mod glb_writer;
pub mod oracle;
pub mod winding;

use proxima::sample::Rng;
use proxima::{Mesh, Vec3};
use std::path::PathBuf;

/// The folder of real meshes: `PROXIMA_DATA_DIR` when set (a checkout
/// elsewhere, such as a `git worktree`), else `../shared/data` beside the
/// checkout; `None` when it is absent.
pub fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("PROXIMA_DATA_DIR").map_or_else(
        || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
        PathBuf::from,
    );
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("skipped: ../shared/data not found (real-mesh tests need the shared folder beside the checkout)");
        None
    }
}

/// Every mesh file of the shared data folder, smallest first.
pub fn shared_meshes() -> Vec<PathBuf> {
    let Some(dir) = data_dir() else { return Vec::new() };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("readable data dir")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy().to_lowercase();
            [".obj", ".ply", ".off", ".stl", ".gz"]
                .iter()
                .any(|ext| name.ends_with(ext))
        })
        .collect();
    files.sort_by_key(|p| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0));
    files
}

/// A random triangle soup of `n` triangles in the unit cube, some of them tiny
/// and some degenerate.
pub fn random_soup(n: usize, seed: u64) -> Mesh {
    let mut rng = Rng::new(seed);
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for i in 0..n {
        let center = Vec3::new(rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0));
        let size = if i % 3 == 0 { 0.2 } else { 0.03 };
        let base = positions.len() as u32;
        for _ in 0..3 {
            positions.push(center + Vec3::new(rng.range(-size, size), rng.range(-size, size), rng.range(-size, size)));
        }
        match i % 17 {
            // repeated vertex
            5 => positions[base as usize + 2] = positions[base as usize],
            // collinear
            9 => {
                let (a, b) = (positions[base as usize], positions[base as usize + 1]);
                positions[base as usize + 2] = a + (b - a) * 2.5;
            }
            _ => {}
        }
        triangles.push([base, base + 1, base + 2]);
    }
    Mesh::from_triangles(positions, &triangles).unwrap()
}

/// A bumpy closed mesh (seeded).
pub fn bumpy_sphere(frequency: u32, seed: u64) -> Mesh {
    proxima::mesh::generate::noisy_icosphere(frequency, seed)
}

/// The non-finite point `bad` twice among finite queries (two close
/// together, one far off), whose answers seed the next search in a batch.
pub fn mixed_with(bad: Vec3) -> [Vec3; 5] {
    [
        Vec3::new(0.3, 0.2, 0.1),
        bad,
        Vec3::new(0.35, 0.2, 0.1),
        bad,
        Vec3::new(-2.0, 1.0, 0.0),
    ]
}

/// Every batch configuration worth checking: input and Morton order, with
/// and without radius seeding.
pub fn batch_options() -> Vec<proxima::BatchOptions> {
    let mut out = Vec::new();
    for reorder in [false, true] {
        for seed_radius in [false, true] {
            out.push(proxima::BatchOptions { reorder, seed_radius });
        }
    }
    out
}

/// Query points of every kind: far away, near the surface, uniform in the box,
/// exactly on vertices, on edge midpoints, at the center (inside closed meshes).
pub fn queries(mesh: &Mesh, n: usize, seed: u64) -> Vec<Vec3> {
    let mut out = proxima::sample::near_surface(mesh, n, 0.01, seed);
    out.extend(proxima::sample::uniform_in_box(mesh, n, seed + 1));
    let b = mesh.bounds();
    let mut rng = Rng::new(seed + 2);
    let positions = mesh.positions();
    let edges = mesh.edge_indices();
    for _ in 0..n / 4 + 1 {
        out.push(positions[rng.below(positions.len())]);
        if !edges.is_empty() {
            let [a, c] = edges[rng.below(edges.len())];
            out.push((positions[a as usize] + positions[c as usize]) * 0.5);
        }
        // far away
        let dir = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X);
        out.push(b.center() + dir * b.diagonal() * 20.0);
    }
    out.push(b.center());
    out
}

/// A fresh directory in the system temp folder, removed when dropped
/// (`tempfile`); reads as a `Path`.
pub struct TempDir(tempfile::TempDir);

impl std::ops::Deref for TempDir {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        self.0.path()
    }
}

/// A fresh temporary directory for the test `name`.
pub fn temp_dir(name: &str) -> TempDir {
    TempDir(
        tempfile::Builder::new()
            .prefix(&format!("proxima-{name}-"))
            .tempdir()
            .unwrap(),
    )
}

/// Runs the test `test` of the module `module_path` (its `module_path!()`)
/// again in a child process of this test binary, with `child` set to 1 and
/// `PROXIMA_MEMORY_BUDGET` to `budget`: set in this process, the variable
/// would race the other tests.
pub fn rerun_with_budget(module_path: &str, test: &str, child: &str, budget: &str) -> std::process::Output {
    // The name the binary lists: the module path past the crate's name.
    let name = match module_path.split_once("::") {
        Some((_, module)) => format!("{module}::{test}"),
        None => test.to_string(),
    };
    std::process::Command::new(std::env::current_exe().unwrap())
        .args(["--exact", &name, "--nocapture", "--test-threads", "1"])
        .env(child, "1")
        .env("PROXIMA_MEMORY_BUDGET", budget)
        .output()
        .unwrap()
}
