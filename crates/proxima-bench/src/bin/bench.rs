//! `proxima bench` with the peer rows: the same options, the same table or
//! JSON, plus parry3d's row on faces (closest points and `--query rays`).
//!
//! ```text
//! cargo run --release -p proxima-bench --bin bench -- MESH [--query closest|sdf|rays] [--primitives P] [--queries N | --points FILE] [--set near|uniform] [--threads T] [--split median|sah] [--planarity TOL] [--json]
//! ```
//!
//! Exits as `proxima` does: 1 with one line on stderr for bad input, 2 for
//! usage errors.

use clap::Parser;
use std::process::ExitCode;

/// Linear search against the trees on the same queries (closest points,
/// signed distances or rays), and parry3d on the faces.
#[derive(Parser)]
#[command(name = "bench", version)]
struct Cli {
    #[command(flatten)]
    args: proxima_bench::Args,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match proxima_bench::run(cli.args, proxima_bench::Peers::Parry3d) {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of standard output is gone: nothing went wrong.
        Err(error)
            if error.chain().any(|cause| {
                cause
                    .downcast_ref::<std::io::Error>()
                    .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
            }) =>
        {
            ExitCode::SUCCESS
        }
        Err(error) => {
            // One line: the chain of causes joined, no backtrace.
            proxima_bench::input::note(&format!("{error:#}").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
