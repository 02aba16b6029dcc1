//! Build: the AABB tree's hierarchy, with a tight sphere per node.
//!
//! The split is the AABB tree's (median along the largest extent, or binned
//! SAH; the same [`BuildConfig`]), so both trees have the same nodes and leaf
//! order and differ only in their bounding volumes. Each node's sphere is the
//! smaller of two candidates, both holding every vertex of the node's
//! primitives:
//!
//! - (a) [`Sphere::from_points_tight`] over those vertices (Ritter, then
//!   shrink-and-regrow passes; radius measured exactly from the center); on
//!   nodes of more than 1024 vertices the center comes from an even sample
//!   of 1024 of them, and the radius from all;
//! - (b) the merge of the children's spheres (inner nodes only).
//!
//! (a) wins at nearly every node (figures in docs/perf-log.md); (b) is
//! kept because it costs nothing and can win
//! where two children's spheres nest. (a) costs two passes over the node's
//! vertices (gather, radius) plus a fixed cost, `O(n log n)` in all, and runs
//! in parallel over nodes; (b) is one bottom-up sweep. The chosen sphere is
//! then widened (see [`SphereTree`]).

use super::SphereTree;
use super::node::SphereNode;
use crate::aabb_tree::AabbTree;
use crate::build::BuildConfig;
use crate::build::NodePair;
use crate::error::BuildError;
use crate::math::Vec3;
use crate::primitive::{BoundingPoints, PrimitiveSet};
use crate::sphere::Sphere;
use rayon::prelude::*;
use std::ops::Range;

/// Widens a sphere by 8 ulps of its largest coordinate, like the AABB tree's
/// boxes: computed closest points may lie a few ulps outside their primitive.
#[inline]
fn widen(s: Sphere) -> Sphere {
    let scale = s.center.abs().max_element() + s.radius;
    Sphere::new(s.center, (s.radius + scale * 8.0 * f32::EPSILON).next_up())
}

/// Nodes with more points than this place their center from an even sample
/// of this many (the radius is still measured over all points).
const CENTER_SAMPLE: usize = 1024;

/// Candidate (a): a tight sphere over `points`. Large nodes find the center
/// from a sample, which makes the build two passes over each level instead
/// of seven, and loses little: those spheres are loose anyway, and the merge
/// of the children often beats them.
fn node_sphere(points: &[Vec3]) -> Sphere {
    if points.len() <= CENTER_SAMPLE {
        return Sphere::from_points_tight(points).unwrap_or_default();
    }
    let step = points.len() / CENTER_SAMPLE;
    let sample: Vec<Vec3> = points.iter().step_by(step).copied().collect();
    let center = Sphere::from_points_tight(&sample).unwrap_or_default().center;
    Sphere::new(center, Sphere::enclosing_radius(center, points))
}

impl<T: BoundingPoints + Copy + Send + Sync> SphereTree<T> {
    /// Builds a tree over `primitives`; the source of each is its input index.
    /// Fails as [`AabbTree::build`] does.
    pub fn build(primitives: Vec<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        Ok(Self::from_tree(AabbTree::build(primitives, config)?))
    }

    /// Builds a tree over primitives extracted from a mesh, keeping their sources.
    pub fn build_set(set: PrimitiveSet<T>, config: &BuildConfig) -> Result<Self, BuildError> {
        Ok(Self::from_tree(AabbTree::build_set(set, config)?))
    }

    /// Builds a tree over `primitives`, where `sources[i]` is the mesh element
    /// that `primitives[i]` came from.
    pub fn build_with_sources(primitives: Vec<T>, sources: Vec<u32>, config: &BuildConfig) -> Result<Self, BuildError> {
        Ok(Self::from_tree(AabbTree::build_with_sources(
            primitives, sources, config,
        )?))
    }

    /// The sphere tree with the hierarchy and leaf order of `tree`.
    pub fn from_tree(tree: AabbTree<T>) -> Self {
        let flat = if tree.is_empty() { 0 } else { tree.node_count() + 1 };
        // Children come after their parent in the flat array, so a backward
        // sweep sees every child before its parent.
        let mut ranges: Vec<Range<usize>> = vec![0..0; flat];
        for i in (0..flat).rev().filter(|&i| i != 1) {
            let node = tree.node(i);
            ranges[i] = if node.is_leaf() {
                node.primitive_range()
            } else {
                let [left, right] = node.children();
                ranges[left as usize].start..ranges[right as usize].end
            };
        }
        let primitives = tree.primitives();
        let mut spheres: Vec<Sphere> = ranges
            .par_iter()
            .map_init(Vec::new, |points: &mut Vec<Vec3>, range| {
                points.clear();
                for primitive in &primitives[range.clone()] {
                    primitive.push_bounding_points(points);
                }
                node_sphere(points)
            })
            .collect();
        for i in (0..flat).rev().filter(|&i| i != 1) {
            let node = tree.node(i);
            if !node.is_leaf() {
                let [left, right] = node.children();
                let merged = spheres[left as usize].merge(&spheres[right as usize]);
                if merged.radius < spheres[i].radius {
                    spheres[i] = merged;
                }
            }
        }
        let nodes = (0..flat / 2)
            .map(|pair| {
                NodePair::new([2 * pair, 2 * pair + 1].map(|i| {
                    if i == 1 {
                        return SphereNode::empty_leaf();
                    }
                    let node = tree.node(i);
                    let sphere = widen(spheres[i]);
                    if node.is_leaf() {
                        SphereNode::leaf(sphere, ranges[i].start as u32, ranges[i].len() as u32)
                    } else {
                        SphereNode::inner(sphere, node.children()[0])
                    }
                }))
            })
            .collect();
        let depth = tree.depth();
        Self {
            nodes,
            leaves: tree.into_leaves(),
            depth,
        }
    }
}
