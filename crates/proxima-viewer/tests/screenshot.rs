//! The automated visual test: the viewer's scripted mode renders one frame
//! to a PNG under a virtual X display (`xvfb-run`, Mesa llvmpipe), and the
//! image is checked with tolerant statistics rather than against a golden
//! image (rasterizers differ in the last pixel):
//!
//! - the image has the window's size and is not blank;
//! - the shaded mesh covers a plausible fraction of the 3D view;
//! - the closest-point marker lands on the pixel that the viewer's own camera
//!   function ([`OrbitCamera::fit`] + [`OrbitCamera::project`]) predicts for
//!   the closest point, computed here independently with an [`AabbTree`];
//! - the query line, grid cells, ray and frustum selection appear when asked for, and not
//!   otherwise;
//! - the signed-distance slice, when asked for, shows both inside (blue) and
//!   outside (red) pixels and its zero contour, and is absent otherwise;
//! - the animated demo draws the mesh moved by its wave: the closest-point
//!   marker lands where the closest point on the moved mesh projects (several
//!   pixels from where it is at rest), and the fan's hits equal brute force
//!   over the moved triangles;
//! - a broken mesh file makes the scripted mode fail with the file's name, and
//!   a slice asked of a mesh without faces fails with the library's reason.
//!
//! The event loop must run on a process's main thread, so this test has its
//! own `main` (`harness = false`): the parent process starts itself again as
//! a child under `xvfb-run -a -s "-screen 0 1280x800x24"` with
//! `PROXIMA_VIEWER_CHILD=<scenario>`, and the child calls
//! [`proxima_viewer::run`]. Without `xvfb-run` it uses `DISPLAY` directly;
//! with neither it prints a `skipped:` line and passes.

use proxima::math::Vec3;
use proxima::prelude::*;
use proxima::{AabbTree, BuildConfig, LinearSearch, Mesh, Sign};
use proxima_viewer::animation::{RayFan, Wave};
use proxima_viewer::scene::colors;
use proxima_viewer::{
    Axis, InitialView, ModelSource, OrbitCamera, PairMode, PrimitiveKind, ScreenshotOptions, ViewerOptions, Viewport,
};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

const BUNNY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../proxima-cli/assets/bunny-npm.obj");
const WINDOW: [f32; 2] = [1280.0, 800.0];

/// A scenario: the mesh and what the viewer shows.
struct Scenario {
    name: &'static str,
    mesh: PathBuf,
    kind: PrimitiveKind,
    query: Vec3,
    cells: Option<f32>,
    ray: Option<(Vec3, Vec3)>,
    /// A second camera's eye and target (frustum query shown).
    frustum: Option<(Vec3, Vec3)>,
    /// A signed-distance slice: its axis, position and sign method.
    slice: Option<(Axis, Option<f32>, Sign)>,
    /// The "Pairs" mode (a second mesh: a copy at the default pose).
    pairs: Option<PairMode>,
    /// The animated demo: the model moved by the wave, the fan of rays.
    animate: bool,
    frames: u32,
}

/// The embedded bunny's faces from the query point (3, 6, 4), nothing else
/// shown, three frames: the base every scenario changes.
fn bunny(name: &'static str) -> Scenario {
    Scenario {
        name,
        mesh: BUNNY.into(),
        kind: PrimitiveKind::Faces,
        query: Vec3::new(3.0, 6.0, 4.0),
        cells: None,
        ray: None,
        frustum: None,
        slice: None,
        pairs: None,
        animate: false,
        frames: 3,
    }
}

