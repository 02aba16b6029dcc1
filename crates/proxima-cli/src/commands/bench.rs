//! `proxima bench`: the benchmarks of proxima-bench (linear search against
//! the trees on the same closest-point, signed-distance or ray queries),
//! without the peer rows: the shipped binary links no peer library. The
//! same run with parry3d's rows is proxima-bench's `bench` binary.

use proxima::prelude::*;
use proxima_bench::Peers;

pub use proxima_bench::Args;
pub use proxima_bench::report::print_table;

/// Where the peer rows are, for `proxima bench --help`.
pub const PEER_ROWS: &str = "The rows of the peer library parry3d (closest points and rays on the faces) come from \
     proxima-bench's `bench` binary, which takes the same options and prints the same output plus those rows:\n  \
     cargo run -p proxima-bench --release --bin bench -- MESH [OPTIONS]";

/// Runs `proxima bench`.
pub fn run(args: Args) -> anyhow::Result<()> {
    proxima_bench::run(args, Peers::None)
}

/// Measures every requested primitive type on `points` (see
/// [`proxima_bench::closest::measure`]), proxima's rows only.
pub fn measure(
    mesh: &Mesh,
    kinds: &[PrimitiveKind],
    points: &[Vec3],
    threads: usize,
    config: &BuildConfig,
    progress: bool,
    planarity: f32,
) -> anyhow::Result<Vec<proxima_bench::report::Record>> {
    proxima_bench::closest::measure(mesh, kinds, points, threads, config, progress, planarity, Peers::None)
}
