//! The faces of one mesh that meet other faces of it.

use super::collide::{PairLimit, collect_parallel};
use super::descent::{PairVisitor, PlacedPair, PlacedTriangle};
use super::triangle_intersection::{neighbours_intersect, triangles_intersect};
use super::{FacePair, PairError, RigidPose, faces_tree};
use crate::index::MeshIndex;
use crate::query::SpatialIndex;
use std::ops::ControlFlow;

/// Every pair of faces `[f, g]` (`f < g`) of the mesh that meet, decided
/// exactly, sorted. Faces that share vertices (by index) are neighbours and
/// meet where they share them: such a pair is reported only when the faces
/// meet beyond the shared vertex or edge (coplanar faces folded onto each
/// other, a face crossing its neighbour); two triangles of one polygon face
/// are never a pair. Faces meeting at the same position through distinct
/// vertex indices (an unwelded seam) are reported: weld first.
///
/// ```
/// use proxima::pair::self_intersections;
/// use proxima::{Mesh, MeshIndex, Vec3};
/// // Two triangles crossing each other, and a third one apart.
/// let p = vec![
///     Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0),
///     Vec3::new(0.5, 0.5, -1.0), Vec3::new(0.5, 0.5, 1.0), Vec3::new(3.0, 3.0, 0.0),
///     Vec3::new(9.0, 9.0, 9.0), Vec3::new(10.0, 9.0, 9.0), Vec3::new(9.0, 10.0, 9.0),
/// ];
/// let mesh = Mesh::from_triangles(p, &[[0, 1, 2], [3, 4, 5], [6, 7, 8]]).unwrap();
/// assert_eq!(self_intersections(&MeshIndex::new(mesh)).unwrap(), [[0, 1]]);
/// ```
pub fn self_intersections(index: &MeshIndex) -> Result<Vec<FacePair>, PairError> {
    let tree = faces_tree(index, "mesh")?;
    let leaves = tree.leaves();
    // Each slot's face and vertex indices in leaf order, read in the order
    // the walk meets them rather than through two indirections.
    let corners = index.mesh().triangle_vertex_indices();
    let slots: Vec<(u32, [u32; 3])> = leaves
        .sources()
        .iter()
        .zip(leaves.indices())
        .map(|(&face, &triangle)| (face, corners[triangle as usize]))
        .collect();
    drop(corners);
    let pair = PlacedPair::new(tree, RigidPose::IDENTITY, tree, RigidPose::IDENTITY);
    let limit = PairLimit::from_budget()?;
    let visitor = || SelfMeeting {
        slots: &slots,
        out: Vec::new(),
        limit: &limit,
    };
    let found = collect_parallel(&pair, true, visitor, |v| v.out);
    limit.check("self-intersecting pairs", found.len())?;
    Ok(found)
}

/// Collects the face pairs of one mesh that meet beyond what they share.
struct SelfMeeting<'t> {
    /// The face and vertex indices of each leaf slot.
    slots: &'t [(u32, [u32; 3])],
    out: Vec<FacePair>,
    limit: &'t PairLimit,
}

impl PairVisitor for SelfMeeting<'_> {
    fn reach_squared(&self) -> f64 {
        0.0
    }

    fn triangles(&mut self, a: &PlacedTriangle, b: &PlacedTriangle) -> ControlFlow<()> {
        let (fa, ia) = self.slots[a.slot as usize];
        let (fb, ib) = self.slots[b.slot as usize];
        if fa == fb {
            return ControlFlow::Continue(());
        }
        let shares = ia.iter().any(|v| ib.contains(v));
        let meet = if shares {
            neighbours_intersect(&a.corners, ia, &b.corners, ib)
        } else {
            triangles_intersect(&a.corners, &b.corners)
        };
        if meet {
            self.out.push([fa.min(fb), fa.max(fb)]);
            return self.limit.add();
        }
        ControlFlow::Continue(())
    }
}