fn scenarios() -> Vec<Scenario> {
    // `PROXIMA_DATA_DIR` when set, else ../shared/data beside the checkout.
    let data = std::env::var_os("PROXIMA_DATA_DIR").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
        std::path::PathBuf::from,
    );
    let dragon = data.join("dragon_vrip.ply.gz");
    let mut list = vec![
        Scenario {
            frames: 5,
            ..bunny("bunny_faces")
        },
        Scenario {
            kind: PrimitiveKind::Edges,
            query: Vec3::new(-3.0, 4.0, 4.5),
            cells: Some(0.5),
            ray: Some((Vec3::new(-6.0, 1.0, -4.0), Vec3::new(1.0, 0.45, 0.7))),
            frames: 5,
            ..bunny("bunny_edges_cells_ray")
        },
        Scenario {
            kind: PrimitiveKind::Polygons,
            frustum: Some((Vec3::new(-15.0, 5.0, 0.0), Vec3::new(0.0, 6.0, 0.0))),
            ..bunny("bunny_polygons_frustum")
        },
        Scenario {
            slice: Some((Axis::Z, None, Sign::WindingNumber)),
            ..bunny("bunny_slice_winding")
        },
        Scenario {
            slice: Some((Axis::X, Some(0.5), Sign::Pseudonormal)),
            ..bunny("bunny_slice_pseudonormal_x")
        },
        Scenario {
            pairs: Some(PairMode::SecondMesh),
            ..bunny("bunny_second_copy")
        },
        Scenario {
            mesh: point_cloud_file(),
            kind: PrimitiveKind::Vertices,
            query: Vec3::ZERO,
            slice: Some((Axis::Z, None, Sign::WindingNumber)),
            ..bunny("points_slice")
        },
        Scenario {
            animate: true,
            frames: 5,
            ..bunny("bunny_animated")
        },
        Scenario {
            mesh: broken_file(),
            query: Vec3::ZERO,
            ..bunny("broken_file")
        },
    ];
    if dragon.exists() {
        list.push(Scenario {
            mesh: dragon,
            kind: PrimitiveKind::Vertices,
            query: Vec3::new(0.0, 0.15, 0.06),
            cells: Some(0.002),
            frames: 8,
            ..bunny("dragon_vertices_cells")
        });
    } else {
        println!("skipped: dragon scenario ({} not found)", dragon.display());
    }
    list
}

fn out_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("proxima-viewer-screenshot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    dir
}

/// The broken mesh, inside the output directory (removed with it when every
/// scenario passes): a child finds that directory from its output path.
fn broken_file() -> PathBuf {
    match std::env::var_os("PROXIMA_VIEWER_OUT") {
        Some(out) => Path::new(&out).with_file_name("broken.obj"),
        None => out_dir().join("broken.obj"),
    }
}

/// A mesh of three vertices and no face (no signed distance), beside the
/// broken file.
fn point_cloud_file() -> PathBuf {
    broken_file().with_file_name("points.obj")
}

fn main() -> ExitCode {
    if let Ok(name) = std::env::var("PROXIMA_VIEWER_CHILD") {
        return child(&name);
    }
    // Honour `cargo test -- --list` and name filters like libtest, roughly.
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--list") {
        println!("screenshot: test");
        return ExitCode::SUCCESS;
    }
    let filter = args.iter().find(|a| !a.starts_with('-'));
    if filter.is_some_and(|f| !"screenshot".contains(f.as_str())) {
        return ExitCode::SUCCESS;
    }
    let xvfb = which("xvfb-run");
    let display = std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty());
    if xvfb.is_none() && !display {
        println!("skipped: viewer screenshot test (neither xvfb-run nor DISPLAY is available)");
        return ExitCode::SUCCESS;
    }
    std::fs::write(broken_file(), "v 0 0 0\nv 1 0 0\nf 1 2 7\n").expect("write the broken file");
    std::fs::write(point_cloud_file(), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").expect("write the point cloud");
    let dir = out_dir();
    let mut failures = 0;
    for scenario in scenarios() {
        let start = Instant::now();
        let result = run_scenario(&scenario, &dir, xvfb.as_deref());
        match result {
            Ok(note) => println!(
                "test screenshot::{} ... ok ({:.1} s) {note}",
                scenario.name,
                start.elapsed().as_secs_f32()
            ),
            Err(e) => {
                println!("test screenshot::{} ... FAILED\n{e}", scenario.name);
                failures += 1;
            }
        }
    }
    if failures == 0 {
        let _ = std::fs::remove_dir_all(&dir);
        println!("screenshot: all scenarios passed (images were in {})", dir.display());
        ExitCode::SUCCESS
    } else {
        println!(
            "screenshot: {failures} scenario(s) failed; images kept in {}",
            dir.display()
        );
        ExitCode::FAILURE
    }
}

