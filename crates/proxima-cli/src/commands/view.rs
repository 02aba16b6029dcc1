//! `proxima view [MESH]`: the interactive viewer, or (with `--screenshot`)
//! one rendered frame written to a PNG.

use crate::common::{DEFAULT_MODEL_NAME, kind_parser, load_or_default, parse_vec3};
use anyhow::Result;
use proxima::{DVec3, PrimitiveKind, Sign, Vec3};
use proxima_viewer::animation::UpdateMode;
use proxima_viewer::{Axis, InitialView, ModelSource, PairMode, ScreenshotOptions, ViewerOptions};
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `proxima view`.
#[derive(clap::Args)]
pub struct Args {
    /// Mesh file (.obj, .ply, .stl, .off, .glb, optionally .gz); the embedded bunny when omitted.
    mesh: Option<PathBuf>,
    /// Render one frame to this PNG and exit (needs a display; under CI use xvfb-run).
    #[arg(long, value_name = "PNG")]
    screenshot: Option<PathBuf>,
    /// Frames drawn before the screenshot (their times are printed).
    #[arg(long, default_value_t = 5, value_name = "N", requires = "screenshot")]
    frames: u32,
    /// Draw the measured frames as while the camera moves (many boxes as points).
    #[arg(long, requires = "screenshot")]
    moving: bool,
    /// Query point.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    query: Option<Vec3>,
    /// Primitives queried, put in the grid and shown in the tree.
    #[arg(long, value_parser = kind_parser())]
    primitives: Option<PrimitiveKind>,
    /// Show the occupied cells of a hash grid with this cell size.
    #[arg(long, value_name = "SIZE", value_parser = parse_cell_size)]
    show_cells: Option<f32>,
    /// Show a ray and the cells it walks through.
    #[arg(long, value_name = "OX,OY,OZ,DX,DY,DZ", value_parser = parse_ray, allow_hyphen_values = true)]
    show_ray: Option<(Vec3, Vec3)>,
    /// Number of cells the ray walks.
    #[arg(long, value_name = "N")]
    ray_steps: Option<u32>,
    /// Show the AABB tree's nodes at this depth.
    #[arg(long, value_name = "DEPTH")]
    tree_depth: Option<u32>,
    /// Highlight the k nearest primitives.
    #[arg(short, value_name = "K")]
    k: Option<usize>,
    /// Show a second camera's frustum, from EYE looking at TARGET, and the primitives its query selects.
    #[arg(long, value_name = "EX,EY,EZ,TX,TY,TZ", value_parser = parse_frustum, allow_hyphen_values = true)]
    frustum: Option<(Vec3, Vec3)>,
    /// Vertical field of view of the second camera, in degrees.
    #[arg(long, value_name = "DEG", value_parser = parse_fov, requires = "frustum")]
    frustum_fov: Option<f32>,
    /// Show a slice coloured by signed distance, normal to AXIS (x, y or z), at POSITION
    /// (the middle of the model's box when omitted).
    #[arg(long, value_name = "AXIS[,POSITION]", value_parser = parse_slice, allow_hyphen_values = true)]
    slice: Option<(Axis, Option<f32>)>,
    /// How the slice and the query point's signed distance decide inside: winding (the
    /// generalized winding number) or pseudonormal.
    #[arg(long, value_name = "METHOD", value_parser = parse_sign)]
    slice_sign: Option<Sign>,
    /// Camera yaw about +y and pitch above the horizon, in degrees (yaw 0 looks along -z;
    /// the default view is 29,17).
    #[arg(long, value_name = "YAW,PITCH", value_parser = parse_angles, allow_hyphen_values = true)]
    camera: Option<[f32; 2]>,
    /// Show pairs: self (the model's self-intersections), second (a second mesh placed by
    /// --pair-pose against the model) or off.
    #[arg(long, value_name = "MODE", value_parser = parse_pairs)]
    pairs: Option<PairMode>,
    /// The second mesh (a copy of the model when omitted); implies --pairs second.
    #[arg(long, value_name = "PATH")]
    second: Option<PathBuf>,
    /// The second mesh's pose: a translation, then angles in degrees about x, y and z
    /// (applied in that order).
    #[arg(long, value_name = "TX,TY,TZ,AX,AY,AZ", value_parser = parse_pair_pose, allow_hyphen_values = true)]
    pair_pose: Option<(DVec3, DVec3)>,
    /// Deform the model every frame by a travelling wave: its trees are refit (or rebuilt:
    /// `--animate rebuild`; the panel switches) and the closest point and a fan of rays from the query point are
    /// answered on the moved surface, with the update's time shown.
    #[arg(long, value_name = "MODE", num_args = 0..=1, default_missing_value = "refit", value_parser = UpdateMode::parse)]
    animate: Option<UpdateMode>,
    /// Window size in points.
    #[arg(long, value_name = "WxH", default_value = "1280x800", value_parser = parse_size)]
    size: [f32; 2],
}

