//! What point-cloud queries refuse.

use crate::budget::BudgetError;
use crate::error::BuildError;

/// Why a point-cloud query or build was refused; each names the argument.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PointsError {
    /// A cloud with no point.
    #[error("{argument}: the point cloud is empty")]
    Empty {
        /// The argument, as the caller spells it.
        argument: &'static str,
    },
    /// A point of the cloud the tree cannot hold.
    #[error("{argument}: {source}")]
    Build {
        /// The argument, as the caller spells it.
        argument: &'static str,
        /// The build's refusal, naming the point.
        source: BuildError,
    },
    /// A query point that is not finite or beyond the supported coordinates.
    #[error("{argument}[{index}]: {source}")]
    Query {
        /// The argument, as the caller spells it.
        argument: &'static str,
        /// The query's position.
        index: usize,
        /// Why it cannot be answered.
        source: crate::QueryError,
    },
    /// A count or radius out of range.
    #[error("{argument} = {value}: {rule}")]
    BadArgument {
        /// The argument, as the caller spells it.
        argument: &'static str,
        /// Its value, as given.
        value: String,
        /// What it must be.
        rule: &'static str,
    },
    /// The answers would not fit the memory budget.
    #[error(transparent)]
    Budget(#[from] BudgetError),
}