fn which(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// The child: render the scenario and exit 0, or print the error and exit 1.
fn child(name: &str) -> ExitCode {
    let scenario = scenarios()
        .into_iter()
        .find(|s| s.name == name)
        .expect("known scenario");
    let out = PathBuf::from(std::env::var("PROXIMA_VIEWER_OUT").expect("PROXIMA_VIEWER_OUT"));
    let options = ViewerOptions {
        source: ModelSource::File(scenario.mesh.clone()),
        initial: InitialView {
            query: Some(scenario.query),
            kind: Some(scenario.kind),
            cells: scenario.cells,
            ray: scenario.ray,
            frustum: scenario.frustum,
            slice: scenario.slice.map(|(axis, position, _)| (axis, position)),
            slice_sign: scenario.slice.map(|(_, _, sign)| sign),
            pairs: scenario.pairs,
            animate: scenario.animate.then_some(proxima_viewer::animation::UpdateMode::Refit),
            ..Default::default()
        },
        screenshot: Some(ScreenshotOptions {
            path: out,
            frames: scenario.frames,
            timeout: Duration::from_secs(240),
            moving: false,
        }),
        window_size: WINDOW,
    };
    match proxima_viewer::run(options) {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("viewer: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs the child under Xvfb (or the current display) with a time limit.
fn spawn_child(name: &str, out: &Path, xvfb: Option<&Path>) -> Result<(bool, String), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut command = match xvfb {
        Some(xvfb) => {
            let mut c = Command::new(xvfb);
            c.args(["-a", "-s", "-screen 0 1280x800x24"]).arg(&exe);
            c
        }
        None => Command::new(&exe),
    };
    let runtime_dir = out.with_extension("runtime");
    let _ = std::fs::create_dir_all(&runtime_dir);
    command
        .env("PROXIMA_VIEWER_CHILD", name)
        .env("PROXIMA_VIEWER_OUT", out)
        .env("XDG_RUNTIME_DIR", &runtime_dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = command.spawn().map_err(|e| format!("cannot start the viewer: {e}"))?;
    let limit = Duration::from_secs(300);
    let start = Instant::now();
    loop {
        if child.try_wait().map_err(|e| e.to_string())?.is_some() {
            break;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("the viewer did not finish within {} s", limit.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let output = child.wait_with_output().map_err(|e| e.to_string())?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    Ok((output.status.success(), text))
}

fn run_scenario(s: &Scenario, dir: &Path, xvfb: Option<&Path>) -> Result<String, String> {
    let out = dir.join(format!("{}.png", s.name));
    let (success, log) = spawn_child(s.name, &out, xvfb)?;
    if s.name == "broken_file" {
        // Bad input: no panic, a non-zero exit and a message naming the file and line.
        check(!success, "the scripted mode succeeded on a broken file")?;
        check(!log.contains("panicked"), &format!("the viewer panicked:\n{log}"))?;
        let expected = format!("{}:3", broken_file().display());
        check(
            log.contains(&expected),
            &format!("no '{expected}' in the output:\n{log}"),
        )?;
        return Ok("(error reported)".into());
    }
    if s.name == "points_slice" {
        check(!success, "the scripted mode drew a slice of a mesh without faces")?;
        check(!log.contains("panicked"), &format!("the viewer panicked:\n{log}"))?;
        check(
            log.contains("slice: the mesh has no faces"),
            &format!("no 'slice: the mesh has no faces' in the output:\n{log}"),
        )?;
        return Ok("(error reported)".into());
    }
    check(success, &format!("the viewer failed:\n{log}"))?;
    let sidecar: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(format!("{}.json", out.display())).map_err(|e| format!("sidecar: {e}"))?,
    )
    .map_err(|e| format!("sidecar: {e}"))?;
    let image = image::open(&out)
        .map_err(|e| format!("{}: {e}", out.display()))?
        .to_rgb8();
    let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN) as f32;
    let ppp = f(&sidecar["pixels_per_point"]);
    let v = &sidecar["viewport"];
    let viewport = Viewport::new([f(&v[0]), f(&v[1])], [f(&v[2]), f(&v[3])]);
    let size = [image.width() as usize, image.height() as usize];
    check(
        sidecar["image_size"][0].as_u64() == Some(size[0] as u64)
            && sidecar["image_size"][1].as_u64() == Some(size[1] as u64),
        "image size differs from the sidecar",
    )?;
    check(
        (size[0] as f32 - WINDOW[0] * ppp).abs() <= 2.0 && (size[1] as f32 - WINDOW[1] * ppp).abs() <= 2.0,
        &format!("image is {size:?}, the window {WINDOW:?} at {ppp} px/pt"),
    )?;

    // The 3D view in pixels.
    let px = viewport.scaled(ppp);
    let x0 = px.min[0].ceil() as u32;
    let y0 = px.min[1].ceil() as u32;
    let x1 = ((px.min[0] + px.size[0]).floor() as u32).min(image.width());
    let y1 = ((px.min[1] + px.size[1]).floor() as u32).min(image.height());
    let view_pixels = ((x1 - x0) * (y1 - y0)) as f64;
    let count = |pred: &dyn Fn([u8; 3]) -> bool| {
        let mut n = 0usize;
        let (mut sx, mut sy) = (0f64, 0f64);
        for y in y0..y1 {
            for x in x0..x1 {
                if pred(image.get_pixel(x, y).0) {
                    n += 1;
                    sx += x as f64;
                    sy += y as f64;
                }
            }
        }
        (
            n,
            if n > 0 {
                [sx / n as f64, sy / n as f64]
            } else {
                [f64::NAN; 2]
            },
        )
    };

    // Not blank: many distinct colours, and the side panel differs from the view.
    let mut distinct = std::collections::HashSet::new();
    for p in image.pixels().step_by(7) {
        distinct.insert(p.0);
    }
    check(
        distinct.len() > 100,
        &format!("only {} distinct colours: blank?", distinct.len()),
    )?;

    // The mesh: shaded from its light-blue base colour, blue dominates.
    let near = |a: u8, b: u8, tol: u8| a.abs_diff(b) <= tol;
    let is_mesh = |p: [u8; 3]| p[2] > 60 && p[2] as i32 > p[0] as i32 + 25 && p[2] as i32 > p[1] as i32 + 5;
    let (mesh, _) = count(&is_mesh);
    let coverage = mesh as f64 / view_pixels;
    let bg = colors::BACKGROUND;
    let (background, _) = count(&|p| near(p[0], bg[0], 2) && near(p[1], bg[1], 2) && near(p[2], bg[2], 2));
    // The slice hides the mesh behind it and the cut removes the mesh in front.
    check(
        s.slice.is_some() || (0.03..0.85).contains(&coverage),
        &format!("mesh covers {:.1}% of the view", 100.0 * coverage),
    )?;
    check(
        background as f64 > 0.1 * view_pixels,
        &format!("background covers only {background} pixels"),
    )?;

    // Where the closest point must appear: the viewer's camera, fitted to the
    // mesh in a view of this aspect, projecting the tree's closest point.
    let rest: Mesh = proxima::io::load(&s.mesh).map_err(|e| e.to_string())?;
    // The animation draws the mesh moved by the wave at the sidecar's time.
    let mesh_data = if s.animate {
        moved(&rest, &sidecar)?
    } else {
        rest.clone()
    };
    let hit = match s.kind {
        PrimitiveKind::Vertices => AabbTree::build_set(mesh_data.vertices(), &BuildConfig::default())
            .map_err(|e| e.to_string())?
            .closest(s.query),
        PrimitiveKind::Edges => AabbTree::build_set(mesh_data.edges(), &BuildConfig::default())
            .map_err(|e| e.to_string())?
            .closest(s.query),
        PrimitiveKind::Faces => AabbTree::build_set(mesh_data.triangles(), &BuildConfig::default())
            .map_err(|e| e.to_string())?
            .closest(s.query),
        PrimitiveKind::Polygons => AabbTree::build_set(mesh_data.polygons(), &BuildConfig::default())
            .map_err(|e| e.to_string())?
            .closest(s.query),
    }
    .ok_or("no closest point")?;
    // The camera is fitted to the model at rest.
    let camera = OrbitCamera::fit(&rest.bounds(), viewport.aspect());
    let expected = camera
        .project(hit.point, &px)
        .ok_or("closest point behind the camera")?;
    let animation_note = if s.animate {
        animation_checks(&rest, &mesh_data, &sidecar, s.query, &camera, &px, expected)?
    } else {
        check(sidecar["animation"].is_null(), "an animation reported without one")?;
        String::new()
    };
    let c = colors::CLOSEST;
    let (marker, centroid) = count(&|p| near(p[0], c[0], 40) && near(p[1], c[1], 40) && near(p[2], c[2], 40));
    check(
        marker >= 20,
        &format!("closest-point marker: only {marker} magenta pixels"),
    )?;
    // Pixel (i, j) covers [i, i + 1) × [j, j + 1): a disc centred on the
    // expected point has its pixel indices centred half a pixel before it.
    let dx = centroid[0] + 0.5 - expected[0] as f64;
    let dy = centroid[1] + 0.5 - expected[1] as f64;
    check(
        dx.hypot(dy) <= 2.0,
        &format!("closest-point marker at {centroid:?}, expected {expected:?} (off by {dx:.2}, {dy:.2})"),
    )?;
    let q = colors::QUERY;
    let (query_marker, _) = count(&|p| near(p[0], q[0], 30) && near(p[1], q[1], 30) && near(p[2], q[2], 30));
    let expected_query = camera.project(s.query, &px).ok_or("query behind the camera")?;
    let query_visible = (0.0..px.size[0]).contains(&(expected_query[0] - px.min[0]))
        && (0.0..px.size[1]).contains(&(expected_query[1] - px.min[1]));
    check(
        !query_visible || query_marker >= 10,
        &format!("query marker: {query_marker} pixels"),
    )?;

    // Cells and ray: present exactly when asked for.
    let cell = colors::CELLS;
    let (cells, _) = count(&|p| near(p[0], cell[0], 6) && near(p[1], cell[1], 6) && near(p[2], cell[2], 6));
    let r = colors::RAY;
    let (ray, _) = count(&|p| near(p[0], r[0], 30) && near(p[1], r[1], 30) && p[2] < 60);
    let g = colors::RAY_CELLS;
    let (ray_cells, _) = count(&|p| near(p[0], g[0], 30) && near(p[1], g[1], 30) && near(p[2], g[2], 30));
    let sidecar_cells = sidecar["cells"].as_u64().unwrap_or(0);
    if s.cells.is_some() {
        check(sidecar_cells > 0, "no occupied cells reported")?;
        check(
            cells as f64 > 0.005 * view_pixels,
            &format!("grid cells: only {cells} pixels"),
        )?;
    } else {
        check(
            sidecar_cells == 0 && cells < 50,
            &format!("{cells} cell-coloured pixels without cells"),
        )?;
    }
    if s.ray.is_some() {
        check(ray > 30, &format!("ray: only {ray} yellow pixels"))?;
        check(ray_cells > 100, &format!("ray cells: only {ray_cells} green pixels"))?;
    } else if s.animate {
        // The fan's hits are drawn in the ray's colour.
        check(ray > 30, &format!("fan: only {ray} yellow pixels"))?;
        check(ray_cells < 10, "ray-cell pixels without a ray")?;
    } else {
        check(ray < 10 && ray_cells < 10, "ray pixels without a ray")?;
    }
    // The frustum's selection: its highlight colour appears exactly when asked for.
    let h = colors::FRUSTUM_SELECTED;
    let (selected, _) = count(&|p| near(p[0], h[0], 30) && near(p[1], h[1], 30) && near(p[2], h[2], 30));
    if s.frustum.is_some() {
        check(
            selected as f64 > 0.002 * view_pixels,
            &format!("frustum selection: only {selected} highlighted pixels"),
        )?;
    } else {
        check(
            selected < 10,
            &format!("{selected} frustum-highlight pixels without a frustum"),
        )?;
    }
    // The slice: blue inside (red = green, unlike the mesh's blue), red
    // outside (green = blue), a dark zero contour; none without a slice.
    let (slice_blue, _) = count(&|p| p[2] as i32 > p[0] as i32 + 60 && p[0].abs_diff(p[1]) <= 4);
    let (slice_red, _) = count(&|p| p[0] as i32 > p[2] as i32 + 60 && p[1].abs_diff(p[2]) <= 4);
    let z = colors::ZERO_CONTOUR;
    let (contour, _) = count(&|p| near(p[0], z[0], 12) && near(p[1], z[1], 12) && near(p[2], z[2], 12));
    let slice_cells = sidecar["slice_cells"].as_u64().unwrap_or(0);
    let slice_inside = sidecar["slice_inside"].as_u64().unwrap_or(0);
    if s.slice.is_some() {
        check(
            slice_cells > 1000 && slice_inside > 0 && slice_inside < slice_cells,
            &format!("slice: {slice_inside} of {slice_cells} cells inside"),
        )?;
        check(
            slice_blue as f64 > 0.01 * view_pixels && slice_red as f64 > 0.01 * view_pixels,
            &format!("slice: {slice_blue} blue and {slice_red} red pixels"),
        )?;
        check(contour > 50, &format!("zero contour: only {contour} dark pixels"))?;
    } else {
        check(
            slice_cells == 0 && slice_blue < 50,
            &format!("{slice_blue} slice-blue pixels and {slice_cells} slice cells without a slice"),
        )?;
    }
    // The pairs: the meeting faces of both meshes and the second mesh's
    // outlines in their colours exactly when asked for; the sidecar's counts
    // equal the library's answer for the same pose.
    let colour = |c: [u8; 4]| count(&|p| near(p[0], c[0], 30) && near(p[1], c[1], 30) && near(p[2], c[2], 30)).0;
    let (meeting, meeting_second, outlines) = (
        colour(colors::PAIR_MEETING),
        colour(colors::PAIR_MEETING_SECOND),
        colour(colors::SECOND_MESH),
    );
    let sidecar_pairs = sidecar["pairs"].as_u64().unwrap_or(0);
    if s.pairs == Some(PairMode::SecondMesh) {
        let index = proxima::MeshIndex::new(mesh_data.clone());
        let settings = proxima_viewer::Settings::for_bounds(&mesh_data.bounds());
        let pose = proxima_viewer::pair_view::settings_pose(&settings)?;
        let pairs = proxima::pair::intersecting_pairs(&index, &proxima::pair::RigidPose::IDENTITY, &index, &pose)
            .map_err(|e| e.to_string())?;
        check(
            !pairs.is_empty() && sidecar_pairs == pairs.len() as u64,
            &format!("pairs: the sidecar says {sidecar_pairs}, the library {}", pairs.len()),
        )?;
        check(
            meeting > 50 && meeting_second > 50 && outlines as f64 > 0.005 * view_pixels,
            &format!("pairs: {meeting} and {meeting_second} meeting-face pixels, {outlines} outline pixels"),
        )?;
    } else {
        // The slice's map passes through the outlines' sand between red and white.
        check(
            sidecar_pairs == 0 && meeting < 10 && meeting_second < 10 && (s.slice.is_some() || outlines < 10),
            &format!("{meeting}, {meeting_second} and {outlines} pair pixels without pairs"),
        )?;
    }
    let frames = format!(
        "frame {} ms mean, {} ms max; {} triangles, {} cells; mesh {:.1}% of the view, marker {:.1} px from the projection, {} frustum-highlight pixels, slice {}/{} cells inside, {} blue and {} red pixels, {} face pairs ({} and {} meeting-face pixels)",
        sidecar["frame_ms_mean"],
        sidecar["frame_ms_max"],
        sidecar["triangles"],
        sidecar_cells,
        100.0 * coverage,
        dx.hypot(dy),
        selected,
        slice_inside,
        slice_cells,
        slice_blue,
        slice_red,
        sidecar_pairs,
        meeting,
        meeting_second
    );
    Ok(frames + &animation_note)
}

/// The model moved by the viewer's wave (its default height and period,
/// sized by the model's box at rest) at the time the sidecar reports.
fn moved(rest: &Mesh, sidecar: &serde_json::Value) -> Result<Mesh, String> {
    let time = sidecar["animation"]["time"]
        .as_f64()
        .ok_or("the sidecar reports no animation time")?;
    let settings = proxima_viewer::Settings::for_bounds(&rest.bounds());
    let wave = Wave::for_bounds(&rest.bounds(), settings.wave_amplitude, settings.wave_period);
    let mut positions = Vec::new();
    wave.displace(rest.positions(), time, &mut positions);
    let mut mesh = rest.clone();
    mesh.set_positions(&positions).map_err(|e| e.to_string())?;
    Ok(mesh)
}

/// The animated scenario's own checks: the wave moved the closest point by
/// several pixels (so the marker check above saw the moved mesh, not the
/// model at rest), and the fan's rays hit the moved mesh as often as brute
/// force over its triangles says.
fn animation_checks(
    rest: &Mesh,
    moved: &Mesh,
    sidecar: &serde_json::Value,
    query: Vec3,
    camera: &OrbitCamera,
    px: &Viewport,
    expected: [f32; 2],
) -> Result<String, String> {
    let at_rest = LinearSearch::new(rest.triangles())
        .closest(query)
        .ok_or("no closest point at rest")?;
    let rest_pixel = camera
        .project(at_rest.point, px)
        .ok_or("closest point behind the camera")?;
    let shift = (rest_pixel[0] - expected[0]).hypot(rest_pixel[1] - expected[1]);
    check(
        shift >= 4.0,
        &format!("the wave moves the closest point by only {shift:.1} px: the scenario cannot tell"),
    )?;
    let settings = proxima_viewer::Settings::for_bounds(&rest.bounds());
    let fan = RayFan::from_query(query, &rest.bounds(), settings.fan_side as usize);
    let linear = LinearSearch::new(moved.triangles());
    let hits = fan
        .directions
        .iter()
        .filter(|&&d| {
            linear
                .first_hit(fan.origin, d, 0.0, f32::INFINITY)
                .is_ok_and(|h| h.is_some())
        })
        .count();
    let a = &sidecar["animation"];
    check(
        a["fan_rays"].as_u64() == Some(fan.directions.len() as u64) && a["fan_hits"].as_u64() == Some(hits as u64),
        &format!(
            "fan: the sidecar says {} of {} rays hit, brute force {hits} of {}",
            a["fan_hits"],
            a["fan_rays"],
            fan.directions.len()
        ),
    )?;
    check(hits > 0 && hits < fan.directions.len(), &format!("fan: {hits} hits"))?;
    Ok(format!(
        "; animated: closest point {shift:.1} px from where it is at rest, {hits} of {} fan rays hit, update {} ms",
        fan.directions.len(),
        a["update_ms"]
    ))
}

fn check(condition: bool, message: &str) -> Result<(), String> {
    if condition { Ok(()) } else { Err(message.to_string()) }
}
