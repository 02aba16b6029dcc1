//! The walk of two 4-wide trees at once: every pair of subtrees whose
//! boxes may hold an answer, down to pairs of leaves, whose triangles are
//! placed in the world and handed to a [`PairVisitor`].
//!
//! The boxes of the second tree are moved into the first tree's frame by
//! the relative pose (Arvo's box of a rotated box: centre moved, half sizes
//! by `|R|`), and those of the first into the second's: a node pair costs
//! one box transform per child of either node and, per child of the second,
//! two 4-lane box distances against the first node's four children, the
//! larger of which (both are lower bounds) is the pair's key. A moved box
//! is widened by
//! [`PlacedPair::pad`], far more than the rounding of both placements, so a
//! pair is skipped only when its triangles, placed in the world by
//! [`RigidPose::apply`], certainly lie beyond the visitor's reach: the exact
//! tests at the leaves then see every pair brute force would.
//!
//! One tree against itself, unmoved (self-intersections), has a walk of its
//! own: `self_intersection/overlaps.rs`.

use super::pose::RigidPose;
use super::queue::NearestQueue;
use slab::Slab;

mod slab;
use crate::math::{DMat3, DVec3};
use crate::wide_tree::{OrientedBounds, OrientedBox, WideChild, WideNode};
use crate::{Aabb, Triangle, WideTree};
use std::ops::ControlFlow;
use wide::f64x4;

/// A triangle of one side placed in the world: its corners, their box, and
/// its leaf-order slot in its tree.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlacedTriangle {
    /// The corners, placed by the side's pose.
    pub(crate) corners: [DVec3; 3],
    /// Smallest corner of their box.
    pub(crate) lo: DVec3,
    /// Largest corner of their box.
    pub(crate) hi: DVec3,
    /// The leaf-order slot of the triangle in its tree.
    pub(crate) slot: u32,
}

impl PlacedTriangle {
    const EMPTY: Self = Self {
        corners: [DVec3::ZERO; 3],
        lo: DVec3::ZERO,
        hi: DVec3::ZERO,
        slot: 0,
    };

    /// Squared distance between the boxes of two placed triangles.
    #[inline]
    pub(crate) fn box_distance_squared(&self, other: &Self) -> f64 {
        let gap = (self.lo - other.hi).max(other.lo - self.hi).max(DVec3::ZERO);
        gap.length_squared()
    }
}

/// What a walk does with the pairs of triangles it reaches.
pub(crate) trait PairVisitor {
    /// Pairs of subtrees whose boxes lie farther apart than this (squared
    /// distance, in the world) are skipped; `0` keeps only overlapping ones.
    fn reach_squared(&self) -> f64;

    /// Tests one pair of triangles, `a` from the first tree, `b` from the
    /// second; `Break` ends the walk.
    fn triangles(&mut self, a: &PlacedTriangle, b: &PlacedTriangle) -> ControlFlow<()>;

    /// Whether nearer subtree pairs should be opened first (distance
    /// queries, whose reach shrinks as answers come).
    fn nearest_first(&self) -> bool {
        false
    }

    /// A direction in the world along which pairs may also be bounded
    /// apart (`None`: none). Any direction `u` bounds the distance between
    /// point sets `P` (of the first tree) and `Q`: it is at least
    /// `(min u·q − max u·p) / |u|`, so the walk skips pairs whose gap along
    /// `u` is beyond reach. A distance query offers the line between its
    /// best pair of points: when both surfaces lie behind the planes
    /// through those points (the usual case for meshes apart), every other
    /// pair's gap along it exceeds the best distance, where box distances
    /// barely do.
    fn separating_direction(&self) -> Option<DVec3> {
        None
    }

    /// Told that some pair of triangles lies within `distance` (two points
    /// of the surfaces, placed in the world, are that far apart), before
    /// the walk reaches them: a distance query may narrow its reach to it.
    fn within(&mut self, distance: f64) {
        let _ = distance;
    }
}

/// A subtree of one side: a wide node, or a leaf's slots.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Part {
    Node(u32),
    Leaf { first: u32, len: u32 },
}

/// A box as `[min, max]`, in `f64`.
type Box64 = [DVec3; 2];

