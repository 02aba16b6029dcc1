//! The "Frustum query" section: a second camera whose frustum is drawn as
//! its twelve edges, with the primitives the tree's frustum query selects
//! highlighted (and the same query by brute force for comparison). Plain
//! data computed from the settings and the model: unit-tested without a
//! window.

use crate::model::Model;
use crate::scene::{Overlay, colors};
use crate::settings::Settings;
use proxima::PrimitiveKind;
use proxima::frustum::Frustum;
use proxima::math::Vec3;

/// Width over height of the second camera's image (the frustum is not tied
/// to the window's shape).
pub const FRUSTUM_ASPECT: f32 = 4.0 / 3.0;

/// The second camera's frustum from the settings, or a one-line reason why
/// the settings describe none (eye on the target, near ≥ far, ...). The up
/// direction is +y, or +z when the camera looks along y.
pub fn settings_frustum(s: &Settings) -> Result<Frustum, String> {
    let direction = s.frustum_target - s.frustum_eye;
    let up = if direction.normalize_or_zero().cross(Vec3::Y).length() < 1e-3 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    Frustum::look_at(
        s.frustum_eye,
        s.frustum_target,
        up,
        s.frustum_fov,
        FRUSTUM_ASPECT,
        s.frustum_near,
        s.frustum_far,
    )
    .map_err(|e| e.to_string())
}

/// The twelve edges of `frustum`: corners joined when their indices differ in
/// one bit (bit 0 right, bit 1 top, bit 2 far; see [`Frustum::corners`]).
pub fn frustum_edges(frustum: &Frustum) -> [[Vec3; 2]; 12] {
    let corners = frustum
        .corners()
        .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32));
    let mut edges = [[Vec3::ZERO; 2]; 12];
    let mut e = 0;
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                edges[e] = [corners[i], corners[i | bit]];
                e += 1;
            }
        }
    }
    edges
}

/// The answer of one frustum query and what it draws.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrustumSelection {
    /// Primitive kind asked.
    pub kind: PrimitiveKind,
    /// Build-input indices of the primitives the tree selects, ascending.
    pub selected: Vec<u32>,
    /// Number of distinct sources (vertices, edges, faces) among them.
    pub sources: usize,
    /// Seconds per tree query (averaged over repeats when fast).
    pub tree_seconds: f64,
    /// Brute force's selection (`None` when not run).
    pub linear: Option<Vec<u32>>,
    /// Seconds for the brute-force query.
    pub linear_seconds: f64,
    /// The frustum's edges and the selected primitives, highlighted.
    pub overlay: Overlay,
}

