//! Refitting the ray tree to moved triangles: packets and boxes anew, the
//! shape kept.

use super::{LEAF, PACKET_INDEX, PAIR, RayNode, RayTree, WIDTH};
use crate::aabb::Aabb;
use crate::build::{check_primitives, surface_area_cost, widen};
use crate::error::BuildError;
use crate::primitive::{PrimitiveSet, Triangle};
use crate::simd::TrianglePacket;
use crate::wide_tree::repack;
use rayon::prelude::*;
use std::ops::Range;

impl RayNode {
    /// The indices of lane `lane`'s one or two packets when it is a leaf
    /// (an empty lane, whose box is empty, is none).
    fn leaf_packets(&self, lane: usize) -> Option<Range<usize>> {
        let child = self.children[lane];
        if child & LEAF == 0 || self.bounds[0][lane] > self.bounds[1][lane] {
            return None;
        }
        let first = (child & PACKET_INDEX) as usize;
        Some(first..first + 1 + usize::from(child & PAIR != 0))
    }

    /// The leaf-order slots of lane `lane` when it is a leaf.
    fn leaf_slots(&self, lane: usize, packets: &[TrianglePacket]) -> Option<Range<usize>> {
        let packets = &packets[self.leaf_packets(lane)?];
        let count: u32 = packets.iter().map(|p| (p.fast | p.slow).count_ones()).sum();
        let start = packets[0].first as usize;
        Some(start..start + count as usize)
    }

    fn set_bounds(&mut self, lane: usize, b: Aabb) {
        let (min, max) = (b.min.to_array(), b.max.to_array());
        for axis in 0..3 {
            self.bounds[2 * axis][lane] = min[axis];
            self.bounds[2 * axis + 1][lane] = max[axis];
        }
    }

    fn union(&self) -> Aabb {
        (0..WIDTH).fold(Aabb::EMPTY, |b, lane| b.merge(&self.child_bounds(lane)))
    }
}

impl RayTree {
    /// Moves the tree's triangles to those of `set` (the tree's own,
    /// moved: for a mesh, its new [`triangles`](crate::Mesh::triangles)) and
    /// refits every packet and box, keeping the tree's shape; linear, in
    /// parallel, no allocation. Hits then equal a fresh build's, field for
    /// field; the speed is that of the old shape on the new positions
    /// ([`surface_area_cost`](Self::surface_area_cost)).
    ///
    /// Fails, changing nothing, as [`AabbTree::refit`](crate::AabbTree::refit) does.
    ///
    /// ```
    /// use proxima::prelude::*;
    /// let mut mesh = proxima::mesh::generate::noisy_icosphere(3, 1);
    /// let mut tree = RayTree::build(&mesh).unwrap();
    /// mesh.set_positions(&mesh.positions().iter().map(|p| *p + Vec3::Z).collect::<Vec<_>>()).unwrap();
    /// tree.refit(&mesh.triangles()).unwrap();
    /// let hit = tree.first_hit(Vec3::new(0.01, 0.02, -5.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap();
    /// assert_eq!(hit, RayTree::build(&mesh).unwrap().first_hit(Vec3::new(0.01, 0.02, -5.0), Vec3::Z, 0.0, f32::INFINITY).unwrap().unwrap());
    /// assert!((hit.t - 5.0).abs() < 0.1);
    /// ```
    pub fn refit(&mut self, set: &PrimitiveSet<Triangle>) -> Result<(), BuildError> {
        check_primitives(&set.primitives)?;
        self.leaves.refill(set)?;
        self.refit_above_leaves();
        Ok(())
    }

    /// [`refit`](Self::refit) with the triangle of each build input index
    /// and source given by `triangle` (a mesh's faces read from it, without
    /// extracting them again): the same faces, moved within the
    /// coordinates a build takes, unchecked.
    pub(crate) fn refit_trusted_by(&mut self, triangle: impl Fn(u32, u32) -> Triangle + Sync) {
        self.leaves.refill_by(triangle);
        self.refit_above_leaves();
    }

    fn refit_above_leaves(&mut self) {
        let (triangles, indices) = (self.leaves.primitives(), self.leaves.indices());
        self.packets
            .as_mut_slice()
            .par_iter_mut()
            .with_min_len(1024)
            .for_each(|packet| repack(packet, triangles, indices));
        let packets = &self.packets[..];
        let nodes = self.nodes.as_mut_slice();
        // Leaf lanes from their one or two packets, just made (the same box
        // as their triangles').
        nodes.par_iter_mut().with_min_len(128).for_each(|node| {
            for lane in 0..WIDTH {
                if let Some(leaf) = node.leaf_packets(lane) {
                    let b = packets[leaf].iter().fold(Aabb::EMPTY, |b, p| b.merge(&p.bounds()));
                    node.set_bounds(lane, widen(b));
                }
            }
        });
        // Children come after their parent in the array.
        for index in (0..nodes.len()).rev() {
            for lane in 0..WIDTH {
                let child = nodes[index].children[lane];
                if child & LEAF == 0 {
                    let b = nodes[child as usize].union();
                    nodes[index].set_bounds(lane, b);
                }
            }
        }
        self.bounds = nodes.first().map_or(Aabb::EMPTY, RayNode::union);
    }

    /// The surface-area cost of the nodes' lanes (each inner lane's box,
    /// each leaf lane's times its triangles) over the root box's; see
    /// [`WideTree::surface_area_cost`](crate::WideTree::surface_area_cost).
    pub fn surface_area_cost(&self) -> f64 {
        let Some(root) = self.nodes.first() else { return 0.0 };
        let lanes = self.nodes.iter().flat_map(|node| {
            (0..WIDTH).filter_map(move |lane| {
                let b = node.child_bounds(lane);
                if node.children[lane] & LEAF == 0 {
                    Some((b, None))
                } else {
                    node.leaf_slots(lane, &self.packets).map(|slots| (b, Some(slots.len())))
                }
            })
        });
        surface_area_cost(root.union(), lanes)
    }
}
