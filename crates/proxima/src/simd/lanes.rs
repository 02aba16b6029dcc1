//! Handing the lanes of a packet ray test to a query's visitor: the lanes
//! hit in lane order, then the lanes the packet test left to the scalar
//! test. Shared by the 4-wide and 8-wide trees, so that both offer a leaf's
//! hits in the same order.

use super::TrianglePacket;
use crate::primitive::{RayIntersect, TriangleHit, WatertightRay};
use crate::query::RayVisitor;
use std::ops::ControlFlow;

/// Offers `visitor` the hits of `ray` on the triangles of `packet` (in
/// `primitives`, the leaf-order array), lanes the packet test cannot decide
/// going to the scalar test; `Break` when the visitor ends the query.
#[inline(always)]
pub(crate) fn offer_packet<T: RayIntersect, V: RayVisitor<T>>(
    packet: &TrianglePacket,
    primitives: &[T],
    ray: &WatertightRay,
    t_min: f32,
    visitor: &mut V,
) -> ControlFlow<()> {
    let (bits, hits, scalar) = packet.ray_hits(ray, t_min, visitor.t_hi());
    let first = packet.first as usize;
    offer_lanes(
        (bits, &hits, scalar),
        |lane| first + lane,
        primitives,
        ray,
        t_min,
        visitor,
    )
}

/// Offers `visitor` the hits of a packet test (`bits`: lanes hit, with
/// their hits; `scalar`: lanes left to the scalar test), lane `k` standing
/// for the primitive at slot `slot(k)`; `Break` when the visitor ends the query.
#[inline(always)]
pub(crate) fn offer_lanes<T: RayIntersect, V: RayVisitor<T>>(
    (mut bits, hits, mut scalar): (u32, &[TriangleHit], u32),
    slot: impl Fn(usize) -> usize,
    primitives: &[T],
    ray: &WatertightRay,
    t_min: f32,
    visitor: &mut V,
) -> ControlFlow<()> {
    while bits != 0 {
        let lane = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        if visitor.offer(slot(lane), hits[lane]) {
            return ControlFlow::Break(());
        }
    }
    while scalar != 0 {
        let s = slot(scalar.trailing_zeros() as usize);
        scalar &= scalar - 1;
        if visitor.visit(s, &primitives[s], ray, t_min) {
            return ControlFlow::Break(());
        }
    }
    ControlFlow::Continue(())
}
