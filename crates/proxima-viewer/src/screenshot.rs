//! The scripted mode: render a few frames, save the window as a PNG with a
//! small JSON sidecar (where the 3D view is, the frame times), and exit.

use crate::camera::Viewport;
use eframe::egui::ColorImage;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What the scripted mode does.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenshotOptions {
    /// The PNG to write. The sidecar goes to the same path with `.json`
    /// appended.
    pub path: PathBuf,
    /// Frames rendered once everything is loaded and built, before the
    /// capture (at least 3; the frame times are measured over them).
    pub frames: u32,
    /// Give up after this long (loading included).
    pub timeout: Duration,
    /// Draw the measured frames as while the camera moves (many boxes as
    /// points), to measure that level of detail.
    pub moving: bool,
}

impl ScreenshotOptions {
    /// Captures `path` after the default 5 frames, with a 5-minute timeout.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            frames: 5,
            timeout: Duration::from_secs(300),
            moving: false,
        }
    }
}

/// The sidecar path of a screenshot: `out.png` → `out.png.json`.
pub fn sidecar_path(png: &Path) -> PathBuf {
    let mut name = png.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// Intervals between frames.
#[derive(Clone, Debug, Default)]
pub struct FrameTimer {
    last: Option<Instant>,
    intervals: Vec<f64>,
}

/// Frame-time statistics in milliseconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStats {
    /// Mean interval.
    pub mean_ms: f64,
    /// Median interval.
    pub median_ms: f64,
    /// Longest interval.
    pub max_ms: f64,
    /// Number of intervals.
    pub count: usize,
}

impl FrameTimer {
    /// Records the start of a frame.
    pub fn tick(&mut self, now: Instant) {
        if let Some(last) = self.last {
            self.intervals.push(now.duration_since(last).as_secs_f64());
        }
        self.last = Some(now);
    }

    /// Forgets everything recorded.
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// Statistics of the recorded intervals (`None` before two ticks).
    pub fn stats(&self) -> Option<FrameStats> {
        if self.intervals.is_empty() {
            return None;
        }
        let mut sorted = self.intervals.clone();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        Some(FrameStats {
            mean_ms: 1e3 * sorted.iter().sum::<f64>() / n as f64,
            median_ms: 1e3 * sorted[n / 2],
            max_ms: 1e3 * sorted[n - 1],
            count: n,
        })
    }
}

/// What the scripted mode reports besides the image.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenshotReport {
    /// Image width and height in pixels.
    pub image_size: [usize; 2],
    /// Pixels per egui point.
    pub pixels_per_point: f32,
    /// The 3D view, in points.
    pub viewport: Viewport,
    /// Frame times over the measured frames.
    pub frames: Option<FrameStats>,
    /// Name of the model shown.
    pub model: String,
    /// Triangles of the model.
    pub triangles: usize,
    /// Occupied grid cells drawn (0 when none).
    pub cells: usize,
    /// Cells of the signed-distance slice drawn (0 when none).
    pub slice_cells: usize,
    /// Of those, the cells inside the mesh.
    pub slice_inside: usize,
    /// Face pairs of the "Pairs" answer shown (0 when none).
    pub pairs: usize,
    /// Distinct faces in those pairs: on the model, on the second mesh.
    pub pair_faces: [usize; 2],
    /// The animation's last frame, when the animation was on.
    pub animation: Option<AnimationReport>,
}

/// What the scripted mode reports of the animation's last frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimationReport {
    /// The animation's clock, in seconds.
    pub time: f64,
    /// Rays in the fan.
    pub fan_rays: usize,
    /// Of those, the rays that hit the moved mesh.
    pub fan_hits: usize,
    /// Milliseconds the last frame's update took (in the settings' mode).
    pub update_ms: f64,
}

