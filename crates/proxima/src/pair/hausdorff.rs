//! The Hausdorff distance between two meshes' surfaces, as a lower and an
//! upper bound that meet within a tolerance.
//!
//! The one-sided distance from `A` to `B` is `h = max over p in A of d(p, B)`.
//!
//! - **Lower bound:** `d(p, B)` of actual points `p` of `A`: first its
//!   vertices, then the midpoints made by refining its triangles. Each is
//!   the smallest `f64` point–triangle distance over `B`'s triangles, found
//!   by a walk of `B`'s tree whose `f32` box keys are given slack for their
//!   rounding, so no triangle that could be nearer is skipped.
//! - **Upper bound of a triangle piece `t` of `A`:** `min over s in B of max
//!   over t's corners v of d(v, s)` (Tang et al., 2009). For a fixed `s`,
//!   `d(·, s)` is convex, so its largest value on `t` is at a corner, and
//!   `d(p, B) <= d(p, s)` for any `s`.
//! - **Refinement:** a piece whose upper bound exceeds the best lower bound
//!   by more than the tolerance is cut into four at its edges' midpoints. If
//!   `s*` is the triangle of `B` nearest to one corner `v0`, then the bound
//!   is at most `d(v0, s*) + diam(t) <= lower + diam(t)`. Pieces therefore
//!   settle once they are smaller than the tolerance, which caps the depth
//!   at `log2(diam / tolerance)`.
//! - **Pruning:** a piece is dropped as soon as one triangle `s` brings its
//!   bound within `lower + tolerance`. Its walk stops there, and so does a
//!   midpoint's walk once it finds a triangle nearer than `lower`.
//!
//! The answer's upper bound is the largest bound of the pieces it kept, so
//! `lower <= h <= upper` holds up to the `f64` rounding of point–triangle
//! distances, about 1e-15 of the coordinates. `upper - lower <= tolerance`
//! unless a piece reached [`MAX_DEPTH`] levels of refinement. Such a piece
//! would be about 2^-24 of its triangle, and this is counted in
//! [`DirectedHausdorff::unsettled`].

use super::PairError;
use crate::index::MeshIndex;
use crate::math::{DVec3, Vec3};
use crate::primitive::closest_f64::point_triangle_closest;
use crate::query::{Counter, NearestQuery, SpatialIndex};
use crate::wide_tree::WideNode;
use crate::wide_tree::walk::{Pending, Slices, WideQuery};
use crate::{Triangle, WideTree};
use rayon::prelude::*;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU64, Ordering};
use wide::f32x4;

/// Refinement levels at most per triangle: 4^24 pieces is far past what
/// any tolerance allowed by [`MIN_RELATIVE_TOLERANCE`] needs.
pub const MAX_DEPTH: u32 = 24;

/// The smallest tolerance, as a fraction of the larger bounding-box
/// diagonal of the two meshes. `f32` coordinates carry about 6e-8 of it.
pub const MIN_RELATIVE_TOLERANCE: f64 = 1e-7;

/// One direction of the Hausdorff distance, from the surface of one mesh
/// (`from`) to the surface of another (`to`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectedHausdorff {
    /// A lower bound: the distance from [`point`](Self::point), which lies
    /// on `from`, to `to`.
    pub lower: f64,
    /// An upper bound: no point of `from` lies farther from `to`.
    pub upper: f64,
    /// The point of `from` farthest from `to` among those measured.
    pub point: DVec3,
    /// The face of `from` that holds `point`.
    pub face: u32,
    /// A point of `to` nearest to `point`, at distance `lower`.
    pub closest: DVec3,
    /// The face of `to` that holds `closest`.
    pub closest_face: u32,
    /// Triangle pieces examined: the work the tolerance cost.
    pub pieces: u64,
    /// Pieces left coarser than the tolerance at [`MAX_DEPTH`] (0 unless
    /// the meshes are extreme): when not 0, `upper - lower` may exceed the
    /// tolerance.
    pub unsettled: u64,
}

