//! Queries between two meshes placed by rigid poses, and within one mesh:
//! distance, collision, face pairs in contact, self-intersections.
//!
//! Each mesh is a [`MeshIndex`]; its faces' 4-wide tree (built on first use
//! and shared with every other query) is walked against the other mesh's
//! tree in one descent (`descent`), pairs of subtrees opened four by four
//! children, the second tree's boxes moved into the first's frame. At the
//! leaves the triangles are placed in the world by [`RigidPose::apply`]
//! (`f64`, a fixed order of operations), and
//!
//! - yes/no answers ([`intersects`], [`intersecting_pairs`],
//!   [`self_intersections`], [`pairs_within`] with `0`) are **exact** for
//!   those placed coordinates: orientation predicates evaluated exactly
//!   ([`triangle_intersection`]); closed triangles, so touching counts;
//! - distances ([`distance`], [`distance_below`], [`pairs_within`]) are the
//!   `f64` minimum over the triangle pairs of [`triangle_distance()`]: the
//!   same value brute force over all pairs computes.
//!
//! Surfaces, not volumes: a mesh wholly inside another without their
//! surfaces meeting does not intersect it. Ask whether one of its vertices
//! is inside (the winding number, [`SignedDistanceField`](crate::SignedDistanceField)) for that.
//!
//! Faces are named by their index in the mesh ([`Mesh::face`](crate::Mesh::face));
//! a polygon's fan triangles share it. docs/pairs.md has the algorithm, the
//! contract and the measurements.
//!
//! ```
//! use proxima::pair::{self, RigidPose};
//! use proxima::{MeshIndex, Mesh, Vec3};
//! let triangle = || Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
//! let (a, b) = (MeshIndex::new(triangle()), MeshIndex::new(triangle()));
//! let lifted = RigidPose::translation_only(proxima::DVec3::new(0.0, 0.0, 2.0)).unwrap();
//! let d = pair::distance(&a, &RigidPose::IDENTITY, &b, &lifted).unwrap();
//! assert_eq!(d.distance, 2.0);
//! assert!(!pair::intersects(&a, &RigidPose::IDENTITY, &b, &lifted).unwrap());
//! assert!(pair::intersects(&a, &RigidPose::IDENTITY, &b, &RigidPose::IDENTITY).unwrap());
//! ```

mod collide;
pub(crate) mod descent;
mod distance;
mod error;
mod hausdorff;
pub mod pose;
mod queue;
mod self_intersection;
pub mod triangle_distance;
pub mod triangle_intersection;

pub use crate::primitive::closest_f64::{point_triangle_closest, segment_segment_closest};
pub use collide::{intersecting_pairs, intersects, intersects_batch, pairs_within};
pub use distance::{PairDistance, distance, distance_batch, distance_below, distance_below_batch};
pub use error::{MAX_TRANSLATION, PairError};
pub use hausdorff::{
    DirectedHausdorff, MAX_DEPTH as HAUSDORFF_MAX_DEPTH, MeshHausdorff, directed_hausdorff, hausdorff,
};
pub use pose::{PoseError, RigidPose};
pub use self_intersection::self_intersections;
pub(crate) use self_intersection::{Report, meeting_pairs};
pub use triangle_distance::{TrianglePairDistance, separated_triangle_distance, triangle_distance};
pub use triangle_intersection::{neighbours_intersect, segment_meets_triangle, triangles_intersect};

use crate::index::MeshIndex;
use crate::wide_tree::OrientedBounds;
use crate::{Triangle, WideTree};

/// The faces' tree of `index`, or why it has none.
pub(crate) fn faces_tree<'i>(index: &'i MeshIndex, mesh: &'static str) -> Result<&'i WideTree<Triangle>, PairError> {
    index
        .tree::<Triangle>()
        .map_err(|source| PairError::Mesh { mesh, source })
}

/// The oriented boxes of `index`'s faces' tree, built if needed, a missing
/// tree reported under the mesh's name.
pub(crate) fn oriented_bounds<'i>(index: &'i MeshIndex, mesh: &'static str) -> Result<&'i OrientedBounds, PairError> {
    index
        .oriented_bounds()
        .map_err(|source| PairError::Mesh { mesh, source })
}

/// Refuses a pose that places its mesh beyond [`MAX_TRANSLATION`], as every
/// query here does, with [`PairError::PoseOutOfRange`] naming the pose by
/// `name()`: front ends check their poses up front under their own names
/// (`--pose-b`, `poses.txt:3`, `pose_b[2]`).
///
/// ```
/// use proxima::pair::{check_pose, RigidPose};
/// let far = RigidPose::translation_only(proxima::DVec3::new(0.0, 2e38, 0.0)).unwrap();
/// let e = check_pose(&far, || "--pose-b".into()).unwrap_err();
/// assert_eq!(e.to_string(), "--pose-b: a translation coordinate of 2e38 is beyond the supported 1e38");
/// assert!(check_pose(&RigidPose::IDENTITY, || unreachable!()).is_ok());
/// ```
pub fn check_pose(pose: &RigidPose, name: impl FnOnce() -> String) -> Result<(), PairError> {
    let t = pose.translation();
    match t.to_array().into_iter().find(|v| v.abs() > MAX_TRANSLATION) {
        Some(value) => Err(PairError::PoseOutOfRange { pose: name(), value }),
        None => Ok(()),
    }
}

/// The faces' trees of `a` and `b` for a batch over `poses`: every pose
/// checked (named by its position), the answers (`bytes_each` per pose)
/// counted against the memory budget before anything is allocated.
pub(crate) fn batch_trees<'i>(
    a: &'i MeshIndex,
    b: &'i MeshIndex,
    poses: &[RigidPose],
    bytes_each: usize,
) -> Result<(&'i WideTree<Triangle>, &'i WideTree<Triangle>), PairError> {
    for (i, pose) in poses.iter().enumerate() {
        check_pose(pose, || format!("poses[{i}]"))?;
    }
    crate::budget::check_fits("poses", poses.len(), poses.len() as u128, bytes_each as u128)?;
    Ok((faces_tree(a, "a")?, faces_tree(b, "b")?))
}

/// Refuses a negative or NaN distance bound (infinity is allowed).
pub(crate) fn check_distance(option: &'static str, value: f64) -> Result<(), PairError> {
    if value >= 0.0 {
        Ok(())
    } else {
        Err(PairError::BadDistance { option, value })
    }
}

/// A face pair's faces as `[face in a, face in b]`.
pub type FacePair = [u32; 2];
