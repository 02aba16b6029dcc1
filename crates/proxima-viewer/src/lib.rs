//! # proxima-viewer
//!
//! The interactive viewer of proxima, started by `proxima view [MESH]`: a
//! shaded mesh with a query point and its closest vertex, edge or face
//! (tree and brute-force timings side by side), the k nearest primitives,
//! the occupied cells of a hash grid, a ray with the cells it walks through,
//! the AABB tree's nodes at a chosen depth, the signed distance and winding
//! number at the query point, a slice through the mesh coloured by signed
//! distance, statistics, and (`--animate`) the mesh deformed by a wave with
//! its trees refit every frame.
//!
//! The only crate of the workspace with windowing and GPU dependencies
//! (eframe/egui with the glow backend). The 3D view is drawn in an egui paint
//! callback with raw OpenGL calls.
//!
//! - [`animation`]: the animated demo: the model deformed by a wave, its
//!   trees refit (or rebuilt) every frame, the closest point and a fan of
//!   rays answered on the moved surface;
//! - [`camera`]: the orbit camera, projection to pixels and picking rays;
//! - [`model`]: a loaded mesh with its trees and the closest-point queries;
//! - [`scene`]: draw data (buffers, boxes, overlay lines and markers) and
//!   picking;
//! - [`cells`]: occupied grid cells and the ray walk;
//! - [`frustum_view`]: a second camera's frustum and the primitives its
//!   frustum query selects;
//! - [`spheres`]: the sphere tree's nodes at a depth as great circles;
//! - [`pair_view`]: the model's self-intersections, or a second mesh placed
//!   by a rigid pose (meeting faces, closest points);
//! - [`slice`]: the signed-distance slice (values, colours, zero contour)
//!   and the query point's signed distance;
//! - [`settings`]: what the side panel edits;
//! - [`frame`]: the composition of a frame's draw data;
//! - [`screenshot`]: the scripted mode (one PNG and exit);
//! - `gl` (private): the OpenGL renderer; `app` (private): the eframe app.
//!
//! Everything but `gl` and `app` is plain data and functions, unit-tested
//! without a window.
#![deny(unsafe_code)]
#![deny(missing_docs)]

pub mod animation;
mod app;
pub mod camera;
pub mod cells;
pub mod frame;
pub mod frustum_view;
mod gl;
mod job;
mod memo;
pub mod model;
pub mod pair_view;
pub mod scene;
pub mod screenshot;
pub mod settings;
pub mod slice;
pub mod spheres;

pub use camera::{OrbitCamera, Viewport};
pub use model::{Model, ModelSource};
/// The library's primitive kinds, re-exported for the command line.
pub use proxima::PrimitiveKind;
pub use screenshot::{AnimationReport, ScreenshotOptions, ScreenshotReport};
pub use settings::{Axis, PairMode, Settings};

use eframe::egui;
use proxima::math::Vec3;
use proxima::{Aabb, DVec3, Sign};
use std::path::PathBuf;
use std::sync::Arc;

/// Settings given on the command line, applied when the first model is
/// loaded (the rest comes from [`Settings::for_bounds`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InitialView {
    /// The query point.
    pub query: Option<Vec3>,
    /// Primitive kind (faces when not given).
    pub kind: Option<PrimitiveKind>,
    /// Show the occupied cells of a grid with this cell size.
    pub cells: Option<f32>,
    /// Show a ray from this origin along this direction.
    pub ray: Option<(Vec3, Vec3)>,
    /// Number of cells the ray walks.
    pub ray_steps: Option<u32>,
    /// Show the tree nodes at this depth.
    pub tree_depth: Option<u32>,
    /// Highlight this many nearest primitives.
    pub k: Option<usize>,
    /// Show a second camera's frustum query from this eye to this target.
    pub frustum: Option<(Vec3, Vec3)>,
    /// Vertical field of view of the second camera, in degrees.
    pub frustum_fov: Option<f32>,
    /// Show the signed-distance slice normal to this axis, at this
    /// coordinate (the middle of the model's box when `None`).
    pub slice: Option<(Axis, Option<f32>)>,
    /// How the slice and the query point's signed distance decide the side.
    pub slice_sign: Option<Sign>,
    /// The camera's yaw about +y and pitch, in degrees (yaw 0 looks along
    /// −z, pitch 90 looks straight down); the default view when `None`.
    pub camera: Option<[f32; 2]>,
    /// The "Pairs" mode (off when not given, the second mesh when `second`
    /// is given).
    pub pairs: Option<PairMode>,
    /// The second mesh's file (a copy of the model when `None`); loaded once,
    /// kept when another model is loaded.
    pub second: Option<PathBuf>,
    /// The second mesh's translation and angles in degrees about x, y, z.
    pub pair_pose: Option<(DVec3, DVec3)>,
    /// Start the animated demo (see [`animation`]), the trees brought up to
    /// date each frame in this mode.
    pub animate: Option<animation::UpdateMode>,
}

