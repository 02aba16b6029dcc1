//! The one place that names the vector library.
//!
//! Everything else imports its vector types from here, so switching the scalar
//! type or the vector crate is a one-file change. Stored data uses [`Vec3`]
//! (12 bytes, tightly packed); per-query temporaries use [`Vec3A`] (16 bytes,
//! SIMD-friendly).

pub use glam::{DMat4, DVec3, DVec4, Mat4, Vec3, Vec3A, Vec4};

/// The scalar type of every coordinate.
pub type Real = f32;

/// `true` when all three components are finite (neither NaN nor infinite).
#[inline]
pub fn is_finite3(v: Vec3) -> bool {
    v.is_finite()
}

/// OpenGL camera matrices (right-handed, clip space `-w..w`), as the frustum
/// queries read them.
pub mod camera {
    pub use glam::camera::rh::proj::opengl::{frustum, orthographic, perspective};
    pub use glam::camera::rh::view::look_at_mat4;
}
