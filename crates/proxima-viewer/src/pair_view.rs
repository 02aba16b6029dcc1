//! The "Pairs" section: the model's self-intersections, or a second mesh
//! (a copy of the model, or another file) placed by a rigid pose, with the
//! faces where the two meet highlighted on both and the closest pair of
//! points joined by a segment. Everything is in world coordinates, the model
//! at the identity. Plain data computed from the library's answers
//! (`proxima::pair`): unit-tested without a window.
//!
//! The second mesh is drawn as its face outlines in the overlay (no shader
//! of its own); large meshes are thinned to [`SECOND_MESH_FACE_LIMIT`]
//! faces, and at most [`HIGHLIGHT_FACE_LIMIT`] meeting faces per mesh are
//! filled, so that a frame's overlay stays small. The answers themselves
//! (pairs, faces, distance) are always complete.

use crate::camera::{OrbitCamera, Viewport};
use crate::scene::{MARKER_SIZE, Overlay, Shape, colors};
use crate::settings::{PairMode, Settings};
use proxima::math::{DMat3, DVec3, Vec3};
use proxima::pair::{self, FacePair, PairDistance, RigidPose};
use proxima::{Mesh, MeshIndex};
use std::time::Instant;

/// At most this many faces of the second mesh are outlined: a larger mesh
/// is drawn by an even sample of its faces (every k-th).
pub const SECOND_MESH_FACE_LIMIT: usize = 20_000;

/// At most this many meeting faces are filled per mesh (the lowest face
/// indices); the counts shown are those of the whole answer.
pub const HIGHLIGHT_FACE_LIMIT: usize = 20_000;

/// The rotation by `degrees.x` about the x axis, then `degrees.y` about the
/// (fixed) y axis, then `degrees.z` about the z axis: `Rz · Ry · Rx`.
/// Zero angles give the identity exactly.
pub fn rotation_from_angles(degrees: DVec3) -> DMat3 {
    DMat3::from_rotation_z(degrees.z.to_radians())
        * DMat3::from_rotation_y(degrees.y.to_radians())
        * DMat3::from_rotation_x(degrees.x.to_radians())
}

/// The pose `p ↦ R p + t` with `R` = [`rotation_from_angles`]`(degrees)`
/// and `t = translation`, or a one-line reason (a non-finite value).
pub fn pose_from_angles(translation: DVec3, degrees: DVec3) -> Result<RigidPose, String> {
    if !degrees.is_finite() {
        return Err(format!("the second mesh's angles must be finite (got {degrees})"));
    }
    RigidPose::new(rotation_from_angles(degrees), translation).map_err(|e| format!("the second mesh's pose: {e}"))
}

/// The second mesh's pose from the settings' translation and angles.
pub fn settings_pose(s: &Settings) -> Result<RigidPose, String> {
    pose_from_angles(s.pair_translation, s.pair_angles)
}

/// The translation that makes a point at the camera's target depth follow a
/// mouse drag of `dx, dy` pixels (x right, y down) in the view plane: how a
/// modifier-drag moves the second mesh.
pub fn drag_translation(camera: &OrbitCamera, dx: f32, dy: f32, viewport: &Viewport) -> DVec3 {
    let height = viewport.size[1].max(1.0);
    let world_per_pixel = 2.0 * camera.distance * (0.5 * camera.fov_y).tan() / height;
    let (right, up, _) = camera.axes();
    ((dx * right - dy * up) * world_per_pixel).as_dvec3()
}