/// Both directions of the Hausdorff distance between meshes `a` and `b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHausdorff {
    /// From `a`'s surface to `b`'s.
    pub forward: DirectedHausdorff,
    /// From `b`'s surface to `a`'s.
    pub backward: DirectedHausdorff,
}

impl MeshHausdorff {
    /// A lower bound of the symmetric Hausdorff distance.
    pub fn lower(&self) -> f64 {
        self.forward.lower.max(self.backward.lower)
    }

    /// An upper bound of the symmetric Hausdorff distance.
    pub fn upper(&self) -> f64 {
        self.forward.upper.max(self.backward.upper)
    }

    /// The direction that realizes the larger lower bound.
    pub fn larger(&self) -> &DirectedHausdorff {
        if self.backward.lower > self.forward.lower {
            &self.backward
        } else {
            &self.forward
        }
    }
}

/// The symmetric Hausdorff distance between the surfaces of meshes `a` and
/// `b`, both in the same frame: bounds that meet within `tolerance`, and the
/// points that realize the lower one (see the module documentation), on
/// all cores.
///
/// ```
/// use proxima::pair::hausdorff;
/// use proxima::{Mesh, MeshIndex, Vec3};
/// let square = |z: f32, size: f32| {
///     let p = vec![Vec3::new(0.0, 0.0, z), Vec3::new(size, 0.0, z), Vec3::new(size, size, z), Vec3::new(0.0, size, z)];
///     MeshIndex::new(Mesh::from_faces(p, &[vec![0, 1, 2, 3]]).unwrap())
/// };
/// // A unit square, and one twice as large 1 above it: the far corner of the
/// // large one is sqrt(1 + 1 + 1) from the small square.
/// let h = hausdorff(&square(0.0, 1.0), &square(1.0, 2.0), 1e-6).unwrap();
/// assert!(h.lower() <= 3f64.sqrt() && 3f64.sqrt() <= h.upper());
/// assert!(h.upper() - h.lower() <= 1e-6);
/// assert_eq!(h.forward.lower, 1.0); // every point of the small square is 1 below the large one
/// assert_eq!(h.larger().point, proxima::DVec3::new(2.0, 2.0, 1.0));
/// ```
pub fn hausdorff(a: &MeshIndex, b: &MeshIndex, tolerance: f64) -> Result<MeshHausdorff, PairError> {
    check_tolerance(a, b, tolerance)?;
    let (tree_a, tree_b) = (super::faces_tree(a, "a")?, super::faces_tree(b, "b")?);
    Ok(MeshHausdorff {
        forward: directed(tree_a, tree_b, tolerance),
        backward: directed(tree_b, tree_a, tolerance),
    })
}

/// The one-sided Hausdorff distance from the surface of `from` to that of
/// `to`, bounded within `tolerance` ([`hausdorff`] computes both sides).
pub fn directed_hausdorff(from: &MeshIndex, to: &MeshIndex, tolerance: f64) -> Result<DirectedHausdorff, PairError> {
    check_tolerance(from, to, tolerance)?;
    let (tree_from, tree_to) = (super::faces_tree(from, "a")?, super::faces_tree(to, "b")?);
    Ok(directed(tree_from, tree_to, tolerance))
}

/// Refuses a tolerance that is not a number, or finer than
/// [`MIN_RELATIVE_TOLERANCE`] of the meshes' size.
fn check_tolerance(a: &MeshIndex, b: &MeshIndex, tolerance: f64) -> Result<(), PairError> {
    let diagonal = |index: &MeshIndex| {
        let bounds = index.mesh().bounds();
        if bounds.min.cmple(bounds.max).all() {
            f64::from((bounds.max - bounds.min).length())
        } else {
            0.0
        }
    };
    let minimum = MIN_RELATIVE_TOLERANCE * diagonal(a).max(diagonal(b));
    if tolerance.is_nan() || tolerance <= 0.0 || tolerance < minimum {
        return Err(PairError::BadTolerance {
            value: tolerance,
            minimum,
        });
    }
    Ok(())
}

/// The best lower bound so far, shared by all workers: a non-negative `f64`
/// whose bits order as its values do.
struct SharedLower(AtomicU64);

