//! Typed errors, one enum per boundary, each beside what raises it (the mesh,
//! the loaders, the trees' build, the grid, rays, frusta, signed distance,
//! query points, poses and two-mesh queries); re-exported here, so that
//! `proxima::error::X` names every one.

pub use crate::build_error::BuildError;
pub use crate::frustum::FrustumError;
pub use crate::grid::GridError;
pub use crate::io::{LoadError, LoadErrorKind};
pub use crate::mesh::{MeshError, PolygonError};
pub use crate::pair::{PairError, PoseError};
pub use crate::query::QueryError;
pub use crate::ray::RayError;
pub use crate::sdf::SdfError;

/// A byte count for a message (`1.5 GiB (1610612736 bytes)`).
pub(crate) fn human(bytes: &u128) -> String {
    let short = crate::budget::human_bytes(*bytes);
    if short.ends_with(" bytes") {
        short
    } else {
        format!("{short} ({bytes} bytes)")
    }
}

pub(crate) fn human64(bytes: &u64) -> String {
    human(&u128::from(*bytes))
}

/// A budget for a message, with the variable that sets it
/// (`2.0 GiB (2147483648 bytes; PROXIMA_MEMORY_BUDGET sets it)`).
pub(crate) fn budget_set_by_env(budget: &u64) -> String {
    let short = crate::budget::human_bytes(u128::from(*budget));
    if short.ends_with(" bytes") {
        format!("{short} (PROXIMA_MEMORY_BUDGET sets it)")
    } else {
        format!("{short} ({budget} bytes; PROXIMA_MEMORY_BUDGET sets it)")
    }
}