impl InitialView {
    /// Overrides `settings` (made for a model in `bounds`) with what was given.
    pub fn apply(&self, settings: &mut Settings, bounds: &Aabb) {
        if let Some(q) = self.query {
            settings.query = q;
        }
        if let Some(kind) = self.kind {
            settings.kind = kind;
        }
        if let Some(h) = self.cells {
            settings.show_cells = true;
            settings.cell_size = h;
        }
        if let Some((origin, direction)) = self.ray {
            settings.show_ray = true;
            settings.ray_origin = origin;
            settings.ray_direction = direction;
        }
        if let Some(steps) = self.ray_steps {
            settings.ray_steps = steps;
        }
        if let Some(depth) = self.tree_depth {
            settings.show_nodes = true;
            settings.node_depth = depth;
        }
        if let Some(k) = self.k {
            settings.k = k;
        }
        if let Some((eye, target)) = self.frustum {
            settings.show_frustum = true;
            settings.frustum_eye = eye;
            settings.frustum_target = target;
            // Near close to this eye, far past the target by the default far distance.
            let distance = (target - eye).length();
            settings.frustum_near = (0.05 * distance).max(1e-6);
            settings.frustum_far += distance;
        }
        if let Some(fov) = self.frustum_fov {
            settings.frustum_fov = fov;
        }
        if let Some((axis, position)) = self.slice {
            settings.show_slice = true;
            settings.slice_axis = axis;
            let (lo, hi) = Settings::slice_range(bounds, axis);
            settings.slice_position = position.unwrap_or(0.5 * (lo + hi));
        }
        if let Some(sign) = self.slice_sign {
            settings.slice_sign = sign;
        }
        if self.second.is_some() {
            settings.pair_mode = PairMode::SecondMesh;
        }
        if let Some(mode) = self.pairs {
            settings.pair_mode = mode;
        }
        if let Some((translation, angles)) = self.pair_pose {
            settings.pair_translation = translation;
            settings.pair_angles = angles;
        }
        if let Some(mode) = self.animate {
            settings.animate = true;
            settings.animation_mode = mode;
        }
    }
}

/// How to start the viewer.
#[derive(Debug)]
pub struct ViewerOptions {
    /// The first model.
    pub source: ModelSource,
    /// Settings for the first model.
    pub initial: InitialView,
    /// Scripted mode: render, save a PNG, exit.
    pub screenshot: Option<ScreenshotOptions>,
    /// Inner size of the window in points.
    pub window_size: [f32; 2],
}

impl ViewerOptions {
    /// Interactive viewer of `source` in a 1280×800 window.
    pub fn new(source: ModelSource) -> Self {
        Self {
            source,
            initial: InitialView::default(),
            screenshot: None,
            window_size: [1280.0, 800.0],
        }
    }
}

/// Why the viewer could not run (or the scripted mode failed).
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    /// No X11 display to open a window on.
    #[error(
        "no display to open a window on (DISPLAY is not set); `proxima demo` runs the main job without one, \
         and `xvfb-run -a proxima view MESH --screenshot out.png` renders the viewer to a PNG"
    )]
    NoDisplay,
    /// The window or the OpenGL context could not be created.
    #[error("cannot open the viewer window: {0}")]
    Window(String),
    /// The scripted mode failed (loading, building, drawing or writing).
    #[error("screenshot: {0}")]
    Screenshot(String),
}

/// `true` when an X11 display is named (the viewer is built for X11 only).
pub fn display_available() -> bool {
    std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty())
}