/// The lane of a wide node a part hangs from (`node * 4 + lane`), which
/// indexes its [`OrientedBounds`] box; [`NO_LANE`] for a root.
type Lane = u32;

/// The lane of a root: no oriented box.
const NO_LANE: Lane = u32::MAX;

/// A pair of subtrees waiting to be opened, each with its box in its own
/// tree's frame (as the tree stores it), and a lower bound of the squared
/// distance between them.
#[derive(Clone, Copy, Debug)]
struct Pending {
    a: Part,
    a_box: Aabb,
    /// Where `a`'s oriented box is ([`Lane`]).
    a_lane: Lane,
    b: Part,
    b_box: Aabb,
    b_lane: Lane,
    key: f64,
}

/// Two trees of triangles, each placed in the world by a pose.
pub(crate) struct PlacedPair<'t> {
    a: &'t WideTree<Triangle>,
    pose_a: RigidPose,
    b: &'t WideTree<Triangle>,
    pose_b: RigidPose,
    /// The second tree's frame to the first's.
    rotation: DMat3,
    abs_rotation: DMat3,
    translation: DVec3,
    /// The first tree's frame to the second's.
    inverse_rotation: DMat3,
    abs_inverse_rotation: DMat3,
    inverse_translation: DVec3,
    /// How much a moved box is widened (see the module documentation).
    pad: f64,
    /// The relative pose is the identity (then boxes are not moved, only
    /// widened, and placed coordinates equal the first frame's when `pose_a`
    /// is the identity too).
    same_frame: bool,
    /// The oriented boxes of both trees' children, when the caller has them.
    oriented: Option<(&'t OrientedBounds, &'t OrientedBounds)>,
}

impl<'t> PlacedPair<'t> {
    /// The pair of `a` placed by `pose_a` and `b` placed by `pose_b`.
    pub(crate) fn new(
        a: &'t WideTree<Triangle>,
        pose_a: RigidPose,
        b: &'t WideTree<Triangle>,
        pose_b: RigidPose,
    ) -> Self {
        use crate::query::SpatialIndex;
        let relative = pose_b.then(&pose_a.inverse());
        let inverse = relative.inverse();
        let rotation = relative.rotation();
        let magnitude = |bounds: crate::Aabb| f64::from(bounds.min.abs().max(bounds.max.abs()).max_element());
        // Every coordinate handled is at most about this large; rounding
        // errors of the placements and of the moved boxes are ~1e-16 of it.
        let scale = magnitude(a.bounds())
            + magnitude(b.bounds())
            + pose_a.translation().abs().max_element()
            + pose_b.translation().abs().max_element();
        // Bounds are measured in either tree's frame; a rotation that is
        // orthonormal only within its tolerance scales lengths there by up
        // to its deviation, which the padding covers too.
        let deviation = pose_a.deviation() + pose_b.deviation();
        Self {
            a,
            pose_a,
            b,
            pose_b,
            rotation,
            abs_rotation: abs(rotation),
            translation: relative.translation(),
            inverse_rotation: inverse.rotation(),
            abs_inverse_rotation: abs(inverse.rotation()),
            inverse_translation: inverse.translation(),
            pad: scale * (1e-9 + 4.0 * deviation),
            same_frame: relative.is_identity(),
            oriented: None,
        }
    }

    /// The pair, bounding subtrees also by the oriented boxes of both
    /// trees' children (built from `a` and `b` by
    /// [`OrientedBounds::build`]) along a visitor's separating direction.
    pub(crate) fn with_oriented(mut self, a: &'t OrientedBounds, b: &'t OrientedBounds) -> Self {
        self.oriented = Some((a, b));
        self
    }

