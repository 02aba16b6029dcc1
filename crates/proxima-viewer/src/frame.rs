//! The composition of a frame's draw data from the settings and what was
//! computed from them. No egui, no GL: unit-tested.

use crate::animation::AnimationFrame;
use crate::camera::{OrbitCamera, Viewport};
use crate::cells::{CellGrid, RayWalk};
use crate::frustum_view::FrustumSelection;
use crate::model::{Model, QueryResult, query_overlay};
use crate::pair_view::PairAnswer;
use crate::scene::{BoxLayer, BoxSet, DrawFrame, Overlay, colors};
use crate::settings::{PairMode, Settings};
use crate::slice::SdfSlice;
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
    /// The latest signed-distance slice (drawn where it was computed, so a
    /// slider drag shows the last one until the next is in).
    pub slice: Option<&'a SdfSlice>,
    /// Whether the query point is inside the mesh, when known.
    pub query_inside: Option<bool>,
    /// The latest "Pairs" answer (drawn when its mode is the one asked, so
    /// a pose drag shows the last one until the next is in).
    pub pairs: Option<&'a PairAnswer>,
    /// The animation's latest frame, when the animation is on: its moved
    /// mesh is drawn instead of the model, and its closest point and fan
    /// instead of the closest-point answer at rest.
    pub animation: Option<&'a AnimationFrame>,
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
        match inputs.animation {
            Some(animation) => frame.mesh = Some(animation.buffers.clone()),
            None => {
                frame.mesh = Some(model.buffers.clone());
                frame.mesh_lod = model.buffers_lod.clone();
            }
        }
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
    if s.show_slice
        && let Some(slice) = inputs.slice
    {
        frame.slice = Some(slice.image.clone());
        frame.overlay.append(slice.contour_overlay());
        if s.slice_cut_mesh {
            frame.clip_plane = cut_towards(frame.eye, slice.plane.axis.index(), slice.plane.position);
        }
    }
    if s.pair_mode != PairMode::Off
        && let Some(pairs) = inputs.pairs
        && pairs.mode == s.pair_mode
    {
        frame.overlay.append(pairs.overlay.clone());
    }
    match inputs.animation {
        Some(animation) => frame.overlay.append(animation.overlay.clone()),
        None => {
            if let Some(result) = inputs.result {
                frame.overlay.append(query_overlay(model, result, inputs.query_inside));
            }
        }
    }
    frame
}

