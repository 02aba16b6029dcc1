//! The sphere tree's node: the binary trees' 32-byte node holding a sphere.

use crate::build::{Node, NodeVolume};
use crate::frustum::{Cull, Frustum, PlaneMask};
use crate::math::{Vec3, Vec3A};
use crate::sphere::Sphere;

/// A node of the sphere tree: its bounding sphere (radius already widened,
/// see [`SphereTree`](super::SphereTree)), and either two children or a
/// range of primitives, with the AABB tree's indexing. The node type is
/// the AABB tree's, so that the two trees differ only in their bounding
/// volume.
pub type SphereNode = Node<Sphere>;

/// Keeps `distance_squared` below the computed distance to any point of the
/// sphere: `|p - c|` is computed with a relative error of a few ulps, and this
/// factor takes them off (see [`SphereTree`](super::SphereTree)).
const SHRINK_DISTANCE: f32 = 1.0 - 4.0 * f32::EPSILON;

/// The center, then the radius in the first lane of the second slot.
impl NodeVolume for Sphere {
    /// A negative radius: no point is inside.
    const EMPTY_SLOTS: [Vec3; 2] = [Vec3::ZERO, Vec3::new(-1.0, 0.0, 0.0)];
    #[inline(always)]
    fn from_slots([center, radius]: [Vec3; 2]) -> Self {
        Sphere::new(center, radius.x)
    }
    #[inline(always)]
    fn to_slots(self) -> [Vec3; 2] {
        [self.center, Vec3::new(self.radius, 0.0, 0.0)]
    }
    /// A lower bound of the squared distance from `p` to the ball (0 inside),
    /// never above the computed distance to any point within it.
    #[inline(always)]
    fn distance_squared([center, radius]: [Vec3; 2], p: Vec3A) -> f32 {
        let d = (p - Vec3A::from(center)).length() * SHRINK_DISTANCE - radius.x;
        if d > 0.0 { d * d } else { 0.0 }
    }
    #[inline(always)]
    fn classify([center, radius]: [Vec3; 2], frustum: &Frustum, mask: PlaneMask) -> Cull {
        frustum.classify_sphere(center, radius.x, mask)
    }
}

impl Node<Sphere> {
    /// The node's sphere.
    #[inline]
    pub fn sphere(&self) -> Sphere {
        self.volume()
    }
}
