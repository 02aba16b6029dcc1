//! The eframe application: side panel, 3D view with mouse controls, the
//! background jobs (loading, grid builds) and the scripted screenshot mode.
//! The drawing itself is `state::compose_frame` (what) and `gl::Renderer`
//! (how).

use crate::camera::{OrbitCamera, Viewport};
use crate::cells::{CellGrid, RayWalk, walk_ray};
use crate::frustum_view::{self, FrustumSelection, settings_frustum};
use crate::gl::Renderer;
use crate::model::{Model, ModelSource, PrimitiveKind, Progress, QueryResult};
use crate::scene::{self, BoxSet, Overlay, colors};
use crate::screenshot::{FrameTimer, ScreenshotOptions, ScreenshotReport, save_png, sidecar_path};
use crate::spheres::spheres_overlay;
use crate::state::{FrameInputs, Settings, compose_frame, nice_size};
use crate::{InitialView, ViewerOptions};
use eframe::egui::mutex::Mutex;
use eframe::egui::{self, Color32, RichText};
use eframe::{egui_glow, glow};
use proxima::math::Vec3;
use std::path::PathBuf;
use std::sync::{Arc, mpsc};
use std::time::Instant;

/// Shared result of the scripted mode, read by [`crate::run`] after the window closes.
pub(crate) type Outcome = Arc<Mutex<Option<Result<ScreenshotReport, String>>>>;

/// A model being loaded on another thread.
struct LoadJob {
    name: String,
    progress: Arc<Mutex<Progress>>,
    receiver: mpsc::Receiver<Result<Model, String>>,
    started: Instant,
}

/// Identifies the inputs of a grid build.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GridKey {
    model: u64,
    kind: PrimitiveKind,
    cell_size: f32,
}

/// A grid being built on another thread.
struct GridJob {
    key: GridKey,
    receiver: mpsc::Receiver<Result<CellGrid, String>>,
}

/// Inputs of the cached query answer.
#[derive(Clone, Copy, Debug, PartialEq)]
struct QueryKey {
    model: u64,
    kind: PrimitiveKind,
    query: Vec3,
    k: usize,
}

/// Inputs of a brute-force answer.
#[derive(Clone, Copy, Debug, PartialEq)]
struct LinearKey {
    model: u64,
    kind: PrimitiveKind,
    query: Vec3,
}

/// Inputs of the cached tree nodes at a depth: model, kind, depth.
type NodeKey = (u64, PrimitiveKind, u32);

/// Inputs of the cached frustum query.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FrustumKey {
    model: u64,
    kind: PrimitiveKind,
    eye: Vec3,
    target: Vec3,
    fov: f32,
    near: f32,
    far: f32,
    linear: bool,
}

/// A brute-force answer and its time.
type LinearAnswer = (Option<proxima::ClosestHit>, f64);

/// Inputs of the cached ray walk.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RayKey {
    model: u64,
    origin: Vec3,
    direction: Vec3,
    cell_size: f32,
    steps: u32,
    grid: Option<GridKey>,
}

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

struct Script {
    options: ScreenshotOptions,
    stage: ScriptStage,
    started: Instant,
    image: Arc<Mutex<Option<Arc<egui::ColorImage>>>>,
    outcome: Outcome,
}

/// The viewer application.
pub struct ViewerApp {
    renderer: Option<Arc<Mutex<Renderer>>>,
    gl_error: Arc<Mutex<Option<String>>>,
    model: Option<Arc<Model>>,
    model_serial: u64,
    load: Option<LoadJob>,
    load_error: Option<String>,
    settings: Settings,
    /// Settings from the command line, applied to the first model only.
    initial: Option<InitialView>,
    camera: OrbitCamera,
    needs_fit: bool,
    viewport: Viewport,
    path_text: String,
    query: Option<(QueryKey, QueryResult)>,
    /// The latest brute-force answer; it runs on a worker thread so that
    /// dragging the query point over a large mesh stays smooth.
    linear: Option<(LinearKey, LinearAnswer)>,
    linear_job: Option<(LinearKey, mpsc::Receiver<LinearAnswer>)>,
    grid: Option<(GridKey, Arc<CellGrid>)>,
    grid_job: Option<GridJob>,
    grid_error: Option<(GridKey, String)>,
    ray: Option<(RayKey, Result<RayWalk, String>)>,
    nodes: Option<(NodeKey, Arc<BoxSet>)>,
    frustum: Option<(FrustumKey, Result<FrustumSelection, String>)>,
    /// Great circles of the sphere tree's nodes at the depth, and their count.
    spheres: Option<(NodeKey, (usize, Overlay))>,
    pick_message: Option<String>,
    timer: FrameTimer,
    last_frame: Option<Instant>,
    frame_ms: f64,
    script: Option<Script>,
}

