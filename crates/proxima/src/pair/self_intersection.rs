//! The faces of one mesh that meet other faces of it.
//!
//! The faces' tree is walked against itself ([`overlaps`]): the mesh is not
//! moved, so node boxes are compared as the tree stores them (`f32`, closed
//! boxes: touching counts), with no padding and no placement, and the exact
//! tests run on the triangles' own coordinates. Nearly every pair that walk
//! finds is a pair of neighbours (on the Stanford dragon, 5.6M of 6.2M share
//! a vertex or an edge): nearly all are settled with no test by the fan
//! certificate of a shared vertex ([`fans`]), the rest by the exact
//! neighbour rule ([`neighbours_intersect`]).

mod fans;
mod overlaps;

use super::collide::PairLimit;
use super::triangle_intersection::{neighbours_intersect, triangles_intersect};
use super::{FacePair, PairError, faces_tree};
use crate::Triangle;
use crate::index::MeshIndex;
use crate::math::Vec3;
use crate::query::SpatialIndex;
use crate::wide_tree::WideTree;
use overlaps::{LeafVisitor, SelfOverlaps};
use rayon::prelude::*;
use std::ops::{ControlFlow, Range};
use wide::{f32x8, u32x8};

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
    meeting_pairs(tree, index.mesh().positions(), &corners, Report::Faces)
}

/// What [`meeting_pairs`] names a pair by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Report {
    /// The faces the triangles came from (the tree's sources); two
    /// triangles of one polygon face are never a pair.
    Faces,
    /// The triangles themselves (the tree's build indices).
    Triangles,
}

/// The pairs of triangles of `tree` that meet beyond what they share,
/// sorted, named as `report` says: the walk of [`self_intersections`] on a
/// tree built over triangles whose vertex indices are `corners` (by build
/// index) into `positions`.
pub(crate) fn meeting_pairs(
    tree: &WideTree<Triangle>,
    positions: &[Vec3],
    corners: &[[u32; 3]],
    report: Report,
) -> Result<Vec<FacePair>, PairError> {
    let leaves = tree.leaves();
    let certified = fans::certified_vertices(positions, corners);
    let names = match report {
        Report::Faces => leaves.sources(),
        Report::Triangles => leaves.indices(),
    };
    // Each slot's face, vertex indices and certificates in leaf order, read
    // in the order the walk meets them rather than through indirections.
    let slots: Vec<Slot> = names
        .par_iter()
        .zip(leaves.indices())
        .map(|(&face, &triangle)| {
            let vertices = corners[triangle as usize];
            let certified = (0..3).fold(0, |bits, k| bits | (u8::from(certified[vertices[k] as usize]) << k));
            Slot {
                vertices,
                face,
                certified,
            }
        })
        .collect();
    drop(certified);
    let boxes = SlotBoxes::new(leaves.primitives(), &slots);
    let limit = PairLimit::from_budget()?;
    let walk = SelfOverlaps::new(tree);
    let tasks = walk.split(16 * rayon::current_num_threads());
    let mut found: Vec<FacePair> = tasks
        .into_par_iter()
        .map_init(Vec::new, |stack, task| {
            let mut meeting = SelfMeeting {
                slots: &slots,
                boxes: &boxes,
                triangles: leaves.primitives(),
                out: Vec::new(),
                limit: &limit,
            };
            let _ = walk.run(task, stack, &mut meeting);
            meeting.out
        })
        .flatten_iter()
        .collect();
    limit.check("self-intersecting pairs", found.len())?;
    found.par_sort_unstable();
    found.dedup();
    Ok(found)
}

/// What the walk reads of one leaf slot.
#[derive(Clone, Copy, Debug)]
struct Slot {
    /// The face's vertex indices.
    vertices: [u32; 3],
    /// The face.
    face: u32,
    /// Bit `k` set when vertex `vertices[k]`'s fan settles every pair of
    /// faces sharing it ([`fans`]).
    certified: u8,
}

/// Collects the face pairs of one mesh that meet beyond what they share.
struct SelfMeeting<'t> {
    slots: &'t [Slot],
    boxes: &'t SlotBoxes,
    /// The triangles in leaf order.
    triangles: &'t [Triangle],
    out: Vec<FacePair>,
    limit: &'t PairLimit,
}

impl SelfMeeting<'_> {
    /// Tests slots `i` and `j`, whose boxes overlap.
    #[inline]
    fn pair(&mut self, i: usize, j: usize) -> ControlFlow<()> {
        let (a, b) = (&self.slots[i], &self.slots[j]);
        let (ia, ib) = (a.vertices, b.vertices);
        // Bit k: a's vertex k is one of b's; without branches, as nearly
        // every pair met is a neighbour settled right here.
        let of_b = |v: u32| u8::from((v == ib[0]) | (v == ib[1]) | (v == ib[2]));
        let shared = of_b(ia[0]) | (of_b(ia[1]) << 1) | (of_b(ia[2]) << 2);
        if (a.face == b.face) | (shared & a.certified != 0) {
            return ControlFlow::Continue(());
        }
        let shares = shared != 0;
        let corners = |t: &Triangle| [t.a, t.b, t.c].map(|p| p.as_dvec3());
        let (ta, tb) = (corners(&self.triangles[i]), corners(&self.triangles[j]));
        let meet = if shares {
            neighbours_intersect(&ta, ia, &tb, ib)
        } else {
            triangles_intersect(&ta, &tb)
        };
        if meet {
            self.out.push([a.face.min(b.face), a.face.max(b.face)]);
            return self.limit.add();
        }
        ControlFlow::Continue(())
    }
}

