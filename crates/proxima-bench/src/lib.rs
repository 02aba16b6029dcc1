//! The benchmarks of proxima, in one place.
//!
//! - `proxima bench` (the command of the shipped binary, without peers) and
//!   the `bench` binary (the same, with the parry3d rows): [`run`] with the
//!   options of [`Args`]. The closest-point benchmark is in [`closest`], the
//!   signed distances in [`sdf`], the rays in [`rays`]; what they share
//!   (rows, timing, the table) in [`report`], which uses none of them.
//! - Peer libraries (parry3d, obvhs) only with the feature `peers` (on by
//!   default; `proxima-cli` turns it off): [`peers`], and the binaries
//!   `bench`, `compare` and `rays_peers`.
//! - Two meshes under rigid motion (issue 36): [`poses`] (seeded pose sets
//!   in files) and [`pairs`] (proxima's pair queries, parry3d's, and the
//!   judging of a peer's answers), run by the `pairs` binary.
//! - Shared by the other binaries and the criterion benches: meshes by name
//!   ([`load_named`]) and ray sets ([`ray_sets()`], [`aimed_rays`]).

/// `println!` that returns an error instead of panicking when standard output
/// is closed (`proxima bench MESH | head -1`); the caller ends quietly on it.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}

pub mod args;
pub mod closest;
pub mod command;
pub mod input;
pub mod meshes;
pub mod pairs;
#[cfg(feature = "peers")]
pub mod peers;
pub mod poses;
pub mod ray_sets;
pub mod rays;
pub mod report;
pub mod sdf;
pub mod timing;

pub use args::{Args, Peers, QueryKind, QuerySet, Split};
pub use command::run;
pub use meshes::{data_dir, load_named};
#[cfg(feature = "peers")]
pub use peers::{parry_distance, parry_input, parry_ray, parry_trimesh};
pub use ray_sets::{Ray, aimed_rays, ray_sets};