/// The clip plane that cuts away the half-space on the eye's side of the
/// plane `x[axis] = position`, so the slice is seen with the mesh behind it.
pub fn cut_towards(eye: proxima::Vec3, axis: usize, position: f32) -> [f32; 4] {
    let side = if eye[axis] >= position { 1.0 } else { -1.0 };
    let mut plane = [0.0; 4];
    plane[axis] = side;
    plane[3] = -side * position;
    plane
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
        let field = crate::slice::signed_distance_field(&m.mesh, proxima::Sign::WindingNumber).unwrap();
        let plane = crate::slice::SlicePlane::through(&m.bounds, crate::settings::Axis::Z, 0.2, 16).unwrap();
        let slice = crate::slice::SdfSlice::compute(&field, plane);
        let index = proxima::MeshIndex::new(m.mesh.clone());
        let pose = crate::pair_view::settings_pose(&settings).unwrap();
        let pairs = crate::pair_view::second_mesh_view(&index, &index, &pose).unwrap();
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
                slice: Some(&slice),
                query_inside: Some(true),
                pairs: Some(&pairs),
                animation: None,
            })
        };
        let plain = frame(&settings);
        assert_eq!(plain.view_projection, camera.view_projection(&viewport));
        assert!(plain.mesh.is_some() && !plain.mesh_points);
        assert!(plain.boxes.is_empty());
        assert_eq!(plain.overlay.markers.len(), 2);
        assert_eq!(plain.overlay.markers[0].color, colors::QUERY_INSIDE);
        assert!(plain.slice.is_none() && plain.clip_plane == [0.0; 4]);
        assert!(!plain.overlay.lines.iter().any(|v| v.color == colors::ZERO_CONTOUR));

        // The slice: its picture, its contour, and the mesh cut on the eye's side.
        settings.show_slice = true;
        let sliced = frame(&settings);
        assert_eq!(sliced.slice.as_ref().unwrap().id, slice.image.id);
        let contour = sliced.overlay.lines.iter().filter(|v| v.color == colors::ZERO_CONTOUR);
        assert_eq!(contour.count(), 2 * slice.contour.len());
        assert!(!slice.contour.is_empty());
        let eye = camera.eye();
        let clip = sliced.clip_plane;
        let cut = |p: Vec3| clip[0] * p.x + clip[1] * p.y + clip[2] * p.z + clip[3] > 0.0;
        assert!(cut(Vec3::new(0.0, 0.0, 0.2) + 0.5 * (eye - Vec3::new(0.0, 0.0, 0.2))) == (eye.z > 0.2));
        assert!(cut(eye) && !cut(Vec3::new(eye.x, eye.y, 0.2 - (eye.z - 0.2))));
        settings.slice_cut_mesh = false;
        assert_eq!(frame(&settings).clip_plane, [0.0; 4]);
        settings.show_slice = false;
        settings.slice_cut_mesh = true;

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

        // The pairs' overlay, only in the mode it was computed for.
        let pair_lines = |f: &DrawFrame| {
            f.overlay
                .lines
                .iter()
                .filter(|v| v.color == colors::SECOND_MESH)
                .count()
        };
        assert_eq!(pair_lines(&frame(&settings)), 0);
        settings.pair_mode = PairMode::SelfIntersections;
        assert_eq!(pair_lines(&frame(&settings)), 0);
        settings.pair_mode = PairMode::SecondMesh;
        let paired = frame(&settings);
        assert_eq!(pair_lines(&paired), 2 * 3 * m.mesh.face_count());
        assert!(paired.overlay.lines.iter().any(|v| v.color == colors::PAIR_CLOSEST));
        settings.pair_mode = PairMode::Off;

        // The animation: its moved mesh instead of the model's, its closest
        // point and fan instead of the answer at rest.
        let mut animation = crate::animation::Animation::new(m.mesh.clone()).unwrap();
        let wave = crate::animation::Wave::for_bounds(&m.bounds, 0.05, 2.0);
        let fan = crate::animation::RayFan::from_query(settings.query, &m.bounds, 3);
        let moved = animation
            .step(&wave, 0.5, Default::default(), settings.query, fan)
            .unwrap();
        settings.show_mesh = true;
        let animated = compose_frame(&FrameInputs {
            animation: Some(&moved),
            ..FrameInputs {
                camera: &camera,
                viewport,
                model: Some(&m),
                settings: &settings,
                result: Some(&result),
                grid: None,
                ray: None,
                nodes: None,
                spheres: None,
                frustum: None,
                slice: None,
                query_inside: Some(true),
                pairs: None,
                animation: None,
            }
        });
        assert_eq!(animated.mesh.as_ref().unwrap().id, moved.buffers.id);
        assert!(animated.mesh_lod.is_none());
        assert_eq!(animated.overlay.markers.len(), 2);
        assert_eq!(animated.overlay.markers[1].color, colors::QUERY);
        let fan_lines = animated
            .overlay
            .lines
            .iter()
            .filter(|v| v.color == colors::RAY || v.color == colors::FAN_MISS);
        assert_eq!(fan_lines.count(), 2 * 9);
        settings.show_mesh = false;

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
            slice: Some(&slice),
            query_inside: None,
            pairs: Some(&pairs),
            animation: None,
        });
        assert!(empty.mesh.is_none() && empty.boxes.is_empty() && empty.overlay.is_empty());
        assert!(empty.slice.is_none());
    }

    #[test]
    fn the_cut_removes_the_eye_side_of_the_plane() {
        let plane = cut_towards(Vec3::new(0.0, 5.0, 0.0), 1, 2.0);
        assert_eq!(plane, [0.0, 1.0, 0.0, -2.0]);
        let plane = cut_towards(Vec3::new(-3.0, 0.0, 0.0), 0, 1.0);
        assert_eq!(plane, [-1.0, 0.0, 0.0, 1.0]);
    }
}
