//! The orbit camera: matrices, projection of world points to pixels, and the
//! picking ray through a pixel. Plain math, no window: the renderer, the
//! picking and the screenshot test all use these same functions.
//!
//! Conventions: right-handed world with +y up; OpenGL clip space (z in
//! [-1, 1]); pixel coordinates with the origin at the top left and y down,
//! in whatever unit the [`Viewport`] is given (egui points in the app,
//! physical pixels in the screenshot test).

use proxima::Aabb;
use proxima::math::{Mat4, Vec3, Vec4};

/// A rectangle of the screen the 3D view is drawn into: top-left corner and
/// size, y down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    /// Left and top edge.
    pub min: [f32; 2],
    /// Width and height (positive).
    pub size: [f32; 2],
}

impl Viewport {
    /// A viewport from its top-left corner and size.
    pub fn new(min: [f32; 2], size: [f32; 2]) -> Self {
        Self { min, size }
    }

    /// Width over height (1 for a degenerate rectangle).
    pub fn aspect(&self) -> f32 {
        if self.size[0] > 0.0 && self.size[1] > 0.0 {
            self.size[0] / self.size[1]
        } else {
            1.0
        }
    }

    /// The same rectangle in units `scale` times smaller (points → pixels
    /// with `scale` = pixels per point).
    pub fn scaled(&self, scale: f32) -> Self {
        Self {
            min: [self.min[0] * scale, self.min[1] * scale],
            size: [self.size[0] * scale, self.size[1] * scale],
        }
    }
}

/// A camera orbiting a target point: it looks at `target` from `distance`
/// away, turned by `yaw` about +y and tilted by `pitch` (radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at and orbited around.
    pub target: Vec3,
    /// Distance from the eye to the target (positive).
    pub distance: f32,
    /// Rotation about +y; 0 looks along −z (the eye on the +z side).
    pub yaw: f32,
    /// Elevation of the eye above the target's horizontal plane.
    pub pitch: f32,
    /// Vertical field of view.
    pub fov_y: f32,
    /// Radius of the scene around the target, for the near and far planes.
    pub scene_radius: f32,
}

/// Pitch stays this far from ±90° so the view never flips over the pole.
const PITCH_LIMIT: f32 = 1.55;
/// Default view direction of [`OrbitCamera::fit`]: a little from the right and above.
const DEFAULT_YAW: f32 = 0.5;
const DEFAULT_PITCH: f32 = 0.3;

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            distance: 3.0,
            yaw: DEFAULT_YAW,
            pitch: DEFAULT_PITCH,
            fov_y: 45f32.to_radians(),
            scene_radius: 1.0,
        }
    }
}

impl OrbitCamera {
    /// The default view of `bounds` in a viewport of the given aspect ratio:
    /// the box's bounding sphere just fits the view.
    pub fn fit(bounds: &Aabb, aspect: f32) -> Self {
        let mut camera = Self::default();
        camera.fit_to(bounds, aspect);
        camera
    }

    /// Keeps the viewing angles and moves the target and distance so that
    /// `bounds` fills the view (an empty or non-finite box gives the unit view).
    pub fn fit_to(&mut self, bounds: &Aabb, aspect: f32) {
        let (center, radius) = if bounds.is_empty() || !bounds.is_finite() {
            (Vec3::ZERO, 1.0)
        } else {
            (bounds.center(), (0.5 * bounds.diagonal()).max(1e-6))
        };
        // The narrower of the two fields of view decides.
        let half_y = 0.5 * self.fov_y;
        let half_x = (half_y.tan() * aspect.max(1e-3)).atan();
        let half = half_y.min(half_x);
        self.target = center;
        self.scene_radius = radius;
        self.distance = radius / half.sin() * 1.05;
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(sy * cp, sp, cy * cp)
    }

    /// World → camera.
    pub fn view(&self) -> Mat4 {
        look_at(self.eye(), self.target, Vec3::Y)
    }