impl ScreenshotReport {
    /// The report as a JSON object (floats written so they read back exactly).
    pub fn to_json(&self) -> String {
        let f = self.frames;
        let opt = |v: Option<f64>| v.map_or("null".to_string(), |x| format!("{x:.3}"));
        format!(
            "{{\n  \"image_size\": [{}, {}],\n  \"pixels_per_point\": {:?},\n  \"viewport\": [{:?}, {:?}, {:?}, {:?}],\n  \
             \"frame_ms_mean\": {},\n  \"frame_ms_median\": {},\n  \"frame_ms_max\": {},\n  \"frames_measured\": {},\n  \
             \"model\": {:?},\n  \"triangles\": {},\n  \"cells\": {},\n  \"slice_cells\": {},\n  \"slice_inside\": {},\n  \"pairs\": {},\n  \"pair_faces\": [{}, {}],\n  \"animation\": {}\n}}\n",
            self.image_size[0],
            self.image_size[1],
            self.pixels_per_point,
            self.viewport.min[0],
            self.viewport.min[1],
            self.viewport.size[0],
            self.viewport.size[1],
            opt(f.map(|s| s.mean_ms)),
            opt(f.map(|s| s.median_ms)),
            opt(f.map(|s| s.max_ms)),
            f.map_or(0, |s| s.count),
            self.model,
            self.triangles,
            self.cells,
            self.slice_cells,
            self.slice_inside,
            self.pairs,
            self.pair_faces[0],
            self.pair_faces[1],
            self.animation.map_or("null".to_string(), |a| format!(
                "{{\"time\": {:?}, \"fan_rays\": {}, \"fan_hits\": {}, \"update_ms\": {:.3}}}",
                a.time, a.fan_rays, a.fan_hits, a.update_ms
            )),
        )
    }
}

/// Writes the image as an opaque RGB PNG (the window's alpha is meaningless).
pub fn save_png(path: &Path, image: &ColorImage) -> Result<(), String> {
    let [w, h] = image.size;
    let rgb: Vec<u8> = image.pixels.iter().flat_map(|c| [c.r(), c.g(), c.b()]).collect();
    image::save_buffer(path, &rgb, w as u32, h as u32, image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::egui::Color32;

    #[test]
    fn frame_timer_statistics() {
        let mut t = FrameTimer::default();
        assert!(t.stats().is_none());
        let start = Instant::now();
        for ms in [0u64, 10, 30, 40] {
            t.tick(start + Duration::from_millis(ms));
        }
        let s = t.stats().unwrap();
        assert_eq!(s.count, 3);
        assert!((s.mean_ms - 40.0 / 3.0).abs() < 1e-9);
        assert!((s.max_ms - 20.0).abs() < 1e-9);
        assert!((s.median_ms - 10.0).abs() < 1e-9);
        t.reset();
        assert!(t.stats().is_none());
    }

    #[test]
    fn sidecar_next_to_the_png_and_json_round_trips_floats() {
        assert_eq!(sidecar_path(Path::new("/tmp/a.png")), PathBuf::from("/tmp/a.png.json"));
        let report = ScreenshotReport {
            image_size: [640, 480],
            pixels_per_point: 1.0,
            viewport: Viewport::new([300.5, 0.0], [339.5, 480.0]),
            frames: None,
            model: "a \"b\"".into(),
            triangles: 3,
            cells: 0,
            slice_cells: 12,
            slice_inside: 5,
            pairs: 7,
            pair_faces: [4, 6],
            animation: None,
        };
        let json = report.to_json();
        assert!(json.contains("\"viewport\": [300.5, 0.0, 339.5, 480.0]"), "{json}");
        assert!(json.contains("\"frame_ms_mean\": null"));
        assert!(
            json.contains("\"slice_cells\": 12,\n  \"slice_inside\": 5,\n  \"pairs\": 7,\n  \"pair_faces\": [4, 6],\n  \"animation\": null\n}"),
            "{json}"
        );
        assert!(json.contains(r#""model": "a \"b\"""#), "{json}");
        let animated = ScreenshotReport {
            animation: Some(AnimationReport {
                time: 0.1,
                fan_rays: 64,
                fan_hits: 20,
                update_ms: 1.25,
            }),
            ..report
        }
        .to_json();
        assert!(
            animated.contains(r#""animation": {"time": 0.1, "fan_rays": 64, "fan_hits": 20, "update_ms": 1.250}"#),
            "{animated}"
        );
    }

    #[test]
    fn png_is_written_opaque() {
        let temp = tempfile::Builder::new()
            .prefix("proxima-viewer-png-")
            .tempdir()
            .unwrap();
        let dir = temp.path();
        let path = dir.join("t.png");
        let mut image = ColorImage::filled([3, 2], Color32::from_rgba_premultiplied(10, 20, 30, 128));
        image.pixels[5] = Color32::from_rgb(255, 0, 255);
        save_png(&path, &image).unwrap();
        let back = image::open(&path).unwrap().to_rgba8();
        assert_eq!(back.dimensions(), (3, 2));
        assert_eq!(back.get_pixel(0, 0).0, [10, 20, 30, 255]);
        assert_eq!(back.get_pixel(2, 1).0, [255, 0, 255, 255]);
        assert!(save_png(&dir.join("missing/dir/t.png"), &image).is_err());
    }
}