impl ViewerApp {
    /// Sets up the renderer and starts loading the first model.
    pub(crate) fn new(cc: &eframe::CreationContext<'_>, options: ViewerOptions, outcome: Outcome) -> Self {
        let (renderer, renderer_error) = match cc.gl.as_ref() {
            Some(gl) => match Renderer::new(gl) {
                Ok(r) => (Some(Arc::new(Mutex::new(r))), None),
                Err(e) => (None, Some(format!("OpenGL setup failed: {e}"))),
            },
            None => (
                None,
                Some("no OpenGL context (the glow renderer is required)".to_string()),
            ),
        };
        let path_text = match &options.source {
            ModelSource::File(p) => p.display().to_string(),
            ModelSource::Mesh { .. } => String::new(),
        };
        let script = options.screenshot.map(|s| Script {
            options: s,
            stage: ScriptStage::Loading,
            started: Instant::now(),
            image: Arc::new(Mutex::new(None)),
            outcome: outcome.clone(),
        });
        let mut app = Self {
            renderer,
            gl_error: Arc::new(Mutex::new(renderer_error)),
            model: None,
            model_serial: 0,
            load: None,
            load_error: None,
            settings: Settings::default(),
            initial: Some(options.initial),
            camera: OrbitCamera::default(),
            needs_fit: true,
            viewport: Viewport::new([0.0, 0.0], [1.0, 1.0]),
            path_text,
            query: None,
            linear: None,
            linear_job: None,
            grid: None,
            grid_job: None,
            grid_error: None,
            ray: None,
            nodes: None,
            frustum: None,
            spheres: None,
            pick_message: None,
            timer: FrameTimer::default(),
            last_frame: None,
            frame_ms: 0.0,
            script,
        };
        app.start_load(options.source, &cc.egui_ctx);
        app
    }

    fn start_load(&mut self, source: ModelSource, ctx: &egui::Context) {
        let name = match &source {
            ModelSource::File(p) => p.display().to_string(),
            ModelSource::Mesh { name, .. } => name.clone(),
        };
        let progress = Arc::new(Mutex::new(Progress {
            stage: "starting".into(),
            fraction: 0.0,
        }));
        let (sender, receiver) = mpsc::channel();
        let (p, c) = (progress.clone(), ctx.clone());
        let spawned = std::thread::Builder::new().name("proxima-load".into()).spawn(move || {
            let result = Model::load(source, &|stage| {
                *p.lock() = stage;
                c.request_repaint();
            });
            let _ = sender.send(result);
            c.request_repaint();
        });
        match spawned {
            Ok(_) => {
                self.load_error = None;
                self.load = Some(LoadJob {
                    name,
                    progress,
                    receiver,
                    started: Instant::now(),
                })
            }
            Err(e) => self.load_error = Some(format!("cannot start loading: {e}")),
        }
    }

    /// Picks up finished background jobs.
    fn poll_jobs(&mut self, ctx: &egui::Context) {
        if let Some(job) = &self.load {
            let received = match job.receiver.try_recv() {
                Ok(result) => Some(result),
                Err(mpsc::TryRecvError::Empty) => None,
                Err(mpsc::TryRecvError::Disconnected) => Some(Err(format!("{}: loading failed", job.name))),
            };
            if let Some(result) = received {
                self.load = None;
                match result {
                    Ok(model) => self.set_model(model),
                    // The previous model stays.
                    Err(e) => self.load_error = Some(e),
                }
            } else {
                ctx.request_repaint_after(std::time::Duration::from_millis(100));
            }
        }
        if let Some((key, receiver)) = &self.linear_job {
            match receiver.try_recv() {
                Ok(answer) => {
                    self.linear = Some((*key, answer));
                    self.linear_job = None;
                }
                Err(mpsc::TryRecvError::Disconnected) => self.linear_job = None,
                Err(mpsc::TryRecvError::Empty) => {}
            }
        }
        if let Some(job) = &self.grid_job {
            let received = match job.receiver.try_recv() {
                Ok(result) => Some(result),
                Err(mpsc::TryRecvError::Empty) => None,
                Err(mpsc::TryRecvError::Disconnected) => Some(Err("the grid build failed".to_string())),
            };
            if let Some(result) = received {
                let key = job.key;
                self.grid_job = None;
                match result {
                    Ok(grid) => {
                        self.grid = Some((key, Arc::new(grid)));
                        self.grid_error = None;
                    }
                    Err(e) => self.grid_error = Some((key, e)),
                }
            } else {
                ctx.request_repaint_after(std::time::Duration::from_millis(100));
            }
        }
    }

