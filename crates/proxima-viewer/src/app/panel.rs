//! The side panel: one function per section, editing [`Settings`] and
//! showing what was derived from them.

use super::{Keys, ViewerApp};
use crate::animation::UpdateMode;
use crate::model::{Model, ModelSource};
use crate::pair_view::SECOND_MESH_FACE_LIMIT;
use crate::settings::{Axis, PairMode, Settings, nice_size};
use crate::slice::sign_name;
use eframe::egui::{self, Color32, RichText};
use proxima::{PrimitiveKind, Sign, Vec3};
use std::path::PathBuf;

impl ViewerApp {
    pub(super) fn panel(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        ui.heading("proxima viewer");
        self.model_section(ui, &ctx);
        ui.separator();
        let Some(model) = self.model.clone() else {
            ui.label("No model loaded.");
            return;
        };
        egui::CollapsingHeader::new("Closest point")
            .default_open(true)
            .show(ui, |ui| {
                self.query_section(ui, &model);
                self.readout_section(ui);
            });
        egui::CollapsingHeader::new("Signed distance slice")
            .default_open(true)
            .show(ui, |ui| self.slice_section(ui, &model));
        egui::CollapsingHeader::new("Hash grid and ray")
            .default_open(true)
            .show(ui, |ui| self.grid_section(ui, &model));
        egui::CollapsingHeader::new("AABB and sphere trees")
            .default_open(true)
            .show(ui, |ui| self.tree_section(ui, &model));
        egui::CollapsingHeader::new("Frustum query")
            .default_open(true)
            .show(ui, |ui| self.frustum_section(ui, &model));
        egui::CollapsingHeader::new("Pairs")
            .default_open(true)
            .show(ui, |ui| self.pairs_section(ui, &model));
        egui::CollapsingHeader::new("Animation")
            .default_open(true)
            .show(ui, |ui| self.animation_section(ui));
        egui::CollapsingHeader::new("Statistics")
            .default_open(true)
            .show(ui, |ui| self.stats_section(ui, &model));
    }

