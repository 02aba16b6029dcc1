//! View frustums: the set of points an OpenGL view-projection matrix keeps.
//!
//! A point `p` is inside when its clip coordinates `(x, y, z, w) = M·(p, 1)`
//! satisfy `-w <= x, y, z <= w`. Each of these six inequalities is a closed
//! half-space `a·x + b·y + c·z + d >= 0` whose coefficients are a sum or
//! difference of two rows of `M` (Gribb & Hartmann, *Fast extraction of
//! viewing frustum planes from the world-view-projection matrix*, 2001).
//!
//! # Precision policy
//!
//! Everything is evaluated in `f64` from the `f32` matrix and coordinates:
//!
//! - Side decisions (is a point inside a plane?) use the *unnormalized* rows
//!   sums, `((a·x + b·y) + c·z) + d` in that order. A sum of two `f32` rows
//!   is exact in `f64` and so are the products, so only the three additions
//!   round; a vertex exactly on a plane of a simple matrix evaluates to 0
//!   and counts as inside (closed sets, touching counts).
//! - That evaluation is monotone in each coordinate, so a box whose farthest
//!   corner along a plane's normal is outside holds no point that is inside,
//!   and a box whose nearest corner is inside holds no point that is outside.
//!   The tree's culling ([`Frustum::classify_box`]) relies on exactly this:
//!   it never rejects a primitive the exact test would accept, nor accepts
//!   one it would reject, so tree answers equal brute force bit for bit.
//! - Segments and triangles first go through the same six side tests (all
//!   vertices outside one plane: no overlap; all inside every plane:
//!   overlap); only those straddling a plane take the separating axis test
//!   against the frustum's eight corners, which are the clip-cube corners
//!   mapped back by the inverse matrix computed in `f64`. Their rounding is
//!   about 1e-16 relative, far below `f32` resolution.
//! - Sphere culling uses the normalized planes with a relative margin of
//!   1e-12, so it too only rejects what is certainly outside.

mod cull;
mod error;
mod look_at;
mod overlap;

pub use cull::{Cull, PlaneMask};
pub use error::FrustumError;
pub use overlap::FrustumOverlap;

use crate::math::{DMat4, DVec4, Mat4, Vec3};

/// Names of the six planes, in the order [`Frustum::planes`] gives them.
pub const PLANE_NAMES: [&str; 6] = ["left", "right", "bottom", "top", "near", "far"];

/// A convex view volume bounded by six planes, built from a view-projection
/// matrix (OpenGL convention: column-major, clip space `-w..w` on all three
/// axes).
///
/// ```
/// use proxima::frustum::Frustum;
/// use proxima::Vec3;
/// let f = Frustum::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 60.0, 1.0, 1.0, 10.0).unwrap();
/// assert!(f.contains_point(Vec3::ZERO));
/// assert!(!f.contains_point(Vec3::new(0.0, 0.0, 6.0))); // behind the eye
/// assert!(!f.contains_point(Vec3::new(0.0, 0.0, -5.5))); // beyond the far plane
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Frustum {
    matrix: Mat4,
    /// Unnormalized planes `[a, b, c, d]`: inside where `a x + b y + c z + d >= 0`.
    raw: [[f64; 4]; 6],
    /// The same planes scaled to a unit normal (signed distances).
    planes: [[f64; 4]; 6],
    /// Clip-cube corners mapped back to world space: bit 0 of the index
    /// picks right (x = +w), bit 1 top, bit 2 far.
    corners: [[f64; 3]; 8],
    /// Directions of the twelve edges joining the corners.
    edges: [[f64; 3]; 12],
}

impl Frustum {
    /// The frustum of a view-projection matrix `m` (projection × view, as
    /// [`camera`](crate::math::camera) builds it: `perspective(..) * look_at_mat4(..)`;
    /// orthographic matrices work too).
    ///
    /// Fails on a matrix with a non-finite entry, a singular matrix, a plane
    /// with a zero normal, or a matrix that keeps no bounded volume (a clip
    /// corner at infinity or behind the eye, as with an infinite far plane).
    pub fn from_view_projection(m: Mat4) -> Result<Frustum, FrustumError> {
        if !m.is_finite() {
            return Err(FrustumError::NonFinite);
        }
        let md = m.as_dmat4();
        let rows: [DVec4; 4] = std::array::from_fn(|i| md.row(i));
        // A scale-free singularity test: |det| against the product of the row lengths.
        let det = md.determinant();
        let scale: f64 = rows.iter().map(|r| r.length()).product();
        if det.is_nan() || det.abs() <= 1e-14 * scale {
            return Err(FrustumError::Singular);
        }
        let [r0, r1, r2, r3] = rows;
        let raw_rows = [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2];
        let mut raw = [[0.0; 4]; 6];
        let mut planes = [[0.0; 4]; 6];
        for (i, row) in raw_rows.iter().enumerate() {
            let normal_length = row.truncate().length();
            if normal_length.is_nan() || normal_length <= 1e-12 * (r3.length() + rows[i / 2].length()) {
                return Err(FrustumError::ZeroNormal { plane: PLANE_NAMES[i] });
            }
            raw[i] = row.to_array();
            planes[i] = (*row / normal_length).to_array();
        }
        let corners = clip_corners(&md.inverse())?;
        let mut edges = [[0.0; 3]; 12];
        let mut e = 0;
        for i in 0..8 {
            for bit in [1, 2, 4] {
                if i & bit == 0 {
                    let (a, b) = (corners[i], corners[i | bit]);
                    edges[e] = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                    e += 1;
                }
            }
        }
        Ok(Frustum {
            matrix: m,
            raw,
            planes,
            corners,
            edges,
        })
    }

