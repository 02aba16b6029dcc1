//! Classifying bounding volumes (boxes, spheres) against a frustum, with a
//! mask of the planes still to test so a subtree never retests a plane its
//! parent passed entirely.

use super::{Frustum, side, to64};
use crate::aabb::Aabb;
use crate::math::Vec3;

/// The planes a bounding volume still has to be tested against: bit `i` set
/// means plane `i` (in [`Frustum::planes`] order) is not yet known to hold
/// the whole volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PlaneMask(pub u8);

impl PlaneMask {
    /// Every plane still to test: the mask of a root.
    pub const ALL: PlaneMask = PlaneMask(0b11_1111);
    /// No plane left: the volume is inside the frustum.
    pub const NONE: PlaneMask = PlaneMask(0);

    /// `true` when plane `i` is still to be tested.
    #[inline]
    pub fn contains(self, plane: usize) -> bool {
        self.0 & (1 << plane) != 0
    }

    /// `true` when no plane is left.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}

/// Where a bounding volume lies relative to a frustum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cull {
    /// Entirely outside one plane: nothing inside it can touch the frustum.
    Outside,
    /// Entirely inside every plane: everything inside it is in the frustum.
    Inside,
    /// Neither decided: the planes it straddles, to test its children against.
    /// (A box near a frustum corner can pass all six plane tests and still be
    /// outside; its contents are then tested exactly.)
    Partial(PlaneMask),
}

impl Frustum {
    /// Classifies the closed box `b` against the planes of `mask` (planes
    /// outside the mask are taken as already passed by an enclosing volume).
    ///
    /// Exact with respect to the primitive tests: `Outside` only when every
    /// point of the box evaluates outside some plane, `Inside` only when every
    /// point evaluates inside every plane (see the precision policy in
    /// [`crate::frustum`]). A box with a NaN coordinate is never `Inside`.
    ///
    /// ```
    /// use proxima::frustum::{Cull, Frustum, PlaneMask};
    /// use proxima::{Aabb, Mat4, Vec3};
    /// let f = Frustum::from_view_projection(Mat4::IDENTITY).unwrap(); // the cube [-1, 1]³
    /// let inside = Aabb::new(Vec3::splat(-0.5), Vec3::splat(0.5));
    /// let straddling = Aabb::new(Vec3::splat(0.5), Vec3::splat(1.5));
    /// let outside = Aabb::new(Vec3::splat(1.5), Vec3::splat(2.0));
    /// assert_eq!(f.classify_box(&inside, PlaneMask::ALL), Cull::Inside);
    /// assert_eq!(f.classify_box(&outside, PlaneMask::ALL), Cull::Outside);
    /// // Straddles the right, top and far planes (x, y, z = 1).
    /// assert_eq!(f.classify_box(&straddling, PlaneMask::ALL), Cull::Partial(PlaneMask(0b10_1010)));
    /// ```
    #[inline]
    pub fn classify_box(&self, b: &Aabb, mask: PlaneMask) -> Cull {
        let (lo, hi) = (to64(b.min), to64(b.max));
        let mut straddled = 0u8;
        for (i, plane) in self.raw_planes().iter().enumerate() {
            if !mask.contains(i) {
                continue;
            }
            // The corner farthest along the normal is the most inside one, the
            // opposite corner the most outside one.
            let pick = |k: usize, toward: bool| if (plane[k] >= 0.0) == toward { hi[k] } else { lo[k] };
            let most_inside = [pick(0, true), pick(1, true), pick(2, true)];
            if side(plane, most_inside) < 0.0 {
                return Cull::Outside;
            }
            let most_outside = [pick(0, false), pick(1, false), pick(2, false)];
            let outer = side(plane, most_outside);
            if outer.is_nan() || outer < 0.0 {
                straddled |= 1 << i;
            }
        }
        if straddled == 0 {
            Cull::Inside
        } else {
            Cull::Partial(PlaneMask(straddled))
        }
    }

    /// Classifies the closed ball of `radius` around `center` against the
    /// planes of `mask`, with signed distances to the normalized planes.
    ///
    /// Conservative by a relative margin of 1e-12 (of the terms' magnitude):
    /// `Outside` and `Inside` are certain for every point of the ball under
    /// the primitive tests' own evaluation; a ball within the margin of a
    /// plane stays `Partial`. A NaN center or radius is never `Inside`.
    pub fn classify_sphere(&self, center: Vec3, radius: f32, mask: PlaneMask) -> Cull {
        let c = to64(center);
        let r = radius as f64;
        let mut straddled = 0u8;
        for (i, plane) in self.planes().iter().enumerate() {
            if !mask.contains(i) {
                continue;
            }
            let distance = side(plane, c);
            let margin = 1e-12
                * (plane[0].abs() * (c[0].abs() + r)
                    + plane[1].abs() * (c[1].abs() + r)
                    + plane[2].abs() * (c[2].abs() + r)
                    + plane[3].abs());
            if distance < -r - margin {
                return Cull::Outside;
            }
            if distance.is_nan() || distance < r + margin {
                straddled |= 1 << i;
            }
        }
        if straddled == 0 {
            Cull::Inside
        } else {
            Cull::Partial(PlaneMask(straddled))
        }
    }
}
