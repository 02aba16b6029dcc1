//! [`RigidPose`]: where a mesh stands, as a rotation and a translation in `f64`.
//!
//! A pose maps a point `p` of a mesh to `R p + t`. Its fields are private so
//! that every pose was checked once, on construction, to be rigid: a rotation
//! matrix within [`ROTATION_TOLERANCE`] of orthonormal with a positive
//! determinant, and finite. A scaled, sheared or mirrored matrix would change
//! distances, and a pair query answers in the meshes' own units, so those are
//! refused with a [`PoseError`] that says which.

use crate::math::{DMat3, DQuat, DVec3, Vec3};

/// How far `RᵀR` may be from the identity (largest entry) and a quaternion's
/// norm from 1: enough for matrices written with 7 significant digits or
/// computed in `f32`, far below any scale or shear a user means.
pub const ROTATION_TOLERANCE: f64 = 1e-6;

/// Why a matrix or quaternion is not a rigid pose.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum PoseError {
    /// An entry is NaN or infinite.
    #[error("the pose has an entry that is not a finite number (NaN or infinity)")]
    NotFinite,
    /// The 3x3 part is not orthonormal: `deviation` is the largest entry of
    /// `|RᵀR - I|`, above [`ROTATION_TOLERANCE`] (a scale or a shear).
    #[error(
        "the pose is not a rotation: R^T R differs from the identity by {deviation:.1e} (tolerance {ROTATION_TOLERANCE:.0e}); scaled or sheared matrices are not rigid"
    )]
    NotRotation {
        /// The largest entry of `|RᵀR - I|`.
        deviation: f64,
    },
    /// The 3x3 part is orthonormal but mirrors space (determinant below 0).
    #[error("the pose is a reflection, not a rotation: its 3x3 part has a negative determinant")]
    Reflection,
    /// The last row of a 4x4 matrix is not exactly `[0, 0, 0, 1]` (a
    /// projective matrix, or a transposed one with the translation at the
    /// bottom).
    #[error(
        "the bottom row of a 4x4 pose matrix must be [0, 0, 0, 1], not {row:?} (is the matrix transposed? rows are [R t; 0 0 0 1])"
    )]
    BottomRow {
        /// The bottom row as given.
        row: [f64; 4],
    },
    /// A quaternion whose norm is not within [`ROTATION_TOLERANCE`] of 1.
    #[error("the quaternion is not a unit quaternion: its norm is {norm} (tolerance {ROTATION_TOLERANCE:.0e} from 1)")]
    QuaternionNotUnit {
        /// The norm of the quaternion as given.
        norm: f64,
    },
}

/// A rigid motion `p ↦ R p + t`: a rotation `R` and a translation `t`, in `f64`.
///
/// ```
/// use proxima::pair::RigidPose;
/// use proxima::math::{DVec3, Vec3};
/// // A quarter turn about z, then 1 along x: (1, 0, 0) goes to (1, 1, 0).
/// let h = std::f64::consts::FRAC_1_SQRT_2;
/// let pose = RigidPose::from_quaternion([0.0, 0.0, h, h], [1.0, 0.0, 0.0]).unwrap();
/// assert!((pose.apply(Vec3::X) - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-15);
/// // A matrix that scales is refused.
/// assert!(RigidPose::from_rows([[2.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidPose {
    rotation: DMat3,
    translation: DVec3,
}

