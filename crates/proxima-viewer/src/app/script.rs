//! The scripted mode (`--screenshot`): wait for the model and the jobs (grid, slice, pairs),
//! draw a few timed frames, save egui's screenshot and its report, close.

use super::{Outcome, ViewerApp};
use crate::screenshot::{AnimationReport, ScreenshotOptions, ScreenshotReport, save_png, sidecar_path};
use eframe::egui;
use eframe::egui::mutex::Mutex;
use proxima::PrimitiveKind;
use std::sync::Arc;
use std::time::Instant;

/// Where the scripted mode is.
enum ScriptStage {
    /// Waiting for the model and grid.
    Loading,
    /// Rendering frames; the count so far.
    Rendering(u32),
    /// Screenshot requested; waiting for the image.
    Capturing,
    /// Done (window closing).
    Done,
}

/// The scripted mode's state.
pub(super) struct Script {
    pub(super) options: ScreenshotOptions,
    stage: ScriptStage,
    started: Instant,
    image: Arc<Mutex<Option<Arc<egui::ColorImage>>>>,
    outcome: Outcome,
}

impl Script {
    /// Starts the script; its result goes to `outcome`.
    pub(super) fn new(options: ScreenshotOptions, outcome: Outcome) -> Self {
        Self {
            options,
            stage: ScriptStage::Loading,
            started: Instant::now(),
            image: Arc::new(Mutex::new(None)),
            outcome,
        }
    }
}

impl ViewerApp {
    pub(super) fn drive_script(&mut self, ctx: &egui::Context) {
        let ready = !self.busy() && (self.model.is_some() || self.load_error.is_some());
        let gl_error = self.gl_error.lock().clone();
        let cells_drawn = if self.settings.show_cells {
            self.current_grid().map_or(0, |g| g.occupied_count())
        } else {
            0
        };
        // A slice asked for that cannot be made fails the script (the
        // readout alone does not: it is not in the picture's purpose).
        let slice_error = if self.settings.show_slice {
            let field_error = self.field(self.settings.slice_sign).and_then(|f| f.as_ref().err());
            let slice_error = self.derived.slice.memo.latest().and_then(|s| s.as_ref().err());
            field_error.or(slice_error).cloned()
        } else {
            None
        };
        let (slice_cells, slice_inside) = self.current_slice().map_or((0, 0), |s| (s.values.len(), s.inside));
        let pairs_error = self.pairs_error().cloned();
        let (pair_count, pair_faces) = self.current_pairs().map_or((0, [0, 0]), |a| {
            (a.pairs.len(), [a.faces_first.len(), a.faces_second.len()])
        });
        let animation_error = self.animation_error().cloned();
        let animation = self.current_animation().map(|frame| AnimationReport {
            time: frame.time,
            fan_rays: frame.fan.directions.len(),
            fan_hits: frame.hit_count(),
            update_ms: 1e3 * frame.update_seconds,
        });
        let Some(script) = &mut self.script else {
            return;
        };
        ctx.request_repaint();
        let fail = |script: &mut Script, message: String| {
            *script.outcome.lock() = Some(Err(message));
            script.stage = ScriptStage::Done;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        };
        if matches!(script.stage, ScriptStage::Done) {
            return;
        }
        if script.started.elapsed() > script.options.timeout {
            let t = script.options.timeout.as_secs();
            return fail(script, format!("timed out after {t} s before the screenshot was taken"));
        }
        if let Some(e) = gl_error {
            return fail(script, e);
        }
        match script.stage {
            ScriptStage::Loading => {
                if ready {
                    if let Some(e) = &self.load_error {
                        return fail(script, e.clone());
                    }
                    if let Some(Err(e)) = self.derived.grid.memo.latest() {
                        return fail(script, format!("grid: {e}"));
                    }
                    if let Some(Err(e)) = self.derived.ray.latest() {
                        return fail(script, format!("ray: {e}"));
                    }
                    if let Some(e) = slice_error {
                        return fail(script, format!("slice: {e}"));
                    }
                    if let Some(e) = pairs_error {
                        return fail(script, format!("pairs: {e}"));
                    }
                    if let Some(e) = animation_error {
                        return fail(script, format!("animation: {e}"));
                    }
                    script.stage = ScriptStage::Rendering(0);
                    self.timer.reset();
                }
            }
            ScriptStage::Rendering(n) => {
                self.timer.tick(Instant::now());
                if n + 1 >= script.options.frames.max(3) {
                    let slot = script.image.clone();
                    ctx.request_screenshot(move |image| *slot.lock() = Some(image));
                    script.stage = ScriptStage::Capturing;
                } else {
                    script.stage = ScriptStage::Rendering(n + 1);
                }
            }
            ScriptStage::Capturing => {
                let image = script.image.lock().take();
                if let Some(image) = image {
                    let report = ScreenshotReport {
                        image_size: image.size,
                        pixels_per_point: ctx.pixels_per_point(),
                        viewport: self.viewport,
                        frames: self.timer.stats(),
                        model: self.model.as_ref().map_or(String::new(), |m| m.name.clone()),
                        triangles: self.model.as_ref().map_or(0, |m| m.count(PrimitiveKind::Faces)),
                        cells: cells_drawn,
                        slice_cells,
                        slice_inside,
                        pairs: pair_count,
                        pair_faces,
                        animation,
                    };
                    let path = script.options.path.clone();
                    let written = save_png(&path, &image).and_then(|()| {
                        std::fs::write(sidecar_path(&path), report.to_json())
                            .map_err(|e| format!("{}: {e}", sidecar_path(&path).display()))
                    });
                    *script.outcome.lock() = Some(written.map(|()| report));
                    script.stage = ScriptStage::Done;
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
            }
            ScriptStage::Done => {}
        }
    }
}
