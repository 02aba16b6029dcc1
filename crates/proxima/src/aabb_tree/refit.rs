//! Refitting the tree to moved primitives: the same shape, new boxes.

use super::AabbTree;
use crate::aabb::Aabb;
use crate::build::{check_primitives, refit, surface_area_cost};
use crate::error::BuildError;
use crate::primitive::{BoundingPoints, PrimitiveSet};

impl<T: BoundingPoints + Copy + Send + Sync> AabbTree<T> {
    /// Moves the tree's primitives to those of `set` (the same primitives,
    /// moved: `set` as the tree was built from, in the same input order)
    /// and sets every box anew from the leaves up, keeping the tree's
    /// shape. Linear in the size of the tree, in parallel over the leaves;
    /// no allocation.
    ///
    /// Every query then gives what a fresh build over `set` would: answers
    /// do not depend on the tree's shape, only its speed does (see
    /// [`surface_area_cost`](Self::surface_area_cost)).
    ///
    /// Fails, changing nothing, when `set` is not the tree's primitives
    /// moved ([`BuildError::RefitMismatch`]) or holds a coordinate a build
    /// refuses ([`BuildError::NonFinite`], [`BuildError::CoordinateTooLarge`]).
    ///
    /// ```
    /// use proxima::prelude::*;
    /// let points: Vec<Point> = (0..100).map(|i| Point(Vec3::new(i as f32, 0.0, 0.0))).collect();
    /// let mut tree = AabbTree::build(points.clone(), &Default::default()).unwrap();
    /// let moved: Vec<Point> = points.iter().map(|p| Point(p.0 * -2.0)).collect();
    /// tree.refit(&PrimitiveSet::from_primitives(moved)).unwrap();
    /// assert_eq!(tree.closest(Vec3::new(-84.2, 1.0, 0.0)).unwrap().primitive, 42);
    /// ```
    pub fn refit(&mut self, set: &PrimitiveSet<T>) -> Result<(), BuildError> {
        check_primitives(&set.primitives)?;
        self.leaves.refill(set)?;
        refit(self.nodes.as_mut_slice(), self.leaves.primitives());
        Ok(())
    }

    /// [`refit`](Self::refit) with the primitive of each build input index
    /// and source given by `primitive` ([`Leaves::refill_by`](crate::query::Leaves)):
    /// the tree's primitives moved, each within the coordinates a build
    /// takes (a mesh index's, whose positions it has checked), unchecked.
    pub(crate) fn refit_trusted_by(&mut self, primitive: impl Fn(u32, u32) -> T + Sync) {
        self.leaves.refill_by(primitive);
        refit(self.nodes.as_mut_slice(), self.leaves.primitives());
    }
}

impl<T> AabbTree<T> {
    /// The tree's surface-area cost: the area of every node's box (times
    /// its primitives for a leaf) over the root's. It grows as a refit
    /// makes boxes overlap; compared with the cost at build, it says when
    /// rebuilding pays.
    pub fn surface_area_cost(&self) -> f64 {
        let lanes = self
            .nodes()
            .skip(1)
            .map(|(_, node)| (node.bounds(), node.is_leaf().then(|| node.primitive_range().len())));
        surface_area_cost(self.root().map_or(Aabb::EMPTY, |n| n.bounds()), lanes)
    }
}
