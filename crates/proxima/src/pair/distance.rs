//! The distance between two placed meshes: the nearest pair of faces.

use super::collide::meeting_pair;
use super::descent::{PairVisitor, PlacedPair, PlacedTriangle, Scratch, Walk};
use super::triangle_distance::{TrianglePairDistance, separated_triangle_distance, triangle_distance};
use super::{PairError, RigidPose, batch_trees, check_distance, check_pose, faces_tree, oriented_bounds};
use crate::index::MeshIndex;
use crate::math::DVec3;
use crate::query::{Leaves, SpatialIndex};
use crate::wide_tree::OrientedBounds;
use crate::{Triangle, WideTree};
use rayon::prelude::*;
use std::ops::ControlFlow;

/// The nearest pair of points of two placed meshes, and where they lie.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairDistance {
    /// The distance between the meshes (0 when their surfaces meet).
    pub distance: f64,
    /// The point on the first mesh, in the world.
    pub point_a: DVec3,
    /// The point on the second mesh, in the world.
    pub point_b: DVec3,
    /// The face of the first mesh that holds `point_a`.
    pub face_a: u32,
    /// The face of the second mesh that holds `point_b`.
    pub face_b: u32,
    /// The triangle of the first mesh's faces ([`Mesh::triangles`](crate::Mesh::triangles) order) that holds `point_a`.
    pub triangle_a: u32,
    /// The same for the second mesh.
    pub triangle_b: u32,
    /// `point_a` in barycentric coordinates of `triangle_a`'s corners
    /// ([`Mesh::triangle_vertex_indices`](crate::Mesh::triangle_vertex_indices) order).
    pub barycentric_a: [f64; 3],
    /// `point_b` in barycentric coordinates of `triangle_b`'s corners.
    pub barycentric_b: [f64; 3],
}

/// The distance between mesh `a` placed by `pose_a` and mesh `b` placed by
/// `pose_b`: the smallest [`triangle_distance`] over all pairs of their
/// triangles. Ties go to the lowest `(triangle_a, triangle_b)`; when the
/// surfaces meet (decided exactly, first), the distance is 0 and the pair
/// is the first meeting pair the walk finds, the points a common point.
///
/// ```
/// use proxima::pair::{distance, RigidPose};
/// use proxima::{DVec3, Mesh, MeshIndex, Vec3};
/// let square = Mesh::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[vec![0, 1, 2, 3]]).unwrap();
/// let index = MeshIndex::new(square);
/// let beside = RigidPose::translation_only(DVec3::new(3.0, 0.0, 0.0)).unwrap();
/// let d = distance(&index, &RigidPose::IDENTITY, &index, &beside).unwrap();
/// assert_eq!(d.distance, 2.0);
/// assert_eq!(d.point_a.x, 1.0);
/// assert_eq!(d.point_b.x, 3.0);
/// ```
pub fn distance(
    a: &MeshIndex,
    pose_a: &RigidPose,
    b: &MeshIndex,
    pose_b: &RigidPose,
) -> Result<PairDistance, PairError> {
    let found = distance_below(a, pose_a, b, pose_b, f64::INFINITY)?;
    Ok(found.expect("two meshes with faces have a finite distance"))
}

/// [`distance`] when it is below `d_max`, else `None`: subtree pairs
/// farther apart than `d_max` are never opened, so a clearance check
/// (`is the arm at least 5 cm from the shelf?`) stops as soon as the answer
/// is known. `d_max = ∞` is [`distance`].
pub fn distance_below(
    a: &MeshIndex,
    pose_a: &RigidPose,
    b: &MeshIndex,
    pose_b: &RigidPose,
    d_max: f64,
) -> Result<Option<PairDistance>, PairError> {
    check_distance("d_max", d_max)?;
    check_pose(pose_a, || "pose_a".into())?;
    check_pose(pose_b, || "pose_b".into())?;
    let (tree_a, tree_b) = (faces_tree(a, "a")?, faces_tree(b, "b")?);
    let oriented = (oriented_bounds(a, "a")?, oriented_bounds(b, "b")?);
    Ok(Scratch::with(|scratch| {
        nearest(tree_a, *pose_a, tree_b, *pose_b, oriented, d_max, scratch)
    }))
}

/// [`distance`] between `a` unmoved and `b` at each of `poses` (the
/// sampling loop of motion planning), on all the threads of the current
/// rayon pool, answers in the order of `poses`.
pub fn distance_batch(a: &MeshIndex, b: &MeshIndex, poses: &[RigidPose]) -> Result<Vec<PairDistance>, PairError> {
    let found = distance_below_batch(a, b, poses, f64::INFINITY)?;
    Ok(found
        .into_iter()
        .map(|d| d.expect("two meshes with faces have a finite distance"))
        .collect())
}

