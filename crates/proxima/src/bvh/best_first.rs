//! An experiment kept for comparison: the closest primitive found best-first
//! (nodes expanded in increasing box distance from a priority queue). The
//! depth-first [`NearestQuery::closest`](crate::query::NearestQuery::closest)
//! was measured faster (docs/perf-log.md); built with the `experimental`
//! feature only.

use super::AabbTree;
use crate::math::{Vec3, Vec3A};
use crate::primitive::ClosestPoint;
use crate::query::{Best, ClosestHit, NearestVisitor, SpatialIndex};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

impl<T: ClosestPoint> AabbTree<T> {
    /// The same answer as [`closest`](crate::query::NearestQuery::closest), found best-first: nodes
    /// are expanded in increasing box distance from a priority queue. Kept as
    /// a tested alternative; the depth-first [`closest`](crate::query::NearestQuery::closest) was
    /// measured faster (see docs/perf-log.md). Allocates its queue.
    pub fn closest_best_first(&self, p: Vec3) -> Option<ClosestHit> {
        if !crate::bvh::answerable(p) {
            return None;
        }
        let p = Vec3A::from(p);
        let mut best = Best::new(self.leaves().indices(), f32::INFINITY);
        let mut queue = BinaryHeap::with_capacity(64);
        if let Some(root) = self.root() {
            queue.push(Pending {
                distance_squared: root.distance_squared(p),
                node: 0,
            });
        }
        while let Some(Pending { distance_squared, node }) = queue.pop() {
            if distance_squared > best.bound {
                break;
            }
            let n = self.node(node as usize);
            if n.is_leaf() {
                for slot in n.primitive_range() {
                    NearestVisitor::<T>::visit(&mut best, slot, &self.leaves().primitives()[slot], p);
                }
            } else {
                for child in n.children() {
                    let d = self.node(child as usize).distance_squared(p);
                    if d <= best.bound {
                        queue.push(Pending {
                            distance_squared: d,
                            node: child,
                        });
                    }
                }
            }
        }
        best.found
            .then(|| self.leaves().hit(best.slot, best.point, best.distance_squared))
    }
}

/// A node waiting in the best-first queue; the heap pops the smallest distance.
#[derive(Clone, Copy, PartialEq)]
struct Pending {
    distance_squared: f32,
    node: u32,
}

impl Eq for Pending {}

impl Ord for Pending {
    fn cmp(&self, other: &Self) -> Ordering {
        other.distance_squared.total_cmp(&self.distance_squared)
    }
}

impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