impl SharedLower {
    fn get(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }

    fn raise(&self, value: f64) {
        self.0.fetch_max(value.to_bits(), Ordering::Relaxed);
    }
}

/// A point of the surface measured from, and what it is nearest to.
#[derive(Clone, Copy, Debug)]
struct Measured {
    distance: f64,
    point: DVec3,
    face: u32,
    closest: DVec3,
    closest_face: u32,
}

/// What one worker found.
#[derive(Clone, Copy, Debug)]
struct Partial {
    lower: Option<Measured>,
    upper: f64,
    pieces: u64,
    unsettled: u64,
}

impl Partial {
    const EMPTY: Self = Self {
        lower: None,
        upper: 0.0,
        pieces: 0,
        unsettled: 0,
    };

    fn merge(self, other: Self) -> Self {
        let lower = match (self.lower, other.lower) {
            (Some(x), Some(y)) => Some(if y.distance > x.distance { y } else { x }),
            (x, y) => x.or(y),
        };
        Self {
            lower,
            upper: self.upper.max(other.upper),
            pieces: self.pieces + other.pieces,
            unsettled: self.unsettled + other.unsettled,
        }
    }

    fn offer(&mut self, m: Measured) {
        if self.lower.is_none_or(|best| m.distance > best.distance) {
            self.lower = Some(m);
        }
    }
}

/// A piece of a triangle of the surface measured from.
#[derive(Clone, Copy, Debug)]
struct Piece {
    corners: [DVec3; 3],
    depth: u32,
    /// Where the piece's candidates start in the worker's list arena.
    list: usize,
    /// How many candidates it has; [`WALK`] for a piece that has no list
    /// and walks the tree.
    len: usize,
    /// The piece is a whole triangle.
    whole: bool,
}

/// The `len` of a piece without a candidate list.
const WALK: usize = usize::MAX;

/// Pieces with more candidates than this walk the tree instead: its
/// nearest-first order finds the settling triangle among many sooner than
/// a scan of the list.
const MAX_CANDIDATES: usize = 24;

/// What a worker keeps between triangles: its stack of pieces, the
/// candidate lists of the pieces on it (a stack too: each piece's list
/// is the last one when it is popped), and the triangle that settled the
/// last piece.
struct Worker {
    stack: Vec<Piece>,
    lists: Vec<u32>,
    hint: usize,
}

/// [`directed_hausdorff`] on the faces' trees.
fn directed(tree_from: &WideTree<Triangle>, tree_to: &WideTree<Triangle>, tolerance: f64) -> DirectedHausdorff {
    let target = Target::new(tree_from, tree_to);
    // Sampled vertices first: their largest distance is usually close to
    // the answer, and it prunes nearly every piece at once. The batch picks
    // the farthest by `f32` distances; its distance is then measured again
    // in `f64` by the walk that keeps every candidate.
    let (vertex, vertex_face) = farthest_sample(tree_from, tree_to);
    let first = target.measure(vertex, -1.0).map(|(distance, closest, slot)| Measured {
        distance,
        point: vertex,
        face: vertex_face,
        closest,
        closest_face: tree_to.tree().source(slot),
    });
    let shared = SharedLower(AtomicU64::new(first.map_or(0.0, |m| m.distance).to_bits()));
    let triangles = tree_from.tree().primitives();
    let start = Partial {
        lower: first,
        ..Partial::EMPTY
    };
    let found = (0..triangles.len())
        .into_par_iter()
        .with_min_len(64)
        .fold(
            || {
                let worker = Worker {
                    stack: Vec::with_capacity(4 * MAX_DEPTH as usize),
                    lists: Vec::new(),
                    hint: 0,
                };
                (Partial::EMPTY, worker)
            },
            |(mut partial, mut worker), slot| {
                let t = &triangles[slot];
                let face = tree_from.tree().source(slot);
                worker.stack.push(Piece {
                    corners: [t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3()],
                    depth: 0,
                    list: 0,
                    len: WALK,
                    whole: true,
                });
                refine(&target, &shared, tolerance, face, &mut worker, &mut partial);
                (partial, worker)
            },
        )
        .map(|(partial, _)| partial)
        .reduce(|| Partial::EMPTY, Partial::merge)
        .merge(start);
    let lower = found.lower.expect("a mesh with faces has a vertex on them");
    DirectedHausdorff {
        lower: lower.distance,
        upper: found.upper.max(lower.distance),
        point: lower.point,
        face: lower.face,
        closest: lower.closest,
        closest_face: lower.closest_face,
        pieces: found.pieces,
        unsettled: found.unsettled,
    }
}