/// [`distance_below`] between `a` unmoved and `b` at each of `poses`
/// (clearance checks over a batch), on all the threads of the current rayon
/// pool, answers in the order of `poses`; `d_max = ∞` is [`distance_batch`].
pub fn distance_below_batch(
    a: &MeshIndex,
    b: &MeshIndex,
    poses: &[RigidPose],
    d_max: f64,
) -> Result<Vec<Option<PairDistance>>, PairError> {
    check_distance("d_max", d_max)?;
    let (tree_a, tree_b) = batch_trees(a, b, poses, size_of::<Option<PairDistance>>())?;
    let oriented = (oriented_bounds(a, "a")?, oriented_bounds(b, "b")?);
    Ok(poses
        .par_iter()
        .map_init(Scratch::default, |scratch, pose| {
            nearest(tree_a, RigidPose::IDENTITY, tree_b, *pose, oriented, d_max, scratch)
        })
        .collect())
}

/// The nearest pair below `d_max` (see [`distance_below`]).
fn nearest(
    a: &WideTree<Triangle>,
    pose_a: RigidPose,
    b: &WideTree<Triangle>,
    pose_b: RigidPose,
    (oriented_a, oriented_b): (&OrientedBounds, &OrientedBounds),
    d_max: f64,
    scratch: &mut Scratch,
) -> Option<PairDistance> {
    let pair = PlacedPair::new(a, pose_a, b, pose_b).with_oriented(oriented_a, oriented_b);
    // Whether the surfaces meet is settled first, by the cheap walk of the
    // overlapping boxes only: then the distance walk knows that no pair
    // meets and measures each without the exact intersection test.
    let (found, slot_a, slot_b) = match meeting_pair(&pair, scratch) {
        Some((ta, tb)) if d_max > 0.0 => (triangle_distance(&ta.corners, &tb.corners), ta.slot, tb.slot),
        Some(_) => return None,
        None => {
            let mut visitor = Nearest {
                a: a.leaves(),
                b: b.leaves(),
                best: None,
                distance: d_max,
                reach_squared: d_max * d_max,
            };
            let _ = Walk::new(&pair, scratch).run(&mut visitor);
            visitor.best?
        }
    };
    let (la, lb) = (a.leaves(), b.leaves());
    Some(PairDistance {
        distance: found.distance,
        point_a: found.point_a,
        point_b: found.point_b,
        face_a: la.sources()[slot_a as usize],
        face_b: lb.sources()[slot_b as usize],
        triangle_a: la.indices()[slot_a as usize],
        triangle_b: lb.indices()[slot_b as usize],
        barycentric_a: found.barycentric_a,
        barycentric_b: found.barycentric_b,
    })
}

/// Keeps the nearest triangle pair met so far.
struct Nearest<'t> {
    a: &'t Leaves<Triangle>,
    b: &'t Leaves<Triangle>,
    best: Option<(TrianglePairDistance, u32, u32)>,
    /// The best distance so far (or the caller's bound).
    distance: f64,
    /// Its square, widened by far more than the rounding of a triangle
    /// pair's distance, so that no pair that could tie or win is skipped.
    reach_squared: f64,
}

impl Nearest<'_> {
    /// The input indices of the triangles at the two slots.
    fn inputs(&self, slot_a: u32, slot_b: u32) -> (u32, u32) {
        (self.a.indices()[slot_a as usize], self.b.indices()[slot_b as usize])
    }
}

impl PairVisitor for Nearest<'_> {
    fn reach_squared(&self) -> f64 {
        self.reach_squared
    }

    fn nearest_first(&self) -> bool {
        true
    }

    fn within(&mut self, distance: f64) {
        // The nearest pair lies within `distance` too, up to the rounding
        // of its own computation, which the widening covers.
        let reach = distance * distance * (1.0 + 1e-9);
        self.reach_squared = self.reach_squared.min(reach);
    }

    fn separating_direction(&self) -> Option<DVec3> {
        // The line of the best pair so far (none when it meets).
        let (best, _, _) = self.best.as_ref()?;
        Some(best.point_b - best.point_a).filter(|d| *d != DVec3::ZERO)
    }

    fn triangles(&mut self, a: &PlacedTriangle, b: &PlacedTriangle) -> ControlFlow<()> {
        // No pair meets (settled before the walk).
        let found = separated_triangle_distance(&a.corners, &b.corners);
        let better = match &self.best {
            None => found.distance < self.distance,
            Some((best, sa, sb)) => {
                found.distance < best.distance
                    || (found.distance == best.distance && self.inputs(a.slot, b.slot) < self.inputs(*sa, *sb))
            }
        };
        if better {
            self.distance = found.distance;
            self.reach_squared = self.reach_squared.min(found.distance * found.distance * (1.0 + 1e-9));
            self.best = Some((found, a.slot, b.slot));
        }
        ControlFlow::Continue(())
    }
}
