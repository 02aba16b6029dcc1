//! The faces of one mesh that meet other faces of it.

use super::collide::{PairLimit, collect_parallel};
use super::descent::{PairVisitor, PlacedPair, PlacedTriangle};
use super::triangle_intersection::{neighbours_intersect, triangles_intersect};
use super::{FacePair, PairError, RigidPose, faces_tree};
use crate::Triangle;
use crate::index::MeshIndex;
use crate::query::{Leaves, SpatialIndex};
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
    let corners = index.mesh().triangle_vertex_indices();
    let pair = PlacedPair::new(tree, RigidPose::IDENTITY, tree, RigidPose::IDENTITY);
    let leaves = tree.leaves();
    let limit = PairLimit::from_budget()?;
    let visitor = || SelfMeeting {
        leaves,
        corners: &corners,
        out: Vec::new(),
        limit: &limit,
    };
    let found = collect_parallel(&pair, true, visitor, |v| v.out);
    limit.check("self-intersecting pairs", found.len())?;
    Ok(found)
}

/// Collects the face pairs of one mesh that meet beyond what they share.
struct SelfMeeting<'t> {
    leaves: &'t Leaves<Triangle>,
    /// Vertex indices per triangle (input order).
    corners: &'t [[u32; 3]],
    out: Vec<FacePair>,
    limit: &'t PairLimit,
}

impl PairVisitor for SelfMeeting<'_> {
    fn reach_squared(&self) -> f64 {
        0.0
    }

    fn triangles(&mut self, a: &PlacedTriangle, b: &PlacedTriangle) -> ControlFlow<()> {
        let (sa, sb) = (a.slot as usize, b.slot as usize);
        let (fa, fb) = (self.leaves.sources()[sa], self.leaves.sources()[sb]);
        if fa == fb {
            return ControlFlow::Continue(());
        }
        let ia = self.corners[self.leaves.indices()[sa] as usize];
        let ib = self.corners[self.leaves.indices()[sb] as usize];
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
