//! The walk's bounds along one direction: [`PairVisitor::separating_direction`]
//! (a distance query's line of its best pair) applied to boxes, oriented
//! boxes and placed triangles of both trees.

#[cfg(doc)]
use super::PairVisitor;
use super::{Lane, NO_LANE, Pending, PlacedPair, own};
use crate::Aabb;
use crate::math::DVec3;

/// A direction of [`PairVisitor::separating_direction`] made ready for
/// boxes of either tree: a box of the first tree reaches at most
/// `a·centre + |a|·half + a_offset` along it, one of the second at least
/// `b·centre − |b|·half + b_offset`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Slab {
    /// The direction as the visitor gave it.
    pub(super) given: DVec3,
    /// The unit direction in the world.
    pub(super) world: DVec3,
    a: DVec3,
    abs_a: DVec3,
    a_offset: f64,
    b: DVec3,
    abs_b: DVec3,
    b_offset: f64,
    /// Widening of every gap, far beyond the rounding of the projections.
    pub(super) pad: f64,
}

impl Slab {
    /// The slab of `given` for the trees of `pair`, `None` for a zero or
    /// non-finite direction.
    pub(super) fn new(given: DVec3, pair: &PlacedPair) -> Option<Self> {
        let world = given.try_normalize()?;
        // A point p of a tree placed by R, t lies at u·(R p + t) = (Rᵀu)·p + u·t.
        let a = pair.pose_a.rotation().transpose() * world;
        let b = pair.pose_b.rotation().transpose() * world;
        Some(Self {
            given,
            world,
            a,
            abs_a: a.abs(),
            a_offset: world.dot(pair.pose_a.translation()),
            b,
            abs_b: b.abs(),
            b_offset: world.dot(pair.pose_b.translation()),
            pad: 4.0 * pair.pad,
        })
    }

    /// How far a part of the first tree reaches along the direction: the
    /// nearer of its box's reach and its oriented box's (when there is one).
    #[inline]
    pub(super) fn a_high(&self, a: &Aabb, lane: Lane, pair: &PlacedPair) -> f64 {
        let [lo, hi] = own(a);
        let aligned = self.a.dot((lo + hi) * 0.5) + self.abs_a.dot((hi - lo) * 0.5);
        let along = match pair.oriented {
            Some((bounds, _)) if lane != NO_LANE => {
                let o = bounds.child(lane as usize / 4, lane as usize % 4);
                aligned.min(self.a.dot(o.centre) + o.radius_along(self.a))
            }
            _ => aligned,
        };
        along + self.a_offset
    }

    /// Where a part of the second tree begins along the direction.
    #[inline]
    pub(super) fn b_low(&self, b: &Aabb, lane: Lane, pair: &PlacedPair) -> f64 {
        let [lo, hi] = own(b);
        let aligned = self.b.dot((lo + hi) * 0.5) - self.abs_b.dot((hi - lo) * 0.5);
        let along = match pair.oriented {
            Some((_, bounds)) if lane != NO_LANE => {
                let o = bounds.child(lane as usize / 4, lane as usize % 4);
                aligned.max(self.b.dot(o.centre) - o.radius_along(self.b))
            }
            _ => aligned,
        };
        along + self.b_offset
    }

    /// The squared gap along the direction from `a_high` to `b_low`,
    /// narrowed by the padding (0 when they overlap).
    #[inline]
    pub(super) fn gap_squared(&self, a_high: f64, b_low: f64) -> f64 {
        let gap = (b_low - a_high - self.pad).max(0.0);
        gap * gap
    }

    /// The squared gap between two parts along the direction.
    #[inline]
    pub(super) fn parts(&self, pending: &Pending, pair: &PlacedPair) -> f64 {
        self.gap_squared(
            self.a_high(&pending.a_box, pending.a_lane, pair),
            self.b_low(&pending.b_box, pending.b_lane, pair),
        )
    }
}
