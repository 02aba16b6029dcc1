//! Refitting a wide tree to moved primitives: the binary tree under it,
//! the triangle packets and the wide nodes' boxes, in place.

use super::convert::cull_slack;
use super::{LEAF, WideNode, WidePrimitive, WideTree};
use crate::aabb::Aabb;
use crate::build::{surface_area_cost, widen};
use crate::error::BuildError;
use crate::primitive::{BoundingPoints, PrimitiveSet, Triangle};
use crate::query::SpatialIndex;
use crate::simd::TrianglePacket;
use rayon::prelude::*;

impl WideNode {
    /// Sets the box of lane `lane`, keeping what the lane holds.
    fn set_bounds(&mut self, lane: usize, b: Aabb) {
        (self.min_x[lane], self.min_y[lane], self.min_z[lane]) = (b.min.x, b.min.y, b.min.z);
        (self.max_x[lane], self.max_y[lane], self.max_z[lane]) = (b.max.x, b.max.y, b.max.z);
    }

    /// The union of the four lanes' boxes (empty lanes add nothing).
    fn union(&self) -> Aabb {
        (0..4).fold(Aabb::EMPTY, |b, lane| b.merge(&self.child_bounds(lane)))
    }

    /// How many primitives lane `lane` holds when it is a non-empty leaf.
    fn leaf_count(&self, lane: usize) -> Option<usize> {
        let count = self.counts[lane];
        (count & LEAF != 0 && count != LEAF).then_some((count & !LEAF) as usize)
    }
}

/// The packet of the same slots as `packet`, made anew from `triangles`
/// (moved), so that its lanes and its marks of the slivers the scalar
/// routine answers are those a build would make.
pub(crate) fn repack(packet: &mut TrianglePacket, triangles: &[Triangle], indices: &[u32]) {
    let first = packet.first as usize;
    let slots = first..first + (packet.fast | packet.slow).count_ones() as usize;
    *packet = TrianglePacket::new(&triangles[slots.clone()], &indices[slots], packet.first);
}

impl<T: BoundingPoints + WidePrimitive + Copy + Send + Sync> WideTree<T> {
    /// Moves the tree's primitives to those of `set` and refits every box
    /// and triangle packet, keeping the tree's shape (see
    /// [`AabbTree::refit`](crate::AabbTree::refit), which it calls, for the
    /// contract and the errors). A leaf lane's box is its primitives' box,
    /// widened as the build widens it; an inner lane's, the union of its
    /// node's lanes. Answers equal a fresh build's over `set`; the speed is
    /// that of the old shape on the new positions
    /// ([`surface_area_cost`](Self::surface_area_cost)).
    ///
    /// ```
    /// use proxima::prelude::*;
    /// let mesh = proxima::mesh::generate::noisy_icosphere(3, 1);
    /// let mut tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    /// let mut moved = mesh.clone();
    /// moved.set_positions(&mesh.positions().iter().map(|p| *p * 3.0).collect::<Vec<_>>()).unwrap();
    /// tree.refit(&moved.triangles()).unwrap();
    /// let fresh = WideTree::build_set(moved.triangles(), &Default::default()).unwrap();
    /// let p = Vec3::new(0.3, 4.0, -1.0);
    /// assert_eq!(tree.closest(p), fresh.closest(p));
    /// ```
    pub fn refit(&mut self, set: &PrimitiveSet<T>) -> Result<(), BuildError> {
        self.tree.refit(set)?;
        self.refit_above_leaves();
        Ok(())
    }

    /// [`refit`](Self::refit) to a set known to be the tree's primitives
    /// moved, each within the coordinates a build takes, unchecked.
    pub(crate) fn refit_trusted(&mut self, set: &PrimitiveSet<T>) {
        self.refit_trusted_by(|input, _| set.primitives[input as usize]);
    }

    /// [`refit_trusted`](Self::refit_trusted) with the primitive of each
    /// build input index and source given by `primitive` (a mesh index's
    /// faces read from its mesh, without extracting them again).
    pub(crate) fn refit_trusted_by(&mut self, primitive: impl Fn(u32, u32) -> T + Sync) {
        self.tree.refit_trusted_by(primitive);
        self.refit_above_leaves();
    }

    /// The packets and wide nodes anew from the refit binary tree's leaves.
    fn refit_above_leaves(&mut self) {
        let (primitives, indices) = (self.tree.primitives(), self.tree.leaves().indices());
        if let Some(triangles) = T::as_triangles(primitives) {
            self.packets
                .as_mut_slice()
                .par_iter_mut()
                .with_min_len(1024)
                .for_each(|packet| repack(packet, triangles, indices));
        }
        let packets = &self.packets[..];
        let nodes = self.nodes.as_mut_slice();
        // Leaf lanes first, in parallel: they read every primitive once,
        // from the packets just made where there are packets (a leaf of
        // `n` triangles has the `ceil(n / 4)` packets from its `children`).
        nodes.par_iter_mut().with_min_len(256).for_each(|node| {
            for lane in 0..4 {
                let Some(n) = node.leaf_count(lane) else { continue };
                let first = node.children[lane] as usize;
                let b = if packets.is_empty() {
                    primitives[first..first + n]
                        .iter()
                        .fold(Aabb::EMPTY, |b, p| b.merge(&p.bounds()))
                } else {
                    packets[first..first + n.div_ceil(4)]
                        .iter()
                        .fold(Aabb::EMPTY, |b, p| b.merge(&p.bounds()))
                };
                node.set_bounds(lane, widen(b));
            }
        });
        // Then inner lanes, children before parents: a node's children come
        // after it in the array.
        for index in (0..nodes.len()).rev() {
            for lane in 0..4 {
                if nodes[index].counts[lane] & LEAF == 0 {
                    let child = nodes[index].children[lane] as usize;
                    let b = nodes[child].union();
                    nodes[index].set_bounds(lane, b);
                }
            }
        }
        self.cull_slack = cull_slack(&self.tree);
    }
}

impl<T> WideTree<T> {
    /// The surface-area cost of the wide nodes' lanes (each inner lane's
    /// box, each leaf lane's times its primitives) over the root box's: it
    /// grows as refits make boxes overlap, and its ratio to the cost at
    /// build is what [`RefitPolicy`](crate::index::RefitPolicy) weighs.
    pub fn surface_area_cost(&self) -> f64 {
        let Some(root) = self.nodes.first() else { return 0.0 };
        let lanes = self.nodes.iter().flat_map(|node| {
            (0..4).filter_map(move |lane| {
                let b = node.child_bounds(lane);
                // A leaf lane's count, without reading its packet.
                if node.counts[lane] & LEAF == 0 {
                    Some((b, None))
                } else {
                    node.leaf_count(lane).map(|n| (b, Some(n)))
                }
            })
        });
        surface_area_cost(root.union(), lanes)
    }
}
