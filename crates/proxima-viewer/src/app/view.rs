//! The 3D view: the frame composed from the state and drawn by the GL
//! renderer in a paint callback, status text over it, and the mouse (orbit,
//! pan, zoom, fit, picking the query point on the surface, ctrl-drag moving
//! the second mesh).

use super::ViewerApp;
use crate::camera::{OrbitCamera, Viewport};
use crate::frame::{FrameInputs, compose_frame};
use crate::pair_view;
use crate::scene::colors;
use crate::settings::PairMode;
use eframe::egui::{self, Color32};
use eframe::egui_glow;
use std::sync::Arc;
use std::time::Duration;

impl ViewerApp {
    pub(super) fn view(&mut self, ui: &mut egui::Ui) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), egui::Sense::click_and_drag());
        self.viewport = Viewport::new([rect.min.x, rect.min.y], [rect.width(), rect.height()]);
        if let Some(model) = &self.model
            && self.needs_fit
            && rect.width() > 1.0
        {
            self.camera = OrbitCamera::default();
            if let Some([yaw, pitch]) = self.camera_angles.take() {
                self.camera.set_angles_degrees(yaw, pitch);
            }
            self.camera.fit_to(&model.bounds, self.viewport.aspect());
            self.needs_fit = false;
        }
        let interactive = self.handle_mouse(ui, &response);
        if interactive {
            // Draw the full picture once the camera rests.
            ui.ctx().request_repaint_after(Duration::from_millis(250));
        }

        let d = &self.derived;
        let mut frame = compose_frame(&FrameInputs {
            camera: &self.camera,
            viewport: self.viewport,
            model: self.model.as_deref(),
            settings: &self.settings,
            result: d.query.latest(),
            grid: self.current_grid().map(|g| g.as_ref()),
            ray: d.ray.latest().and_then(|r| r.as_ref().ok()),
            nodes: d.nodes.latest(),
            spheres: d.spheres.latest().map(|(_, o)| o),
            frustum: d.frustum.latest().and_then(|f| f.as_ref().ok()),
            slice: self.current_slice().map(|s| s.as_ref()),
            query_inside: self.current_readout().and_then(|r| r.inside()),
            pairs: self.current_pairs().map(|p| p.as_ref()),
            animation: self.current_animation(),
        });
        frame.interactive = interactive;
        if let Some(script) = &self.script {
            // Every measured frame is drawn in full, not copied from the last one.
            frame.redraw = true;
            frame.interactive |= script.options.moving;
        }
        if let Some(renderer) = &self.renderer {
            let renderer = renderer.clone();
            let errors = self.gl_error.clone();
            let frame = Arc::new(frame);
            let callback = egui::PaintCallback {
                rect,
                callback: Arc::new(egui_glow::CallbackFn::new(move |info, painter| {
                    let window = painter.intermediate_fbo();
                    if let Err(e) = renderer
                        .lock()
                        .paint(painter.gl(), &frame, &info, window, colors::BACKGROUND)
                    {
                        *errors.lock() = Some(format!("drawing failed: {e}"));
                    }
                })),
            };
            ui.painter().add(callback);
        }

        // Status text over the view.
        let painter = ui.painter_at(rect);
        let mut status = Vec::new();
        if let Some(job) = &self.load {
            let p = job.progress();
            status.push(format!(
                "loading {}: {} ({:.0}%)",
                job.key(),
                p.stage,
                100.0 * p.fraction
            ));
        }
        if self.derived.grid.running() {
            status.push("building the grid…".to_string());
        }
        if self.building_field() {
            status.push("building the signed distance field…".to_string());
        }
        if self.derived.slice.running() {
            status.push("computing the slice…".to_string());
        }
        if self.second.running() {
            status.push("loading the second mesh…".to_string());
        }
        if self.derived.pairs.running() {
            status.push("computing the pairs…".to_string());
        }
        let hovering_files = ui.input(|i| !i.raw.hovered_files.is_empty());
        if hovering_files {
            status.push("drop the file to load it".to_string());
        }
        for (i, text) in status.iter().enumerate() {
            painter.text(
                rect.left_top() + egui::vec2(10.0, 10.0 + 18.0 * i as f32),
                egui::Align2::LEFT_TOP,
                text,
                egui::FontId::proportional(15.0),
                Color32::from_rgb(255, 220, 120),
            );
        }
    }

    /// Camera, picking and the second mesh by mouse; `true` while the
    /// camera is moving.
    fn handle_mouse(&mut self, ui: &egui::Ui, response: &egui::Response) -> bool {
        let (shift, ctrl, scroll) = ui.input(|i| (i.modifiers.shift, i.modifiers.command, i.smooth_scroll_delta.y));
        let delta = response.drag_delta();
        if ctrl && self.settings.pair_mode == PairMode::SecondMesh && response.dragged_by(egui::PointerButton::Primary)
        {
            // Ctrl-drag moves the second mesh in the view plane; the camera stays.
            let t = pair_view::drag_translation(&self.camera, delta.x, delta.y, &self.viewport);
            if t.is_finite() {
                self.settings.pair_translation += t;
            }
            return false;
        }
        let panning = response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
            || (shift && response.dragged_by(egui::PointerButton::Primary));
        if panning {
            self.camera.pan(delta.x, delta.y, &self.viewport);
        } else if response.dragged_by(egui::PointerButton::Primary) {
            self.camera.orbit(delta.x, delta.y);
        }
        if response.hovered() && scroll != 0.0 {
            self.camera.zoom((-scroll * 0.002).exp());
        }
        if response.double_clicked() {
            if let Some(model) = &self.model {
                self.camera.fit_to(&model.bounds, self.viewport.aspect());
            }
        } else if response.clicked()
            && let Some(pos) = response.interact_pointer_pos()
        {
            self.pick_at([pos.x, pos.y]);
        }
        response.dragged() || (response.hovered() && scroll != 0.0)
    }

    fn pick_at(&mut self, pixel: [f32; 2]) {
        let Some(model) = &self.model else {
            return;
        };
        if !model.can_pick() {
            self.derived.pick_message = Some("picking needs faces; this mesh has none".into());
            return;
        }
        let (origin, direction) = self.camera.ray_through(pixel, &self.viewport);
        match model.pick(origin, direction) {
            Some(hit) => {
                let offset = self.settings.pick_offset * model.bounds.diagonal();
                self.settings.query = hit.offset(offset);
                self.derived.pick_message = Some(format!("picked face {}", hit.face));
            }
            None => self.derived.pick_message = Some("missed the surface".into()),
        }
    }
}