/// Runs the frustum query of `kind` by the tree (timed), and by brute force
/// when `with_linear`, and builds the overlay: the frustum's edges and every
/// selected primitive in [`colors::FRUSTUM_SELECTED`] (faces filled).
pub fn select(model: &Model, kind: PrimitiveKind, frustum: &Frustum, with_linear: bool) -> FrustumSelection {
    let (selected, tree_seconds) = model.frustum_query(kind, frustum);
    let (linear, linear_seconds) = if with_linear {
        let (l, t) = model.frustum_linear(kind, frustum);
        (Some(l), t)
    } else {
        (None, 0.0)
    };
    let mut overlay = Overlay::default();
    for [a, b] in frustum_edges(frustum) {
        overlay.line(a, b, colors::FRUSTUM);
    }
    let mut sources: Vec<u32> = Vec::with_capacity(selected.len());
    for &input in &selected {
        if let Some(shape) = model.input_shape(kind, input) {
            overlay.shape(&shape, colors::FRUSTUM_SELECTED, true);
        }
        sources.extend(model.input_source(kind, input));
    }
    sources.sort_unstable();
    sources.dedup();
    FrustumSelection {
        kind,
        sources: sources.len(),
        selected,
        tree_seconds,
        linear,
        linear_seconds,
        overlay,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelSource;
    use proxima::Mesh;
    use proxima::frustum::FrustumOverlap;

    /// A wavy n × n grid of quads: enough primitives for the tree to prune.
    fn grid_model(n: u32) -> Model {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
                positions.push(Vec3::new(x, 0.1 * (7.0 * x).sin() * (5.0 * z).cos(), z));
            }
        }
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                triangles.push([v, v + n + 1, v + 1]);
                triangles.push([v + 1, v + n + 1, v + n + 2]);
            }
        }
        let mesh = Mesh::from_triangles(positions, &triangles).unwrap();
        Model::load(
            ModelSource::Mesh {
                mesh,
                name: "grid".into(),
            },
            &|_| {},
        )
        .unwrap()
    }

    #[test]
    fn the_twelve_edges_join_corners_differing_in_one_bit() {
        let f = Frustum::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 50.0, 1.5, 1.0, 9.0).unwrap();
        let corners: Vec<Vec3> = f
            .corners()
            .iter()
            .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
            .collect();
        let edges = frustum_edges(&f);
        let mut degree = [0; 8];
        let mut pairs = Vec::new();
        for [a, b] in edges {
            let i = corners.iter().position(|&c| c == a).unwrap();
            let j = corners.iter().position(|&c| c == b).unwrap();
            assert_eq!((i ^ j).count_ones(), 1, "edge {i}-{j} is a diagonal");
            degree[i] += 1;
            degree[j] += 1;
            pairs.push((i.min(j), i.max(j)));
        }
        // Every corner meets three edges, and no edge repeats.
        assert_eq!(degree, [3; 8]);
        pairs.sort_unstable();
        pairs.dedup();
        assert_eq!(pairs.len(), 12);
        // Near edges are shorter than far edges (a perspective frustum).
        let length = |i: usize, j: usize| (corners[i] - corners[j]).length();
        assert!(length(0, 1) < length(4, 5) && length(0, 2) < length(4, 6));
        assert!((length(0, 4) - length(3, 7)).abs() < 1e-3);
    }

    #[test]
    fn the_default_second_camera_sees_part_of_the_model() {
        let m = grid_model(24);
        let s = Settings::for_bounds(&m.bounds);
        let f = settings_frustum(&s).unwrap();
        for kind in PrimitiveKind::ALL {
            let n = select(&m, kind, &f, false).selected.len();
            assert!(n > 0 && n < m.count(kind), "{kind:?}: {n} of {}", m.count(kind));
        }
        let mut bad = s.clone();
        bad.frustum_target = bad.frustum_eye;
        assert!(settings_frustum(&bad).is_err());
        bad = s.clone();
        bad.frustum_far = bad.frustum_near;
        assert!(settings_frustum(&bad).is_err());
        // Looking straight down still has an up direction.
        bad = s;
        bad.frustum_target = bad.frustum_eye - Vec3::Y;
        assert!(settings_frustum(&bad).is_ok());
    }

    #[test]
    fn the_selection_equals_brute_force() {
        let m = grid_model(24);
        let center = m.bounds.center();
        let views = [
            (Vec3::new(-1.0, 0.5, 0.5), center, 30.0, 0.1, 3.0),
            (Vec3::new(0.5, 2.0, 0.5), Vec3::new(0.3, 0.0, 0.6), 20.0, 1.0, 2.1),
            (Vec3::new(0.5, 0.05, -0.2), Vec3::new(0.5, 0.0, 1.0), 60.0, 0.3, 0.8),
        ];
        for (eye, target, fov, near, far) in views {
            let mut s = Settings::for_bounds(&m.bounds);
            (
                s.frustum_eye,
                s.frustum_target,
                s.frustum_fov,
                s.frustum_near,
                s.frustum_far,
            ) = (eye, target, fov, near, far);
            let f = settings_frustum(&s).unwrap();
            for kind in PrimitiveKind::ALL {
                let sel = select(&m, kind, &f, true);
                assert_eq!(sel.linear.as_ref(), Some(&sel.selected), "{kind:?}");
                // Independent brute force over the primitives' own shapes.
                let brute: Vec<u32> = (0..m.count(kind) as u32)
                    .filter(|&i| match m.input_shape(kind, i).unwrap() {
                        crate::scene::Shape::Point(p) => proxima::Point(p).overlaps_frustum(&f),
                        crate::scene::Shape::Segment(a, b) => proxima::LineSegment::new(a, b).overlaps_frustum(&f),
                        // A polygon overlaps when one of its fan triangles does.
                        crate::scene::Shape::Polygon(v) => {
                            (1..v.len() - 1).any(|i| proxima::Triangle::new(v[0], v[i], v[i + 1]).overlaps_frustum(&f))
                        }
                    })
                    .collect();
                assert_eq!(sel.selected, brute, "{kind:?}");
                assert!(sel.tree_seconds > 0.0);
                assert!(sel.sources <= sel.selected.len());
                // Twelve frustum lines, then the selected primitives.
                let frustum_lines = sel.overlay.lines.iter().filter(|v| v.color == colors::FRUSTUM).count();
                assert_eq!(frustum_lines, 24);
                let highlighted = match kind {
                    PrimitiveKind::Vertices => sel.overlay.points.len(),
                    PrimitiveKind::Edges => sel.overlay.lines.len() / 2 - 12,
                    PrimitiveKind::Faces | PrimitiveKind::Polygons => sel.overlay.triangles.len() / 3,
                };
                let expected: usize = sel
                    .selected
                    .iter()
                    .map(|&i| match m.input_shape(kind, i).unwrap() {
                        crate::scene::Shape::Polygon(v) => v.len() - 2,
                        _ => 1,
                    })
                    .sum();
                assert_eq!(highlighted, expected, "{kind:?}");
            }
        }
    }
}
