//! The view-projection matrix of a look-at camera, computed in `f64`.
//!
//! glam's `f32` camera functions square and multiply the camera's vectors in
//! `f32`, where an eye 1e30 from its target overflows the squared length
//! (`1e60`) and an `up` of `(1e-45, 1e-45, 0)` underflows it: either looks
//! like a view direction parallel to `up`. In `f64` neither happens (every
//! `f32` squared, and every product of two, is finite and non-zero there),
//! so a camera is refused as a bad view only for what it is: non-finite, an
//! eye on its target, `up` zero or parallel to the view.
//!
//! The matrix is rounded to `f32` once, at the end. A value beyond `f32`
//! there is named ([`FrustumError::Overflow`]); a matrix that no longer
//! bounds the camera's frustum once rounded is blamed on what lost it: the
//! projection alone ([`FrustumError::Projection`]: a `far / near` beyond
//! `f32`'s depth resolution, extreme fields of view) or the eye's distance
//! from the origin ([`FrustumError::EyeTooFar`]).

use super::Frustum;
use crate::error::FrustumError;
use crate::math::{DMat4, DVec3, DVec4, Vec3};

/// `sin` of the smallest angle between `up` and the view direction: below
/// it, `up` counts as parallel (the side axis would be mostly rounding).
const MIN_SINE: f64 = 1e-6;

/// A look-at camera (its parameters checked by [`Frustum::look_at`]).
pub(crate) struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_degrees: f32,
    pub aspect: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// The frustum of `perspective(fov_y, aspect, near, far) * look_at(eye,
    /// target, up)` in OpenGL's right-handed convention (clip space
    /// `-w..w`): glam's formulas evaluated in `f64`, rounded to `f32` once.
    pub(crate) fn frustum(&self) -> Result<Frustum, FrustumError> {
        let (rotation, translation) = self.view()?;
        let projection = self.projection()?;
        let view = |translation: DVec3| {
            let mut view = rotation;
            view.w_axis = translation.extend(1.0);
            view
        };
        let matrix = rounded(&(projection * view(translation)), "view-projection matrix entry")?;
        Frustum::from_view_projection(matrix).map_err(|error| {
            // The same camera at the origin tells the projection's failure
            // from the eye's: if it holds, the translation is to blame.
            match rounded(&(projection * view(DVec3::ZERO)), "view-projection matrix entry")
                .and_then(Frustum::from_view_projection)
            {
                Ok(_) => FrustumError::EyeTooFar {
                    distance: self.eye.as_dvec3().length(),
                    near: self.near,
                    far: self.far,
                    error: Box::new(error),
                },
                Err(error) => FrustumError::Projection {
                    near: self.near,
                    far: self.far,
                    fov_y_degrees: self.fov_y_degrees,
                    aspect: self.aspect,
                    error: Box::new(error),
                },
            }
        })
    }

    /// The view matrix without its translation, and the translation (the
    /// eye's coordinates along the side, up and backward axes, negated).
    fn view(&self) -> Result<(DMat4, DVec3), FrustumError> {
        let (eye, target, up) = (self.eye, self.target, self.up);
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(FrustumError::View);
        }
        let (eye, target, up) = (eye.as_dvec3(), target.as_dvec3(), up.as_dvec3());
        let forward = (target - eye).try_normalize().ok_or(FrustumError::View)?;
        let up = up.try_normalize().ok_or(FrustumError::View)?;
        let side = forward.cross(up);
        let sine = side.length();
        if sine <= MIN_SINE {
            return Err(FrustumError::View);
        }
        let side = side / sine;
        let true_up = side.cross(forward);
        let rotation = DMat4::from_cols(
            DVec4::new(side.x, true_up.x, -forward.x, 0.0),
            DVec4::new(side.y, true_up.y, -forward.y, 0.0),
            DVec4::new(side.z, true_up.z, -forward.z, 0.0),
            DVec4::W,
        );
        let translation = DVec3::new(-eye.dot(side), -eye.dot(true_up), eye.dot(forward));
        if let Some(&value) = translation.to_array().iter().find(|t| t.abs() > f32::MAX as f64) {
            return Err(FrustumError::Overflow {
                what: "eye distance along a view axis",
                value,
            });
        }
        Ok((rotation, translation))
    }

    /// The perspective projection, its entries checked against `f32`.
    fn projection(&self) -> Result<DMat4, FrustumError> {
        let (near, far) = (self.near as f64, self.far as f64);
        let half = 0.5 * (self.fov_y_degrees as f64).to_radians();
        let vertical = half.cos() / half.sin();
        let horizontal = vertical / self.aspect as f64;
        let depth = -(far + near) / (far - near);
        let depth_offset = -2.0 * far * near / (far - near);
        for (what, value) in [
            ("vertical scale cot(fov / 2)", vertical),
            ("horizontal scale cot(fov / 2) / aspect", horizontal),
            ("depth scale (far + near) / (far - near)", depth),
            ("depth offset 2 far near / (far - near)", depth_offset),
        ] {
            if value.abs() > f32::MAX as f64 {
                return Err(FrustumError::Overflow { what, value });
            }
        }
        Ok(DMat4::from_cols(
            DVec4::new(horizontal, 0.0, 0.0, 0.0),
            DVec4::new(0.0, vertical, 0.0, 0.0),
            DVec4::new(0.0, 0.0, depth, -1.0),
            DVec4::new(0.0, 0.0, depth_offset, 0.0),
        ))
    }
}

/// `matrix` rounded to `f32`, or the first entry beyond it, as `what`.
fn rounded(matrix: &DMat4, what: &'static str) -> Result<crate::math::Mat4, FrustumError> {
    match matrix.to_cols_array().iter().find(|x| x.abs() > f32::MAX as f64) {
        Some(&value) => Err(FrustumError::Overflow { what, value }),
        None => Ok(matrix.as_mat4()),
    }
}