    /// The first tree.
    pub(crate) fn a(&self) -> &'t WideTree<Triangle> {
        self.a
    }

    /// The second tree.
    pub(crate) fn b(&self) -> &'t WideTree<Triangle> {
        self.b
    }

    /// A box of the second tree moved into the first's frame and widened.
    #[inline]
    fn move_b(&self, b: &Aabb) -> Box64 {
        self.moved(b, &self.rotation, &self.abs_rotation, self.translation)
    }

    /// A box of the first tree moved into the second's frame and widened.
    #[inline]
    fn move_a(&self, a: &Aabb) -> Box64 {
        self.moved(
            a,
            &self.inverse_rotation,
            &self.abs_inverse_rotation,
            self.inverse_translation,
        )
    }

    #[inline]
    fn moved(&self, b: &Aabb, rotation: &DMat3, abs_rotation: &DMat3, translation: DVec3) -> Box64 {
        let (lo, hi) = (DVec3::from(b.min), DVec3::from(b.max));
        let pad = DVec3::splat(self.pad);
        if self.same_frame {
            return [lo - pad, hi + pad];
        }
        let centre = (lo + hi) * 0.5;
        let half = (hi - lo) * 0.5;
        let centre = *rotation * centre + translation;
        let half = *abs_rotation * half + pad;
        [centre - half, centre + half]
    }

    /// The oriented box of lane `lane` of the first tree, if any.
    #[inline]
    fn oriented_a(&self, lane: Lane) -> Option<&'t OrientedBox> {
        let (bounds, _) = self.oriented?;
        (lane != NO_LANE).then(|| bounds.child(lane as usize / 4, lane as usize % 4))
    }

    /// The oriented box of lane `lane` of the second tree moved into the
    /// first tree's frame (a parallelepiped when the rotation is not
    /// exactly orthonormal, which [`OrientedBox::radius_along`] projects
    /// exactly all the same), if any.
    #[inline]
    fn oriented_b(&self, lane: Lane) -> Option<OrientedBox> {
        let (_, bounds) = self.oriented?;
        if lane == NO_LANE {
            return None;
        }
        let b = bounds.child(lane as usize / 4, lane as usize % 4);
        Some(OrientedBox {
            centre: self.rotation * b.centre + self.translation,
            axes: b.axes.map(|axis| self.rotation * axis),
            ..*b
        })
    }

    /// A lower bound of the squared distance between oriented box `a` of
    /// the first tree and `b` of the second (moved by
    /// [`oriented_b`](Self::oriented_b)): the larger gap along either box's
    /// third axis (its triangles' normal), measured in the first tree's
    /// frame, and along the line of their centres (for compact boxes apart,
    /// the best of the three). Stops at the first beyond `reach` (squared).
    #[inline]
    fn oriented_key(&self, a: &OrientedBox, b: &OrientedBox, reach: f64) -> f64 {
        let gap_squared = |u: DVec3| {
            let apart = (b.centre.dot(u) - a.centre.dot(u)).abs();
            let gap = (apart - a.radius_along(u) - b.radius_along(u) - 2.0 * self.pad).max(0.0);
            gap * gap
        };
        let mut key = match (b.centre - a.centre).try_normalize() {
            Some(u) => gap_squared(u),
            None => 0.0,
        };
        for u in [a.axes[2], b.axes[2]] {
            if key > reach {
                break;
            }
            key = key.max(gap_squared(u));
        }
        key
    }

    /// [`oriented_key`](Self::oriented_key) of two lanes (0 when either has
    /// no oriented box).
    #[inline]
    fn lanes_key(&self, a: Lane, b: Lane, reach: f64) -> f64 {
        match (self.oriented_a(a), self.oriented_b(b)) {
            (Some(a), Some(b)) => self.oriented_key(a, &b, reach),
            _ => 0.0,
        }
    }

    /// A lower bound of the squared distance between box `a` of the first
    /// tree and box `b` of the second: the larger of the two gaps measured
    /// in either frame (each box moved into the other's frame grows, so
    /// each alone is a lower bound, and together they are tighter).
    #[inline]
    fn key(&self, a: &Aabb, b: &Aabb) -> f64 {
        let one = distances_squared(&soa(&[own(a)]), &self.move_b(b)).as_array()[0];
        if self.same_frame {
            return one;
        }
        let other = distances_squared(&soa(&[self.move_a(a)]), &own(b)).as_array()[0];
        one.max(other)
    }

    /// Places the triangles of the leaf slots `first..first + len` of
    /// `tree` by `pose` into `out`, returning how many.
    #[inline]
    fn place(
        tree: &WideTree<Triangle>,
        pose: &RigidPose,
        first: u32,
        len: u32,
        out: &mut [PlacedTriangle; 8],
    ) -> usize {
        use crate::query::SpatialIndex;
        let primitives = tree.leaves().primitives();
        // What `apply` does for the identity, decided once per leaf.
        let identity = pose.is_identity();
        let mut n = 0;
        for slot in first..first + len {
            let t = &primitives[slot as usize];
            let corners = if identity {
                [t.a, t.b, t.c].map(|p| p.as_dvec3())
            } else {
                [pose.apply(t.a), pose.apply(t.b), pose.apply(t.c)]
            };
            out[n] = PlacedTriangle {
                corners,
                lo: corners[0].min(corners[1]).min(corners[2]),
                hi: corners[0].max(corners[1]).max(corners[2]),
                slot,
            };
            n += 1;
        }
        n
    }
}

