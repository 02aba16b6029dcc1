//! The composition of a frame's draw data from the settings and what was
//! computed from them. No egui, no GL: unit-tested.

use crate::camera::{OrbitCamera, Viewport};
use crate::cells::{CellGrid, RayWalk};
use crate::frustum_view::FrustumSelection;
use crate::model::{Model, QueryResult, query_overlay};
use crate::scene::{BoxLayer, BoxSet, DrawFrame, Overlay, colors};
use crate::settings::Settings;
use std::sync::Arc;

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
        frame.overlay.append(query_overlay(model, result));
    }
    frame
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cells::walk_ray;
    use crate::model::ModelSource;
    use proxima::{Aabb, Mesh, PrimitiveKind, Vec3};

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