/// The answer of one "Pairs" question and what it draws.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairAnswer {
    /// The mode asked ([`PairMode::SelfIntersections`] or [`PairMode::SecondMesh`]).
    pub mode: PairMode,
    /// The second mesh's pose (the identity for self-intersections).
    pub pose: RigidPose,
    /// The face pairs that meet: `[model face, second mesh face]`, or
    /// `[f, g]` with `f < g` for self-intersections; sorted.
    pub pairs: Vec<FacePair>,
    /// The model's faces in some pair, ascending.
    pub faces_first: Vec<u32>,
    /// The second mesh's faces in some pair, ascending (empty for
    /// self-intersections).
    pub faces_second: Vec<u32>,
    /// Seconds taken by the intersection query.
    pub pairs_seconds: f64,
    /// The closest pair of points (second mesh only).
    pub distance: Option<PairDistance>,
    /// Seconds taken by the distance query.
    pub distance_seconds: f64,
    /// Faces of the second mesh (0 for self-intersections).
    pub second_faces: usize,
    /// Of those, the faces outlined.
    pub second_faces_drawn: usize,
    /// Faces filled on the model and on the second mesh (each at most
    /// [`HIGHLIGHT_FACE_LIMIT`]).
    pub highlighted: [usize; 2],
    /// The second mesh's outlines, the meeting faces filled
    /// ([`colors::PAIR_MEETING`] on the model, [`colors::PAIR_MEETING_SECOND`]
    /// on the second mesh) and the closest-points segment
    /// ([`colors::PAIR_CLOSEST`]) with a marker at each end.
    pub overlay: Overlay,
}

/// The faces of the model's mesh that meet other faces of it
/// (`pair::self_intersections`), highlighted. The error (a mesh without
/// faces) is one line.
pub fn self_intersection_view(index: &MeshIndex) -> Result<PairAnswer, String> {
    let started = Instant::now();
    let pairs = pair::self_intersections(index).map_err(|e| e.to_string())?;
    let pairs_seconds = started.elapsed().as_secs_f64();
    let faces_first = distinct(pairs.iter().flatten().copied());
    let mut overlay = Overlay::default();
    let highlighted = highlight(
        &mut overlay,
        index.mesh(),
        &RigidPose::IDENTITY,
        &faces_first,
        colors::PAIR_MEETING,
    );
    Ok(PairAnswer {
        mode: PairMode::SelfIntersections,
        pose: RigidPose::IDENTITY,
        pairs,
        faces_first,
        pairs_seconds,
        highlighted: [highlighted, 0],
        overlay,
        ..PairAnswer::default()
    })
}

/// The model (`first`, at the identity) against `second` placed by `pose`:
/// the meeting face pairs (`pair::intersecting_pairs`) highlighted on both,
/// the closest points (`pair::distance`) joined, the second mesh outlined.
/// `second` may be `first` itself (a moved copy). The error (a mesh without
/// faces, a pose beyond the supported range) is one line.
pub fn second_mesh_view(first: &MeshIndex, second: &MeshIndex, pose: &RigidPose) -> Result<PairAnswer, String> {
    let identity = RigidPose::IDENTITY;
    let started = Instant::now();
    let pairs = pair::intersecting_pairs(first, &identity, second, pose).map_err(|e| e.to_string())?;
    let pairs_seconds = started.elapsed().as_secs_f64();
    let started = Instant::now();
    let closest = pair::distance(first, &identity, second, pose).map_err(|e| e.to_string())?;
    let distance_seconds = started.elapsed().as_secs_f64();
    let faces_first = distinct(pairs.iter().map(|p| p[0]));
    let faces_second = distinct(pairs.iter().map(|p| p[1]));

    let mut overlay = Overlay::default();
    let mesh = second.mesh();
    let second_faces = mesh.face_count();
    // An even sample: every `step`-th face, at most the limit.
    let step = second_faces.div_ceil(SECOND_MESH_FACE_LIMIT).max(1);
    let mut second_faces_drawn = 0;
    for f in (0..second_faces).step_by(step) {
        overlay.shape(&placed_face(mesh, f, pose), colors::SECOND_MESH, false);
        second_faces_drawn += 1;
    }
    let highlighted = [
        highlight(
            &mut overlay,
            first.mesh(),
            &identity,
            &faces_first,
            colors::PAIR_MEETING,
        ),
        highlight(&mut overlay, mesh, pose, &faces_second, colors::PAIR_MEETING_SECOND),
    ];
    let (a, b) = (closest.point_a.as_vec3(), closest.point_b.as_vec3());
    overlay.line(a, b, colors::PAIR_CLOSEST);
    overlay.marker(a, colors::PAIR_CLOSEST, MARKER_SIZE);
    overlay.marker(b, colors::PAIR_CLOSEST, MARKER_SIZE);
    Ok(PairAnswer {
        mode: PairMode::SecondMesh,
        pose: *pose,
        pairs,
        faces_first,
        faces_second,
        pairs_seconds,
        distance: Some(closest),
        distance_seconds,
        second_faces,
        second_faces_drawn,
        highlighted,
        overlay,
    })
}