/// The matrix of the absolute values of `m`'s entries.
fn abs(m: DMat3) -> DMat3 {
    DMat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs())
}

/// The root part of a tree and its box (`None` for an empty tree); it has
/// no oriented box ([`NO_LANE`]).
fn root(tree: &WideTree<Triangle>) -> Option<(Part, Aabb)> {
    use crate::query::SpatialIndex;
    if tree.nodes().is_empty() {
        return None;
    }
    Some((Part::Node(0), tree.bounds()))
}

/// A box of a tree in `f64`, in its own frame.
#[inline]
fn own(b: &Aabb) -> Box64 {
    [DVec3::from(b.min), DVec3::from(b.max)]
}

/// The children of wide node `node`: its parts and their boxes (in the
/// tree's own frame), empty lanes left out.
#[inline]
fn children(tree: &WideTree<Triangle>, node: u32) -> ([(Part, Aabb, Lane); 4], usize) {
    let n: &WideNode = &tree.nodes()[node as usize];
    let mut out = [(Part::Node(0), Aabb::default(), NO_LANE); 4];
    let mut count = 0;
    for lane in 0..4 {
        let part = match tree.child(node as usize, lane) {
            WideChild::Empty => continue,
            WideChild::Inner(i) => Part::Node(i as u32),
            WideChild::Leaf(range) => Part::Leaf {
                first: range.start as u32,
                len: range.len() as u32,
            },
        };
        out[count] = (part, n.child_bounds(lane), node * 4 + lane as u32);
        count += 1;
    }
    (out, count)
}

/// Squared distances between the box `b` and the four boxes `a` (given as
/// structure of arrays; unused lanes hold empty boxes, at infinite distance).
#[inline]
fn distances_squared(a: &[f64x4; 6], b: &Box64) -> f64x4 {
    let zero = f64x4::ZERO;
    let axis = |a_lo: f64x4, a_hi: f64x4, b_lo: f64, b_hi: f64| {
        let gap = (f64x4::splat(b_lo) - a_hi).max(a_lo - f64x4::splat(b_hi)).max(zero);
        gap * gap
    };
    axis(a[0], a[3], b[0].x, b[1].x) + axis(a[1], a[4], b[0].y, b[1].y) + axis(a[2], a[5], b[0].z, b[1].z)
}

/// Up to four boxes as structure of arrays, unused lanes empty.
#[inline]
fn soa(boxes: &[Box64]) -> [f64x4; 6] {
    let mut lanes = [
        [f64::INFINITY; 4],
        [f64::INFINITY; 4],
        [f64::INFINITY; 4],
        [f64::NEG_INFINITY; 4],
        [f64::NEG_INFINITY; 4],
        [f64::NEG_INFINITY; 4],
    ];
    for (i, [lo, hi]) in boxes.iter().enumerate() {
        lanes[0][i] = lo.x;
        lanes[1][i] = lo.y;
        lanes[2][i] = lo.z;
        lanes[3][i] = hi.x;
        lanes[4][i] = hi.y;
        lanes[5][i] = hi.z;
    }
    lanes.map(f64x4::new)
}

/// The pending pairs of a walk, kept between walks so that a batch of
/// walks on one thread allocates once.
#[derive(Default)]
pub(crate) struct Scratch {
    stack: Vec<Pending>,
    queue: NearestQueue<Pending>,
}

