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

/// Runs `proxima ARGS` with `env` under an address-space limit of `kib` KiB
/// (`ulimit -v`, as a container or a shared machine sets one): an
/// allocation past it fails and aborts the process (status 134), so a run
/// that ends with status 0 or 1 stayed below it. `PROXIMA_MEMORY_BUDGET` is
/// unset unless `env` sets it, so that the default budget is the one used.
pub fn proxima_under_limit(kib: u64, args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut command = std::process::Command::new("sh");
    command
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .env_remove("PROXIMA_MEMORY_BUDGET");
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().expect("run proxima under sh")
}

// The GLB writers, shared with the library's tests.
#[path = "../../../proxima/tests/common/glb_writer.rs"]
mod glb_writer;
#[allow(unused_imports)] // Each test binary uses some of the helpers.
pub use glb_writer::{glb, instanced_glb};

/// Runs the `proxima` binary with `args`, failing the test (with its
/// standard error) unless it succeeds.
pub fn proxima_ok(args: &[&str]) -> std::process::Output {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .output()
        .expect("run proxima");
    assert!(
        out.status.success(),
        "proxima {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}
