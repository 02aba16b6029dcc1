//! The eframe application: its state, the background jobs (loading, grid
//! builds, brute force) and the values derived from the settings. The side
//! panel is `panel.rs`, the 3D view and the mouse `view.rs`, the scripted
//! screenshot mode `script.rs`; the drawing itself is `frame::compose_frame`
//! (what) and `gl::Renderer` (how). The signed distance fields (one per sign
//! method, built on first use) and the slice are background jobs too.

mod panel;
mod script;
mod view;

use crate::animation::{Animation, AnimationFrame, RayFan, Wave};
use crate::camera::{OrbitCamera, Viewport};
use crate::cells::{CellGrid, RayWalk, walk_ray};
use crate::frustum_view::{self, FrustumSelection, settings_frustum};
use crate::gl::Renderer;
use crate::job::{Background, Job, Poll};
use crate::memo::Memo;
use crate::model::{Model, ModelSource, Progress, QueryResult};
use crate::pair_view::{self, PairAnswer};
use crate::scene::{BoxSet, Overlay};
use crate::screenshot::{FrameTimer, ScreenshotReport};
use crate::settings::{Axis, PairMode, Settings};
use crate::slice::{SLICE_RESOLUTION, SdfReadout, SdfSlice, SlicePlane, signed_distance_field};
use crate::spheres::spheres_overlay;
use crate::{InitialView, ViewerOptions};
use eframe::egui;
use eframe::egui::mutex::Mutex;
use eframe::glow;
use proxima::{ClosestHit, DVec3, MeshIndex, PrimitiveKind, Sign, SignedDistanceField, Vec3};
use script::Script;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The animation's clock in the scripted mode, in seconds (a quarter of the
/// default period: the wave at its most lopsided).
pub(crate) const SCRIPT_ANIMATION_TIME: f64 = 0.5;

/// Shared result of the scripted mode, read by [`crate::run`] after the window closes.
pub(crate) type Outcome = Arc<Mutex<Option<Result<ScreenshotReport, String>>>>;

/// Inputs of the closest-point answer: kind, query point, k.
type QueryKey = (PrimitiveKind, Vec3, usize);
/// Inputs of a brute-force answer: kind, query point.
type LinearKey = (PrimitiveKind, Vec3);
/// Inputs of the tree nodes and sphere tree nodes shown: kind, depth.
type NodeKey = (PrimitiveKind, u32);
/// Inputs of a grid build: kind, cell size.
type GridKey = (PrimitiveKind, f32);

/// Inputs of a signed-distance slice.
#[derive(Clone, Copy, Debug, PartialEq)]
struct SliceKey {
    axis: Axis,
    position: f32,
    sign: Sign,
}

/// Inputs of the query point's signed distance: the point and the sign method.
type ReadoutKey = (Vec3, Sign);

/// A signed distance field, or why it could not be built.
type FieldResult = Result<Arc<SignedDistanceField>, String>;

/// The slot of a sign method's field in [`Derived::fields`].
fn field_slot(sign: Sign) -> usize {
    match sign {
        Sign::WindingNumber => 0,
        Sign::Pseudonormal => 1,
    }
}

/// Inputs of the frustum query.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FrustumKey {
    kind: PrimitiveKind,
    eye: Vec3,
    target: Vec3,
    fov: f32,
    near: f32,
    far: f32,
    linear: bool,
}

/// Inputs of the ray walk (the grid when one of the same cell size is shown).
#[derive(Clone, Copy, Debug, PartialEq)]
struct RayKey {
    origin: Vec3,
    direction: Vec3,
    cell_size: f32,
    steps: u32,
    grid: Option<GridKey>,
}

/// Inputs of the "Pairs" answer: the mode and, for the second mesh, its
/// translation and angles (self-intersections do not depend on them, so
/// moving the pose does not ask again).
#[derive(Clone, Copy, Debug, PartialEq)]
struct PairKey {
    mode: PairMode,
    translation: DVec3,
    angles: DVec3,
}

impl PairKey {
    /// The key of what the settings ask, `None` when the section is off.
    fn of(s: &Settings) -> Option<Self> {
        let (translation, angles) = match s.pair_mode {
            PairMode::Off => return None,
            PairMode::SelfIntersections => (DVec3::ZERO, DVec3::ZERO),
            PairMode::SecondMesh => (s.pair_translation, s.pair_angles),
        };
        Some(Self {
            mode: s.pair_mode,
            translation,
            angles,
        })
    }
}

