//! Collision between two placed meshes: whether they meet, which face
//! pairs meet, which face pairs are within a distance.

use super::descent::{PairVisitor, PlacedPair, PlacedTriangle, Scratch, Task, Walk};
use super::triangle_distance::triangle_distance;
use super::triangle_intersection::triangles_intersect;
use super::{FacePair, PairError, RigidPose, batch_trees, check_distance, check_pose, faces_tree};
use crate::index::MeshIndex;
use crate::query::SpatialIndex;
use rayon::prelude::*;
use std::ops::ControlFlow;

/// `true` when the surface of mesh `a` placed by `pose_a` meets that of `b`
/// placed by `pose_b` (closed triangles: touching counts), decided exactly
/// for the placed coordinates; the walk stops at the first meeting pair.
///
/// ```
/// use proxima::pair::{intersects, RigidPose};
/// use proxima::{DVec3, Mesh, MeshIndex, Vec3};
/// let triangle = MeshIndex::new(Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap());
/// // Moved by exactly its own width along x: the two touch at one edge's end.
/// let touching = RigidPose::translation_only(DVec3::new(1.0, 0.0, 0.0)).unwrap();
/// assert!(intersects(&triangle, &RigidPose::IDENTITY, &triangle, &touching).unwrap());
/// let apart = RigidPose::translation_only(DVec3::new(1.0f64.next_up(), 0.0, 0.0)).unwrap();
/// assert!(!intersects(&triangle, &RigidPose::IDENTITY, &triangle, &apart).unwrap());
/// ```
pub fn intersects(a: &MeshIndex, pose_a: &RigidPose, b: &MeshIndex, pose_b: &RigidPose) -> Result<bool, PairError> {
    check_pose(pose_a, || "pose_a".into())?;
    check_pose(pose_b, || "pose_b".into())?;
    let (tree_a, tree_b) = (faces_tree(a, "a")?, faces_tree(b, "b")?);
    let pair = PlacedPair::new(tree_a, *pose_a, tree_b, *pose_b);
    Ok(Scratch::with(|scratch| first_meeting(&pair, scratch)))
}

/// [`intersects`] for `a` unmoved and `b` at each of `poses`, on all the
/// threads of the current rayon pool, answers in the order of `poses`.
pub fn intersects_batch(a: &MeshIndex, b: &MeshIndex, poses: &[RigidPose]) -> Result<Vec<bool>, PairError> {
    let (tree_a, tree_b) = batch_trees(a, b, poses, 1)?;
    Ok(poses
        .par_iter()
        .map_init(Scratch::default, |scratch, pose| {
            first_meeting(&PlacedPair::new(tree_a, RigidPose::IDENTITY, tree_b, *pose), scratch)
        })
        .collect())
}

/// Every pair of faces (face of `a`, face of `b`) whose surfaces meet,
/// touching included, decided exactly; sorted, each pair once (a polygon
/// face meets another if any of its fan triangles does).
pub fn intersecting_pairs(
    a: &MeshIndex,
    pose_a: &RigidPose,
    b: &MeshIndex,
    pose_b: &RigidPose,
) -> Result<Vec<FacePair>, PairError> {
    pairs_within(a, pose_a, b, pose_b, 0.0)
}

/// Every pair of faces (face of `a`, face of `b`) at distance at most `d`
/// ([`triangle_distance`], `f64`): contacts with a margin, clearance maps.
/// `d = 0` gives exactly [`intersecting_pairs`] (decided by the exact test,
/// not by a computed distance). Sorted, each pair once.
pub fn pairs_within(
    a: &MeshIndex,
    pose_a: &RigidPose,
    b: &MeshIndex,
    pose_b: &RigidPose,
    d: f64,
) -> Result<Vec<FacePair>, PairError> {
    check_distance("d", d)?;
    check_pose(pose_a, || "pose_a".into())?;
    check_pose(pose_b, || "pose_b".into())?;
    let (tree_a, tree_b) = (faces_tree(a, "a")?, faces_tree(b, "b")?);
    let pair = PlacedPair::new(tree_a, *pose_a, tree_b, *pose_b);
    let limit = PairLimit::from_budget()?;
    let visitor = || Within {
        pair: &pair,
        d,
        out: Vec::new(),
        limit: &limit,
    };
    let found = collect_parallel(&pair, visitor, |v| v.out);
    limit.check("d", d)?;
    Ok(found)
}

/// Whether any triangle pair of `pair` meets.
fn first_meeting(pair: &PlacedPair<'_>, scratch: &mut Scratch) -> bool {
    meeting_pair(pair, scratch).is_some()
}

