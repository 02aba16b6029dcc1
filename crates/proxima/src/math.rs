//! The one place that names the vector library (glam).
//!
//! Everything else imports its vector and matrix types from here. Stored data
//! uses [`Vec3`] (12 bytes, tightly packed); per-query temporaries use
//! [`Vec3A`] (16 bytes, SIMD-friendly); `f64` work (exact fallbacks, winding
//! numbers, glTF transforms) uses [`DVec3`], [`DMat3`], [`DMat4`], [`DQuat`].
//!
//! One coupling is not a matter of names: the wide tree's triangle packets
//! (`wide_tree/packet.rs`, `wide_tree/avx2.rs`) repeat [`Vec3A`]'s dot and
//! cross products operation for operation, so that each lane equals the
//! scalar answer bit for bit. Another vector crate must keep that order, or
//! those routines must follow it.

pub use glam::{BVec3A, DMat3, DMat4, DQuat, DVec3, DVec4, Mat4, Vec3, Vec3A, Vec4};

/// OpenGL camera matrices (right-handed, clip space `-w..w`), as the frustum
/// queries read them.
pub mod camera {
    pub use glam::camera::rh::proj::opengl::{frustum, orthographic, perspective};
    pub use glam::camera::rh::view::look_at_mat4;
}
