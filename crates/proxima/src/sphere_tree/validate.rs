//! Invariant checks.

use super::SphereTree;
use super::node::SphereNode;
use crate::build::{TreeStats, check_structure};
use crate::math::Vec3;
use crate::primitive::BoundingPoints;
use crate::sphere::Sphere;

/// Slack of the containment checks, in ulps of the sphere's largest
/// coordinate: the rounding of the `f64` distance, not the widening (which is
/// 8 ulps and is what the check must not rely on).
const CHECK_ULPS: f32 = 2.0;

impl<T: BoundingPoints> SphereTree<T> {
    /// Counts nodes, leaves and leaf sizes.
    pub fn stats(&self) -> TreeStats {
        TreeStats::of(
            self.nodes()
                .filter(|(_, n)| n.is_leaf())
                .map(|(_, n)| n.primitive_range().len()),
            self.len(),
            self.node_count(),
            self.depth,
            std::mem::size_of_val(&self.nodes[..]) + self.leaves.memory_bytes(),
        )
    }

    /// Checks the tree's invariants: every node reachable once; every vertex
    /// of every primitive inside its leaf's sphere and every ancestor's (up
    /// to 2 ulps of the sphere's largest coordinate, measured in
    /// `f64`); the leaves cover the primitive array exactly once; the recorded
    /// depth is right; `indices` is a permutation. Returns a description of
    /// the first violation.
    pub fn validate(&self) -> Result<(), String> {
        let mut points: Vec<Vec3> = Vec::new();
        check_structure::<SphereNode>(
            &self.nodes,
            self.len(),
            self.depth,
            self.leaves.indices(),
            |i, ancestors| {
                let n = self.node(i);
                let s = n.sphere();
                if !(s.center.is_finite() && s.radius.is_finite() && s.radius >= 0.0) {
                    return Err(format!("node {i} has a bad sphere {:?}", n.sphere()));
                }
                if !n.is_leaf() {
                    return Ok(());
                }
                for slot in n.primitive_range() {
                    points.clear();
                    self.leaves.primitives()[slot].push_bounding_points(&mut points);
                    for &node in ancestors.iter().chain([&i]) {
                        let s = self.node(node).sphere();
                        let slack = (s.center.abs().max_element() + s.radius) * CHECK_ULPS * f32::EPSILON;
                        let loose = Sphere::new(s.center, s.radius + slack);
                        if let Some(v) = points.iter().find(|&&v| !loose.contains_point(v)) {
                            return Err(format!(
                                "vertex {v} of primitive slot {slot} outside the sphere of node {node} ({s:?})"
                            ));
                        }
                    }
                }
                Ok(())
            },
        )
    }
}
