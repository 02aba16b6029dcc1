//! Invariant checks.

use super::SphereTree;
use crate::bvh::TreeStats;
use crate::math::Vec3;
use crate::primitive::BoundingPoints;

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
            std::mem::size_of_val(&self.nodes[..])
                + std::mem::size_of_val(&self.primitives[..])
                + 4 * (self.indices.len() + self.sources.len()),
        )
    }

    /// Checks the tree's invariants: every node reachable once; every vertex
    /// of every primitive inside its leaf's sphere and every ancestor's (up
    /// to [`CHECK_ULPS`] ulps of the sphere's largest coordinate, measured in
    /// `f64`); the leaves cover the primitive array exactly once; the recorded
    /// depth is right; `indices` is a permutation. Returns a description of
    /// the first violation.
    pub fn validate(&self) -> Result<(), String> {
        if self.nodes.is_empty() {
            return if self.primitives.is_empty() {
                Ok(())
            } else {
                Err("primitives without nodes".into())
            };
        }
        let mut covered = vec![false; self.primitives.len()];
        let flat = 2 * self.nodes.len();
        let mut seen = vec![false; flat];
        seen[1] = true; // padding
        // Each entry carries its path from the root, so that a leaf checks its
        // vertices against every ancestor's sphere; depth is bounded by MAX_DEPTH.
        let mut stack = vec![(0usize, vec![0usize])];
        let mut max_depth = 0;
        let mut points: Vec<Vec3> = Vec::new();
        while let Some((i, path)) = stack.pop() {
            if i >= flat {
                return Err(format!("node {i} past the end"));
            }
            if std::mem::replace(&mut seen[i], true) {
                return Err(format!("node {i} reached twice"));
            }
            max_depth = max_depth.max(path.len() as u32 - 1);
            let n = self.node(i);
            if !(n.center.is_finite() && n.radius.is_finite() && n.radius >= 0.0) {
                return Err(format!("node {i} has a bad sphere {:?}", n.sphere()));
            }
            if !n.is_leaf() {
                if !n.children()[0].is_multiple_of(2) {
                    return Err(format!("node {i} has an odd first child"));
                }
                for c in n.children() {
                    let mut child_path = path.clone();
                    child_path.push(c as usize);
                    stack.push((c as usize, child_path));
                }
                continue;
            }
            for slot in n.primitive_range() {
                let Some(c) = covered.get_mut(slot) else {
                    return Err(format!("leaf {i} past the end"));
                };
                if std::mem::replace(c, true) {
                    return Err(format!("primitive slot {slot} in two leaves"));
                }
                points.clear();
                self.primitives[slot].push_bounding_points(&mut points);
                for &ancestor in &path {
                    let s = self.node(ancestor).sphere();
                    let slack = (s.center.abs().max_element() + s.radius) * CHECK_ULPS * f32::EPSILON;
                    let loose = crate::sphere::Sphere::new(s.center, s.radius + slack);
                    if let Some(v) = points.iter().find(|&&v| !loose.contains_point(v)) {
                        return Err(format!(
                            "vertex {v} of primitive slot {slot} outside the sphere of node {ancestor} ({s:?})"
                        ));
                    }
                }
            }
        }
        if let Some(slot) = covered.iter().position(|c| !c) {
            return Err(format!("primitive slot {slot} in no leaf"));
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return Err(format!("node {i} unreachable"));
        }
        if max_depth != self.depth {
            return Err(format!("depth is {max_depth}, recorded {}", self.depth));
        }
        let mut perm = self.indices.clone();
        perm.sort_unstable();
        if perm.iter().enumerate().any(|(i, &v)| v as usize != i) {
            return Err("indices are not a permutation".into());
        }
        Ok(())
    }
}
