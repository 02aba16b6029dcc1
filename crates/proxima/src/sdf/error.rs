//! What a signed distance field, or a grid or sample of one, refuses.

use crate::build_error::BuildError;

/// Why a signed distance field, or a grid or sample of one, cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SdfError {
    /// The mesh has no face, so neither a distance nor a side.
    #[error("the mesh has no faces: a signed distance needs triangles")]
    NoFaces,
    /// The tree could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A count or resolution of zero.
    #[error("{option} must be at least 1")]
    Zero {
        /// The option.
        option: &'static str,
    },
    /// The output would not fit the memory budget
    /// ([`check_fits`](crate::budget::check_fits): `PROXIMA_MEMORY_BUDGET` or the default).
    #[error("{option} = {value} needs {bytes} bytes, more than the memory budget of {budget} bytes")]
    MemoryBudget {
        /// The option that sizes the output.
        option: &'static str,
        /// Its value.
        value: u64,
        /// Bytes it needs.
        bytes: u64,
        /// The budget.
        budget: u64,
    },
    /// The memory budget of the environment cannot be read
    /// ([`BudgetError::Environment`](crate::budget::BudgetError)).
    #[error(transparent)]
    Budget(#[from] crate::budget::BudgetError),
    /// A spread or margin so large that samples would lie beyond the
    /// coordinates a query accepts
    /// ([`MAX_QUERY_COORDINATE`](crate::build::MAX_QUERY_COORDINATE)).
    #[error("{option} = {value} puts samples beyond ±{bound:e}, where squared distances overflow f32")]
    TooFar {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f32,
        /// The largest coordinate a query accepts.
        bound: f32,
    },
    /// A length (a sample spread or margin, a grid's bounds) that is negative or not finite.
    #[error("{option} must be finite and not negative, got {value}")]
    Parameter {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f32,
    },
}