impl Scratch {
    /// Runs `work` with this thread's scratch, kept between calls so that
    /// single queries repeated on one thread allocate once too (a fresh one
    /// when the thread's is in use, as in a query made from within a walk).
    pub(crate) fn with<R>(work: impl FnOnce(&mut Scratch) -> R) -> R {
        thread_local! {
            static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::default();
        }
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut scratch) => work(&mut scratch),
            Err(_) => work(&mut Scratch::default()),
        })
    }
}

/// One walk over a [`PlacedPair`].
pub(crate) struct Walk<'p, 't, 's> {
    pair: &'p PlacedPair<'t>,
    stack: &'s mut Vec<Pending>,
    queue: &'s mut NearestQueue<Pending>,
    /// The visitor's separating direction, as last asked.
    slab: Option<Slab>,
}

impl<'p, 't, 's> Walk<'p, 't, 's> {
    /// A walk over `pair`'s two trees.
    pub(crate) fn new(pair: &'p PlacedPair<'t>, scratch: &'s mut Scratch) -> Self {
        Self {
            pair,
            stack: &mut scratch.stack,
            queue: &mut scratch.queue,
            slab: None,
        }
    }

    /// The pair of roots, or `None` when either tree is empty.
    fn start(&self) -> Option<Pending> {
        let (a, a_box) = root(self.pair.a)?;
        let (b, b_box) = root(self.pair.b)?;
        Some(Pending {
            a,
            a_box,
            a_lane: NO_LANE,
            b,
            b_box,
            b_lane: NO_LANE,
            key: self.pair.key(&a_box, &b_box),
        })
    }

    /// Splits the walk into at least `tasks` independent pending pairs (fewer
    /// when the trees run out), for threads to take one each; all of them
    /// together meet the same triangle pairs as [`run`](Self::run).
    pub(crate) fn split<V: PairVisitor>(&mut self, tasks: usize, visitor: &mut V) -> Vec<Task> {
        let mut queue: std::collections::VecDeque<Pending> = self.start().into_iter().collect();
        let mut done = Vec::new();
        while queue.len() < tasks {
            let Some(next) = queue.pop_front() else { break };
            if matches!((next.a, next.b), (Part::Leaf { .. }, Part::Leaf { .. })) {
                done.push(next);
                continue;
            }
            self.stack.clear();
            let _ = self.open(next, visitor);
            queue.extend(self.stack.drain(..));
        }
        queue.extend(done);
        queue.into_iter().map(Task).collect()
    }

    /// Walks every pair of subtrees in reach, from the roots.
    pub(crate) fn run<V: PairVisitor>(&mut self, visitor: &mut V) -> ControlFlow<()> {
        match self.start() {
            Some(start) => self.run_from(Task(start), visitor),
            None => ControlFlow::Continue(()),
        }
    }

    /// Walks every pair of subtrees in reach under `task`.
    pub(crate) fn run_from<V: PairVisitor>(&mut self, task: Task, visitor: &mut V) -> ControlFlow<()> {
        self.stack.clear();
        self.stack.push(task.0);
        if visitor.nearest_first() {
            // Best first over the whole walk: the pair with the least box
            // distance is opened next, and the walk ends when even that one
            // is out of reach.
            self.queue.clear();
            for pending in self.stack.drain(..) {
                self.queue.push(pending.key, pending);
            }
            while let Some(next) = self.queue.pop() {
                let reach = visitor.reach_squared();
                if next.key > reach {
                    break;
                }
                // The direction may have changed since the pair was pushed.
                self.refresh(visitor);
                if self.slab.is_some_and(|slab| slab.parts(&next, self.pair) > reach) {
                    continue;
                }
                self.open(next, visitor)?;
                for pending in self.stack.drain(..) {
                    self.queue.push(pending.key, pending);
                }
            }
            return ControlFlow::Continue(());
        }
        while let Some(next) = self.stack.pop() {
            let reach = visitor.reach_squared();
            if next.key > reach {
                continue;
            }
            self.refresh(visitor);
            if self.slab.is_some_and(|slab| slab.parts(&next, self.pair) > reach) {
                continue;
            }
            self.open(next, visitor)?;
        }
        ControlFlow::Continue(())
    }