fn parse_cell_size(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(h) if h.is_finite() && h > 0.0 => Ok(h),
        _ => Err(format!("expected a positive cell size, got '{text}'")),
    }
}

fn parse_ray(text: &str) -> Result<(Vec3, Vec3), String> {
    let numbers: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    if numbers.len() != 6 {
        return Err(format!("expected six numbers OX,OY,OZ,DX,DY,DZ, got '{text}'"));
    }
    let origin = parse_vec3(&numbers[..3].join(","))?;
    let direction = parse_vec3(&numbers[3..].join(","))?;
    if direction == Vec3::ZERO {
        return Err("the ray direction must not be zero".into());
    }
    Ok((origin, direction))
}

fn parse_frustum(text: &str) -> Result<(Vec3, Vec3), String> {
    let numbers: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    if numbers.len() != 6 {
        return Err(format!("expected six numbers EX,EY,EZ,TX,TY,TZ, got '{text}'"));
    }
    let eye = parse_vec3(&numbers[..3].join(","))?;
    let target = parse_vec3(&numbers[3..].join(","))?;
    if eye == target {
        return Err("the frustum's eye and target must differ".into());
    }
    Ok((eye, target))
}

fn parse_pairs(text: &str) -> Result<PairMode, String> {
    text.parse()
}

fn parse_pair_pose(text: &str) -> Result<(DVec3, DVec3), String> {
    let numbers: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    let values: Vec<f64> = numbers.iter().filter_map(|s| s.parse::<f64>().ok()).collect();
    match values[..] {
        [tx, ty, tz, ax, ay, az] if numbers.len() == 6 && values.iter().all(|v| v.is_finite()) => {
            Ok((DVec3::new(tx, ty, tz), DVec3::new(ax, ay, az)))
        }
        _ => Err(format!("expected six finite numbers TX,TY,TZ,AX,AY,AZ, got '{text}'")),
    }
}

fn parse_fov(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(d) if d > 0.0 && d < 180.0 => Ok(d),
        _ => Err(format!(
            "expected a field of view between 0 and 180 degrees, got '{text}'"
        )),
    }
}

fn parse_slice(text: &str) -> Result<(Axis, Option<f32>), String> {
    let (axis, position) = match text.split_once(',') {
        Some((axis, position)) => (axis, Some(position)),
        None => (text, None),
    };
    let axis: Axis = axis.parse()?;
    let position = match position {
        None => None,
        Some(p) => match p.trim().parse::<f32>() {
            Ok(v) if v.is_finite() => Some(v),
            _ => return Err(format!("expected a finite slice position after the axis, got '{p}'")),
        },
    };
    Ok((axis, position))
}

fn parse_sign(text: &str) -> Result<Sign, String> {
    text.trim().parse()
}

fn parse_angles(text: &str) -> Result<[f32; 2], String> {
    let numbers: Vec<&str> = text.split([',', ' ', '\t']).filter(|s| !s.is_empty()).collect();
    let angles: Vec<f32> = numbers.iter().filter_map(|s| s.parse::<f32>().ok()).collect();
    match angles[..] {
        [yaw, pitch] if numbers.len() == 2 && yaw.is_finite() && (-90.0..=90.0).contains(&pitch) => Ok([yaw, pitch]),
        _ => Err(format!(
            "expected YAW,PITCH in degrees with the pitch between -90 and 90, got '{text}'"
        )),
    }
}

fn parse_size(text: &str) -> Result<[f32; 2], String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT, got '{text}'"))?;
    let parse = |s: &str| match s.trim().parse::<f32>() {
        Ok(v) if (64.0..=8192.0).contains(&v) => Ok(v),
        _ => Err(format!("'{s}' is not a size between 64 and 8192")),
    };
    Ok([parse(w)?, parse(h)?])
}