impl LeafVisitor for SelfMeeting<'_> {
    fn leaves(&mut self, a: Range<usize>, b: Range<usize>, same: bool) -> ControlFlow<()> {
        // Leaves hold at most 8 slots; larger ones (not built by this
        // crate's builders) are taken 8 at a time.
        for first in b.clone().step_by(LANES) {
            let lanes = (b.end - first).min(LANES);
            let others = self.boxes.eight(first);
            for mine in a.clone().step_by(LANES) {
                let own = self.boxes.eight(mine);
                for i in mine..a.end.min(mine + LANES) {
                    let mut mask = own.overlapping(i - mine, &others) & ((1 << lanes) - 1);
                    if mask != 0 {
                        mask &= !own.settled(i - mine, self.slots[i].certified, &others);
                    }
                    if same && i >= first {
                        // One leaf with itself: each unordered pair once, j > i.
                        let at = i - first;
                        mask &= if at < LANES { !((2u32 << at) - 1) } else { 0 };
                    }
                    while mask != 0 {
                        let j = first + mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        self.pair(i, j)?;
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }
}

/// Slots compared eight at a time.
const LANES: usize = 8;

/// The exact boxes of the triangles (`f32` corners) in leaf order, per
/// coordinate, padded with empty boxes so that eight can be read from any
/// slot.
struct SlotBoxes {
    lo: [Vec<f32>; 3],
    hi: [Vec<f32>; 3],
    /// Each slot's vertex indices, per corner, and its face.
    vertex: [Vec<u32>; 3],
    face: Vec<u32>,
}

/// Eight slots' boxes, per coordinate.
struct Eight {
    lo: [f32x8; 3],
    hi: [f32x8; 3],
    vertex: [u32x8; 3],
    face: u32x8,
}

impl Eight {
    /// Which of `others`' boxes overlap box `lane` of these (closed boxes),
    /// as a bit mask.
    #[inline]
    fn overlapping(&self, lane: usize, others: &Eight) -> u32 {
        let mut both = others.lo[0].simd_le(f32x8::splat(self.hi[0].as_array()[lane]));
        for k in 0..3 {
            let (lo, hi) = (self.lo[k].as_array()[lane], self.hi[k].as_array()[lane]);
            both = both & others.lo[k].simd_le(f32x8::splat(hi)) & f32x8::splat(lo).simd_le(others.hi[k]);
        }
        both.to_bitmask()
    }

    /// Which of `others`' slots are settled against slot `lane` of these
    /// without a test, as a bit mask: the same face, or a neighbour through
    /// a vertex whose fan is certified (`certified`, bit k for vertex k).
    #[inline]
    fn settled(&self, lane: usize, certified: u8, others: &Eight) -> u32 {
        let mut settled = others.face.simd_eq(u32x8::splat(self.face.as_array()[lane]));
        for k in 0..3 {
            if certified & (1 << k) != 0 {
                let v = u32x8::splat(self.vertex[k].as_array()[lane]);
                settled =
                    settled | others.vertex[0].simd_eq(v) | others.vertex[1].simd_eq(v) | others.vertex[2].simd_eq(v);
            }
        }
        settled.to_bitmask()
    }
}

impl SlotBoxes {
    fn new(triangles: &[Triangle], slots: &[Slot]) -> Self {
        let padded = triangles.len() + LANES;
        let coordinate = |k: usize, pick: fn(&Triangle, usize) -> f32, empty: f32| {
            let mut out = Vec::with_capacity(padded);
            out.extend(triangles.iter().map(|t| pick(t, k)));
            out.resize(padded, empty);
            out
        };
        let low = |t: &Triangle, k: usize| t.a[k].min(t.b[k]).min(t.c[k]);
        let high = |t: &Triangle, k: usize| t.a[k].max(t.b[k]).max(t.c[k]);
        let index = |pick: &dyn Fn(&Slot) -> u32| {
            let mut out = Vec::with_capacity(padded);
            out.extend(slots.iter().map(pick));
            out.resize(padded, u32::MAX);
            out
        };
        Self {
            lo: std::array::from_fn(|k| coordinate(k, low, f32::INFINITY)),
            hi: std::array::from_fn(|k| coordinate(k, high, f32::NEG_INFINITY)),
            vertex: std::array::from_fn(|k| index(&|s: &Slot| s.vertices[k])),
            face: index(&|s: &Slot| s.face),
        }
    }

    /// The boxes of slots `first..first + 8`.
    #[inline]
    fn eight(&self, first: usize) -> Eight {
        let load = |v: &Vec<f32>| f32x8::new(v[first..first + LANES].try_into().unwrap_or([0.0; LANES]));
        let indices = |v: &Vec<u32>| u32x8::new(v[first..first + LANES].try_into().unwrap_or([0; LANES]));
        Eight {
            lo: self.lo.each_ref().map(load),
            hi: self.hi.each_ref().map(load),
            vertex: self.vertex.each_ref().map(indices),
            face: indices(&self.face),
        }
    }
}