/// A mesh index for the pair queries, or why there is none.
type IndexResult = Result<Arc<MeshIndex>, String>;

/// The keys of the values derived from the settings, computed in one place.
/// The derived values are dropped with the model, so no key names it.
struct Keys {
    query: QueryKey,
    linear: LinearKey,
    nodes: NodeKey,
    grid: GridKey,
    frustum: FrustumKey,
}

impl Keys {
    fn of(s: &Settings) -> Self {
        Self {
            query: (s.kind, s.query, s.k),
            linear: (s.kind, s.query),
            nodes: (s.kind, s.node_depth),
            grid: (s.kind, s.cell_size),
            frustum: FrustumKey {
                kind: s.kind,
                eye: s.frustum_eye,
                target: s.frustum_target,
                fov: s.frustum_fov,
                near: s.frustum_near,
                far: s.frustum_far,
                linear: s.compare_linear,
            },
        }
    }
}

/// A brute-force answer and its time.
type LinearAnswer = (Option<ClosestHit>, f64);

/// Everything computed from the model and the settings; a new model starts
/// from `Default` (pending jobs for the old one are abandoned).
#[derive(Default)]
struct Derived {
    query: Memo<QueryKey, QueryResult>,
    /// Brute force runs on a worker thread so that dragging the query point
    /// over a large mesh stays smooth.
    linear: Background<LinearKey, LinearAnswer>,
    grid: Background<GridKey, Result<Arc<CellGrid>, String>>,
    ray: Memo<RayKey, Result<RayWalk, String>>,
    nodes: Memo<NodeKey, Arc<BoxSet>>,
    /// Great circles of the sphere tree's nodes at the depth, and their count.
    spheres: Memo<NodeKey, (usize, Overlay)>,
    frustum: Memo<FrustumKey, Result<FrustumSelection, String>>,
    /// The signed distance field per sign method ([`field_slot`]), each
    /// built on a worker thread when first needed.
    fields: [Background<Sign, FieldResult>; 2],
    slice: Background<SliceKey, Result<Arc<SdfSlice>, String>>,
    readout: Memo<ReadoutKey, SdfReadout>,
    pick_message: Option<String>,
    /// The model's mesh indexed for the pair queries (a copy of the mesh;
    /// its faces' tree is built by the first pair query, on the worker).
    pair_index: Option<Arc<MeshIndex>>,
    /// Self-intersections or the second mesh's answer, on a worker thread
    /// (the queries take seconds on meshes of a million faces).
    pairs: Background<PairKey, Result<Arc<PairAnswer>, String>>,
    /// The animated copy of the model (made when the animation is first
    /// switched on), or why it cannot be animated.
    animation: Option<Result<Animation, String>>,
    /// The animation's latest frame.
    animation_frame: Option<AnimationFrame>,
    /// When the animation (re)started: its clock's zero.
    animation_start: Option<Instant>,
}

