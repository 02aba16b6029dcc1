//! The viewer's settings (what the panel edits) and the composition of a
//! frame's draw data from them. No egui, no GL: unit-tested.

use crate::camera::{OrbitCamera, Viewport};
use crate::cells::{CellGrid, RayWalk};
use crate::frustum_view::FrustumSelection;
use crate::model::{Model, PrimitiveKind, QueryResult};
use crate::scene::{self, BoxLayer, BoxSet, DrawFrame, Overlay, colors};
use proxima::Aabb;
use proxima::math::Vec3;
use std::sync::Arc;

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
        }
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

/// What one frame shows, gathered from the viewer's state.
pub struct FrameInputs<'a> {
    /// The camera.
    pub camera: &'a OrbitCamera,
    /// The rectangle drawn into.
    pub viewport: Viewport,
    /// The model, if one is loaded.
    pub model: Option<&'a Model>,
    /// The panel settings.
    pub settings: &'a Settings,
    /// The current closest-point answer.
    pub result: Option<&'a QueryResult>,
    /// The current grid (drawn when its kind and cell size match the settings).
    pub grid: Option<&'a CellGrid>,
    /// The current ray walk.
    pub ray: Option<&'a RayWalk>,
    /// Boxes of the tree nodes at the chosen depth.
    pub nodes: Option<&'a Arc<BoxSet>>,
    /// Great circles of the sphere tree's nodes at the chosen depth.
    pub spheres: Option<&'a Overlay>,
    /// The second camera's frustum query (drawn when its kind matches).
    pub frustum: Option<&'a FrustumSelection>,
}