/// Settles the pieces on the worker's stack (those of one face), cutting
/// each whose bound is too loose (see the module documentation).
///
/// A whole triangle's bound walks the tree. When it is cut, the triangles
/// of the other surface whose boxes lie within its bound of its box are
/// gathered once: only they can settle a piece of it, since a piece's best
/// bound is at most its parent's (by convexity). Its pieces then take
/// their bounds from that list, each passing on to its own pieces the
/// candidates within its bound.
fn refine(
    target: &Target<'_>,
    shared: &SharedLower,
    tolerance: f64,
    face: u32,
    worker: &mut Worker,
    partial: &mut Partial,
) {
    while let Some(piece) = worker.stack.pop() {
        partial.pieces += 1;
        let lower = shared.get();
        let settled = lower + tolerance;
        let enough = settled * settled;
        // The triangle that settled the previous piece (a neighbour: the
        // pieces come in tree order) usually settles this one too, with
        // no walk.
        let near = reach_squared(&piece.corners, 3, &target.corners(worker.hint), enough, f64::INFINITY);
        let (upper2, slot) = if near <= enough {
            (near, worker.hint)
        } else if piece.len == WALK {
            target.bound(&piece.corners, settled)
        } else {
            let list = &worker.lists[piece.list..piece.list + piece.len];
            best_of(&piece.corners, list, target, enough, (near, worker.hint))
        };
        worker.hint = slot;
        let upper = upper2.sqrt();
        if upper <= settled || piece.depth == MAX_DEPTH {
            partial.upper = partial.upper.max(upper);
            partial.unsettled += u64::from(upper > settled);
            if piece.len != WALK {
                worker.lists.truncate(piece.list);
            }
            continue;
        }
        // A whole triangle that does not settle: its corners (not measured
        // yet, unlike the midpoints of the pieces cut from it) may raise
        // the lower bound enough.
        if piece.whole {
            for &v in &piece.corners {
                target.offer(v, lower, face, shared, partial);
            }
            if upper <= shared.get() + tolerance {
                partial.upper = partial.upper.max(upper);
                continue;
            }
        }
        let [a, b, c] = piece.corners;
        let (ab, bc, ca) = ((a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5);
        let lower = shared.get();
        let best = target.corners(slot);
        for m in [ab, bc, ca] {
            // Nearer than the lower bound to the piece's best triangle: it
            // cannot raise it, and needs no walk.
            if point_triangle_closest(m, &best).0.distance_squared(m) > lower * lower {
                target.offer(m, lower, face, shared, partial);
            }
        }
        // The candidates of the four pieces, each those of the parent's
        // within the parent's bound of the piece's box, moved down over the
        // parent's list when done. A piece with too many walks the tree.
        let base = if piece.len == WALK {
            let base = worker.lists.len();
            target.gather(&piece.corners, upper, &mut worker.lists, MAX_CANDIDATES);
            base
        } else {
            piece.list
        };
        let from = base..worker.lists.len();
        let depth = piece.depth + 1;
        let mut children = [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]].map(|corners| Piece {
            corners,
            depth,
            list: 0,
            len: WALK,
            whole: false,
        });
        if !from.is_empty() {
            let reach = upper2 * (1.0 + 1e-9);
            for child in &mut children {
                let (lo, hi) = corner_box(&child.corners);
                child.list = worker.lists.len();
                for k in from.clone() {
                    let s = target.corners(worker.lists[k] as usize);
                    let (s_lo, s_hi) = corner_box(&s);
                    if (lo - s_hi).max(s_lo - hi).max(DVec3::ZERO).length_squared() <= reach {
                        worker.lists.push(worker.lists[k]);
                    }
                }
                child.len = worker.lists.len() - child.list;
            }
        }
        let end = from.end;
        worker.lists.copy_within(end.., base);
        worker.lists.truncate(worker.lists.len() - (end - base));
        for mut child in children {
            if child.len != WALK {
                child.list -= end - base;
            }
            worker.stack.push(child);
        }
    }
}