    /// Takes the visitor's current separating direction.
    #[inline]
    fn refresh<V: PairVisitor>(&mut self, visitor: &V) {
        let given = visitor.separating_direction();
        if given != self.slab.map(|slab| slab.given) {
            self.slab = given.and_then(|given| Slab::new(given, self.pair));
        }
    }

    /// [`PlacedPair::key`] of the pending pair's boxes, raised by the gap
    /// along the separating direction.
    #[inline]
    fn key(&self, pending: &Pending, reach: f64) -> f64 {
        let mut key = self.pair.key(&pending.a_box, &pending.b_box);
        if let Some(slab) = &self.slab {
            key = key.max(slab.parts(pending, self.pair));
        }
        if key > reach {
            return key;
        }
        key.max(self.pair.lanes_key(pending.a_lane, pending.b_lane, reach))
    }

    /// Opens one pending pair: its child pairs in reach go on the stack
    /// (nearest on top when the visitor asks), or, for two leaves, its
    /// triangle pairs go to the visitor.
    fn open<V: PairVisitor>(&mut self, next: Pending, visitor: &mut V) -> ControlFlow<()> {
        let pair = self.pair;
        let reach = visitor.reach_squared();
        match (next.a, next.b) {
            (Part::Leaf { first: fa, len: na }, Part::Leaf { first: fb, len: nb }) => {
                return self.leaves(fa, na, fb, nb, visitor);
            }
            (Part::Node(na), Part::Node(nb)) => {
                let (a_children, a_count) = children(pair.a, na);
                let (b_children, b_count) = children(pair.b, nb);
                let mut a_own = [[DVec3::ZERO; 2]; 4];
                let mut a_moved = [[DVec3::ZERO; 2]; 4];
                for (i, (_, bounds, _)) in a_children[..a_count].iter().enumerate() {
                    a_own[i] = own(bounds);
                    a_moved[i] = pair.move_a(bounds);
                }
                let a_own = soa(&a_own[..a_count]);
                let a_moved = soa(&a_moved[..a_count]);
                if let Some((bounds_a, bounds_b)) = pair.oriented.filter(|_| visitor.nearest_first()) {
                    // Two points of the surfaces bound the answer from above
                    // long before the walk reaches their leaves.
                    let place = |bounds: &OrientedBounds, pose: &RigidPose, lane: Lane| {
                        pose.apply(bounds.child(lane as usize / 4, lane as usize % 4).witness)
                    };
                    let mut b_points = [DVec3::ZERO; 4];
                    for (j, (_, _, lane)) in b_children[..b_count].iter().enumerate() {
                        b_points[j] = place(bounds_b, &pair.pose_b, *lane);
                    }
                    let mut nearest = f64::INFINITY;
                    for (_, _, lane) in &a_children[..a_count] {
                        let p = place(bounds_a, &pair.pose_a, *lane);
                        for q in &b_points[..b_count] {
                            nearest = nearest.min(p.distance_squared(*q));
                        }
                    }
                    visitor.within(nearest.sqrt());
                }
                let reach = visitor.reach_squared();
                let a_high = self.slab.map(|slab| {
                    let mut high = [f64::NEG_INFINITY; 4];
                    for (i, (_, bounds, lane)) in a_children[..a_count].iter().enumerate() {
                        high[i] = slab.a_high(bounds, *lane, pair);
                    }
                    (slab, f64x4::new(high))
                });
                for &(b, b_box, b_lane) in &b_children[..b_count] {
                    let mut keys = distances_squared(&a_own, &pair.move_b(&b_box));
                    if !pair.same_frame {
                        keys = keys.max(distances_squared(&a_moved, &own(&b_box)));
                    }
                    if let Some((slab, a_high)) = a_high {
                        let low = slab.b_low(&b_box, b_lane, pair);
                        let gap = (f64x4::splat(low - slab.pad) - a_high).max(f64x4::ZERO);
                        keys = keys.max(gap * gap);
                    }
                    let in_reach = keys.as_array()[..a_count].iter().any(|&key| key <= reach);
                    if let Some(b_oriented) = pair.oriented_b(b_lane).filter(|_| in_reach) {
                        let mut oriented = [0.0; 4];
                        for (i, (_, _, a_lane)) in a_children[..a_count].iter().enumerate() {
                            if keys.as_array()[i] > reach {
                                continue;
                            }
                            if let Some(a_oriented) = pair.oriented_a(*a_lane) {
                                oriented[i] = pair.oriented_key(a_oriented, &b_oriented, reach);
                            }
                        }
                        keys = keys.max(f64x4::new(oriented));
                    }
                    for (i, &key) in keys.as_array()[..a_count].iter().enumerate() {
                        if key <= reach {
                            let (a, a_box, a_lane) = a_children[i];
                            self.stack.push(Pending {
                                a,
                                a_box,
                                a_lane,
                                b,
                                b_box,
                                b_lane,
                                key,
                            });
                        }
                    }
                }
            }
            (Part::Node(na), Part::Leaf { .. }) => {
                let (a_children, a_count) = children(pair.a, na);
                for &(a, a_box, a_lane) in &a_children[..a_count] {
                    let mut child = Pending {
                        a,
                        a_box,
                        a_lane,
                        ..next
                    };
                    child.key = self.key(&child, reach);
                    if child.key <= reach {
                        self.stack.push(child);
                    }
                }
            }
            (Part::Leaf { .. }, Part::Node(nb)) => {
                let (b_children, b_count) = children(pair.b, nb);
                for &(b, b_box, b_lane) in &b_children[..b_count] {
                    let mut child = Pending {
                        b,
                        b_box,
                        b_lane,
                        ..next
                    };
                    child.key = self.key(&child, reach);
                    if child.key <= reach {
                        self.stack.push(child);
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// The triangle pairs of two leaves, each pair whose boxes are in reach.
    fn leaves<V: PairVisitor>(&mut self, fa: u32, na: u32, fb: u32, nb: u32, visitor: &mut V) -> ControlFlow<()> {
        let pair = self.pair;
        let mut a = [PlacedTriangle::EMPTY; 8];
        let mut b = [PlacedTriangle::EMPTY; 8];
        // Leaves hold at most 8 triangles; larger ones (not built by this
        // crate's builders) are taken 8 at a time.
        for a_first in (fa..fa + na).step_by(8) {
            let a_len = (fa + na - a_first).min(8);
            let a_count = PlacedPair::place(pair.a, &pair.pose_a, a_first, a_len, &mut a);
            for b_first in (fb..fb + nb).step_by(8) {
                let b_len = (fb + nb - b_first).min(8);
                let b_count = PlacedPair::place(pair.b, &pair.pose_b, b_first, b_len, &mut b);
                // Each triangle's reach along the separating direction,
                // projected once per direction rather than once per pair.
                let mut projected: Option<DVec3> = None;
                let (mut high, mut low) = ([0.0; 8], [0.0; 8]);
                for (i, ta) in a[..a_count].iter().enumerate() {
                    for (j, tb) in b[..b_count].iter().enumerate() {
                        let reach = visitor.reach_squared();
                        if ta.box_distance_squared(tb) > reach {
                            continue;
                        }
                        // The direction changes as the visitor's answers do.
                        self.refresh(visitor);
                        if let Some(slab) = &self.slab {
                            if projected != Some(slab.world) {
                                projected = Some(slab.world);
                                for (h, t) in high.iter_mut().zip(&a[..a_count]) {
                                    *h = t
                                        .corners
                                        .iter()
                                        .map(|p| slab.world.dot(*p))
                                        .fold(f64::NEG_INFINITY, f64::max);
                                }
                                for (l, t) in low.iter_mut().zip(&b[..b_count]) {
                                    *l = t
                                        .corners
                                        .iter()
                                        .map(|q| slab.world.dot(*q))
                                        .fold(f64::INFINITY, f64::min);
                                }
                            }
                            if slab.gap_squared(high[i], low[j]) > reach {
                                continue;
                            }
                        }
                        visitor.triangles(ta, tb)?;
                    }
                }
            }
        }
        ControlFlow::Continue(())
    }
}

/// A pending pair of subtrees handed to one thread by [`Walk::split`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Task(Pending);
