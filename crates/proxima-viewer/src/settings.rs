//! The viewer's settings: what the side panel edits. Plain data.

use crate::animation::{UpdateMode, Wave};
use proxima::{Aabb, DVec3, PrimitiveKind, Sign, Vec3};

/// A coordinate axis: the normal of the signed-distance slice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The x axis.
    X,
    /// The y axis.
    Y,
    /// The z axis (the default: the slice faces the default camera).
    #[default]
    Z,
}

impl Axis {
    /// The three axes in order.
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    /// Index of the coordinate (x = 0).
    pub fn index(self) -> usize {
        self as usize
    }

    /// `"x"`, `"y"` or `"z"`.
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

impl std::str::FromStr for Axis {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "x" | "X" => Ok(Axis::X),
            "y" | "Y" => Ok(Axis::Y),
            "z" | "Z" => Ok(Axis::Z),
            _ => Err(format!("expected the axis x, y or z, got '{s}'")),
        }
    }
}

/// What the "Pairs" section shows: nothing, the faces of the model that meet
/// other faces of it, or a moved copy of the model against the model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PairMode {
    /// Nothing.
    #[default]
    Off,
    /// The model's self-intersections.
    SelfIntersections,
    /// A second mesh (a copy of the model, or the file given with
    /// `--second`) placed by the pose of the settings.
    SecondMesh,
}

impl PairMode {
    /// The three modes in the panel's order.
    pub const ALL: [PairMode; 3] = [PairMode::Off, PairMode::SelfIntersections, PairMode::SecondMesh];

    /// The panel's label.
    pub fn name(self) -> &'static str {
        match self {
            PairMode::Off => "off",
            PairMode::SelfIntersections => "self-intersections",
            PairMode::SecondMesh => "second mesh",
        }
    }
}

impl std::str::FromStr for PairMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim() {
            "off" => Ok(PairMode::Off),
            "self" | "self-intersections" => Ok(PairMode::SelfIntersections),
            "second" | "copy" | "second-mesh" => Ok(PairMode::SecondMesh),
            _ => Err(format!("expected off, self or second, got '{s}'")),
        }
    }
}

/// Everything the side panel edits.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Primitive kind of the queries, the grid and the tree shown.
    pub kind: PrimitiveKind,
    /// The query point.
    pub query: Vec3,
    /// A picked query point sits this far off the surface, as a fraction of
    /// the model's bounding-box diagonal.
    pub pick_offset: f32,
    /// Number of nearest primitives highlighted (0: only the closest).
    pub k: usize,
    /// Also run (and time) brute force for each query.
    pub compare_linear: bool,
    /// Draw the shaded mesh.
    pub show_mesh: bool,
    /// Draw the occupied cells of a hash grid.
    pub show_cells: bool,
    /// Side of the grid's cubic cells.
    pub cell_size: f32,
    /// Draw a ray and the cells it passes through.
    pub show_ray: bool,
    /// Start of the ray.
    pub ray_origin: Vec3,
    /// Direction of the ray (normalized when walked).
    pub ray_direction: Vec3,
    /// Number of cells walked.
    pub ray_steps: u32,
    /// Draw the tree's nodes at `node_depth`.
    pub show_nodes: bool,
    /// Depth of the nodes drawn (root = 0).
    pub node_depth: u32,
    /// Draw the sphere tree's nodes at `node_depth`.
    pub show_spheres: bool,
    /// Draw a second camera's frustum and the primitives its query selects.
    pub show_frustum: bool,
    /// Position of the second camera.
    pub frustum_eye: Vec3,
    /// Point the second camera looks at.
    pub frustum_target: Vec3,
    /// Vertical field of view of the second camera, in degrees.
    pub frustum_fov: f32,
    /// Near plane distance of the second camera.
    pub frustum_near: f32,
    /// Far plane distance of the second camera.
    pub frustum_far: f32,
    /// Show the signed distance and winding number at the query point (the
    /// signed distance field is built on a worker thread when first asked).
    pub show_signed_distance: bool,
    /// Draw a plane through the mesh coloured by signed distance.
    pub show_slice: bool,
    /// The slice plane's normal.
    pub slice_axis: Axis,
    /// The slice plane's coordinate along its axis.
    pub slice_position: f32,
    /// How the slice (and the query point's signed distance) decide inside
    /// from outside.
    pub slice_sign: Sign,
    /// Hide the part of the mesh between the slice and the camera.
    pub slice_cut_mesh: bool,
    /// The "Pairs" section's mode.
    pub pair_mode: PairMode,
    /// Where the second mesh is moved to, after its rotation (world units).
    pub pair_translation: DVec3,
    /// The second mesh's rotation: angles about the fixed x, y and z axes, in
    /// degrees, applied in that order (see `pair_view::rotation_from_angles`).
    pub pair_angles: DVec3,
    /// Deform the model every frame by a travelling wave, bring its trees up
    /// to date and answer the closest point and a fan of rays on it (see
    /// [`crate::animation`]).
    pub animate: bool,
    /// How each frame brings the trees up to date.
    pub animation_mode: UpdateMode,
    /// The wave's height, as a fraction of the box diagonal.
    pub wave_amplitude: f32,
    /// Seconds per cycle of the wave.
    pub wave_period: f32,
    /// The fan has this many rays along each side (from the query point,
    /// towards the model's centre).
    pub fan_side: u32,
}

impl Default for Settings {
    fn default() -> Self {
        Self::for_bounds(&Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)))
    }
}

