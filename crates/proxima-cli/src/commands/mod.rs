//! One file per subcommand, each with its `Args` and `run`.

pub mod bench;
pub mod closest;
pub mod collide;
pub mod demo;
pub mod distance;
pub mod frustum;
pub mod grid;
pub mod hausdorff;
pub mod info;
pub mod knn;
pub mod radius;
pub mod raycast;
pub mod raycast_batch;
pub mod sdf;
pub mod self_intersections;
pub mod traverse;
pub mod view;
pub mod voxelize;