/// The first pair of triangles of `pair` the walk finds meeting, if any.
pub(crate) fn meeting_pair(pair: &PlacedPair<'_>, scratch: &mut Scratch) -> Option<(PlacedTriangle, PlacedTriangle)> {
    struct First(Option<(PlacedTriangle, PlacedTriangle)>);
    impl PairVisitor for First {
        fn reach_squared(&self) -> f64 {
            0.0
        }
        fn triangles(&mut self, a: &PlacedTriangle, b: &PlacedTriangle) -> ControlFlow<()> {
            if triangles_intersect(&a.corners, &b.corners) {
                self.0 = Some((*a, *b));
                return ControlFlow::Break(());
            }
            ControlFlow::Continue(())
        }
    }
    let mut first = First(None);
    let _ = Walk::new(pair, scratch).run(&mut first);
    first.0
}

/// Collects the face pairs of every triangle pair within `d`.
struct Within<'p, 't> {
    pair: &'p PlacedPair<'t>,
    d: f64,
    out: Vec<FacePair>,
    limit: &'p PairLimit,
}

/// How many triangle pairs a pair list may collect before it stops: as many
/// as the memory budget holds (a generous `d`, or a mesh of a million
/// copies of one face, would otherwise fill the memory). Shared by the
/// threads of one query.
pub(crate) struct PairLimit {
    found: std::sync::atomic::AtomicUsize,
    most: usize,
}

impl PairLimit {
    /// The limit of the memory budget (`PROXIMA_MEMORY_BUDGET` or the default).
    pub(crate) fn from_budget() -> Result<Self, PairError> {
        let budget = crate::budget::memory_budget_from_env().map_err(crate::budget::BudgetError::Environment)?;
        Ok(Self {
            found: 0.into(),
            most: (budget / size_of::<FacePair>() as u64) as usize,
        })
    }

    /// Counts one more pair; `Break` once past the limit.
    #[inline]
    pub(crate) fn add(&self) -> ControlFlow<()> {
        if self.found.fetch_add(1, std::sync::atomic::Ordering::Relaxed) >= self.most {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }

    /// The budget error when the walk stopped at the limit, naming `option`.
    pub(crate) fn check(&self, option: &str, value: impl std::fmt::Display) -> Result<(), PairError> {
        let found = self.found.load(std::sync::atomic::Ordering::Relaxed);
        if found > self.most {
            crate::budget::check_fits(option, value, found as u128, size_of::<FacePair>() as u128)?;
        }
        Ok(())
    }
}

impl PairVisitor for Within<'_, '_> {
    fn reach_squared(&self) -> f64 {
        // Widened: a pair whose computed distance is d must not be skipped
        // by the rounding of its boxes' distance.
        self.d * self.d * (1.0 + 1e-9)
    }

    fn triangles(&mut self, a: &PlacedTriangle, b: &PlacedTriangle) -> ControlFlow<()> {
        let near = if self.d == 0.0 {
            triangles_intersect(&a.corners, &b.corners)
        } else {
            triangle_distance(&a.corners, &b.corners).distance <= self.d
        };
        if near {
            let face_a = self.pair.a().leaves().sources()[a.slot as usize];
            let face_b = self.pair.b().leaves().sources()[b.slot as usize];
            self.out.push([face_a, face_b]);
            return self.limit.add();
        }
        ControlFlow::Continue(())
    }
}

/// Runs a walk split into tasks on the current rayon pool, each task with
/// its own visitor, and gathers what `take` gets from each: sorted,
/// duplicates removed.
pub(crate) fn collect_parallel<V: PairVisitor + Send>(
    pair: &PlacedPair<'_>,
    visitor: impl Fn() -> V + Sync,
    take: impl Fn(V) -> Vec<FacePair> + Sync,
) -> Vec<FacePair> {
    let mut scratch = Scratch::default();
    let tasks: Vec<Task> = {
        let mut walk = Walk::new(pair, &mut scratch);
        walk.split(16 * rayon::current_num_threads(), &mut visitor())
    };
    let mut found: Vec<FacePair> = tasks
        .into_par_iter()
        .map_init(Scratch::default, |scratch, task| {
            let mut v = visitor();
            let mut walk = Walk::new(pair, scratch);
            let _ = walk.run_from(task, &mut v);
            take(v)
        })
        .flatten_iter()
        .collect();
    found.par_sort_unstable();
    found.dedup();
    found
}
