//! Two meshes, or one mesh against itself: rigid poses and the exact
//! triangle-pair tests and distances the pair queries are built on.
//!
//! - [`pose`]: [`RigidPose`], a rotation and a translation in `f64`.
//! - [`triangle_intersection`]: exact closed-triangle intersection
//!   ([`triangles_intersect`]) and the rule for faces of one mesh that share
//!   vertices ([`neighbours_intersect`]).
//! - [`triangle_distance`]: the distance between two triangles with its
//!   closest points ([`triangle_distance()`]).

pub mod pose;
pub mod triangle_distance;
pub mod triangle_intersection;

pub use pose::{PoseError, RigidPose};
pub use triangle_distance::{TrianglePairDistance, point_triangle_closest, segment_segment_closest, triangle_distance};
pub use triangle_intersection::{neighbours_intersect, segment_meets_triangle, triangles_intersect};