/// The box of three corners.
fn corner_box(c: &[DVec3; 3]) -> (DVec3, DVec3) {
    (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]))
}

/// The smallest largest squared corner distance over the triangles of
/// `list` (slots of the other surface's tree), starting from `best`; stops
/// at the first within `enough`.
fn best_of(
    corners: &[DVec3; 3],
    list: &[u32],
    target: &Target<'_>,
    enough: f64,
    mut best: (f64, usize),
) -> (f64, usize) {
    for &slot in list {
        let worst = reach_squared(corners, 3, &target.corners(slot as usize), enough, best.0);
        if worst < best.0 {
            best = (worst, slot as usize);
            if worst <= enough {
                break;
            }
        }
    }
    best
}

/// Triangles of the surface measured from whose first corner is measured
/// before the refinement starts: one in this many, in tree order (spread
/// over the surface). The others' corners are measured only when their
/// triangle does not settle at once.
const SAMPLE_STRIDE: usize = 16;

/// Among the first corners of every [`SAMPLE_STRIDE`]-th triangle of
/// `from` (leaf order), the one farthest from `to` by the `f32`
/// closest-point batch, and the face that holds it.
fn farthest_sample(from: &WideTree<Triangle>, to: &WideTree<Triangle>) -> (DVec3, u32) {
    let slots: Vec<usize> = (0..from.len()).step_by(SAMPLE_STRIDE).collect();
    let points: Vec<Vec3> = slots.iter().map(|&i| from.tree().primitives()[i].a).collect();
    let hits = to.closest_batch(&points);
    let far = hits
        .iter()
        .enumerate()
        .max_by(|(_, x), (_, y)| {
            let d = |h: &&Option<crate::ClosestHit>| h.as_ref().map_or(f32::INFINITY, |h| h.distance);
            d(x).total_cmp(&d(y))
        })
        .map_or(0, |(i, _)| i);
    (points[far].as_dvec3(), from.tree().source(slots[far]))
}

/// The surface measured to: its faces' tree, and the absolute slack that
/// keeps the tree's `f32` box keys from skipping a candidate.
struct Target<'t> {
    tree: &'t WideTree<Triangle>,
    slack: f64,
}

impl<'t> Target<'t> {
    fn new(from: &WideTree<Triangle>, to: &'t WideTree<Triangle>) -> Self {
        let magnitude = |bounds: crate::Aabb| f64::from(bounds.min.abs().max(bounds.max.abs()).max_element());
        // A query corner rounded to `f32` moves by half an ulp of the
        // largest coordinate (2^-24 of it), and a box distance computed in
        // `f32` errs by a few ulps of the distance, covered by the
        // relative slack in `key_bound`; 2^-20 of the coordinates is well
        // past both.
        let scale = magnitude(from.bounds()).max(magnitude(to.bounds()));
        Self {
            tree: to,
            slack: scale * (1.0 / (1u64 << 20) as f64),
        }
    }

    /// `d(p, to)` when it exceeds `above`: the distance, the nearest point
    /// and its slot; `None` when some triangle lies within `above` (never,
    /// for a negative `above`).
    fn measure(&self, p: DVec3, above: f64) -> Option<(f64, DVec3, usize)> {
        let mut reach = Reach::new([p; 3], 1, above, self.slack);
        self.tree.walk(|_| &mut reach, &mut ());
        if reach.stopped {
            return None;
        }
        let (d2, slot) = (reach.best, reach.best_slot);
        let t = &self.tree.tree().primitives()[slot];
        let (closest, _) = point_triangle_closest(p, &[t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3()]);
        Some((d2.sqrt(), closest, slot))
    }

