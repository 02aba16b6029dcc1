//! Signed distance, winding numbers and inside tests on triangle meshes.
//!
//! [`SignedDistanceField`] answers `signed_distance(p)` (the closest query's
//! distance, negative inside and positive outside), `winding_number(p)` and
//! `contains(p)`, one at a time or in batches on all cores, and evaluates
//! dense grids and training samples. The side comes from the generalized
//! winding number by default ([`Sign::WindingNumber`]: right on open,
//! non-manifold and self-crossing meshes), or from angle-weighted
//! pseudonormals ([`Sign::Pseudonormal`]: faster, right on closed oriented
//! surfaces that do not cross themselves). `docs/sdf.md` compares the
//! methods and where each fails.
//!
//! One concept per file: the solid angle of a triangle (`solid_angle.rs`),
//! winding numbers by a tree of dipole expansions (`winding.rs`),
//! pseudonormals (`pseudonormal.rs`), the certificate that decides the
//! winding number's side from the closest query (`certificate.rs`), the field and its batches
//! (`field.rs`), the gradient (`gradient.rs`), grids and samples (`grid.rs`).

mod certificate;
mod error;
mod field;
mod gradient;
mod grid;
mod pseudonormal;
mod solid_angle;
mod winding;

pub use certificate::{CertificateStats, SignCertificate};
pub use error::SdfError;
pub use field::{SdfConfig, Sign, SignedDistance, SignedDistanceField, certificate_pays};
pub use gradient::{ON_SURFACE, SdfGradient, signed_distance_gradient, signed_distance_gradients};
pub use grid::{Samples, SdfGrid};
pub use pseudonormal::{Feature, Pseudonormals};
pub use solid_angle::solid_angle;
pub use winding::{DEFAULT_BETA, REFINE_MARGIN, WindingNumbers, WindingStats, winding_number_exact};