    fn set_model(&mut self, model: Model) {
        self.model_serial += 1;
        let mut settings = Settings::for_bounds(&model.bounds);
        // Keep the user's choices that do not depend on the model's size.
        if self.model.is_some() {
            let s = &self.settings;
            settings.kind = s.kind;
            settings.k = s.k;
            settings.compare_linear = s.compare_linear;
            settings.show_mesh = s.show_mesh;
            settings.show_cells = s.show_cells;
            settings.show_ray = s.show_ray;
            settings.show_nodes = s.show_nodes;
            settings.node_depth = s.node_depth;
            settings.show_frustum = s.show_frustum;
            settings.show_spheres = s.show_spheres;
            settings.frustum_fov = s.frustum_fov;
        }
        if let Some(initial) = self.initial.take() {
            initial.apply(&mut settings);
        }
        if !model.has(settings.kind) {
            settings.kind = PrimitiveKind::Vertices;
        }
        self.settings = settings;
        self.load_error = None;
        self.query = None;
        self.linear = None;
        self.grid = None;
        self.grid_error = None;
        self.ray = None;
        self.nodes = None;
        self.frustum = None;
        self.spheres = None;
        self.pick_message = None;
        self.needs_fit = true;
        self.model = Some(Arc::new(model));
    }

    /// Recomputes what depends on the settings: the query answer, the tree
    /// nodes and the ray now; the grid on another thread.
    fn update_derived(&mut self, ctx: &egui::Context) {
        let Some(model) = self.model.clone() else {
            return;
        };
        let s = &self.settings;
        let key = QueryKey {
            model: self.model_serial,
            kind: s.kind,
            query: s.query,
            k: s.k,
        };
        if self.query.as_ref().is_none_or(|(k, _)| *k != key) {
            let result = model.query(s.kind, s.query, s.k, false);
            self.query = Some((key, result));
        }
        let linear_key = LinearKey {
            model: self.model_serial,
            kind: s.kind,
            query: s.query,
        };
        let have_linear = self.linear.as_ref().is_some_and(|(k, _)| *k == linear_key);
        if s.compare_linear && !have_linear && self.linear_job.is_none() {
            let (sender, receiver) = mpsc::channel();
            let (c, m) = (ctx.clone(), model.clone());
            let spawned = std::thread::Builder::new()
                .name("proxima-linear".into())
                .spawn(move || {
                    let _ = sender.send(m.linear_closest(linear_key.kind, linear_key.query));
                    c.request_repaint();
                });
            if spawned.is_ok() {
                self.linear_job = Some((linear_key, receiver));
            }
        }
        let node_key = (self.model_serial, s.kind, s.node_depth);
        if s.show_nodes && self.nodes.as_ref().is_none_or(|(k, _)| *k != node_key) {
            let boxes = Arc::new(BoxSet::new(model.nodes_at_depth(s.kind, s.node_depth)));
            self.nodes = Some((node_key, boxes));
        }
        if s.show_spheres && self.spheres.as_ref().is_none_or(|(k, _)| *k != node_key) {
            let spheres = model.sphere_nodes_at_depth(s.kind, s.node_depth);
            self.spheres = Some((node_key, (spheres.len(), spheres_overlay(&spheres))));
        }
        let frustum_key = FrustumKey {
            model: self.model_serial,
            kind: s.kind,
            eye: s.frustum_eye,
            target: s.frustum_target,
            fov: s.frustum_fov,
            near: s.frustum_near,
            far: s.frustum_far,
            linear: s.compare_linear,
        };
        if s.show_frustum && self.frustum.as_ref().is_none_or(|(k, _)| *k != frustum_key) {
            let selection = settings_frustum(s).map(|f| frustum_view::select(&model, s.kind, &f, s.compare_linear));
            self.frustum = Some((frustum_key, selection));
        }
        let grid_key = GridKey {
            model: self.model_serial,
            kind: s.kind,
            cell_size: s.cell_size,
        };
        let wanted = s.show_cells;
        let have = self.grid.as_ref().is_some_and(|(k, _)| *k == grid_key);
        let failed = self.grid_error.as_ref().is_some_and(|(k, _)| *k == grid_key);
        if wanted && !have && !failed && self.grid_job.is_none() {
            let (sender, receiver) = mpsc::channel();
            let c = ctx.clone();
            let m = model.clone();
            let spawned = std::thread::Builder::new().name("proxima-grid".into()).spawn(move || {
                let _ = sender.send(CellGrid::build(&m, grid_key.kind, grid_key.cell_size));
                c.request_repaint();
            });
            match spawned {
                Ok(_) => {
                    self.grid_job = Some(GridJob {
                        key: grid_key,
                        receiver,
                    })
                }
                Err(e) => self.grid_error = Some((grid_key, format!("cannot start the grid build: {e}"))),
            }
        }
        if s.show_ray {
            let grid = self.grid.as_ref().filter(|(k, _)| *k == grid_key && wanted);
            let ray_key = RayKey {
                model: self.model_serial,
                origin: s.ray_origin,
                direction: s.ray_direction,
                cell_size: s.cell_size,
                steps: s.ray_steps,
                grid: grid.map(|(k, _)| *k),
            };
            if self.ray.as_ref().is_none_or(|(k, _)| *k != ray_key) {
                let walk = walk_ray(
                    s.ray_origin,
                    s.ray_direction,
                    s.cell_size,
                    s.ray_steps,
                    grid.map(|(_, g)| g.as_ref()),
                );
                self.ray = Some((ray_key, walk));
            }
        }
    }