    /// An upper bound of `max over p in the triangle of d(p, to)²`: the
    /// smallest, over `to`'s triangles `s`, of the largest squared distance
    /// of a corner to `s` (as soon as one is within `settled`, that one),
    /// and the slot of that `s`.
    fn bound(&self, corners: &[DVec3; 3], settled: f64) -> (f64, usize) {
        let mut reach = Reach::new(*corners, 3, settled, self.slack);
        self.tree.walk(|_| &mut reach, &mut ());
        (reach.best, reach.best_slot)
    }

    /// Measures point `p` of face `face` of the surface measured from, and
    /// raises the lower bound to its distance when that exceeds `lower`.
    fn offer(&self, p: DVec3, lower: f64, face: u32, shared: &SharedLower, partial: &mut Partial) {
        if let Some((distance, closest, slot)) = self.measure(p, lower) {
            shared.raise(distance);
            partial.offer(Measured {
                distance,
                point: p,
                face,
                closest,
                closest_face: self.tree.tree().source(slot),
            });
        }
    }

    /// Appends to `out` the slots of every triangle whose box lies within
    /// `reach` of the box of `corners` (and perhaps a few more: the tree's
    /// `f32` boxes are given slack), or nothing when there are more than
    /// `most`.
    fn gather(&self, corners: &[DVec3; 3], reach: f64, out: &mut Vec<u32>, most: usize) {
        let start = out.len();
        let (lo, hi) = corner_box(corners);
        let r = (reach + self.slack) * (1.0 + 1e-5);
        let splat = |v: DVec3| {
            [
                f32x4::splat(v.x as f32),
                f32x4::splat(v.y as f32),
                f32x4::splat(v.z as f32),
            ]
        };
        let mut gather = Gather {
            lo: splat(lo - DVec3::splat(r)),
            hi: splat(hi + DVec3::splat(r)),
            box_lo: lo,
            box_hi: hi,
            reach_squared: r * r,
            room: most,
            out,
        };
        self.tree.walk(|_| &mut gather, &mut ());
        if gather.room == 0 && gather.out.len() - start > most {
            gather.out.truncate(start);
        }
    }

    /// The corners of the triangle at `slot`, in `f64`.
    fn corners(&self, slot: usize) -> [DVec3; 3] {
        let t = &self.tree.tree().primitives()[slot];
        [t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3()]
    }
}

/// The walk for [`Target::measure`] and [`Target::bound`]: the triangle of
/// `to` whose largest squared distance to the query's corners is smallest.
struct Reach {
    corners: [DVec3; 3],
    /// The corners splatted per axis, in `f32`, for the node keys.
    lanes: [[f32x4; 3]; 3],
    /// Corners in use: 1 (a point) or 3.
    count: usize,
    best: f64,
    best_slot: usize,
    /// Subtrees whose key exceeds this are skipped (see [`Reach::key_bound`]).
    key_bound: f32,
    /// A triangle within this squared distance ends the walk.
    stop_squared: f64,
    stopped: bool,
    slack: f64,
}

impl Reach {
    fn new(corners: [DVec3; 3], count: usize, stop: f64, slack: f64) -> Self {
        let lanes = corners.map(|c| {
            let c = c.as_vec3();
            [f32x4::splat(c.x), f32x4::splat(c.y), f32x4::splat(c.z)]
        });
        Self {
            corners,
            lanes,
            count,
            best: f64::INFINITY,
            best_slot: 0,
            key_bound: f32::INFINITY,
            // A negative `stop`: never stop.
            stop_squared: if stop >= 0.0 { stop * stop } else { -1.0 },
            stopped: false,
            slack,
        }
    }

    /// The key bound for the best so far: its distance widened by the
    /// slack, squared, with a relative margin for the keys' `f32` rounding.
    fn key_bound(&self) -> f32 {
        let r = (self.best.sqrt() + self.slack) * (1.0 + 1e-5);
        (r * r) as f32
    }
}

