//! Query points: which ones the structures answer.

use crate::build::MAX_QUERY_COORDINATE;
use crate::math::Vec3;

/// Whether `p` is a point the queries answer: finite, and within
/// ±[`MAX_QUERY_COORDINATE`] on every axis.
///
/// ```
/// use proxima::build::MAX_QUERY_COORDINATE;
/// use proxima::{QueryError, Vec3, check_query_point};
/// assert!(check_query_point(Vec3::splat(MAX_QUERY_COORDINATE)).is_ok());
/// assert_eq!(
///     check_query_point(Vec3::new(1e30, 0.0, 0.0)),
///     Err(QueryError::CoordinateTooLarge { bound: MAX_QUERY_COORDINATE })
/// );
/// assert_eq!(check_query_point(Vec3::new(f32::NAN, 0.0, 0.0)), Err(QueryError::NonFinite));
/// ```
pub fn check_query_point(p: Vec3) -> Result<(), QueryError> {
    if !p.is_finite() {
        Err(QueryError::NonFinite)
    } else if p.abs().max_element() > MAX_QUERY_COORDINATE {
        Err(QueryError::CoordinateTooLarge {
            bound: MAX_QUERY_COORDINATE,
        })
    } else {
        Ok(())
    }
}

/// [`check_query_point`] as a test on the query path.
#[inline(always)]
pub(crate) fn answerable(p: Vec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_QUERY_COORDINATE
}

/// A query point the trees cannot answer for.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QueryError {
    /// A coordinate is NaN or infinite.
    #[error("query point has a non-finite coordinate")]
    NonFinite,
    /// A coordinate beyond the bound
    /// ([`MAX_QUERY_COORDINATE`](crate::build::MAX_QUERY_COORDINATE)) where
    /// squared distances overflow `f32`.
    #[error("query point has a coordinate beyond ±{bound:e}, where squared distances overflow f32")]
    CoordinateTooLarge {
        /// The largest accepted magnitude.
        bound: f32,
    },
}
