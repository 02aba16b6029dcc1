//! The sphere tree's nodes at a depth, drawn as three great circles each
//! (one per coordinate plane): plain data, unit-tested without a window.

use crate::scene::{Overlay, colors};
use proxima::math::Vec3;
use proxima::{Sphere, SphereTree};

/// Line segments per great circle.
pub const CIRCLE_SEGMENTS: usize = 48;

/// The spheres of the nodes of `tree` at exactly `depth` (the root is depth
/// 0), in node order. Leaves above that depth are not included, as in
/// [`crate::scene::nodes_at_depth`].
pub fn sphere_nodes_at_depth<T>(tree: &SphereTree<T>, depth: u32) -> Vec<Sphere> {
    let mut out = Vec::new();
    if tree.root().is_none() {
        return out;
    }
    let mut stack = vec![(0usize, 0u32)];
    while let Some((index, d)) = stack.pop() {
        let node = tree.node(index);
        if d == depth {
            out.push(node.sphere());
        } else if !node.is_leaf() {
            let [a, b] = node.children();
            stack.push((b as usize, d + 1));
            stack.push((a as usize, d + 1));
        }
    }
    out
}

/// The segments of three great circles of `sphere`, in the xy, yz and zx
/// planes through its center, `segments` per circle.
pub fn great_circles(sphere: &Sphere, segments: usize) -> Vec<[Vec3; 2]> {
    let segments = segments.max(3);
    let mut out = Vec::with_capacity(3 * segments);
    let axes = [(Vec3::X, Vec3::Y), (Vec3::Y, Vec3::Z), (Vec3::Z, Vec3::X)];
    for (u, v) in axes {
        let point = |i: usize| {
            let angle = std::f32::consts::TAU * i as f32 / segments as f32;
            sphere.center + sphere.radius * (angle.cos() * u + angle.sin() * v)
        };
        for i in 0..segments {
            out.push([point(i), point(i + 1)]);
        }
    }
    out
}

/// The great circles of every sphere, in [`colors::SPHERES`].
pub fn spheres_overlay(spheres: &[Sphere]) -> Overlay {
    let mut overlay = Overlay::default();
    for sphere in spheres {
        for [a, b] in great_circles(sphere, CIRCLE_SEGMENTS) {
            overlay.line(a, b, colors::SPHERES);
        }
    }
    overlay
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::nodes_at_depth;
    use proxima::{AabbTree, BuildConfig, Point};

    #[test]
    fn every_circle_point_lies_on_the_sphere() {
        let sphere = Sphere {
            center: Vec3::new(1.0, -2.0, 0.5),
            radius: 3.0,
        };
        let lines = great_circles(&sphere, 20);
        assert_eq!(lines.len(), 60);
        for [a, b] in &lines {
            for p in [a, b] {
                assert!(((*p - sphere.center).length() - 3.0).abs() < 1e-5, "{p}");
            }
        }
        // Each circle closes: its last segment ends where its first begins.
        for circle in lines.chunks(20) {
            assert!((circle[19][1] - circle[0][0]).length() < 1e-5);
            assert!(circle.windows(2).all(|w| w[0][1] == w[1][0]));
        }
        // Three distinct planes: the circles span all three axes.
        let extent = lines
            .iter()
            .fold(Vec3::ZERO, |m, [a, _]| m.max((*a - sphere.center).abs()));
        assert!((extent - Vec3::splat(3.0)).abs().max_element() < 1e-5);
    }

    #[test]
    fn spheres_at_a_depth_bound_the_same_nodes_as_the_boxes() {
        let points: Vec<Point> = (0..500)
            .map(|i| {
                let t = i as f32 * 0.37;
                Point(Vec3::new(t.sin() * 3.0, (t * 1.3).cos(), (i as f32 * 0.011).fract()))
            })
            .collect();
        let config = BuildConfig::default();
        let boxes = AabbTree::build(points.clone(), &config).unwrap();
        let spheres = SphereTree::build(points.clone(), &config).unwrap();
        for depth in 0..=boxes.depth() {
            let b = nodes_at_depth(&boxes, depth);
            let s = sphere_nodes_at_depth(&spheres, depth);
            // Same hierarchy: as many spheres as boxes.
            assert_eq!(b.len(), s.len(), "depth {depth}");
            // Near the root no leaf ends early: the spheres cover every point.
            if depth <= 2 {
                for p in &points {
                    assert!(
                        s.iter().any(|sp| (p.0 - sp.center).length() <= sp.radius),
                        "depth {depth}: {p:?} outside every sphere"
                    );
                }
            }
        }
        assert!(sphere_nodes_at_depth(&spheres, boxes.depth() + 1).is_empty());
        let overlay = spheres_overlay(&sphere_nodes_at_depth(&spheres, 1));
        assert_eq!(overlay.lines.len(), 2 * 2 * 3 * CIRCLE_SEGMENTS);
    }
}