    fn busy(&self) -> bool {
        self.load.is_some() || self.grid_job.is_some() || self.linear_job.is_some()
    }

    /// The brute-force answer for the current query, if it is in.
    fn current_linear(&self) -> Option<LinearAnswer> {
        let (key, _) = self.query.as_ref()?;
        let (k, answer) = self.linear.as_ref()?;
        (k.model == key.model && k.kind == key.kind && k.query == key.query).then_some(*answer)
    }

    fn current_grid(&self) -> Option<&Arc<CellGrid>> {
        self.grid.as_ref().map(|(_, g)| g)
    }

    // ---------------------------------------------------------------- panel

    fn panel(&mut self, ui: &mut egui::Ui) {
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
            .show(ui, |ui| self.query_section(ui, &model));
        egui::CollapsingHeader::new("Hash grid and ray")
            .default_open(true)
            .show(ui, |ui| self.grid_section(ui, &model));
        egui::CollapsingHeader::new("AABB and sphere trees")
            .default_open(true)
            .show(ui, |ui| self.tree_section(ui, &model));
        egui::CollapsingHeader::new("Frustum query")
            .default_open(true)
            .show(ui, |ui| self.frustum_section(ui, &model));
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
            let p = job.progress.lock().clone();
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(format!("{} ({:.1} s)", p.stage, job.started.elapsed().as_secs_f32()));
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
        if let Some(message) = &self.pick_message {
            ui.label(RichText::new(message).weak());
        }
        ui.add(egui::Slider::new(&mut s.k, 0..=64).text("k nearest"));
        ui.checkbox(&mut s.compare_linear, "also run linear search");
        let linear = self.current_linear();
        let s = &self.settings;
        let Some((_, r)) = &self.query else {
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

    fn grid_section(&mut self, ui: &mut egui::Ui, model: &Model) {
        let busy_grid = self.grid_job.is_some();
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
        let key = GridKey {
            model: self.model_serial,
            kind: s.kind,
            cell_size: s.cell_size,
        };
        if s.show_cells {
            if busy_grid {
                ui.horizontal(|ui| {
                    ui.spinner();
                    ui.label("building the grid…");
                });
            }
            if let Some((k, e)) = &self.grid_error
                && *k == key
            {
                ui.colored_label(Color32::from_rgb(255, 110, 110), e);
            }
            if let Some((k, g)) = &self.grid
                && *k == key
            {
                ui.label(format!(
                    "{} occupied cells, {} entries (built in {})",
                    g.occupied_count(),
                    g.stats.entries,
                    format_seconds(g.build_seconds)
                ));
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
            && let Some((_, walk)) = &self.ray
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
            && let Some((_, boxes)) = &self.nodes
        {
            ui.label(format!("{} nodes at depth {}", boxes.len(), s.node_depth));
        }
        ui.checkbox(
            &mut s.show_spheres,
            format!("show the {} sphere tree's nodes at that depth", s.kind.name()),
        );
        if s.show_spheres
            && let Some((_, (count, _))) = &self.spheres
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
            && let Some((_, selection)) = &self.frustum
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

    // ---------------------------------------------------------------- 3D view

    fn view(&mut self, ui: &mut egui::Ui) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), egui::Sense::click_and_drag());
        self.viewport = Viewport::new([rect.min.x, rect.min.y], [rect.width(), rect.height()]);
        if let Some(model) = &self.model
            && self.needs_fit
            && rect.width() > 1.0
        {
            self.camera = OrbitCamera::fit(&model.bounds, self.viewport.aspect());
            self.needs_fit = false;
        }
        let interactive = self.handle_mouse(ui, &response);
        if interactive {
            // Draw the full picture once the camera rests.
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(250));
        }

        let mut frame = {
            let result = self.query.as_ref().map(|(_, r)| r);
            let ray = self.ray.as_ref().and_then(|(_, r)| r.as_ref().ok());
            compose_frame(&FrameInputs {
                camera: &self.camera,
                viewport: self.viewport,
                model: self.model.as_deref(),
                settings: &self.settings,
                result,
                grid: self.current_grid().map(|g| g.as_ref()),
                ray,
                nodes: self.nodes.as_ref().map(|(_, b)| b),
                spheres: self.spheres.as_ref().map(|(_, (_, o))| o),
                frustum: self.frustum.as_ref().and_then(|(_, f)| f.as_ref().ok()),
            })
        };
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
            let p = job.progress.lock().clone();
            status.push(format!(
                "loading {}: {} ({:.0}%)",
                job.name,
                p.stage,
                100.0 * p.fraction
            ));
        }
        if self.grid_job.is_some() {
            status.push("building the grid…".to_string());
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

    /// Camera and picking by mouse; `true` while the camera is moving.
    fn handle_mouse(&mut self, ui: &egui::Ui, response: &egui::Response) -> bool {
        let (shift, scroll) = ui.input(|i| (i.modifiers.shift, i.smooth_scroll_delta.y));
        let delta = response.drag_delta();
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
        let Some(tree) = model.face_tree() else {
            self.pick_message = Some("picking needs faces; this mesh has none".into());
            return;
        };
        let (origin, direction) = self.camera.ray_through(pixel, &self.viewport);
        match scene::pick(tree, origin, direction) {
            Some(hit) => {
                let offset = self.settings.pick_offset * model.bounds.diagonal();
                self.settings.query = hit.offset(offset);
                self.pick_message = Some(format!("picked face {}", hit.face));
            }
            None => self.pick_message = Some("missed the surface".into()),
        }
    }

    fn handle_dropped_files(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).collect());
        if let Some(path) = dropped.into_iter().next() {
            if self.load.is_some() {
                self.load_error = Some("still loading the previous file; drop it again when done".into());
                return;
            }
            self.path_text = path.display().to_string();
            self.start_load(ModelSource::File(path), ctx);
        }
    }