/// Face `f` of `mesh` where `pose` puts it, rounded to `f32` for drawing.
pub fn placed_face(mesh: &Mesh, f: usize, pose: &RigidPose) -> Shape {
    let p = mesh.positions();
    Shape::Polygon(
        mesh.face(f)
            .iter()
            .map(|&i| pose.apply(p[i as usize]).as_vec3())
            .collect(),
    )
}

/// Fills (and outlines) the first [`HIGHLIGHT_FACE_LIMIT`] of `faces`;
/// returns how many were drawn.
fn highlight(overlay: &mut Overlay, mesh: &Mesh, pose: &RigidPose, faces: &[u32], color: [u8; 4]) -> usize {
    let drawn = faces.len().min(HIGHLIGHT_FACE_LIMIT);
    for &f in &faces[..drawn] {
        overlay.shape(&placed_face(mesh, f as usize, pose), color, true);
    }
    drawn
}

/// The distinct values, ascending.
fn distinct(values: impl Iterator<Item = u32>) -> Vec<u32> {
    let mut v: Vec<u32> = values.collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The segments of `overlay` drawn in `color`, as end-point pairs.
pub fn segments_in(overlay: &Overlay, color: [u8; 4]) -> Vec<[Vec3; 2]> {
    overlay
        .lines
        .chunks_exact(2)
        .filter(|l| l[0].color == color)
        .map(|l| [Vec3::from_array(l[0].position), Vec3::from_array(l[1].position)])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proxima::math::DQuat;
    use proxima::mesh::generate::noisy_icosphere;
    use proxima::pair::{neighbours_intersect, triangle_distance, triangles_intersect};

    /// Every face's corners placed by `pose`, and its vertex indices (the
    /// test meshes are triangle meshes: one triangle per face).
    fn placed(mesh: &Mesh, pose: &RigidPose) -> Vec<([DVec3; 3], [u32; 3])> {
        let p = mesh.positions();
        mesh.faces()
            .map(|f| {
                assert_eq!(f.len(), 3, "a triangle mesh");
                let ids = [f[0], f[1], f[2]];
                (ids.map(|i| pose.apply(p[i as usize])), ids)
            })
            .collect()
    }

    /// Brute force over all face pairs of the two placed meshes.
    fn brute_pairs(a: &Mesh, b: &Mesh, pose: &RigidPose) -> Vec<FacePair> {
        let (ta, tb) = (placed(a, &RigidPose::IDENTITY), placed(b, pose));
        let mut out = Vec::new();
        for (i, (x, _)) in ta.iter().enumerate() {
            for (j, (y, _)) in tb.iter().enumerate() {
                if triangles_intersect(x, y) {
                    out.push([i as u32, j as u32]);
                }
            }
        }
        out
    }

    /// Brute force of the least distance over all face pairs.
    fn brute_distance(a: &Mesh, b: &Mesh, pose: &RigidPose) -> f64 {
        let (ta, tb) = (placed(a, &RigidPose::IDENTITY), placed(b, pose));
        let mut best = f64::INFINITY;
        for (x, _) in &ta {
            for (y, _) in &tb {
                best = best.min(triangle_distance(x, y).distance);
            }
        }
        best
    }

    fn unit_cube() -> Mesh {
        let p: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let t = [
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        Mesh::from_triangles(p, &t).unwrap()
    }

    /// Checks every field of a second-mesh answer against brute force.
    fn check_second(mesh: &Mesh, pose: &RigidPose) -> PairAnswer {
        let index = MeshIndex::new(mesh.clone());
        let answer = second_mesh_view(&index, &index, pose).unwrap();
        let brute = brute_pairs(mesh, mesh, pose);
        assert_eq!(answer.pairs, brute);
        assert_eq!(answer.faces_first, distinct(brute.iter().map(|p| p[0])));
        assert_eq!(answer.faces_second, distinct(brute.iter().map(|p| p[1])));
        let d = answer.distance.unwrap();
        assert_eq!(d.distance, brute_distance(mesh, mesh, pose));
        assert_eq!(Some(d), pair::distance(&index, &RigidPose::IDENTITY, &index, pose).ok());
        assert_eq!(d.distance == 0.0, !brute.is_empty());
        // The segment joins the PairDistance points, each end marked.
        let ends = [d.point_a.as_vec3(), d.point_b.as_vec3()];
        assert_eq!(segments_in(&answer.overlay, colors::PAIR_CLOSEST), [ends]);
        let markers: Vec<Vec3> = answer
            .overlay
            .markers
            .iter()
            .filter(|m| m.color == colors::PAIR_CLOSEST)
            .map(|m| Vec3::from_array(m.position))
            .collect();
        assert_eq!(markers, ends);
        // The highlighted triangles are the meeting faces, placed.
        let filled = |color: [u8; 4]| -> Vec<Vec3> {
            let v = answer.overlay.triangles.iter().filter(|v| v.color == color);
            v.map(|v| Vec3::from_array(v.position)).collect()
        };
        let corners = |faces: &[u32], pose: &RigidPose| -> Vec<Vec3> {
            let t = placed(mesh, pose);
            faces
                .iter()
                .flat_map(|&f| t[f as usize].0.map(|c| c.as_vec3()))
                .collect()
        };
        assert_eq!(
            filled(colors::PAIR_MEETING),
            corners(&answer.faces_first, &RigidPose::IDENTITY)
        );
        assert_eq!(filled(colors::PAIR_MEETING_SECOND), corners(&answer.faces_second, pose));
        assert_eq!(
            answer.highlighted,
            [answer.faces_first.len(), answer.faces_second.len()]
        );
        // Every face of the (small) second mesh is outlined where the pose puts it.
        assert_eq!(
            (answer.second_faces, answer.second_faces_drawn),
            (mesh.face_count(), mesh.face_count())
        );
        let outlines = segments_in(&answer.overlay, colors::SECOND_MESH);
        assert_eq!(outlines.len(), 3 * mesh.face_count());
        let second = placed(mesh, pose);
        assert_eq!(
            outlines[3..6],
            [0, 1, 2].map(|k| [second[1].0[k].as_vec3(), second[1].0[(k + 1) % 3].as_vec3()])
        );
        answer
    }

    #[test]
    fn a_moved_copy_meets_and_nears_the_model_as_brute_force_says() {
        let mesh = noisy_icosphere(3, 7);
        let mut s = Settings::for_bounds(&mesh.bounds());
        s.pair_mode = PairMode::SecondMesh;
        // The default pose overlaps the model: the surfaces cross.
        let crossing = check_second(&mesh, &settings_pose(&s).unwrap());
        assert!(!crossing.pairs.is_empty() && crossing.distance.unwrap().distance == 0.0);
        s.pair_angles = DVec3::new(20.0, -35.0, 170.0);
        s.pair_translation = DVec3::new(0.7, -0.4, 0.3);
        let turned = check_second(&mesh, &settings_pose(&s).unwrap());
        assert!(!turned.pairs.is_empty());
        // Far enough: no pair, a positive distance between distinct points.
        s.pair_translation = DVec3::new(3.0, 0.5, -0.2);
        let apart = check_second(&mesh, &settings_pose(&s).unwrap());
        assert!(apart.pairs.is_empty() && apart.highlighted == [0, 0]);
        assert!(apart.distance.unwrap().distance > 0.5);
    }

    #[test]
    fn a_copy_moved_by_exactly_its_width_touches_and_one_ulp_more_does_not() {
        let cube = unit_cube();
        let at = |x: f64| pose_from_angles(DVec3::new(x, 0.0, 0.0), DVec3::ZERO).unwrap();
        // Zero angles give the identity rotation exactly, so x = 1 puts the
        // copy's face x = 0 on the model's face x = 1.
        assert_eq!(at(1.0).rotation(), DMat3::IDENTITY);
        let touching = check_second(&cube, &at(1.0));
        assert!(touching.faces_first.contains(&10) && touching.faces_second.contains(&8));
        assert_eq!(touching.distance.unwrap().distance, 0.0);
        let apart = check_second(&cube, &at(1.0f64.next_up()));
        assert!(apart.pairs.is_empty());
        assert_eq!(apart.distance.unwrap().distance, 1.0f64.next_up() - 1.0);
        let overlapping = check_second(&cube, &at(1.0f64.next_down()));
        assert!(overlapping.pairs.len() > touching.pairs.len() / 2);
        assert_eq!(overlapping.distance.unwrap().distance, 0.0);
    }

    #[test]
    fn self_intersections_are_highlighted_as_brute_force_says() {
        // Two spheres in one mesh (separate vertices), overlapping.
        let sphere = noisy_icosphere(3, 3);
        let n = sphere.vertex_count() as u32;
        let mut positions = sphere.positions().to_vec();
        positions.extend(sphere.positions().iter().map(|&p| p + Vec3::new(0.9, 0.2, 0.0)));
        let mut triangles: Vec<[u32; 3]> = sphere.faces().map(|f| [f[0], f[1], f[2]]).collect();
        let first: Vec<[u32; 3]> = triangles.clone();
        triangles.extend(first.iter().map(|t| t.map(|i| i + n)));
        let mesh = Mesh::from_triangles(positions, &triangles).unwrap();
        let answer = self_intersection_view(&MeshIndex::new(mesh.clone())).unwrap();
        // Brute force over all face pairs: neighbours (sharing vertex
        // indices) meet only beyond what they share.
        let t = placed(&mesh, &RigidPose::IDENTITY);
        let mut brute = Vec::new();
        for f in 0..t.len() {
            for g in f + 1..t.len() {
                let ((a, ia), (b, ib)) = (t[f], t[g]);
                let neighbours = ia.iter().any(|i| ib.contains(i));
                let meet = if neighbours {
                    neighbours_intersect(&a, ia, &b, ib)
                } else {
                    triangles_intersect(&a, &b)
                };
                if meet {
                    brute.push([f as u32, g as u32]);
                }
            }
        }
        assert!(!brute.is_empty());
        assert_eq!(answer.pairs, brute);
        // Each pair crosses the two spheres.
        assert!(
            brute
                .iter()
                .all(|&[f, g]| (f as usize) < first.len() && g as usize >= first.len())
        );
        assert_eq!(answer.faces_first, distinct(brute.iter().flatten().copied()));
        assert!(answer.faces_second.is_empty() && answer.distance.is_none());
        let filled = answer
            .overlay
            .triangles
            .iter()
            .filter(|v| v.color == colors::PAIR_MEETING)
            .count();
        assert_eq!(filled, 3 * answer.faces_first.len());
        assert_eq!(answer.highlighted, [answer.faces_first.len(), 0]);
        // One sphere alone meets nothing.
        let alone = self_intersection_view(&MeshIndex::new(sphere)).unwrap();
        assert!(alone.pairs.is_empty() && alone.overlay.is_empty());
    }

    #[test]
    fn the_slider_pose_is_the_quaternion_pose_of_the_same_rotation() {
        // q = qz · qy · qx, each a half-angle quaternion written out.
        let about = |axis: usize, degrees: f64| {
            let (s, c) = (0.5 * degrees.to_radians()).sin_cos();
            let mut v = [0.0; 3];
            v[axis] = s;
            DQuat::from_xyzw(v[0], v[1], v[2], c)
        };
        let angles = [
            [0.0, 0.0, 0.0],
            [180.0, 0.0, 0.0],
            [0.0, -180.0, 0.0],
            [0.0, 0.0, 180.0],
            [90.0, 90.0, 90.0],
            [30.0, -45.0, 120.0],
            [-180.0, 180.0, -180.0],
            [179.999, -0.001, 57.3],
        ];
        for [x, y, z] in angles {
            let t = DVec3::new(0.25, -3.0, 1e3);
            let pose = pose_from_angles(t, DVec3::new(x, y, z)).unwrap();
            let q = about(2, z) * about(1, y) * about(0, x);
            let expected = RigidPose::from_quaternion(q.to_array(), t.to_array()).unwrap();
            let (r, e) = (pose.rotation().to_cols_array(), expected.rotation().to_cols_array());
            for k in 0..9 {
                assert!((r[k] - e[k]).abs() <= 1e-12, "{x} {y} {z}: {r:?} against {e:?}");
            }
            assert_eq!(pose.translation(), expected.translation());
        }
        let mut s = Settings {
            pair_angles: DVec3::new(10.0, f64::NAN, 0.0),
            ..Settings::default()
        };
        assert!(settings_pose(&s).is_err());
        s.pair_angles = DVec3::ZERO;
        s.pair_translation = DVec3::new(f64::INFINITY, 0.0, 0.0);
        assert!(settings_pose(&s).is_err());
    }

    #[test]
    fn a_drag_moves_the_second_mesh_with_the_mouse() {
        let bounds = proxima::Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let camera = OrbitCamera::fit(&bounds, 1.5);
        let viewport = Viewport::new([10.0, 20.0], [600.0, 400.0]);
        let p = camera.target;
        let before = camera.project(p, &viewport).unwrap();
        for (dx, dy) in [(30.0, -20.0), (-5.0, 0.0), (0.0, 12.5)] {
            let moved = p + drag_translation(&camera, dx, dy, &viewport).as_vec3();
            let after = camera.project(moved, &viewport).unwrap();
            assert!((after[0] - before[0] - dx).abs() < 0.05, "{before:?} {after:?}");
            assert!((after[1] - before[1] - dy).abs() < 0.05, "{before:?} {after:?}");
        }
        assert_eq!(drag_translation(&camera, 0.0, 0.0, &viewport), DVec3::ZERO);
    }

    #[test]
    fn bad_input_is_a_one_line_error() {
        let cube = MeshIndex::new(unit_cube());
        let far = pose_from_angles(DVec3::new(2e38, 0.0, 0.0), DVec3::ZERO).unwrap();
        let e = second_mesh_view(&cube, &cube, &far).unwrap_err();
        assert!(e.contains("beyond") && !e.contains('\n'), "{e}");
        let points = MeshIndex::new(Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X], &[]).unwrap());
        let e = self_intersection_view(&points).unwrap_err();
        assert!(!e.is_empty() && !e.contains('\n'), "{e}");
        assert!(second_mesh_view(&cube, &points, &RigidPose::IDENTITY).is_err());
    }

    #[test]
    fn a_large_second_mesh_is_outlined_by_a_sample() {
        // 20 · 33² = 21,780 faces: more than the limit, every second face drawn.
        let mesh = noisy_icosphere(33, 1);
        assert!(mesh.face_count() > SECOND_MESH_FACE_LIMIT);
        let index = MeshIndex::new(mesh.clone());
        let pose = pose_from_angles(DVec3::new(5.0, 0.0, 0.0), DVec3::ZERO).unwrap();
        let answer = second_mesh_view(&index, &index, &pose).unwrap();
        assert_eq!(answer.second_faces, mesh.face_count());
        assert_eq!(answer.second_faces_drawn, mesh.face_count().div_ceil(2));
        assert!(answer.second_faces_drawn <= SECOND_MESH_FACE_LIMIT);
        assert_eq!(
            segments_in(&answer.overlay, colors::SECOND_MESH).len(),
            3 * answer.second_faces_drawn
        );
    }
}