impl WideQuery<Triangle> for &mut Reach {
    #[inline(always)]
    fn keys(&self, node: &WideNode) -> (f32x4, u32) {
        let mut keys = node.distances_squared(self.lanes[0][0], self.lanes[0][1], self.lanes[0][2]);
        for lanes in &self.lanes[1..self.count] {
            keys = keys.fast_max(node.distances_squared(lanes[0], lanes[1], lanes[2]));
        }
        (keys, keys.simd_le(f32x4::splat(self.key_bound)).to_bitmask())
    }

    #[inline(always)]
    fn bound(&self) -> f32 {
        self.key_bound
    }

    fn leaf<C: Counter>(&mut self, tree: &Slices<'_, Triangle>, leaf: Pending, counter: &mut C) -> ControlFlow<()> {
        let slots = leaf_slots(tree, leaf);
        counter.primitives(slots.len() as u64);
        for (slot, t) in slots.clone().zip(&tree.primitives[slots]) {
            let s = [t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3()];
            let worst = reach_squared(&self.corners, self.count, &s, self.stop_squared.max(0.0), self.best);
            if worst < self.best {
                self.best = worst;
                self.best_slot = slot;
                self.key_bound = self.key_bound();
                if worst <= self.stop_squared {
                    self.stopped = true;
                    return ControlFlow::Break(());
                }
            }
        }
        ControlFlow::Continue(())
    }
}

/// An upper bound of the largest squared distance from the first `count`
/// `corners` to triangle `s`: exact, unless the distance to `s`'s nearest
/// vertex (which bounds the distance to `s` from above) already brings
/// every corner within `enough`, when that bound is returned. Once the
/// answer is known to be at least `give_up`, some value at least
/// `give_up` is returned without refining it: `s` is then of no use.
#[inline]
fn reach_squared(corners: &[DVec3; 3], count: usize, s: &[DVec3; 3], enough: f64, give_up: f64) -> f64 {
    // The box of `s` bounds every corner's distance from below.
    let (lo, hi) = (s[0].min(s[1]).min(s[2]), s[0].max(s[1]).max(s[2]));
    let mut box_bound = 0.0f64;
    for &v in &corners[..count] {
        box_bound = box_bound.max((lo - v).max(v - hi).max(DVec3::ZERO).length_squared());
    }
    if box_bound >= give_up {
        return box_bound;
    }
    let vertex_bound = corners[..count]
        .iter()
        .map(|&v| s.iter().map(|&k| k.distance_squared(v)).fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max);
    if vertex_bound <= enough {
        return vertex_bound;
    }
    let mut worst = 0.0f64;
    for &v in &corners[..count] {
        worst = worst.max(point_triangle_closest(v, s).0.distance_squared(v));
        if worst >= give_up {
            break;
        }
    }
    worst
}

/// The leaf-order slots of a leaf's triangles (a tree with triangle
/// packets names a leaf by its first packet).
fn leaf_slots(tree: &Slices<'_, Triangle>, leaf: Pending) -> std::ops::Range<usize> {
    let first = match tree.packets.get(leaf.child as usize) {
        Some(packet) => packet.first as usize,
        None => leaf.child as usize,
    };
    first..first + leaf.leaf_len()
}

/// The walk of [`Target::gather`]: every subtree whose box overlaps the
/// piece's box widened by the reach.
struct Gather<'o> {
    /// The widened box, splatted per axis.
    lo: [f32x4; 3],
    hi: [f32x4; 3],
    /// The piece's own box, in `f64`, for the leaves' exact test.
    box_lo: DVec3,
    box_hi: DVec3,
    reach_squared: f64,
    /// How many more may be gathered; one more ends the walk.
    room: usize,
    out: &'o mut Vec<u32>,
}