impl Settings {
    /// Sensible settings for a model in `bounds`: a query point outside the
    /// model, cells of 1/40 of the diagonal, a ray along the box diagonal.
    pub fn for_bounds(bounds: &Aabb) -> Self {
        let b = if bounds.is_empty() || !bounds.is_finite() {
            Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
        } else {
            *bounds
        };
        let size = b.size().max(Vec3::splat(1e-6));
        let diagonal = b.diagonal().max(1e-6);
        Self {
            kind: PrimitiveKind::Faces,
            query: b.center() + Vec3::new(0.6 * size.x, 0.25 * size.y, 0.6 * size.z),
            pick_offset: 0.02,
            k: 0,
            compare_linear: true,
            show_mesh: true,
            show_cells: false,
            cell_size: nice_size(diagonal / 40.0),
            show_ray: false,
            ray_origin: b.min - 0.1 * size,
            ray_direction: size,
            ray_steps: 400,
            show_nodes: false,
            node_depth: 3,
            show_spheres: false,
            // From the -x side, a narrow view aimed above the centre: it
            // sees part of the model, not all of it.
            show_frustum: false,
            frustum_eye: b.center() - Vec3::new(diagonal, 0.0, 0.0),
            frustum_target: b.center() + Vec3::new(0.0, 0.25 * size.y, 0.0),
            frustum_fov: 25.0,
            frustum_near: 0.2 * diagonal,
            frustum_far: 2.0 * diagonal,
            show_signed_distance: true,
            show_slice: false,
            slice_axis: Axis::Z,
            slice_position: b.center().z,
            slice_sign: Sign::WindingNumber,
            slice_cut_mesh: true,
            pair_mode: PairMode::Off,
            // Half the model's width along x: the copy overlaps the model,
            // so its surface crosses the model's.
            pair_translation: DVec3::new(0.5 * size.x as f64, 0.0, 0.0),
            pair_angles: DVec3::ZERO,
            animate: false,
            animation_mode: UpdateMode::Refit,
            wave_amplitude: Wave::DEFAULT_AMPLITUDE,
            wave_period: Wave::DEFAULT_PERIOD,
            fan_side: 8,
        }
    }

    /// Range of each translation slider of the second mesh: ± the bounding
    /// box's diagonal (1 for an empty or non-finite box).
    pub fn pair_translation_range(bounds: &Aabb) -> f64 {
        let d = bounds.diagonal() as f64;
        if d.is_finite() && d > 0.0 { d } else { 1.0 }
    }

    /// Range of the slice position along `axis`: the bounding box grown by
    /// [`SLICE_MARGIN`] of its size on each side (the slice's extent).
    pub fn slice_range(bounds: &Aabb, axis: Axis) -> (f32, f32) {
        let b = if bounds.is_empty() || !bounds.is_finite() {
            Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
        } else {
            *bounds
        };
        let a = axis.index();
        let grow = SLICE_MARGIN * b.size()[a];
        (b.min[a] - grow, b.max[a] + grow)
    }

    /// Range of the query sliders: the bounding box grown by half its size
    /// on every side.
    pub fn query_range(bounds: &Aabb) -> Aabb {
        if bounds.is_empty() || !bounds.is_finite() {
            return Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        }
        let margin = 0.5 * bounds.size().max_element().max(1e-6);
        bounds.inflate(margin)
    }

    /// Range of the cell size control for a model of this diagonal.
    pub fn cell_size_range(diagonal: f32) -> (f32, f32) {
        let d = if diagonal.is_finite() && diagonal > 0.0 {
            diagonal
        } else {
            1.0
        };
        (d / 2000.0, d / 2.0)
    }
}

/// The slice covers the bounding box grown by this fraction of its size on
/// every side (as the CLI's `proxima sdf --grid`).
pub const SLICE_MARGIN: f32 = 0.05;

/// `x` rounded to one significant digit of 1, 2 or 5 (0.0123 → 0.01).
pub fn nice_size(x: f32) -> f32 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    // In f64, so that 5 × 0.01 rounds to the f32 nearest 0.05.
    let x = x as f64;
    let base = 10f64.powf(x.log10().floor());
    let mantissa = x / base;
    let m = if mantissa < 1.5 {
        1.0
    } else if mantissa < 3.5 {
        2.0
    } else if mantissa < 7.5 {
        5.0
    } else {
        10.0
    };
    (m * base) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_sizes() {
        assert_eq!(nice_size(0.0123), 0.01);
        assert_eq!(nice_size(0.03), 0.02);
        assert_eq!(nice_size(0.04), 0.05);
        assert_eq!(nice_size(8.0), 10.0);
        assert_eq!(nice_size(0.0), 1.0);
        assert_eq!(nice_size(f32::NAN), 1.0);
    }

    #[test]
    fn axes_parse_and_slice_ranges_grow_the_box() {
        assert_eq!("y".parse::<Axis>(), Ok(Axis::Y));
        assert_eq!(" Z ".parse::<Axis>(), Ok(Axis::Z));
        assert!("w".parse::<Axis>().is_err());
        assert_eq!(Axis::ALL.map(Axis::name), ["x", "y", "z"]);
        let b = Aabb::new(Vec3::new(0.0, -2.0, 1.0), Vec3::new(10.0, 2.0, 1.0));
        assert_eq!(Settings::slice_range(&b, Axis::X), (-0.5, 10.5));
        let (lo, hi) = Settings::slice_range(&b, Axis::Y);
        assert!((lo + 2.2).abs() < 1e-6 && (hi - 2.2).abs() < 1e-6);
        assert_eq!(Settings::slice_range(&b, Axis::Z), (1.0, 1.0));
        let s = Settings::for_bounds(&b);
        assert_eq!((s.slice_axis, s.slice_position), (Axis::Z, 1.0));
        assert!(!s.show_slice && s.show_signed_distance && s.slice_cut_mesh);
    }
}