    // ---------------------------------------------------------------- scripted mode

    fn drive_script(&mut self, ctx: &egui::Context) {
        let ready = !self.busy() && (self.model.is_some() || self.load_error.is_some());
        let gl_error = self.gl_error.lock().clone();
        let cells_drawn = if self.settings.show_cells {
            self.current_grid().map_or(0, |g| g.occupied_count())
        } else {
            0
        };
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
                    if let Some((_, e)) = &self.grid_error {
                        return fail(script, format!("grid: {e}"));
                    }
                    if let Some((_, Err(e))) = &self.ray {
                        return fail(script, format!("ray: {e}"));
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

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let now = Instant::now();
        self.last_frame = Some(now);
        self.frame_ms = 1e3 * frame.info().cpu_usage.unwrap_or(0.0) as f64;
        let ctx = ui.ctx().clone();
        self.poll_jobs(&ctx);
        self.handle_dropped_files(&ctx);
        self.update_derived(&ctx);

        egui::Panel::left("controls")
            .exact_size(340.0)
            .resizable(false)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.panel(ui));
            });
        egui::CentralPanel::no_frame().show(ui, |ui| self.view(ui));
        self.drive_script(&ctx);
    }

    fn on_exit(&mut self, gl: Option<&glow::Context>) {
        if let (Some(gl), Some(renderer)) = (gl, &self.renderer) {
            renderer.lock().destroy(gl);
        }
    }
}

/// `1.234 ms`, `56.7 µs`, `2.31 s`.
pub fn format_seconds(s: f64) -> String {
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