/// Opens the viewer (or renders the screenshot).
pub fn run(args: Args) -> Result<()> {
    // Fail before opening a window when there is no display to open it on.
    if !proxima_viewer::display_available() {
        return Err(proxima_viewer::ViewerError::NoDisplay.into());
    }
    let source = match args.mesh {
        Some(path) => ModelSource::File(path),
        None => {
            let (mesh, name) = load_or_default(None)?;
            debug_assert_eq!(name, DEFAULT_MODEL_NAME);
            ModelSource::Mesh { mesh, name }
        }
    };
    let kind = args.primitives;
    let options = ViewerOptions {
        source,
        initial: InitialView {
            query: args.query,
            kind,
            cells: args.show_cells,
            ray: args.show_ray,
            ray_steps: args.ray_steps,
            tree_depth: args.tree_depth,
            k: args.k,
            frustum: args.frustum,
            frustum_fov: args.frustum_fov,
            slice: args.slice,
            slice_sign: args.slice_sign,
            camera: args.camera,
            pairs: args.pairs,
            second: args.second,
            pair_pose: args.pair_pose,
            animate: args.animate,
        },
        screenshot: args.screenshot.map(|path| ScreenshotOptions {
            path,
            frames: args.frames,
            timeout: Duration::from_secs(300),
            moving: args.moving,
        }),
        window_size: args.size,
    };
    let screenshot = options.screenshot.as_ref().map(|s| s.path.clone());
    if let Some(report) = proxima_viewer::run(options)? {
        let path = screenshot.unwrap_or_default();
        print!(
            "{}: {}x{} px",
            path.display(),
            report.image_size[0],
            report.image_size[1]
        );
        if let Some(f) = report.frames {
            print!(
                ", frame time {:.1} ms mean, {:.1} ms median, {:.1} ms max over {} frames",
                f.mean_ms, f.median_ms, f.max_ms, f.count
            );
        }
        crate::outln!(
            " ({}, {} triangles, {} cells)",
            report.model,
            report.triangles,
            report.cells
        );
        if let Some(a) = report.animation {
            crate::outln!(
                "animation at {:.2} s: update {:.3} ms, {} of {} fan rays hit",
                a.time,
                a.update_ms,
                a.fan_hits,
                a.fan_rays
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_and_size_arguments() {
        let (o, d) = parse_ray("0,0.1,-1, 0 0 1").unwrap();
        assert_eq!((o, d), (Vec3::new(0.0, 0.1, -1.0), Vec3::Z));
        assert!(parse_ray("0,0,0,0,0,0").is_err());
        assert!(parse_ray("1,2,3").is_err());
        assert!(parse_ray("1,2,3,nan,0,1").is_err());
        assert_eq!(parse_size("640x480").unwrap(), [640.0, 480.0]);
        assert!(parse_size("640").is_err() && parse_size("0x10").is_err());
        assert_eq!(parse_cell_size("0.05").unwrap(), 0.05);
        assert_eq!(
            parse_frustum("-3,0,0, 0 1 0").unwrap(),
            (Vec3::new(-3.0, 0.0, 0.0), Vec3::Y)
        );
        assert!(parse_frustum("1,1,1,1,1,1").is_err() && parse_frustum("1,2,3").is_err());
        assert_eq!(parse_fov("30").unwrap(), 30.0);
        assert!(parse_fov("0").is_err() && parse_fov("180").is_err() && parse_fov("x").is_err());
        assert!(parse_cell_size("0").is_err() && parse_cell_size("-1").is_err() && parse_cell_size("x").is_err());
    }

    #[test]
    fn slice_sign_and_camera_arguments() {
        assert_eq!(parse_slice("z").unwrap(), (Axis::Z, None));
        assert_eq!(parse_slice("x,-0.25").unwrap(), (Axis::X, Some(-0.25)));
        assert!(parse_slice("w").is_err() && parse_slice("y,nan").is_err() && parse_slice("y,").is_err());
        assert_eq!(parse_sign("winding").unwrap(), Sign::WindingNumber);
        assert_eq!(parse_sign("pseudonormal").unwrap(), Sign::Pseudonormal);
        assert!(parse_sign("parity").is_err());
        assert_eq!(parse_angles("0,90").unwrap(), [0.0, 90.0]);
        assert_eq!(parse_angles("-30 10").unwrap(), [-30.0, 10.0]);
        assert!(parse_angles("0,91").is_err() && parse_angles("1").is_err() && parse_angles("1,x").is_err());
        assert!(parse_angles("inf,0").is_err() && parse_angles("1,2,3").is_err());
    }

    #[test]
    fn pair_arguments() {
        assert_eq!(parse_pairs("self").unwrap(), PairMode::SelfIntersections);
        assert_eq!(parse_pairs("second").unwrap(), PairMode::SecondMesh);
        assert_eq!(parse_pairs("off").unwrap(), PairMode::Off);
        assert!(parse_pairs("both").is_err());
        assert_eq!(
            parse_pair_pose("0.5,0,-1, 0 90 -180").unwrap(),
            (DVec3::new(0.5, 0.0, -1.0), DVec3::new(0.0, 90.0, -180.0))
        );
        assert!(parse_pair_pose("1,2,3").is_err() && parse_pair_pose("1,2,3,4,5,nan").is_err());
        assert!(parse_pair_pose("1,2,3,4,5,6,7").is_err() && parse_pair_pose("1,2,3,4,5,x").is_err());
    }
}
