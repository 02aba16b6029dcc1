//! One file per subcommand, each with its `Args` and `run`.

pub mod bench;
pub mod closest;
pub mod demo;
pub mod frustum;
pub mod grid;
pub mod info;
pub mod raycast;
pub mod raycast_batch;
pub mod sdf;
pub mod traverse;
pub mod view;
pub mod voxelize;