/// The viewer application.
pub struct ViewerApp {
    renderer: Option<Arc<Mutex<Renderer>>>,
    gl_error: Arc<Mutex<Option<String>>>,
    model: Option<Arc<Model>>,
    /// A model being loaded, by name, with its progress.
    load: Option<Job<String, Result<Model, String>, Progress>>,
    load_error: Option<String>,
    settings: Settings,
    /// Settings from the command line, applied to the first model only.
    initial: Option<InitialView>,
    derived: Derived,
    camera: OrbitCamera,
    needs_fit: bool,
    viewport: Viewport,
    path_text: String,
    timer: FrameTimer,
    frame_ms: f64,
    script: Option<Script>,
    /// Camera yaw and pitch in degrees from the command line, applied when
    /// the first model is fitted.
    camera_angles: Option<[f32; 2]>,
    /// The second mesh's file (`--second`); a copy of the model when `None`.
    second_path: Option<PathBuf>,
    /// That file, loaded and indexed on a worker thread when first needed
    /// (kept across models).
    second: Background<PathBuf, IndexResult>,
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
        let camera_angles = options.initial.camera;
        let second_path = options.initial.second.clone();
        let mut app = Self {
            renderer,
            gl_error: Arc::new(Mutex::new(renderer_error)),
            model: None,
            load: None,
            load_error: None,
            settings: Settings::default(),
            initial: Some(options.initial),
            derived: Derived::default(),
            camera: OrbitCamera::default(),
            needs_fit: true,
            viewport: Viewport::new([0.0, 0.0], [1.0, 1.0]),
            path_text,
            timer: FrameTimer::default(),
            frame_ms: 0.0,
            script: options.screenshot.map(|s| Script::new(s, outcome)),
            camera_angles,
            second_path,
            second: Background::default(),
        };
        app.start_load(options.source, &cc.egui_ctx);
        app
    }

    fn start_load(&mut self, source: ModelSource, ctx: &egui::Context) {
        let name = match &source {
            ModelSource::File(p) => p.display().to_string(),
            ModelSource::Mesh { name, .. } => name.clone(),
        };
        let starting = Progress {
            stage: "starting".into(),
            fraction: 0.0,
        };
        let job = Job::spawn("load", name, starting, ctx, move |reporter| {
            Model::load(source, &|stage| reporter.report(stage))
        });
        match job {
            Ok(job) => {
                self.load_error = None;
                self.load = Some(job);
            }
            Err(e) => self.load_error = Some(e),
        }
    }

    /// Picks up finished background jobs.
    fn poll_jobs(&mut self, ctx: &egui::Context) {
        if let Some(job) = &self.load {
            let result = match job.poll() {
                Poll::Running => None,
                Poll::Done(result) => Some(result),
                Poll::Lost => Some(Err(format!("{}: loading failed", job.key()))),
            };
            if let Some(result) = result {
                self.load = None;
                match result {
                    Ok(model) => self.set_model(model),
                    // The previous model stays.
                    Err(e) => self.load_error = Some(e),
                }
            }
        }
        // A lost brute-force job is asked again; a lost grid build is an error.
        self.derived.linear.poll(|| None);
        self.derived
            .grid
            .poll(|| Some(Err("the grid build failed".to_string())));
        for field in &mut self.derived.fields {
            field.poll(|| Some(Err("building the signed distance field failed".to_string())));
        }
        self.derived
            .slice
            .poll(|| Some(Err("computing the slice failed".to_string())));
        self.derived
            .pairs
            .poll(|| Some(Err("the pair query failed".to_string())));
        self.second
            .poll(|| Some(Err("loading the second mesh failed".to_string())));
        if self.busy() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
    }

    fn set_model(&mut self, model: Model) {
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
            settings.show_signed_distance = s.show_signed_distance;
            settings.show_slice = s.show_slice;
            settings.slice_axis = s.slice_axis;
            settings.slice_sign = s.slice_sign;
            settings.slice_cut_mesh = s.slice_cut_mesh;
            settings.pair_mode = s.pair_mode;
            settings.pair_angles = s.pair_angles;
            settings.animate = s.animate;
            settings.animation_mode = s.animation_mode;
            settings.wave_amplitude = s.wave_amplitude;
            settings.wave_period = s.wave_period;
            settings.fan_side = s.fan_side;
            let (lo, hi) = Settings::slice_range(&model.bounds, s.slice_axis);
            settings.slice_position = 0.5 * (lo + hi);
        }
        if let Some(initial) = self.initial.take() {
            initial.apply(&mut settings, &model.bounds);
        }
        if !model.has(settings.kind) {
            settings.kind = PrimitiveKind::Vertices;
        }
        self.settings = settings;
        self.load_error = None;
        self.derived = Derived::default();
        self.needs_fit = true;
        self.model = Some(Arc::new(model));
    }

    /// Recomputes what depends on the settings and changed: the query answer,
    /// the tree nodes, the frustum selection and the ray now; brute force and
    /// the grid on worker threads.
    fn update_derived(&mut self, ctx: &egui::Context) {
        let Some(model) = self.model.clone() else {
            return;
        };
        let (s, d) = (&self.settings, &mut self.derived);
        let keys = Keys::of(s);
        d.query
            .get_or_compute(keys.query, |&(kind, query, k)| model.query(kind, query, k, false));
        if s.compare_linear {
            let m = model.clone();
            // Not started (no thread left): the panel keeps its spinner.
            let _ = d.linear.request("linear", keys.linear, ctx, move |(kind, query)| {
                m.linear_closest(kind, query)
            });
        }
        if s.show_nodes {
            d.nodes.get_or_compute(keys.nodes, |&(kind, depth)| {
                Arc::new(BoxSet::new(model.nodes_at_depth(kind, depth)))
            });
        }
        if s.show_spheres {
            d.spheres.get_or_compute(keys.nodes, |&(kind, depth)| {
                let spheres = model.sphere_nodes_at_depth(kind, depth);
                (spheres.len(), spheres_overlay(&spheres))
            });
        }
        if s.show_frustum {
            d.frustum.get_or_compute(keys.frustum, |k| {
                settings_frustum(s).map(|f| frustum_view::select(&model, k.kind, &f, k.linear))
            });
        }
        if s.show_cells {
            let m = model.clone();
            let started = d.grid.request("grid", keys.grid, ctx, move |(kind, cell_size)| {
                CellGrid::build(&m, kind, cell_size).map(Arc::new)
            });
            if let Err(e) = started {
                d.grid.memo.set(keys.grid, Err(e));
            }
        }
        if s.show_ray {
            let grid = d
                .grid
                .memo
                .get(&keys.grid)
                .filter(|_| s.show_cells)
                .and_then(|g| g.as_ref().ok());
            let key = RayKey {
                origin: s.ray_origin,
                direction: s.ray_direction,
                cell_size: s.cell_size,
                steps: s.ray_steps,
                grid: grid.map(|_| keys.grid),
            };
            d.ray.get_or_compute(key, |k| {
                walk_ray(k.origin, k.direction, k.cell_size, k.steps, grid.map(|g| g.as_ref()))
            });
        }
        self.update_signed_distance(&model, ctx);
        self.update_pairs(&model, ctx);
        self.update_animation(&model, ctx);
    }

    /// One frame of the animation when it is on: the model moved to the
    /// wave's shape at the clock's time, its trees updated, the closest
    /// point and the fan answered, and the next frame asked for. The
    /// scripted mode holds the clock at [`SCRIPT_ANIMATION_TIME`], so that
    /// the picture does not depend on how fast frames come.
    fn update_animation(&mut self, model: &Arc<Model>, ctx: &egui::Context) {
        let (s, d) = (&self.settings, &mut self.derived);
        if !s.animate {
            d.animation_start = None;
            return;
        }
        let animation = d.animation.get_or_insert_with(|| Animation::new(model.mesh.clone()));
        let Ok(animation) = animation else {
            return;
        };
        let t = match self.script {
            Some(_) => SCRIPT_ANIMATION_TIME,
            None => d
                .animation_start
                .get_or_insert_with(Instant::now)
                .elapsed()
                .as_secs_f64(),
        };
        let wave = Wave::for_bounds(&model.bounds, s.wave_amplitude, s.wave_period);
        let fan = RayFan::from_query(s.query, &model.bounds, s.fan_side as usize);
        match animation.step(&wave, t, s.animation_mode, s.query, fan) {
            Ok(frame) => d.animation_frame = Some(frame),
            Err(e) => d.animation = Some(Err(e)),
        }
        ctx.request_repaint();
    }

    /// The animation's latest frame, when the animation is on.
    fn current_animation(&self) -> Option<&AnimationFrame> {
        if self.settings.animate {
            self.derived.animation_frame.as_ref()
        } else {
            None
        }
    }

    /// Why the model cannot be animated, when the animation is on.
    fn animation_error(&self) -> Option<&String> {
        match &self.derived.animation {
            Some(Err(e)) if self.settings.animate => Some(e),
            _ => None,
        }
    }

    /// Starts the "Pairs" query the settings ask for, once its meshes are
    /// at hand: the model's index (made now, cheap: its tree is built by the
    /// query) and, with `--second`, the second file (loaded on a worker).
    fn update_pairs(&mut self, model: &Arc<Model>, ctx: &egui::Context) {
        let Some(key) = PairKey::of(&self.settings) else {
            return;
        };
        let d = &mut self.derived;
        let first = d
            .pair_index
            .get_or_insert_with(|| Arc::new(MeshIndex::new(model.mesh.clone())))
            .clone();
        let second = match (&self.second_path, key.mode) {
            (Some(path), PairMode::SecondMesh) => {
                let started = self.second.request("second", path.clone(), ctx, |path| {
                    proxima::io::load(&path)
                        .map(|mesh| Arc::new(MeshIndex::new(mesh)))
                        .map_err(|e| e.to_string())
                });
                if let Err(e) = started {
                    self.second.memo.set(path.clone(), Err(e));
                }
                match self.second.memo.get(path) {
                    Some(Ok(index)) => index.clone(),
                    // Loading, or failed (the panel says which).
                    _ => return,
                }
            }
            _ => first.clone(),
        };
        let started = d.pairs.request("pairs", key, ctx, move |k| {
            match k.mode {
                PairMode::SecondMesh => pair_view::pose_from_angles(k.translation, k.angles)
                    .and_then(|pose| pair_view::second_mesh_view(&first, &second, &pose)),
                _ => pair_view::self_intersection_view(&first),
            }
            .map(Arc::new)
        });
        if let Err(e) = started {
            d.pairs.memo.set(key, Err(e));
        }
    }

    /// The latest "Pairs" answer in the mode shown (a pose drag shows the
    /// last one until the next is in).
    fn current_pairs(&self) -> Option<&Arc<PairAnswer>> {
        let mode = self.settings.pair_mode;
        let answer = self.derived.pairs.memo.latest()?.as_ref().ok()?;
        (mode != PairMode::Off && answer.mode == mode).then_some(answer)
    }

    /// The error of the "Pairs" query asked for, if it failed.
    fn pairs_error(&self) -> Option<&String> {
        let key = PairKey::of(&self.settings)?;
        if key.mode == PairMode::SecondMesh
            && let Some(path) = &self.second_path
            && let Some(Err(e)) = self.second.memo.get(path)
        {
            return Some(e);
        }
        self.derived.pairs.memo.get(&key)?.as_ref().err()
    }

    /// Starts what the signed distance readout and the slice need: the
    /// fields of the sign methods shown, then the slice; the readout itself
    /// is one query, answered now.
    fn update_signed_distance(&mut self, model: &Arc<Model>, ctx: &egui::Context) {
        let (s, d) = (&self.settings, &mut self.derived);
        if !(s.show_signed_distance || s.show_slice) {
            return;
        }
        let mut needed = vec![s.slice_sign];
        if s.show_signed_distance && s.slice_sign != Sign::WindingNumber {
            needed.push(Sign::WindingNumber);
        }
        for sign in needed {
            let background = &mut d.fields[field_slot(sign)];
            let m = model.clone();
            let started = background.request("sdf", sign, ctx, move |sign| signed_distance_field(&m.mesh, sign));
            if let Err(e) = started {
                background.memo.set(sign, Err(e));
            }
        }
        let field = d.fields[field_slot(s.slice_sign)]
            .memo
            .get(&s.slice_sign)
            .and_then(|f| f.as_ref().ok())
            .cloned();
        if s.show_slice
            && let Some(field) = field.clone()
        {
            let key = SliceKey {
                axis: s.slice_axis,
                position: s.slice_position,
                sign: s.slice_sign,
            };
            let bounds = model.bounds;
            let started = d.slice.request("slice", key, ctx, move |k| {
                SlicePlane::through(&bounds, k.axis, k.position, SLICE_RESOLUTION)
                    .map(|plane| Arc::new(SdfSlice::compute(&field, plane)))
            });
            if let Err(e) = started {
                d.slice.memo.set(key, Err(e));
            }
        }
        let winding = d.fields[field_slot(Sign::WindingNumber)]
            .memo
            .get(&Sign::WindingNumber)
            .and_then(|f| f.as_ref().ok());
        if s.show_signed_distance
            && let (Some(field), Some(winding)) = (&field, winding)
        {
            d.readout
                .get_or_compute((s.query, s.slice_sign), |&(p, _)| SdfReadout::at(field, winding, p));
        }
    }

    /// The field of `sign` if it was asked for: built, failed, or `None` while building.
    fn field(&self, sign: Sign) -> Option<&FieldResult> {
        self.derived.fields[field_slot(sign)].memo.get(&sign)
    }

    /// `true` while a signed distance field is being built.
    fn building_field(&self) -> bool {
        self.derived.fields.iter().any(|f| f.running())
    }

    /// The query point's signed distance, when shown and in.
    fn current_readout(&self) -> Option<&SdfReadout> {
        let s = &self.settings;
        if !s.show_signed_distance {
            return None;
        }
        self.derived.readout.get(&(s.query, s.slice_sign))
    }

    /// The latest slice computed, when the slice is shown.
    fn current_slice(&self) -> Option<&Arc<SdfSlice>> {
        if !self.settings.show_slice {
            return None;
        }
        self.derived.slice.memo.latest()?.as_ref().ok()
    }

    fn busy(&self) -> bool {
        self.load.is_some()
            || self.derived.grid.running()
            || self.derived.linear.running()
            || self.building_field()
            || self.derived.slice.running()
            || self.derived.pairs.running()
            || self.second.running()
    }

    /// The brute-force answer for the current query, if it is in.
    fn current_linear(&self) -> Option<LinearAnswer> {
        let &(kind, query, _) = self.derived.query.key()?;
        self.derived.linear.memo.get(&(kind, query)).copied()
    }

    /// The latest grid built.
    fn current_grid(&self) -> Option<&Arc<CellGrid>> {
        self.derived.grid.memo.latest()?.as_ref().ok()
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
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
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