/// Opens the viewer window and runs until it is closed (or, in scripted
/// mode, until the screenshot is written). Must be called on the main thread.
pub fn run(options: ViewerOptions) -> Result<Option<ScreenshotReport>, ViewerError> {
    if !display_available() {
        return Err(ViewerError::NoDisplay);
    }
    let scripted = options.screenshot.is_some();
    let native = eframe::NativeOptions {
        renderer: eframe::Renderer::Glow,
        depth_buffer: 24,
        multisampling: 0,
        viewport: egui::ViewportBuilder::default()
            .with_inner_size(options.window_size)
            .with_title("proxima viewer")
            .with_drag_and_drop(true),
        glow_options: eframe::egui_glow::GlowConfiguration {
            // Frame times in the scripted mode measure the drawing, not the display's refresh.
            vsync: !scripted,
            ..Default::default()
        },
        ..Default::default()
    };
    let outcome: app::Outcome = Arc::new(egui::mutex::Mutex::new(None));
    let slot = outcome.clone();
    eframe::run_native(
        "proxima viewer",
        native,
        Box::new(move |cc| Ok(Box::new(app::ViewerApp::new(cc, options, slot)))),
    )
    .map_err(|e| ViewerError::Window(e.to_string()))?;
    if !scripted {
        return Ok(None);
    }
    match outcome.lock().take() {
        Some(Ok(report)) => Ok(Some(report)),
        Some(Err(e)) => Err(ViewerError::Screenshot(e)),
        None => Err(ViewerError::Screenshot(
            "the window closed before the screenshot was taken".into(),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_initial_view_overrides_only_what_was_given() {
        let mut s = Settings::default();
        let before = s.clone();
        let bounds = Aabb::new(Vec3::ZERO, Vec3::new(2.0, 4.0, 6.0));
        InitialView::default().apply(&mut s, &bounds);
        assert_eq!(s, before);
        let v = InitialView {
            query: Some(Vec3::ONE),
            kind: Some(PrimitiveKind::Edges),
            cells: Some(0.05),
            ray: Some((Vec3::ZERO, Vec3::X)),
            ray_steps: Some(7),
            tree_depth: Some(4),
            k: Some(3),
            frustum: Some((Vec3::new(5.0, 0.0, 0.0), Vec3::ZERO)),
            frustum_fov: Some(40.0),
            slice: Some((Axis::Y, None)),
            slice_sign: Some(Sign::Pseudonormal),
            camera: Some([0.0, 90.0]),
            pairs: Some(PairMode::SelfIntersections),
            second: None,
            pair_pose: Some((DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.0, 90.0, -180.0))),
            animate: Some(animation::UpdateMode::Rebuild),
        };
        v.apply(&mut s, &bounds);
        assert_eq!(s.query, Vec3::ONE);
        assert_eq!(s.kind, PrimitiveKind::Edges);
        assert!(s.show_cells && s.cell_size == 0.05);
        assert!(s.show_ray && s.ray_direction == Vec3::X && s.ray_steps == 7);
        assert!(s.show_nodes && s.node_depth == 4);
        assert_eq!(s.k, 3);
        assert!(s.show_frustum && s.frustum_eye == Vec3::new(5.0, 0.0, 0.0) && s.frustum_fov == 40.0);
        assert!(crate::frustum_view::settings_frustum(&s).is_ok());
        assert!(s.show_slice && s.slice_axis == Axis::Y && s.slice_sign == Sign::Pseudonormal);
        assert!((s.slice_position - 2.0).abs() < 1e-6, "{}", s.slice_position);
        assert_eq!(s.pair_mode, PairMode::SelfIntersections);
        assert_eq!(s.pair_translation, DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(s.pair_angles, DVec3::new(0.0, 90.0, -180.0));
        assert!(s.animate && s.animation_mode == animation::UpdateMode::Rebuild);
        // A second file asks for the second mesh unless a mode is given.
        let second = InitialView {
            second: Some("other.obj".into()),
            ..Default::default()
        };
        second.apply(&mut s, &bounds);
        assert_eq!(s.pair_mode, PairMode::SecondMesh);
        let at = InitialView {
            slice: Some((Axis::X, Some(-0.25))),
            ..Default::default()
        };
        at.apply(&mut s, &bounds);
        assert_eq!((s.slice_axis, s.slice_position), (Axis::X, -0.25));
    }

    #[test]
    fn no_display_is_a_one_line_error() {
        let text = ViewerError::NoDisplay.to_string();
        assert!(!text.contains('\n'));
        assert!(text.contains("proxima demo") && text.contains("--screenshot"));
    }
}
