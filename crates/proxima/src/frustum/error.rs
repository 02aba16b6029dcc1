//! What a view-projection matrix or a look-at camera refuses.

/// A view-projection matrix or camera that bounds no usable view volume.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrustumError {
    /// A matrix entry or camera parameter is NaN or infinite.
    #[error("the view-projection matrix has a non-finite entry")]
    NonFinite,
    /// The matrix cannot be inverted (its rows are linearly dependent).
    #[error("the view-projection matrix is singular")]
    Singular,
    /// A Gribb–Hartmann plane has a zero normal: it bounds nothing.
    #[error("the {plane} plane of the view-projection matrix has a zero normal")]
    ZeroNormal {
        /// Which plane (`left`, `right`, `bottom`, `top`, `near` or `far`).
        plane: &'static str,
    },
    /// Some corner of the clip cube maps to infinity or behind the eye, so the
    /// set the matrix keeps is unbounded or empty.
    #[error("the view-projection matrix bounds no finite volume (a clip-cube corner maps to w <= 0)")]
    NoVolume,
    /// A vertical field of view outside (0, 180) degrees.
    #[error("field of view must be between 0 and 180 degrees (exclusive), got {degrees}")]
    FieldOfView {
        /// The requested angle.
        degrees: f32,
    },
    /// An aspect ratio that is not finite and positive.
    #[error("aspect ratio must be finite and positive, got {aspect}")]
    Aspect {
        /// The requested ratio.
        aspect: f32,
    },
    /// A near distance that is not finite and positive.
    #[error("near distance must be finite and positive, got {near}")]
    Near {
        /// The requested distance.
        near: f32,
    },
    /// A far distance that is not finite or not beyond the near distance.
    #[error("far distance must be finite and greater than near ({near}), got {far}")]
    Far {
        /// The near distance.
        near: f32,
        /// The requested far distance.
        far: f32,
    },
    /// A camera with a non-finite vector, the eye on its target, or `up`
    /// zero or parallel to the view direction.
    #[error("look-at camera needs finite vectors, eye != target, and up not parallel to the view direction")]
    View,
    /// A look-at camera whose view-projection matrix (computed in `f64`) has
    /// a value beyond `f32`.
    #[error("the camera's {what} is {}, beyond f32", short(*value))]
    Overflow {
        /// Which value: the eye's distance along a view axis, a scale or
        /// offset of the projection, or an entry of the product.
        what: &'static str,
        /// The value.
        value: f64,
    },
    /// A look-at camera whose projection alone (the camera moved to the
    /// origin) gives a view-projection matrix that bounds no frustum in
    /// `f32`: a `far / near` beyond `f32`'s depth resolution (about 2^24:
    /// the far plane rounds onto the near one), or an extreme field of view
    /// or distance scale.
    #[error(
        "the projection of near = {}, far = {} (far / near = {}), a field of view of {fov_y_degrees} degrees and \
         aspect {aspect} is beyond an f32 view-projection matrix: {error}",
        short(*near as f64), short(*far as f64), short(*far as f64 / *near as f64)
    )]
    Projection {
        /// The near distance.
        near: f32,
        /// The far distance.
        far: f32,
        /// The vertical field of view.
        fov_y_degrees: f32,
        /// The aspect ratio.
        aspect: f32,
        /// What the projection's matrix failed.
        error: Box<FrustumError>,
    },
    /// A look-at camera whose projection holds at the origin, but whose eye
    /// lies so far from the origin, compared with `near`, that its `f32`
    /// view-projection matrix no longer bounds the frustum (the translation
    /// swamps the near and far planes).
    #[error(
        "the eye lies {} from the origin, too far for an f32 view-projection matrix with near = {} and far = {}: \
         {error}",
        short(*distance), short(*near as f64), short(*far as f64)
    )]
    EyeTooFar {
        /// The eye's distance from the origin.
        distance: f64,
        /// The near distance.
        near: f32,
        /// The far distance.
        far: f32,
        /// What the camera's matrix failed.
        error: Box<FrustumError>,
    },
}

/// `x` as a message shows it: `f32`'s shortest digits (`1e31`, not
/// `9.999999848243207e30`), in exponent form outside `[1e-4, 1e7)`; seven
/// digits beyond `f32`.
fn short(x: f64) -> String {
    let rounded = x as f32;
    if !rounded.is_finite() {
        format!("{x:.6e}")
    } else if rounded == 0.0 || (1e-4..1e7).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}