impl Default for RigidPose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl RigidPose {
    /// The pose that leaves every point where it is.
    pub const IDENTITY: Self = Self {
        rotation: DMat3::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// A pose from a rotation matrix and a translation. The matrix is kept as
    /// given (not re-orthonormalized, so exact matrices such as quarter turns
    /// stay exact) once it is finite, within [`ROTATION_TOLERANCE`] of
    /// orthonormal and of positive determinant.
    pub fn new(rotation: DMat3, translation: DVec3) -> Result<Self, PoseError> {
        if !rotation.is_finite() || !translation.is_finite() {
            return Err(PoseError::NotFinite);
        }
        let deviation = Self { rotation, translation }.deviation();
        if deviation > ROTATION_TOLERANCE {
            return Err(PoseError::NotRotation { deviation });
        }
        if rotation.determinant() < 0.0 {
            return Err(PoseError::Reflection);
        }
        Ok(Self { rotation, translation })
    }

    /// A pose from the rows of a 4x4 row-major matrix `[R t; 0 0 0 1]`, as
    /// numpy writes it (`m[i][3]` is the translation). The bottom row must be
    /// `[0, 0, 0, 1]` exactly.
    pub fn from_rows(m: [[f64; 4]; 4]) -> Result<Self, PoseError> {
        if m.iter().flatten().any(|x| !x.is_finite()) {
            return Err(PoseError::NotFinite);
        }
        if m[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(PoseError::BottomRow { row: m[3] });
        }
        let column = |j: usize| DVec3::new(m[0][j], m[1][j], m[2][j]);
        Self::new(DMat3::from_cols(column(0), column(1), column(2)), column(3))
    }

    /// A pose from a unit quaternion `[x, y, z, w]` (scalar last) and a
    /// translation. The quaternion's norm must be within
    /// [`ROTATION_TOLERANCE`] of 1; it is then normalized.
    pub fn from_quaternion(q: [f64; 4], translation: [f64; 3]) -> Result<Self, PoseError> {
        if q.iter().chain(&translation).any(|x| !x.is_finite()) {
            return Err(PoseError::NotFinite);
        }
        let quat = DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
        let norm = quat.length();
        if (norm - 1.0).abs() > ROTATION_TOLERANCE {
            return Err(PoseError::QuaternionNotUnit { norm });
        }
        Ok(Self {
            rotation: DMat3::from_quat(quat / norm),
            translation: DVec3::from_array(translation),
        })
    }

    /// A pure translation (rotation exactly the identity).
    pub fn translation_only(t: DVec3) -> Result<Self, PoseError> {
        if !t.is_finite() {
            return Err(PoseError::NotFinite);
        }
        Ok(Self {
            rotation: DMat3::IDENTITY,
            translation: t,
        })
    }

    /// The rotation `R`.
    pub fn rotation(&self) -> DMat3 {
        self.rotation
    }

    /// The translation `t`.
    pub fn translation(&self) -> DVec3 {
        self.translation
    }

    /// The rows of the 4x4 matrix `[R t; 0 0 0 1]` (the inverse of
    /// [`RigidPose::from_rows`], exactly).
    pub fn to_rows(&self) -> [[f64; 4]; 4] {
        let (r, t) = (self.rotation, self.translation);
        let row = |i: usize| [r.col(0)[i], r.col(1)[i], r.col(2)[i], t[i]];
        [row(0), row(1), row(2), [0.0, 0.0, 0.0, 1.0]]
    }

    /// The pose that undoes this one: `Rᵀ`, `-Rᵀ t` (the inverse within the
    /// rotation's tolerance and rounding).
    pub fn inverse(&self) -> Self {
        let rotation = self.rotation.transpose();
        Self {
            rotation,
            translation: -(rotation * self.translation),
        }
    }

    /// This pose followed by `next`: `p ↦ next(self(p))`, that is
    /// `R_next R_self p + (R_next t_self + t_next)`.
    pub fn then(&self, next: &Self) -> Self {
        Self {
            rotation: next.rotation * self.rotation,
            translation: next.rotation * self.translation + next.translation,
        }
    }

    /// Where the `f32` mesh vertex `p` lands, `R p + t`, in `f64`.
    ///
    /// The order of operations is fixed, so that one vertex and one pose give
    /// the same bits wherever a query computes them: coordinate `i` is
    /// `((R[i][0]·x + R[i][1]·y) + R[i][2]·z) + t[i]`, each operation rounded
    /// once (no fused multiply-add). The identity returns `p` exactly (its
    /// `f64` widening, negative zeros included).
    pub fn apply(&self, p: Vec3) -> DVec3 {
        self.apply_f64(p.as_dvec3())
    }

    /// [`RigidPose::apply`] for an `f64` point, in the same order of operations.
    pub fn apply_f64(&self, p: DVec3) -> DVec3 {
        if self.is_identity() {
            // 1·x + 0·y + 0·z + 0 equals x, but turns -0 into +0.
            return p;
        }
        let (r, t) = (self.rotation, self.translation);
        let row = |i: usize| ((r.col(0)[i] * p.x + r.col(1)[i] * p.y) + r.col(2)[i] * p.z) + t[i];
        DVec3::new(row(0), row(1), row(2))
    }

    /// How far the rotation is from orthonormal: the largest entry of
    /// `|RᵀR - I|` (0 for the identity, within [`ROTATION_TOLERANCE`] for
    /// every pose). Lengths measured in the pose's frame differ from those
    /// in the world by at most about this fraction.
    pub fn deviation(&self) -> f64 {
        let gram = self.rotation.transpose() * self.rotation - DMat3::IDENTITY;
        gram.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()))
    }

    /// `true` when the rotation is exactly the identity and the translation
    /// exactly zero.
    pub fn is_identity(&self) -> bool {
        self.rotation == DMat3::IDENTITY && self.translation == DVec3::ZERO
    }
}