    /// Near and far clipping distances: the scene sphere around the target,
    /// with margin, never a near plane at or behind the eye.
    pub fn clip_range(&self) -> (f32, f32) {
        let r = self.scene_radius.max(1e-6);
        let far = self.distance + 4.0 * r;
        let near = (self.distance - 4.0 * r).max(far * 1e-4).max(1e-6);
        (near, far)
    }

    /// Camera → OpenGL clip space for a viewport of the given aspect ratio.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let (near, far) = self.clip_range();
        perspective_gl(self.fov_y, aspect.max(1e-6), near, far)
    }

    /// World → clip space.
    pub fn view_projection(&self, viewport: &Viewport) -> Mat4 {
        self.projection(viewport.aspect()) * self.view()
    }

    /// Where `p` appears in `viewport` (x right, y down), or `None` when it is
    /// behind the eye. Points outside the view give coordinates outside the
    /// rectangle.
    pub fn project(&self, p: Vec3, viewport: &Viewport) -> Option<[f32; 2]> {
        let clip = self.view_projection(viewport) * Vec4::new(p.x, p.y, p.z, 1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc_x = clip.x / clip.w;
        let ndc_y = clip.y / clip.w;
        Some([
            viewport.min[0] + (0.5 * ndc_x + 0.5) * viewport.size[0],
            viewport.min[1] + (0.5 - 0.5 * ndc_y) * viewport.size[1],
        ])
    }

    /// The ray from the eye through `pixel` of `viewport`: origin and unit
    /// direction.
    pub fn ray_through(&self, pixel: [f32; 2], viewport: &Viewport) -> (Vec3, Vec3) {
        let ndc_x = 2.0 * (pixel[0] - viewport.min[0]) / viewport.size[0].max(1e-6) - 1.0;
        let ndc_y = 1.0 - 2.0 * (pixel[1] - viewport.min[1]) / viewport.size[1].max(1e-6);
        // From the camera's axes rather than by inverting the projection:
        // exact up to rounding, even far from the target.
        let eye = self.eye();
        let (right, up, forward) = self.axes();
        let half = (0.5 * self.fov_y).tan();
        let direction = forward + (ndc_x * half * viewport.aspect()) * right + (ndc_y * half) * up;
        (eye, direction.normalize_or(forward))
    }

    /// The camera's right, up and forward unit vectors in world space.
    pub fn axes(&self) -> (Vec3, Vec3, Vec3) {
        let view = self.view();
        // Rows of the view rotation; the camera looks along its −z.
        let right = Vec3::new(view.x_axis.x, view.y_axis.x, view.z_axis.x);
        let up = Vec3::new(view.x_axis.y, view.y_axis.y, view.z_axis.y);
        let back = Vec3::new(view.x_axis.z, view.y_axis.z, view.z_axis.z);
        (right, up, -back)
    }

    /// Sets the viewing angles in degrees: `yaw` about +y (0 looks along −z)
    /// and `pitch` above the horizon, kept short of ±90° so the view never
    /// flips.
    ///
    /// ```
    /// use proxima_viewer::OrbitCamera;
    /// let mut camera = OrbitCamera::default();
    /// camera.set_angles_degrees(90.0, 100.0);
    /// assert!((camera.yaw - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    /// assert!(camera.pitch < std::f32::consts::FRAC_PI_2);
    /// ```
    pub fn set_angles_degrees(&mut self, yaw: f32, pitch: f32) {
        self.yaw = yaw.to_radians().rem_euclid(std::f32::consts::TAU);
        self.pitch = pitch.to_radians().clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Turns the camera by a mouse drag of `dx, dy` pixels (a drag across a
    /// 400-pixel view turns it by about 180°).
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        const RADIANS_PER_PIXEL: f32 = std::f32::consts::PI / 400.0;
        self.yaw -= dx * RADIANS_PER_PIXEL;
        self.pitch = (self.pitch + dy * RADIANS_PER_PIXEL).clamp(-PITCH_LIMIT, PITCH_LIMIT);
        self.yaw = self.yaw.rem_euclid(std::f32::consts::TAU);
    }

    /// Moves the target with a drag of `dx, dy` pixels so the point under the
    /// mouse at the target's depth follows it.
    pub fn pan(&mut self, dx: f32, dy: f32, viewport: &Viewport) {
        let height = viewport.size[1].max(1.0);
        let world_per_pixel = 2.0 * self.distance * (0.5 * self.fov_y).tan() / height;
        let (right, up, _) = self.axes();
        self.target += (-dx * right + dy * up) * world_per_pixel;
    }

    /// Moves the eye towards the target by `factor` (< 1 zooms in), keeping it
    /// within a sensible range of the scene size.
    pub fn zoom(&mut self, factor: f32) {
        if !factor.is_finite() || factor <= 0.0 {
            return;
        }
        let r = self.scene_radius.max(1e-6);
        self.distance = (self.distance * factor).clamp(1e-3 * r, 100.0 * r);
    }
}

/// The right-handed view matrix of an eye at `eye` looking at `target`
/// (the camera looks along its −z axis, +y up).
fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Mat4 {
    let f = (target - eye).normalize_or(-Vec3::Z);
    let s = f.cross(up).normalize_or(Vec3::X);
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// The OpenGL perspective projection (right-handed eye space, clip z in
/// [−1, 1]).
fn perspective_gl(fov_y: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let f = 1.0 / (0.5 * fov_y).tan();
    Mat4::from_cols(
        Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, (far + near) / (near - far), -1.0),
        Vec4::new(0.0, 0.0, 2.0 * far * near / (near - far), 0.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
    }

    #[test]
    fn fit_centers_the_box_and_shows_all_of_it() {
        let b = Aabb::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(3.0, 3.0, 4.0));
        for aspect in [0.5, 1.0, 1.6, 3.0] {
            let camera = OrbitCamera::fit(&b, aspect);
            let vp = Viewport::new([10.0, 20.0], [400.0 * aspect, 400.0]);
            let c = camera.project(b.center(), &vp).unwrap();
            assert!((c[0] - (10.0 + 200.0 * aspect)).abs() < 1e-2, "{c:?}");
            assert!((c[1] - 220.0).abs() < 1e-2, "{c:?}");
            for corner in b.corners() {
                let p = camera.project(corner, &vp).unwrap();
                assert!(
                    p[0] >= vp.min[0] && p[0] <= vp.min[0] + vp.size[0],
                    "{p:?} aspect {aspect}"
                );
                assert!(
                    p[1] >= vp.min[1] && p[1] <= vp.min[1] + vp.size[1],
                    "{p:?} aspect {aspect}"
                );
            }
            let (near, far) = camera.clip_range();
            let d = (camera.eye() - b.center()).length();
            assert!(near < d - camera.scene_radius && far > d + camera.scene_radius);
        }
    }

    #[test]
    #[allow(deprecated)]
    fn matrices_match_glam() {
        let eye = Vec3::new(1.0, 2.0, 3.0);
        let target = Vec3::new(-0.5, 0.2, 0.1);
        let ours = look_at(eye, target, Vec3::Y);
        let glam = Mat4::look_at_rh(eye, target, Vec3::Y);
        assert!(ours.abs_diff_eq(glam, 1e-6), "{ours} vs {glam}");
        let ours = perspective_gl(0.8, 1.6, 0.01, 50.0);
        let glam = Mat4::perspective_rh_gl(0.8, 1.6, 0.01, 50.0);
        assert!(ours.abs_diff_eq(glam, 1e-6), "{ours} vs {glam}");
    }

    #[test]
    fn fit_of_an_empty_box_is_finite() {
        let camera = OrbitCamera::fit(&Aabb::EMPTY, 1.0);
        assert!(camera.eye().is_finite());
        assert!(
            camera
                .view_projection(&Viewport::new([0.0, 0.0], [0.0, 0.0]))
                .is_finite()
        );
    }

    #[test]
    fn the_picking_ray_passes_through_the_projected_point() {
        let mut camera = OrbitCamera::fit(&unit_box(), 1.5);
        camera.orbit(37.0, -55.0);
        camera.pan(12.0, 7.0, &Viewport::new([0.0, 0.0], [600.0, 400.0]));
        let vp = Viewport::new([100.0, 50.0], [600.0, 400.0]);
        for p in [Vec3::new(0.3, -0.2, 0.7), Vec3::new(-0.9, 0.9, -0.1), Vec3::ZERO] {
            let pixel = camera.project(p, &vp).unwrap();
            let (origin, dir) = camera.ray_through(pixel, &vp);
            assert!((dir.length() - 1.0).abs() < 1e-5);
            // Distance from p to the ray.
            let t = (p - origin).dot(dir);
            let off = (origin + t * dir - p).length();
            assert!(off < 2e-5 * camera.distance, "{p} is {off} from the ray");
            assert!(t > 0.0);
        }
    }

    #[test]
    fn the_center_pixel_looks_at_the_target() {
        let camera = OrbitCamera::fit(&unit_box(), 1.0);
        let vp = Viewport::new([0.0, 0.0], [300.0, 300.0]);
        let (origin, dir) = camera.ray_through([150.0, 150.0], &vp);
        assert!((origin - camera.eye()).length() < 1e-5);
        let expected = (camera.target - camera.eye()).normalize();
        assert!(dir.dot(expected) > 1.0 - 1e-6);
    }

    #[test]
    fn projection_puts_up_up_and_right_right() {
        let camera = OrbitCamera {
            yaw: 0.0,
            pitch: 0.0,
            ..OrbitCamera::fit(&unit_box(), 1.0)
        };
        let vp = Viewport::new([0.0, 0.0], [200.0, 200.0]);
        let up = camera.project(Vec3::new(0.0, 0.5, 0.0), &vp).unwrap();
        let right = camera.project(Vec3::new(0.5, 0.0, 0.0), &vp).unwrap();
        assert!(up[1] < 100.0 && (up[0] - 100.0).abs() < 1e-3);
        assert!(right[0] > 100.0 && (right[1] - 100.0).abs() < 1e-3);
        // Behind the eye: no pixel.
        assert!(
            camera
                .project(camera.eye() + (camera.eye() - camera.target), &vp)
                .is_none()
        );
    }

    #[test]
    fn orbit_keeps_the_distance_and_clamps_the_pitch() {
        let mut camera = OrbitCamera::fit(&unit_box(), 1.0);
        let d = (camera.eye() - camera.target).length();
        camera.orbit(123.0, 10_000.0);
        assert!(camera.pitch <= PITCH_LIMIT);
        assert!(((camera.eye() - camera.target).length() - d).abs() < 1e-4);
        assert!(camera.view().is_finite());
    }

    #[test]
    fn pan_moves_the_target_with_the_mouse() {
        let mut camera = OrbitCamera::fit(&unit_box(), 1.0);
        let vp = Viewport::new([0.0, 0.0], [400.0, 400.0]);
        let target = camera.target;
        let before = camera.project(target, &vp).unwrap();
        camera.pan(30.0, -20.0, &vp);
        // The old target point now sits 30 px right and 20 px up of where it was.
        let after = camera.project(target, &vp).unwrap();
        assert!((after[0] - before[0] - 30.0).abs() < 0.05, "{before:?} {after:?}");
        assert!((after[1] - before[1] + 20.0).abs() < 0.05, "{before:?} {after:?}");
    }

    #[test]
    fn zoom_is_bounded_and_ignores_nonsense() {
        let mut camera = OrbitCamera::fit(&unit_box(), 1.0);
        let d = camera.distance;
        camera.zoom(f32::NAN);
        camera.zoom(-2.0);
        assert_eq!(camera.distance, d);
        camera.zoom(0.5);
        assert!((camera.distance - 0.5 * d).abs() < 1e-5);
        for _ in 0..100 {
            camera.zoom(0.1);
        }
        assert!(camera.distance > 0.0 && camera.clip_range().0 > 0.0);
    }
}