    /// The frustum of a perspective camera at `eye` looking at `target`:
    /// `perspective(fov_y, aspect, near, far) * look_at_mat4(eye, target, up)` (the
    /// glam functions re-exported in [`camera`](crate::math::camera), formerly `Mat4::perspective_rh_gl`
    /// and `Mat4::look_at_rh`), evaluated in `f64` and rounded to `f32` once,
    /// so that an eye far from its target (`1e30`) or a tiny `up`
    /// (`1e-45`) is not lost to `f32` overflow or underflow on the way.
    ///
    /// `fov_y_degrees` must lie in (0, 180), `aspect` be positive, `0 < near <
    /// far`, all finite; `eye` must differ from `target` and `up` must be
    /// neither zero nor parallel to the view direction
    /// ([`FrustumError::View`]). A matrix entry beyond `f32` is
    /// [`FrustumError::Overflow`]; a matrix that no longer bounds the
    /// frustum once rounded to `f32` is [`FrustumError::Projection`] (a
    /// `far / near` beyond `f32`'s depth resolution, about 2^24) or
    /// [`FrustumError::EyeTooFar`] (an eye far from the origin compared with
    /// `near`).
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_degrees: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Result<Frustum, FrustumError> {
        if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
            return Err(FrustumError::FieldOfView { degrees: fov_y_degrees });
        }
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(FrustumError::Aspect { aspect });
        }
        if !(near.is_finite() && near > 0.0) {
            return Err(FrustumError::Near { near });
        }
        if !(far.is_finite() && far > near) {
            return Err(FrustumError::Far { near, far });
        }
        look_at::Camera {
            eye,
            target,
            up,
            fov_y_degrees,
            aspect,
            near,
            far,
        }
        .frustum()
    }

    /// The matrix this frustum was built from.
    pub fn matrix(&self) -> Mat4 {
        self.matrix
    }

    /// The six planes `[a, b, c, d]` (left, right, bottom, top, near, far;
    /// see [`PLANE_NAMES`]) with unit normals pointing inside: `a x + b y + c
    /// z + d` is the signed distance to the plane, positive inside.
    pub fn planes(&self) -> &[[f64; 4]; 6] {
        &self.planes
    }

    /// The eight corners (bit 0 of the index picks right, bit 1 top, bit 2 far).
    pub fn corners(&self) -> &[[f64; 3]; 8] {
        &self.corners
    }

    /// `true` when `p` is inside all six closed half-spaces.
    #[inline]
    pub fn contains_point(&self, p: Vec3) -> bool {
        let p = to64(p);
        self.raw.iter().all(|plane| side(plane, p) >= 0.0)
    }

    /// The unnormalized planes used for every side decision.
    #[inline]
    pub(crate) fn raw_planes(&self) -> &[[f64; 4]; 6] {
        &self.raw
    }

    #[inline]
    pub(crate) fn edges(&self) -> &[[f64; 3]; 12] {
        &self.edges
    }
}

/// The eight clip-cube corners `(±1, ±1, ±1)` mapped back by `inverse`.
fn clip_corners(inverse: &DMat4) -> Result<[[f64; 3]; 8], FrustumError> {
    let mut corners = [[0.0; 3]; 8];
    for (i, corner) in corners.iter_mut().enumerate() {
        let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
        let h = *inverse * DVec4::new(sign(1), sign(2), sign(4), 1.0);
        // The corner lies in front of the eye only when w > 0; w = 0 is a
        // point at infinity (an infinite far plane).
        let scale = h.truncate().abs().max_element();
        if !h.is_finite() || h.w <= 1e-12 * scale {
            return Err(FrustumError::NoVolume);
        }
        *corner = (h.truncate() / h.w).to_array();
    }
    Ok(corners)
}

/// `((a x + b y) + c z) + d`, always in this order (see the precision policy).
#[inline(always)]
pub(crate) fn side(plane: &[f64; 4], p: [f64; 3]) -> f64 {
    plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] + plane[3]
}

/// The point in `f64` (exact).
#[inline(always)]
pub(crate) fn to64(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}