    fn model_section(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        if let Some(model) = &self.model {
            ui.label(RichText::new(&model.name).strong());
        }
        ui.horizontal(|ui| {
            let edit = ui.add(
                egui::TextEdit::singleline(&mut self.path_text)
                    .hint_text("mesh path (.obj .ply .stl .off, .gz)")
                    .desired_width(200.0),
            );
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            let clicked = ui.add_enabled(self.load.is_none(), egui::Button::new("Load")).clicked();
            if (enter || clicked) && self.load.is_none() && !self.path_text.trim().is_empty() {
                let path = PathBuf::from(self.path_text.trim());
                self.start_load(ModelSource::File(path), ctx);
            }
        });
        ui.label(RichText::new("or drop a mesh file on the window").weak());
        if let Some(job) = &self.load {
            let p = job.progress();
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(format!("{} ({:.1} s)", p.stage, job.seconds()));
            });
            ui.add(egui::ProgressBar::new(p.fraction).show_percentage());
        }
        if let Some(error) = &self.load_error {
            ui.colored_label(Color32::from_rgb(255, 110, 110), format!("Could not load: {error}"));
            if self.model.is_some() {
                ui.label(RichText::new("(the previous model is kept)").weak());
            }
        }
        if let Some(error) = self.gl_error.lock().as_ref() {
            ui.colored_label(Color32::from_rgb(255, 110, 110), error);
        }
    }

    fn query_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let s = &mut self.settings;
        if s.animate {
            ui.label(
                RichText::new("Answers below are on the model at rest; the Animation section's on the moved mesh.")
                    .weak(),
            );
        }
        ui.horizontal(|ui| {
            for kind in PrimitiveKind::ALL {
                ui.add_enabled_ui(model.has(kind), |ui| ui.radio_value(&mut s.kind, kind, kind.name()));
            }
        });
        let range = Settings::query_range(&model.bounds);
        let diagonal = model.bounds.diagonal().max(1e-6);
        for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
            ui.horizontal(|ui| {
                let mut v = s.query[axis];
                let slider = egui::Slider::new(&mut v, range.min[axis]..=range.max[axis])
                    .text(name)
                    .clamping(egui::SliderClamping::Never)
                    .drag_value_speed((diagonal / 500.0) as f64);
                if ui.add(slider).changed() && v.is_finite() {
                    s.query[axis] = v;
                }
            });
        }
        ui.label(RichText::new("Click the surface to place the query point; drag to orbit.").weak());
        ui.add(
            egui::Slider::new(&mut s.pick_offset, 0.0..=0.25)
                .text("pick offset (× diagonal)")
                .fixed_decimals(3),
        );
        if let Some(message) = &self.derived.pick_message {
            ui.label(RichText::new(message).weak());
        }
        ui.add(egui::Slider::new(&mut s.k, 0..=64).text("k nearest"));
        ui.checkbox(&mut s.compare_linear, "also run linear search");
        let linear = self.current_linear();
        let s = &self.settings;
        let Some(r) = self.derived.query.latest() else {
            return;
        };
        match r.tree {
            Some(hit) => {
                egui::Grid::new("closest").num_columns(2).show(ui, |ui| {
                    ui.label("closest");
                    ui.label(format!("{} {}", r.kind.name().trim_end_matches('s'), hit.source));
                    ui.end_row();
                    ui.label("point");
                    ui.label(format!("{:.4}, {:.4}, {:.4}", hit.point.x, hit.point.y, hit.point.z));
                    ui.end_row();
                    ui.label("distance");
                    ui.label(format!("{:.6}", hit.distance));
                    ui.end_row();
                });
            }
            None => {
                ui.label("no answer (no primitives)");
            }
        }
        egui::Grid::new("timings").num_columns(3).striped(true).show(ui, |ui| {
            ui.label("");
            ui.label(RichText::new("AABB tree").strong());
            ui.label(RichText::new("linear").strong());
            ui.end_row();
            ui.label("query time");
            ui.label(format_seconds(r.tree_seconds));
            match (s.compare_linear, linear) {
                (false, _) => ui.label("–"),
                (true, None) => ui.spinner(),
                (true, Some((_, seconds))) => ui.label(format_seconds(seconds)),
            };
            ui.end_row();
            if let (true, Some((hit, seconds))) = (s.compare_linear, linear)
                && r.tree_seconds > 0.0
            {
                ui.label("speed-up");
                ui.label(format!("{:.0}×", seconds / r.tree_seconds));
                ui.label(if hit == r.tree {
                    "same answer"
                } else {
                    "DIFFERENT answer"
                });
                ui.end_row();
            }
        });
    }

    /// The query point's signed distance and winding number, next to its
    /// closest point.
    fn readout_section(&mut self, ui: &mut egui::Ui) {
        ui.checkbox(
            &mut self.settings.show_signed_distance,
            "signed distance and winding number",
        );
        let s = &self.settings;
        if !s.show_signed_distance {
            return;
        }
        if let Some(Err(e)) = self.field(s.slice_sign) {
            ui.colored_label(Color32::from_rgb(255, 110, 110), e);
            return;
        }
        let Some(r) = self.current_readout() else {
            if self.building_field() {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("building the signed distance field…");
                });
            }
            return;
        };
        egui::Grid::new("signed distance").num_columns(2).show(ui, |ui| {
            ui.label("signed distance");
            match r.signed_distance {
                Some(d) => {
                    ui.label(format!("{:.6}", d.distance));
                    ui.end_row();
                    ui.label("side");
                    let side = if d.is_inside() { "inside" } else { "outside" };
                    ui.label(format!("{side} (by the {})", sign_name(r.sign)))
                }
                None => ui.label("no answer"),
            };
            ui.end_row();
            ui.label("winding number");
            ui.label(format!("{:.4}", r.winding_number));
            ui.end_row();
        });
        if r.methods_disagree() {
            let by_winding = if r.winding_number > 0.5 { "inside" } else { "outside" };
            ui.colored_label(
                Color32::from_rgb(255, 200, 80),
                format!("the winding number says {by_winding}: the methods disagree here"),
            );
        }
    }

    fn slice_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let running = self.derived.slice.running();
        let s = &mut self.settings;
        ui.checkbox(&mut s.show_slice, "show a slice coloured by signed distance");
        let axis_before = s.slice_axis;
        ui.horizontal(|ui| {
            ui.label("normal");
            for axis in Axis::ALL {
                ui.radio_value(&mut s.slice_axis, axis, axis.name());
            }
        });
        let (lo, hi) = Settings::slice_range(&model.bounds, s.slice_axis);
        if s.slice_axis != axis_before {
            s.slice_position = 0.5 * (lo + hi);
        }
        let mut position = s.slice_position;
        let slider = egui::Slider::new(&mut position, lo..=hi)
            .text("position")
            .clamping(egui::SliderClamping::Never)
            .drag_value_speed(((hi - lo).max(1e-6) / 500.0) as f64);
        if ui.add(slider).changed() && position.is_finite() {
            s.slice_position = position;
        }
        ui.horizontal(|ui| {
            ui.label("sign by");
            for sign in [Sign::WindingNumber, Sign::Pseudonormal] {
                ui.radio_value(&mut s.slice_sign, sign, sign_name(sign));
            }
        });
        ui.checkbox(&mut s.slice_cut_mesh, "cut the mesh away in front of the slice");
        ui.label(
            RichText::new("Blue inside, red outside, white on the surface; the black line is where the sign changes.")
                .weak(),
        );
        if !s.show_slice {
            return;
        }
        let sign = s.slice_sign;
        if let Some(Err(e)) = self.field(sign) {
            ui.colored_label(Color32::from_rgb(255, 110, 110), e);
            return;
        }
        if running || self.building_field() {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label("computing…");
            });
        }
        match self.derived.slice.memo.latest() {
            Some(Ok(slice)) => {
                let [nu, nv] = slice.plane.resolution;
                ui.label(format!(
                    "{nu} × {nv} cells at {} = {:.4} by the {}: {} inside, max |d| {:.4}, in {}",
                    slice.plane.axis.name(),
                    slice.plane.position,
                    sign_name(slice.sign),
                    slice.inside,
                    slice.max_abs,
                    format_seconds(slice.seconds)
                ));
            }
            Some(Err(e)) => {
                ui.colored_label(Color32::from_rgb(255, 110, 110), e);
            }
            None => {}
        }
    }

    fn grid_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let busy_grid = self.derived.grid.running();
        let s = &mut self.settings;
        ui.checkbox(&mut s.show_cells, "render non-empty grid cells");
        let (lo, hi) = Settings::cell_size_range(model.bounds.diagonal());
        let mut h = s.cell_size;
        let slider = egui::Slider::new(&mut h, lo..=hi)
            .logarithmic(true)
            .text("cell size")
            .max_decimals(6);
        if ui.add(slider).changed() && h.is_finite() && h > 0.0 {
            s.cell_size = h;
        }
        ui.horizontal(|ui| {
            for f in [0.5f32, 2.0] {
                if ui.button(if f < 1.0 { "½" } else { "×2" }).clicked() {
                    s.cell_size = nice_size(s.cell_size * f).clamp(lo, hi);
                }
            }
        });
        let key = Keys::of(s).grid;
        if s.show_cells {
            if busy_grid {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("building the grid…");
                });
            }
            match self.derived.grid.memo.get(&key) {
                Some(Ok(g)) => {
                    ui.label(format!(
                        "{} occupied cells, {} entries (built in {})",
                        g.occupied_count(),
                        g.stats.entries,
                        format_seconds(g.build_seconds)
                    ));
                }
                Some(Err(e)) => {
                    ui.colored_label(Color32::from_rgb(255, 110, 110), e);
                }
                None => {}
            }
        }
        ui.separator();
        ui.checkbox(&mut s.show_ray, "render ray");
        vec3_row(ui, "origin", &mut s.ray_origin, model.bounds.diagonal() / 500.0);
        vec3_row(ui, "direction", &mut s.ray_direction, 0.01);
        ui.add(
            egui::Slider::new(&mut s.ray_steps, 1..=5000)
                .logarithmic(true)
                .text("steps"),
        );
        if s.show_ray
            && let Some(walk) = self.derived.ray.latest()
        {
            match walk {
                Ok(w) => {
                    ui.label(format!(
                        "{} cells walked, {} occupied{}",
                        w.cells.len(),
                        w.occupied_boxes.len(),
                        if s.show_cells { "" } else { " (grid not shown)" }
                    ));
                    if let Some(hit) = w.hit {
                        ui.label(format!("first hit at {:.4}, {:.4}, {:.4}", hit.x, hit.y, hit.z));
                    }
                }
                Err(e) => {
                    ui.colored_label(Color32::from_rgb(255, 110, 110), e);
                }
            }
        }
    }

    fn tree_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let s = &mut self.settings;
        let depth = model.tree_stats(s.kind).depth;
        ui.checkbox(
            &mut s.show_nodes,
            format!("show the {} tree's nodes at depth", s.kind.name()),
        );
        ui.add(egui::Slider::new(&mut s.node_depth, 0..=depth.max(1)).text("depth"));
        if s.show_nodes
            && let Some(boxes) = self.derived.nodes.latest()
        {
            ui.label(format!("{} nodes at depth {}", boxes.len(), s.node_depth));
        }
        ui.checkbox(
            &mut s.show_spheres,
            format!("show the {} sphere tree's nodes at that depth", s.kind.name()),
        );
        if s.show_spheres
            && let Some((count, _)) = self.derived.spheres.latest()
        {
            ui.label(format!("{count} spheres at depth {}", s.node_depth));
        }
    }

    fn frustum_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let s = &mut self.settings;
        ui.checkbox(
            &mut s.show_frustum,
            format!("second camera: {} in its frustum", s.kind.name()),
        );
        let speed = model.bounds.diagonal() / 500.0;
        vec3_row(ui, "eye", &mut s.frustum_eye, speed);
        vec3_row(ui, "target", &mut s.frustum_target, speed);
        ui.add(egui::Slider::new(&mut s.frustum_fov, 1.0..=170.0).text("fov (degrees)"));
        let reach = 10.0 * model.bounds.diagonal().max(1e-6);
        ui.add(
            egui::Slider::new(&mut s.frustum_near, reach * 1e-5..=reach)
                .logarithmic(true)
                .text("near"),
        );
        ui.add(
            egui::Slider::new(&mut s.frustum_far, reach * 1e-5..=reach)
                .logarithmic(true)
                .text("far"),
        );
        if s.show_frustum
            && let Some(selection) = self.derived.frustum.latest()
        {
            match selection {
                Ok(sel) => {
                    ui.label(format!(
                        "{} {} selected ({} sources) in {}",
                        sel.selected.len(),
                        sel.kind.name(),
                        sel.sources,
                        format_seconds(sel.tree_seconds)
                    ));
                    if let Some(linear) = &sel.linear {
                        let agree = if *linear == sel.selected {
                            "same set"
                        } else {
                            "DIFFERENT SET"
                        };
                        ui.label(format!(
                            "brute force: {} in {} ({agree})",
                            linear.len(),
                            format_seconds(sel.linear_seconds)
                        ));
                    }
                }
                Err(e) => {
                    ui.colored_label(Color32::from_rgb(255, 110, 110), e);
                }
            }
        }
    }

    /// The "Pairs" section: the mode, the second mesh's pose and the answers.
    fn pairs_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let running = self.derived.pairs.running() || self.second.running();
        let s = &mut self.settings;
        ui.horizontal(|ui| {
            for mode in PairMode::ALL {
                ui.radio_value(&mut s.pair_mode, mode, mode.name());
            }
        });
        if s.pair_mode == PairMode::SecondMesh {
            let second = match &self.second_path {
                Some(path) => path.display().to_string(),
                None => "a copy of the model".to_string(),
            };
            ui.label(format!("second mesh: {second}"));
            let reach = Settings::pair_translation_range(&model.bounds);
            for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                let mut v = s.pair_translation[axis];
                let slider = egui::Slider::new(&mut v, -reach..=reach)
                    .text(format!("move {name}"))
                    .clamping(egui::SliderClamping::Never)
                    .drag_value_speed(reach / 500.0);
                if ui.add(slider).changed() && v.is_finite() {
                    s.pair_translation[axis] = v;
                }
            }
            for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                let mut v = s.pair_angles[axis];
                let slider = egui::Slider::new(&mut v, -180.0..=180.0).text(format!("turn about {name} (°)"));
                if ui.add(slider).changed() && v.is_finite() {
                    s.pair_angles[axis] = v;
                }
            }
            ui.horizontal(|ui| {
                if ui.button("reset pose").clicked() {
                    let defaults = Settings::for_bounds(&model.bounds);
                    (s.pair_translation, s.pair_angles) = (defaults.pair_translation, defaults.pair_angles);
                }
                ui.label(RichText::new("ctrl-drag moves it in the view plane").weak());
            });
        }
        if s.pair_mode == PairMode::Off {
            return;
        }
        if running {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(if self.second.running() {
                    "loading the second mesh…"
                } else {
                    "computing…"
                });
            });
        }
        if let Some(e) = self.pairs_error() {
            ui.colored_label(Color32::from_rgb(255, 110, 110), e);
            return;
        }
        let Some(a) = self.current_pairs() else {
            return;
        };
        let capped = |drawn: usize, total: usize| {
            if drawn < total {
                format!(" (the first {drawn} highlighted)")
            } else {
                String::new()
            }
        };
        match a.mode {
            PairMode::SelfIntersections => {
                ui.label(format!(
                    "{} face pairs meet: {} faces{} in {}",
                    a.pairs.len(),
                    a.faces_first.len(),
                    capped(a.highlighted[0], a.faces_first.len()),
                    format_seconds(a.pairs_seconds)
                ));
            }
            _ => {
                ui.label(format!(
                    "{} face pairs meet: {} faces of the model{}, {} of the second mesh{}, in {}",
                    a.pairs.len(),
                    a.faces_first.len(),
                    capped(a.highlighted[0], a.faces_first.len()),
                    a.faces_second.len(),
                    capped(a.highlighted[1], a.faces_second.len()),
                    format_seconds(a.pairs_seconds)
                ));
                if let Some(d) = &a.distance {
                    ui.label(format!(
                        "distance {:.6} (face {} to face {}) in {}",
                        d.distance,
                        d.face_a,
                        d.face_b,
                        format_seconds(a.distance_seconds)
                    ));
                }
                if a.second_faces_drawn < a.second_faces {
                    ui.label(
                        RichText::new(format!(
                            "outlining {} of the second mesh's {} faces (one in {})",
                            a.second_faces_drawn,
                            a.second_faces,
                            a.second_faces.div_ceil(SECOND_MESH_FACE_LIMIT)
                        ))
                        .weak(),
                    );
                }
            }
        }
    }

    fn animation_section(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        ui.checkbox(&mut s.animate, "deform the model by a wave");
        if !s.animate {
            return;
        }
        ui.horizontal(|ui| {
            ui.label("each frame:");
            for mode in UpdateMode::ALL {
                ui.radio_value(&mut s.animation_mode, mode, mode.name());
            }
            ui.label("the trees");
        });
        ui.add(
            egui::Slider::new(&mut s.wave_amplitude, 0.0..=0.2)
                .text("height (× diagonal)")
                .fixed_decimals(3),
        );
        ui.add(egui::Slider::new(&mut s.wave_period, 0.25..=10.0).text("period (s)"));
        ui.add(egui::Slider::new(&mut s.fan_side, 1..=32).text("fan rays per side"));
        ui.label(RichText::new("The fan starts at the query point, aimed at the model's centre.").weak());
        if let Some(e) = self.animation_error() {
            ui.colored_label(Color32::from_rgb(255, 110, 110), e);
            return;
        }
        let Some(frame) = self.current_animation() else {
            return;
        };
        let times = self
            .derived
            .animation
            .as_ref()
            .and_then(|a| a.as_ref().ok())
            .map(|a| a.times());
        egui::Grid::new("animation").num_columns(2).show(ui, |ui| {
            let mut row = |a: &str, b: String| {
                ui.label(a);
                ui.label(b);
                ui.end_row();
            };
            let mean = |t: Option<f64>| t.map_or("—".to_string(), format_seconds);
            if let Some(times) = times {
                row("refit (mean)", mean(times.refit));
                row("rebuild (mean)", mean(times.rebuild));
                if let (Some(refit), Some(rebuild)) = (times.refit, times.rebuild) {
                    row("rebuild / refit", format!("{:.1}×", rebuild / refit));
                }
            }
            let rays = frame.fan.directions.len();
            row(
                "queries",
                format!(
                    "closest + {rays} rays ({} hit) in {}",
                    frame.hit_count(),
                    format_seconds(frame.query_seconds)
                ),
            );
            if frame.cost_ratio.is_finite() {
                row(
                    "faces' tree cost",
                    format!("{:.2}× its cost at build", frame.cost_ratio),
                );
            }
            if let Some(hit) = frame.closest {
                row("closest", format!("face {}, distance {:.6}", hit.source, hit.distance));
            }
        });
        ui.label(
            RichText::new("Answers are the same either way; a refit tree slows down as its boxes come to overlap.")
                .weak(),
        );
    }

    fn stats_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let t = &model.timings;
        egui::Grid::new("stats").num_columns(2).striped(true).show(ui, |ui| {
            let mut row = |a: &str, b: String| {
                ui.label(a);
                ui.label(b);
                ui.end_row();
            };
            row("vertices", model.mesh.vertex_count().to_string());
            row("edges", model.count(PrimitiveKind::Edges).to_string());
            row("faces", model.mesh.face_count().to_string());
            row("triangles", model.count(PrimitiveKind::Faces).to_string());
            row("convex polygons", model.count(PrimitiveKind::Polygons).to_string());
            row("load", format_seconds(t.load));
            row("normals, buffers", format_seconds(t.buffers));
            for kind in PrimitiveKind::ALL {
                let st = model.tree_stats(kind);
                row(
                    &format!("{} tree", kind.name()),
                    format!(
                        "{} build, depth {}, {} nodes",
                        format_seconds(model.build_seconds(kind)),
                        st.depth,
                        st.nodes
                    ),
                );
            }
            let st = model.tree_stats(self.settings.kind);
            row(
                "leaves",
                format!(
                    "{} ({}–{} primitives, mean {:.2})",
                    st.leaves, st.min_leaf_size, st.max_leaf_size, st.mean_leaf_size
                ),
            );
            row("tree memory", format!("{:.1} MB", st.memory_bytes as f64 / 1e6));
            if let Some(g) = self.current_grid() {
                row(
                    "grid",
                    format!(
                        "{} {} cells of {}, max {}/cell",
                        g.occupied_count(),
                        g.kind.name(),
                        g.cell_size,
                        g.stats.max_per_cell
                    ),
                );
            }
            row("frame (CPU)", format!("{:.1} ms", self.frame_ms));
        });
        ui.checkbox(&mut self.settings.show_mesh, "show the mesh");
        ui.label(
            RichText::new(
                "Mouse: drag to orbit, right/middle or shift-drag to pan, wheel to zoom, double-click to fit.",
            )
            .weak(),
        );
    }
}

/// `1.234 ms`, `56.7 µs`, `2.31 s`.
pub(crate) fn format_seconds(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.2} µs", s * 1e6)
    }
}

fn vec3_row(ui: &mut egui::Ui, label: &str, v: &mut Vec3, speed: f32) {
    ui.horizontal(|ui| {
        ui.label(label);
        for axis in 0..3 {
            let mut x = v[axis];
            if ui
                .add(egui::DragValue::new(&mut x).speed(speed as f64).max_decimals(4))
                .changed()
                && x.is_finite()
            {
                v[axis] = x;
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::format_seconds;

    #[test]
    fn seconds_are_formatted_in_a_readable_unit() {
        assert_eq!(format_seconds(2.3149), "2.31 s");
        assert_eq!(format_seconds(0.001234), "1.23 ms");
        assert_eq!(format_seconds(5.67e-5), "56.70 µs");
    }
}