impl WideQuery<Triangle> for &mut Gather<'_> {
    #[inline(always)]
    fn keys(&self, node: &WideNode) -> (f32x4, u32) {
        let overlaps = f32x4::new(node.min_x).simd_le(self.hi[0])
            & f32x4::new(node.max_x).simd_ge(self.lo[0])
            & f32x4::new(node.min_y).simd_le(self.hi[1])
            & f32x4::new(node.max_y).simd_ge(self.lo[1])
            & f32x4::new(node.min_z).simd_le(self.hi[2])
            & f32x4::new(node.max_z).simd_ge(self.lo[2]);
        (f32x4::ZERO, overlaps.to_bitmask())
    }

    #[inline(always)]
    fn bound(&self) -> f32 {
        0.0
    }

    fn leaf<C: Counter>(&mut self, tree: &Slices<'_, Triangle>, leaf: Pending, counter: &mut C) -> ControlFlow<()> {
        let slots = leaf_slots(tree, leaf);
        counter.primitives(slots.len() as u64);
        for (slot, t) in slots.clone().zip(&tree.primitives[slots]) {
            let (lo, hi) = corner_box(&[t.a.as_dvec3(), t.b.as_dvec3(), t.c.as_dvec3()]);
            let gap = (self.box_lo - hi).max(lo - self.box_hi).max(DVec3::ZERO);
            if gap.length_squared() <= self.reach_squared {
                self.out.push(slot as u32);
                if self.room == 0 {
                    return ControlFlow::Break(());
                }
                self.room -= 1;
            }
        }
        ControlFlow::Continue(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Mesh, Vec3};

    fn index(positions: Vec<Vec3>, triangles: &[[u32; 3]]) -> MeshIndex {
        MeshIndex::new(Mesh::from_triangles(positions, triangles).unwrap())
    }

    /// The largest distance from an acute triangle to three small ones at
    /// its corners lies near its circumcentre, inside it, where no vertex
    /// or edge midpoint is: only refinement finds it. The bounds must
    /// bracket a dense sampling's value.
    #[test]
    fn the_farthest_point_inside_a_face_is_bracketed() {
        let corners = [Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0), Vec3::new(1.0, 3.0, 0.0)];
        let big = index(corners.to_vec(), &[[0, 1, 2]]);
        let mut p = Vec::new();
        let mut t = Vec::new();
        for (i, c) in corners.into_iter().enumerate() {
            let k = 3 * i as u32;
            p.extend([c, c + Vec3::new(0.01, 0.0, 0.0), c + Vec3::new(0.0, 0.01, 0.01)]);
            t.push([k, k + 1, k + 2]);
        }
        let small_triangles: Vec<[DVec3; 3]> = t.iter().map(|t| t.map(|i| p[i as usize].as_dvec3())).collect();
        let small = index(p, &t);
        let h = directed_hausdorff(&big, &small, 1e-6).unwrap();
        // Brute force on a barycentric grid of step 1/n: every point of the
        // triangle is within `spacing` of a sample, and d(., small) is
        // 1-Lipschitz, so the true value lies in [sampled, sampled + spacing].
        let n = 400;
        let spacing = 4.0 / n as f64;
        let [a, b, c] = corners.map(|c| c.as_dvec3());
        let mut sampled = 0.0f64;
        for i in 0..=n {
            for j in 0..=n - i {
                let q = a + (b - a) * (i as f64 / n as f64) + (c - a) * (j as f64 / n as f64);
                let d = small_triangles
                    .iter()
                    .map(|s| point_triangle_closest(q, s).0.distance(q))
                    .fold(f64::INFINITY, f64::min);
                sampled = sampled.max(d);
            }
        }
        assert!(h.lower <= h.upper && h.upper - h.lower <= 1e-6, "{h:?}");
        assert!(
            h.upper >= sampled && h.lower <= sampled + spacing,
            "{h:?} against {sampled}"
        );
        // The circumcentre (2, 1) is sqrt(5) from the corners.
        assert!((h.upper - 5f64.sqrt()).abs() < 0.02, "{h:?}");
        assert_eq!(h.unsettled, 0);
        assert!(h.pieces > 10, "{h:?}");
    }

    #[test]
    fn tolerance_is_checked() {
        let t = index(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]);
        for bad in [0.0, -1.0, f64::NAN, 1e-9] {
            assert!(
                matches!(hausdorff(&t, &t, bad), Err(PairError::BadTolerance { .. })),
                "{bad}"
            );
        }
        let h = hausdorff(&t, &t, f64::INFINITY).unwrap();
        assert_eq!((h.lower(), h.upper()), (0.0, 0.0));
    }
}