/// The draw data of one frame.
pub fn compose_frame(inputs: &FrameInputs<'_>) -> DrawFrame {
    let s = inputs.settings;
    let mut frame = DrawFrame {
        view_projection: inputs.camera.view_projection(&inputs.viewport),
        eye: inputs.camera.eye(),
        ..DrawFrame::default()
    };
    let Some(model) = inputs.model else {
        return frame;
    };
    if s.show_mesh {
        frame.mesh = Some(model.buffers.clone());
        frame.mesh_lod = model.buffers_lod.clone();
        frame.mesh_points = model.mesh.face_count() == 0;
    }
    if s.show_cells
        && let Some(grid) = inputs.grid
        && grid.kind == s.kind
        && grid.cell_size == s.cell_size
    {
        frame.boxes.push(BoxLayer {
            set: grid.boxes.clone(),
            color: colors::CELLS,
        });
    }
    if s.show_nodes
        && let Some(nodes) = inputs.nodes
    {
        frame.boxes.push(BoxLayer {
            set: nodes.clone(),
            color: colors::NODES,
        });
    }
    if s.show_ray
        && let Some(ray) = inputs.ray
    {
        frame.boxes.push(BoxLayer {
            set: ray.empty_boxes.clone(),
            color: colors::RAY_CELLS,
        });
        frame.boxes.push(BoxLayer {
            set: ray.occupied_boxes.clone(),
            color: colors::RAY_CELLS_OCCUPIED,
        });
        frame.overlay.append(ray.overlay());
    }
    if s.show_spheres
        && let Some(spheres) = inputs.spheres
    {
        frame.overlay.append(spheres.clone());
    }
    if s.show_frustum
        && let Some(selection) = inputs.frustum
        && selection.kind == s.kind
    {
        frame.overlay.append(selection.overlay.clone());
    }
    if let Some(result) = inputs.result {
        frame.overlay.append(scene::query_overlay(model, result));
    }
    frame
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cells::walk_ray;
    use crate::model::ModelSource;
    use proxima::Mesh;

    fn model() -> Model {
        let mesh = Mesh::from_triangles(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
        .unwrap();
        Model::load(
            ModelSource::Mesh {
                mesh,
                name: "tetra".into(),
            },
            &|_| {},
        )
        .unwrap()
    }

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
    fn defaults_put_the_query_outside_and_the_ray_through_the_model() {
        let m = model();
        let s = Settings::for_bounds(&m.bounds);
        assert!(!m.bounds.contains_point(s.query));
        assert!(Settings::query_range(&m.bounds).contains_point(s.query));
        let (lo, hi) = Settings::cell_size_range(m.bounds.diagonal());
        assert!(lo < s.cell_size && s.cell_size < hi);
        let walk = walk_ray(s.ray_origin, s.ray_direction, s.cell_size, s.ray_steps, None).unwrap();
        assert!(walk.cells.len() > 10);
        // Degenerate bounds still give finite, usable settings.
        let e = Settings::for_bounds(&Aabb::EMPTY);
        assert!(e.query.is_finite() && e.cell_size > 0.0 && e.ray_direction != Vec3::ZERO);
    }

    #[test]
    fn the_frame_shows_what_the_settings_ask() {
        let m = model();
        let camera = OrbitCamera::fit(&m.bounds, 1.0);
        let mut settings = Settings::for_bounds(&m.bounds);
        let result = m.query(settings.kind, settings.query, 0, true);
        let grid = CellGrid::build(&m, PrimitiveKind::Faces, settings.cell_size).unwrap();
        let ray = walk_ray(
            settings.ray_origin,
            settings.ray_direction,
            settings.cell_size,
            20,
            Some(&grid),
        )
        .unwrap();
        let nodes = Arc::new(BoxSet::new(m.nodes_at_depth(PrimitiveKind::Faces, 1)));
        let frustum = crate::frustum_view::settings_frustum(&settings).unwrap();
        let selection = crate::frustum_view::select(&m, PrimitiveKind::Faces, &frustum, false);
        let spheres = crate::spheres::spheres_overlay(&m.sphere_nodes_at_depth(PrimitiveKind::Faces, 0));
        let viewport = Viewport::new([0.0, 0.0], [300.0, 200.0]);
        let frame = |settings: &Settings| {
            compose_frame(&FrameInputs {
                camera: &camera,
                viewport,
                model: Some(&m),
                settings,
                result: Some(&result),
                grid: Some(&grid),
                ray: Some(&ray),
                nodes: Some(&nodes),
                spheres: Some(&spheres),
                frustum: Some(&selection),
            })
        };
        let plain = frame(&settings);
        assert_eq!(plain.view_projection, camera.view_projection(&viewport));
        assert!(plain.mesh.is_some() && !plain.mesh_points);
        assert!(plain.boxes.is_empty());
        assert_eq!(plain.overlay.markers.len(), 2);

        settings.show_cells = true;
        settings.show_nodes = true;
        settings.show_ray = true;
        settings.show_mesh = false;
        let all = frame(&settings);
        assert!(all.mesh.is_none());
        let colors_drawn: Vec<[u8; 4]> = all.boxes.iter().map(|l| l.color).collect();
        assert_eq!(
            colors_drawn,
            [
                colors::CELLS,
                colors::NODES,
                colors::RAY_CELLS,
                colors::RAY_CELLS_OCCUPIED
            ]
        );
        assert_eq!(all.boxes[0].set.len(), grid.occupied_count());
        assert_eq!(all.boxes[2].set.len() + all.boxes[3].set.len(), 20);
        assert!(all.overlay.lines.iter().any(|v| v.color == colors::RAY));
        assert!(!all.overlay.lines.iter().any(|v| v.color == colors::FRUSTUM));
        settings.show_frustum = true;
        let with_frustum = frame(&settings);
        let frustum_lines = with_frustum.overlay.lines.iter().filter(|v| v.color == colors::FRUSTUM);
        assert_eq!(frustum_lines.count(), 24);
        settings.show_frustum = false;
        assert!(!with_frustum.overlay.lines.iter().any(|v| v.color == colors::SPHERES));
        settings.show_spheres = true;
        let sphere_lines = frame(&settings)
            .overlay
            .lines
            .iter()
            .filter(|v| v.color == colors::SPHERES)
            .count();
        assert_eq!(sphere_lines, spheres.lines.len());
        assert!(sphere_lines > 0);
        settings.show_spheres = false;

        // A grid of another cell size or kind is not drawn (a rebuild is pending).
        settings.cell_size *= 2.0;
        assert_eq!(frame(&settings).boxes.len(), 3);

        // Without a model only the camera is set.
        let empty = compose_frame(&FrameInputs {
            camera: &camera,
            viewport,
            model: None,
            settings: &settings,
            result: None,
            grid: None,
            ray: None,
            nodes: None,
            spheres: None,
            frustum: None,
        });
        assert!(empty.mesh.is_none() && empty.boxes.is_empty() && empty.overlay.is_empty());
    }
}
