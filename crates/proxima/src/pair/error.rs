//! What the two-mesh queries refuse.

use crate::budget::BudgetError;
use crate::index::IndexError;

/// Placed coordinates stay below this: a pose's translation is at most this
/// large in each coordinate, so that the exact predicates' products of
/// coordinate differences (up to the sixth power of the largest) stay
/// finite in `f64`.
pub const MAX_TRANSLATION: f64 = 1e38;

/// Why a query between two meshes (or within one) was refused.
#[derive(Debug, thiserror::Error)]
pub enum PairError {
    /// One mesh cannot take part: it has no faces.
    #[error("mesh {mesh}: {source}")]
    Mesh {
        /// Which mesh: `"a"`, `"b"` or `"mesh"`.
        mesh: &'static str,
        /// What is missing.
        #[source]
        source: IndexError,
    },
    /// A pose moves its mesh beyond [`MAX_TRANSLATION`].
    #[error("{pose}: a translation coordinate of {value:e} is beyond the supported {MAX_TRANSLATION:e}")]
    PoseOutOfRange {
        /// Which pose (`"pose_a"`, `"pose_b"`, `"poses[12]"`).
        pose: String,
        /// The offending translation coordinate.
        value: f64,
    },
    /// A distance bound that is negative or not finite (infinity is allowed
    /// where the bound is optional).
    #[error("{option} must be at least 0 (got {value})")]
    BadDistance {
        /// The argument's name.
        option: &'static str,
        /// What was given.
        value: f64,
    },
    /// A Hausdorff tolerance that is not positive, or finer than the
    /// meshes' `f32` coordinates can resolve.
    #[error("tolerance = {value}: must be positive and at least {minimum:e} (1e-7 of the meshes' size)")]
    BadTolerance {
        /// What was given.
        value: f64,
        /// The smallest accepted for these meshes.
        minimum: f64,
    },
    /// The answers of a batch would not fit in the memory budget.
    #[error(transparent)]
    Budget(#[from] BudgetError),
}
