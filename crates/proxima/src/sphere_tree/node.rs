//! The 32-byte sphere node.

use crate::build::PairedNode;
use crate::math::{Vec3, Vec3A};
use crate::sphere::Sphere;

/// A node of the flat node array: its bounding sphere, and either two
/// children or a range of primitives. Indexing is the AABB tree's: children
/// sit side by side at `first` and `first + 1` (an even index), in one
/// 64-byte cache line; a leaf owns the primitives `first..first + count` of
/// the tree's leaf-ordered primitive array.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct SphereNode {
    /// Center of the node's sphere.
    pub center: Vec3,
    first: u32,
    /// Radius of the node's sphere, already widened (see
    /// [`SphereTree`](super::SphereTree)).
    pub radius: f32,
    /// Number of primitives; 0 marks an inner node.
    count: u32,
}

// Same size as the AABB tree's node: two per cache line, so that the two
// trees differ only in their bounding volume.
const _: () = assert!(std::mem::size_of::<SphereNode>() == 32);

/// Two sibling nodes in one 64-byte cache line (flat node `i` at
/// `pairs[i / 2][i % 2]`; node 1 is padding).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct SpherePair(pub(crate) [SphereNode; 2]);

const _: () = assert!(std::mem::size_of::<SpherePair>() == 64 && std::mem::align_of::<SpherePair>() == 64);

impl AsRef<[SphereNode; 2]> for SpherePair {
    #[inline(always)]
    fn as_ref(&self) -> &[SphereNode; 2] {
        &self.0
    }
}

/// Keeps `distance_squared` below the computed distance to any point of the
/// sphere: `|p - c|` is computed with a relative error of a few ulps, and this
/// factor takes them off (see [`SphereTree`](super::SphereTree)).
const SHRINK_DISTANCE: f32 = 1.0 - 4.0 * f32::EPSILON;

impl SphereNode {
    pub(crate) const PADDING: SphereNode = SphereNode {
        center: Vec3::ZERO,
        first: 0,
        radius: -1.0,
        count: 0,
    };

    pub(crate) fn new(sphere: Sphere, first: u32, count: u32) -> Self {
        Self {
            center: sphere.center,
            first,
            radius: sphere.radius,
            count,
        }
    }

    /// The node's sphere.
    #[inline]
    pub fn sphere(&self) -> Sphere {
        Sphere::new(self.center, self.radius)
    }

    /// `true` for a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// For a leaf, the range of its primitives in the tree's primitive array.
    #[inline]
    pub fn primitive_range(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }

    /// For an inner node, the indices of its two children.
    #[inline]
    pub fn children(&self) -> [u32; 2] {
        [self.first, self.first + 1]
    }

    /// A lower bound of the squared distance from `p` to the ball (0 inside),
    /// never above the computed distance to any point within it.
    #[inline(always)]
    pub fn distance_squared(&self, p: Vec3A) -> f32 {
        let d = (p - Vec3A::from(self.center)).length() * SHRINK_DISTANCE - self.radius;
        if d > 0.0 { d * d } else { 0.0 }
    }
}

impl PairedNode for SphereNode {
    type Pair = SpherePair;
    #[inline(always)]
    fn is_leaf(&self) -> bool {
        self.count > 0
    }
    #[inline(always)]
    fn primitive_range(&self) -> std::ops::Range<usize> {
        SphereNode::primitive_range(self)
    }
    #[inline(always)]
    fn first_child(&self) -> u32 {
        self.first
    }
    #[inline(always)]
    fn distance_squared(&self, p: Vec3A) -> f32 {
        SphereNode::distance_squared(self, p)
    }
    #[inline(always)]
    fn classify(&self, frustum: &crate::frustum::Frustum, mask: crate::frustum::PlaneMask) -> crate::frustum::Cull {
        frustum.classify_sphere(self.center, self.radius, mask)
    }
}
