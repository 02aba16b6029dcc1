//! The base-tree layer every tree shares: build parameters and limits
//! (`config.rs`), the top-down build of a binary hierarchy (`hierarchy.rs`,
//! its median split in `median.rs`, binned SAH beside it), the node stored
//! in 64-byte sibling pairs (`node.rs`), the one walk of a binary tree
//! (`walk.rs`: distance and ray queries) and its frustum walk (`frustum.rs`),
//! and the structure checks and statistics (`structure.rs`).
//!
//! The [`AabbTree`](crate::AabbTree) is this hierarchy as built; the sphere
//! tree, the 4-wide tree and the ray tree are made from it. Nothing here
//! depends on any of them.

mod config;
mod frustum;
mod hierarchy;
mod median;
mod node;
mod quality;
mod structure;
mod walk;

pub use config::{BuildConfig, MAX_COORDINATE, MAX_DEPTH, MAX_QUERY_COORDINATE, SplitMethod};
pub(crate) use frustum::frustum_walk;
pub(crate) use hierarchy::{build_hierarchy, refit, widen};
pub(crate) use node::NodePair;
pub use node::{Node, NodeVolume};
pub(crate) use quality::{check_primitives, surface_area_cost};
pub use structure::TreeStats;
pub(crate) use structure::check_structure;
pub(crate) use walk::{BinaryQuery, nearest_walk, walk};
