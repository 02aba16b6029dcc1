//! Convex polygon primitives.
//!
//! - On meshes whose polygons are exactly planar and convex (built from small
//!   integers, so every coordinate and every plane is exact in `f32`): every
//!   face is accepted, and closest distances equal the fan triangulation's
//!   (within `f32` rounding), grid cells are the same set, ray hits the same.
//! - Trees (binary and wide) over polygons equal brute force over the same
//!   polygons, field for field; grid cells (classic and scan-line) equal a
//!   brute-force enumeration with the exact box test.
//! - Proptest: `closest_point` against an independent `f64` oracle (minimum
//!   over fan triangles by plane projection and edges, and dense sampling);
//!   box overlap against clipping of the polygon by the box's six closed
//!   half-spaces (exact rationals on integer input, `f64` otherwise); faces
//!   that are planar only within tolerance stay within the documented `2t`.
//! - The real quad and n-gon meshes: fallback counts, tree == brute force,
//!   grid == brute force, and the `2t` bound at a loose tolerance.

use crate::common;

use crate::common::oracle::{D3, Num, Q, clip_by_box, d3, dist, triangle_distance};
use crate::common::{data_dir, queries};
use proptest::prelude::*;
use proxima::WideTree;
use proxima::grid::{Cell, GridConfig, GridInsert, GridLayout, HashGrid, InsertMethod, InsertParams};
use proxima::mesh::PolygonExtraction;
use proxima::prelude::*;
use proxima::primitive::polygon::{DEFAULT_PLANARITY_TOLERANCE, MAX_POLYGON_VERTICES};
use proxima::primitive::{PolygonBoxTest, WatertightRay};
use proxima::sample::Rng;
use proxima::{
    Aabb, AabbTree, Bounded, BoxOverlap, BuildConfig, ClosestPoint, ConvexPolygon, LinearSearch, Mesh, PolygonError,
    PrimitiveSet, Triangle, Vec3, Vec3A,
};
use std::collections::{BTreeSet, HashMap};

// ------------------------------------------------------------ generators ---

/// The strictly convex hull (counter-clockwise, no collinear vertices) of
/// integer points.
fn lattice_hull(mut points: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    points.sort_unstable();
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: (i64, i64), a: (i64, i64), b: (i64, i64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut hull: Vec<(i64, i64)> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(i64, i64)>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// A convex lattice polygon of `n` directions (and their opposites): a
/// strictly convex `2n`-gon with integer vertices.
fn lattice_2n_gon(n: usize) -> Vec<(i64, i64)> {
    let dirs = [(1, 0), (2, 1), (1, 1), (1, 2), (0, 1), (-1, 2), (-1, 1), (-2, 1)];
    let mut edges: Vec<(i64, i64)> = dirs[..n].to_vec();
    edges.extend(dirs[..n].iter().map(|&(x, y)| (-x, -y)));
    let mut p = (0, 0);
    edges
        .iter()
        .map(|&(x, y)| {
            let at = p;
            p = (p.0 + x, p.1 + y);
            at
        })
        .collect()
}

/// Builds a mesh from faces given by position, welding equal positions.
fn weld(faces: &[Vec<Vec3>]) -> Mesh {
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let faces: Vec<Vec<u32>> = faces
        .iter()
        .map(|face| {
            face.iter()
                .map(|&p| {
                    *index.entry(p.to_array().map(f32::to_bits)).or_insert_with(|| {
                        positions.push(p);
                        positions.len() as u32 - 1
                    })
                })
                .collect()
        })
        .collect();
    Mesh::from_faces(positions, &faces).unwrap()
}

/// The cube `[0, n·scale]³`, each side cut into `n × n` quads (outward).
fn subdivided_cube(n: i32, scale: f32) -> Mesh {
    let mut faces = Vec::new();
    for axis in 0..3 {
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |a: i32, b: i32| {
                        let mut c = [0.0f32; 3];
                        c[axis] = side as f32 * scale;
                        c[(axis + 1) % 3] = a as f32 * scale;
                        c[(axis + 2) % 3] = b as f32 * scale;
                        Vec3::from_array(c)
                    };
                    let mut quad = vec![corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)];
                    if side == 0 {
                        quad.reverse();
                    }
                    faces.push(quad);
                }
            }
        }
    }
    weld(&faces)
}

/// A prism over a convex lattice polygon: two caps and a quad per side.
fn prism(base: &[(i64, i64)], height: f32, scale: f32, offset: Vec3) -> Mesh {
    let at = |&(x, y): &(i64, i64), z: f32| offset + Vec3::new(x as f32 * scale, y as f32 * scale, z);
    let mut faces = vec![
        base.iter().rev().map(|p| at(p, 0.0)).collect::<Vec<_>>(),
        base.iter().map(|p| at(p, height)).collect(),
    ];
    for i in 0..base.len() {
        let (a, b) = (&base[i], &base[(i + 1) % base.len()]);
        faces.push(vec![at(a, 0.0), at(b, 0.0), at(b, height), at(a, height)]);
    }
    weld(&faces)
}

/// A soup of exactly planar convex polygons in random orientations: lattice
/// hulls placed with integer vectors `u`, `w` (every vertex an integer times
/// `scale`, a power of two, so every coordinate is exact).
fn planar_soup(count: usize, seed: u64, scale: f32) -> Mesh {
    let mut rng = Rng::new(seed);
    let mut int = |lo: i64, hi: i64| lo + rng.below((hi - lo + 1) as usize) as i64;
    let mut faces = Vec::new();
    while faces.len() < count {
        let k = int(3, 14) as usize;
        let hull = lattice_hull((0..k).map(|_| (int(-5, 5), int(-5, 5))).collect());
        let (u, w, o) = (
            [int(-3, 3), int(-3, 3), int(-3, 3)],
            [int(-3, 3), int(-3, 3), int(-3, 3)],
            [int(-20, 20), int(-20, 20), int(-20, 20)],
        );
        let normal = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        if hull.len() < 3 || normal == [0, 0, 0] {
            continue;
        }
        faces.push(
            hull.iter()
                .map(|&(a, b)| Vec3::from_array(std::array::from_fn(|k| (o[k] + a * u[k] + b * w[k]) as f32 * scale)))
                .collect(),
        );
    }
    weld(&faces)
}

/// Meshes whose every face is exactly planar and convex.
fn planar_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("cube 6x6", subdivided_cube(6, 0.25)),
        (
            "hexagon prism",
            prism(&lattice_2n_gon(3), 1.5, 0.5, Vec3::new(0.25, -1.0, 0.5)),
        ),
        ("octagon prism", prism(&lattice_2n_gon(4), 0.75, 0.25, Vec3::ZERO)),
        (
            "16-gon prism",
            prism(&lattice_2n_gon(8), 2.0, 0.125, Vec3::new(-1.0, 0.0, 3.0)),
        ),
        ("planar soup", planar_soup(300, 5, 0.125)),
    ]
}

// --------------------------------------------------------------- oracles ---

/// Distance from `p` to the polygon's fan triangulation, in `f64`.
fn fan_distance(polygon: &ConvexPolygon, p: D3) -> f64 {
    polygon
        .fan_triangles()
        .map(|t| triangle_distance(&t, p))
        .fold(f64::INFINITY, f64::min)
}

/// `true` when the planar convex polygon meets the closed box.
fn clip_oracle<N: Num>(points: &[Vec3], b: &Aabb) -> bool {
    clip_by_box::<N>(points, b)
}

// ----------------------------------------------------------- comparisons ---

/// Trees (binary, wide and sphere) against brute force over the same set, every field.
fn check_tree<T: proxima::MeshPrimitive>(set: PrimitiveSet<T>, points: &[Vec3]) {
    let tree = AabbTree::build_set(set.clone(), &BuildConfig::default()).unwrap();
    tree.validate().unwrap();
    let spheres = proxima::SphereTree::build_set(set.clone(), &BuildConfig::default()).unwrap();
    spheres.validate().unwrap();
    let linear = LinearSearch::new(set);
    for &p in points {
        let expected = linear.closest(p);
        assert_eq!(tree.closest(p), expected, "closest at {p}");
        assert_eq!(spheres.closest(p), expected, "sphere tree, closest at {p}");
        assert_eq!(tree.k_nearest(p, 3), linear.k_nearest(p, 3), "k-nearest at {p}");
        assert_eq!(
            spheres.k_nearest(p, 3),
            linear.k_nearest(p, 3),
            "sphere tree, k-nearest at {p}"
        );
    }
    let batch = tree.closest_batch(points);
    for (i, &p) in points.iter().enumerate() {
        assert_eq!(batch[i], linear.closest(p));
    }
    let wide = WideTree::from_tree(tree);
    for &p in points {
        assert_eq!(wide.closest(p), linear.closest(p), "wide tree at {p}");
    }
    let knn = wide.k_nearest_batch(points, 4);
    for (i, &p) in points.iter().enumerate() {
        assert_eq!(knn[i], linear.k_nearest(p, 4));
    }
}

/// Every (cell, source face) pair of a grid.
fn cell_sources<T>(grid: &HashGrid<T>) -> BTreeSet<(Cell, u32)> {
    let mut out = BTreeSet::new();
    for (cell, entries) in grid.occupied() {
        for &e in entries {
            out.insert((cell, grid.sources()[e as usize]));
        }
    }
    out
}

/// Cells of each polygon by classic and scan-line insertion, against every
/// cell of its box range tested with `overlaps_box` (brute force). A
/// 3-vertex polygon must give its triangle's cells (`tests/grid.rs` checks
/// those against an oracle).
fn check_cells(polygons: &[ConvexPolygon], layout: &GridLayout) {
    for (i, polygon) in polygons.iter().enumerate() {
        let mut expected: Vec<Cell> = match polygon.as_triangle() {
            Some(tri) => {
                let mut cells = Vec::new();
                tri.visit_cells(&InsertParams::new(layout), |c| cells.push(c)).unwrap();
                cells
            }
            None => {
                // A range that is one line of cells is touched whole by any
                // connected set (`insert.rs`); this also holds where the f64
                // test rounds a touching contact away (beast.obj has a vertex
                // at x = -4.3e-19 beside one at x = 0, on a cell boundary).
                let range = layout.cell_range(&polygon.bounds()).unwrap();
                let line = range.is_line();
                range
                    .iter()
                    .filter(|&c| {
                        let (lo, hi) = layout.cell_bounds(c);
                        line || polygon.overlaps_bounds(lo, hi)
                    })
                    .collect()
            }
        };
        expected.sort_unstable();
        for method in [InsertMethod::Classic, InsertMethod::Scanline] {
            let params = InsertParams {
                method,
                ..InsertParams::new(layout)
            };
            let mut cells = Vec::new();
            polygon.visit_cells(&params, |c| cells.push(c)).unwrap();
            cells.sort_unstable();
            assert_eq!(cells, expected, "polygon {i} {polygon:?}, {method:?}");
        }
    }
}

/// The first hit by brute force: (t, source), lowest index on ties.
fn first_hit_polygons(set: &PrimitiveSet<ConvexPolygon>, ray: &WatertightRay) -> Option<(f32, u32)> {
    let mut best: Option<(f32, u32)> = None;
    for (polygon, &source) in set.primitives.iter().zip(&set.sources) {
        if let Some(hit) = polygon.intersect_ray(ray, 0.0, f32::INFINITY)
            && best.is_none_or(|b| hit.t < b.0)
        {
            best = Some((hit.t, source));
        }
    }
    best
}

fn first_hit_triangles(set: &PrimitiveSet<Triangle>, ray: &WatertightRay) -> Option<(f32, u32)> {
    let mut best: Option<(f32, u32)> = None;
    for (tri, &source) in set.primitives.iter().zip(&set.sources) {
        if let Some(hit) = ray.intersect(tri, 0.0, f32::INFINITY)
            && best.is_none_or(|b| hit.t < b.0)
        {
            best = Some((hit.t, source));
        }
    }
    best
}

fn scale_of(mesh: &Mesh, p: Vec3) -> f64 {
    let b = mesh.bounds();
    b.min.abs().max(b.max.abs()).max(p.abs()).max_element().max(1e-30) as f64
}

// ------------------------------------------------------ planar meshes ---

#[test]
fn exactly_planar_faces_are_all_accepted() {
    for (name, mesh) in planar_meshes() {
        let r = mesh.extract_polygons(DEFAULT_PLANARITY_TOLERANCE);
        assert_eq!(r.fan_triangulated, 0, "{name}: {r:?}");
        assert_eq!(r.polygon_faces() + r.triangles, mesh.face_count(), "{name}");
        for polygon in &r.set.primitives {
            assert!(polygon.len() <= MAX_POLYGON_VERTICES);
            assert!(
                polygon.thickness() <= 1e-6 * polygon.bounds().diagonal() as f64,
                "{name}"
            );
        }
        // Sources in face order, every face present.
        assert!(r.set.sources.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(r.set.sources.last().map(|&s| s as usize + 1), Some(mesh.face_count()));
    }
    // The 16-gon caps are cut into pieces of 8, 8 and 4 vertices.
    let mesh = prism(&lattice_2n_gon(8), 2.0, 0.125, Vec3::ZERO);
    let r = mesh.extract_polygons(DEFAULT_PLANARITY_TOLERANCE);
    assert_eq!(r.split, 2);
    let cap: Vec<usize> = r
        .set
        .sources
        .iter()
        .zip(&r.set.primitives)
        .filter(|(s, _)| **s == 0)
        .map(|(_, p)| p.len())
        .collect();
    assert_eq!(cap, [8, 8, 4]);
    // The pieces' fan triangles are the face's.
    let fan: Vec<Triangle> = r.set.primitives[..3]
        .iter()
        .flat_map(|p| p.fan_triangles().collect::<Vec<_>>())
        .collect();
    let expected: Vec<Triangle> = mesh.triangles().primitives[..14].to_vec();
    assert_eq!(fan, expected);
}

#[test]
fn planar_meshes_closest_equals_fan_triangulation() {
    for (name, mesh) in planar_meshes() {
        let polygons = mesh.polygons();
        let triangles = mesh.triangles();
        let points = queries(&mesh, 300, 3);
        let poly_tree = AabbTree::build_set(polygons.clone(), &BuildConfig::default()).unwrap();
        let tri_tree = AabbTree::build_set(triangles.clone(), &BuildConfig::default()).unwrap();
        for &p in &points {
            let a = poly_tree.closest(p).unwrap();
            let b = tri_tree.closest(p).unwrap();
            // f32 rounding of two different formulas, relative to the coordinates.
            let tol = (scale_of(&mesh, p) * 1e-6) as f32;
            assert!((a.distance - b.distance).abs() <= tol, "{name} at {p}: {a:?} vs {b:?}");
            // The face found is as close (it may differ only on a tie).
            let face_distance = triangles
                .primitives
                .iter()
                .zip(&triangles.sources)
                .filter(|(_, s)| **s == a.source)
                .map(|(t, _)| t.distance_squared(p.into()).sqrt())
                .fold(f32::INFINITY, f32::min);
            assert!((face_distance - b.distance).abs() <= tol, "{name} at {p}");
        }
    }
}

#[test]
fn planar_meshes_trees_equal_brute_force() {
    for (_, mesh) in planar_meshes() {
        check_tree(mesh.polygons(), &queries(&mesh, 120, 9));
    }
}

#[test]
fn planar_meshes_grid_cells_equal_fan_triangulation() {
    for (name, mesh) in planar_meshes() {
        let polygons = mesh.polygons();
        for (size, origin) in [
            (0.25, Vec3::ZERO),
            (0.5, Vec3::splat(0.125)),
            (0.3, Vec3::new(-0.1, 0.05, 0.0)),
        ] {
            for insert in [InsertMethod::Classic, InsertMethod::Scanline] {
                let config = GridConfig {
                    origin,
                    insert,
                    ..GridConfig::cubic(size)
                };
                let a: HashGrid<_> = HashGrid::build(polygons.clone(), &config).unwrap();
                let b: HashGrid<_> = HashGrid::build(mesh.triangles(), &config).unwrap();
                assert_eq!(cell_sources(&a), cell_sources(&b), "{name}, cell {size}, {insert:?}");
            }
            check_cells(&polygons.primitives, &config_layout(size, origin));
        }
    }
}

fn config_layout(size: f32, origin: Vec3) -> GridLayout {
    GridLayout::new(origin, Vec3::splat(size)).unwrap()
}

#[test]
fn huge_tiny_and_offset_coordinates() {
    // Powers of two keep every plane exact. At 2^-100 the f32 edge signs
    // underflow to zero and the f64 path answers; at 2^50 the products are
    // near 1e30. Offset far from the origin, small faces lose their shape in
    // f32 and fall back; either way tree == brute force.
    for (factor, offset) in [(2f32.powi(50), 0.0), (2f32.powi(-100), 0.0), (1e-3, 1e6)] {
        for (name, mesh) in planar_meshes() {
            let positions: Vec<Vec3> = mesh
                .positions()
                .iter()
                .map(|&p| p * factor + Vec3::splat(offset))
                .collect();
            let faces: Vec<Vec<u32>> = mesh.faces().map(|f| f.to_vec()).collect();
            let mesh = Mesh::from_faces(positions, &faces).unwrap();
            let r = mesh.extract_polygons(DEFAULT_PLANARITY_TOLERANCE);
            if offset == 0.0 {
                assert_eq!(r.fan_triangulated, 0, "{name} x {factor}");
            }
            let points = queries(&mesh, 40, 2);
            check_tree(r.set.clone(), &points);
            let tri_tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
            let polygons = LinearSearch::new(r.set);
            for &p in &points {
                let (a, b) = (polygons.closest(p), tri_tree.closest(p));
                let tol = (scale_of(&mesh, p) * 1e-6) as f32;
                match (a, b) {
                    (Some(a), Some(b)) => {
                        assert!((a.distance - b.distance).abs() <= tol, "{name} x {factor}: {a:?} {b:?}")
                    }
                    (a, b) => assert_eq!(a.is_none(), b.is_none(), "{name} x {factor} at {p}"),
                }
            }
        }
    }
}

#[test]
fn planar_meshes_ray_hits_equal_fan_triangulation() {
    for (name, mesh) in planar_meshes() {
        let polygons = mesh.polygons();
        let triangles = mesh.triangles();
        let b = mesh.bounds();
        let mut rng = Rng::new(17);
        let positions = mesh.positions();
        let mut hits = 0;
        for i in 0..400 {
            let origin = b.center() + (rng.in_box(&b) - b.center()) * 2.5;
            // Aim at vertices and edge midpoints too: rays through shared edges.
            let target = match i % 3 {
                0 => positions[rng.below(positions.len())],
                1 => (positions[rng.below(positions.len())] + positions[rng.below(positions.len())]) * 0.5,
                _ => rng.in_box(&b),
            };
            let Some(ray) = WatertightRay::new(origin, target - origin) else {
                continue;
            };
            let a = first_hit_polygons(&polygons, &ray);
            assert_eq!(a, first_hit_triangles(&triangles, &ray), "{name}: ray {i}");
            hits += usize::from(a.is_some());
        }
        assert!(hits > 100, "{name}: only {hits} hits");
    }
}

#[test]
fn rays_from_inside_a_closed_polygon_mesh_always_hit() {
    // Watertight: from the center of the cube towards its vertices, edge
    // midpoints and random points, every ray meets a face.
    let mesh = subdivided_cube(4, 0.5);
    let polygons = mesh.polygons();
    let center = mesh.bounds().center() + Vec3::new(1.0 / 64.0, 0.0, 0.0);
    let mut rng = Rng::new(3);
    let edges = mesh.edge_indices();
    for i in 0..2000 {
        let p = mesh.positions();
        let target = match i % 3 {
            0 => p[rng.below(p.len())],
            1 => {
                let [a, b] = edges[rng.below(edges.len())];
                (p[a as usize] + p[b as usize]) * 0.5
            }
            _ => Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
        };
        let ray = WatertightRay::new(center, target - center).unwrap();
        assert!(
            first_hit_polygons(&polygons, &ray).is_some(),
            "ray {i} towards {target} escaped"
        );
    }
}

#[test]
fn triangle_meshes_answer_as_triangles_bit_for_bit() {
    // Every face of a triangle mesh is a 3-vertex polygon delegating to the
    // triangle's routines: the same hits, points, distances and cells.
    for mesh in [common::random_soup(400, 3), common::bumpy_sphere(10, 2)] {
        let polygons = mesh.polygons();
        let triangles = mesh.triangles();
        assert_eq!(polygons.sources, triangles.sources);
        let a = AabbTree::build_set(polygons.clone(), &BuildConfig::default()).unwrap();
        let b = AabbTree::build_set(triangles.clone(), &BuildConfig::default()).unwrap();
        for p in queries(&mesh, 200, 8) {
            assert_eq!(a.closest(p), b.closest(p), "at {p}");
            assert_eq!(a.k_nearest(p, 5), b.k_nearest(p, 5), "at {p}");
        }
        let config = GridConfig::cubic(mesh.bounds().diagonal() / 37.0);
        let a: HashGrid<_> = HashGrid::build(polygons.clone(), &config).unwrap();
        let b: HashGrid<_> = HashGrid::build(triangles.clone(), &config).unwrap();
        assert_eq!(cell_sources(&a), cell_sources(&b));
        let mut rng = Rng::new(4);
        let bounds = mesh.bounds();
        for _ in 0..300 {
            let (o, t) = (rng.in_box(&bounds.inflate(0.5)), rng.in_box(&bounds));
            let Some(ray) = WatertightRay::new(o, t - o) else {
                continue;
            };
            assert_eq!(
                first_hit_polygons(&polygons, &ray),
                first_hit_triangles(&triangles, &ray)
            );
        }
    }
}

// ---------------------------------------------------------- construction ---

#[test]
fn construction_accepts_and_rejects() {
    let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let p = ConvexPolygon::new(&square).unwrap();
    assert_eq!((p.len(), p.normal(), p.thickness()), (4, Vec3::Z, 0.0));
    // Clockwise: the normal flips.
    let mut reversed = square;
    reversed.reverse();
    assert_eq!(ConvexPolygon::new(&reversed).unwrap().normal(), -Vec3::Z);
    // Bent, dart, collinear corner, repeated vertex, zero area, pentagram.
    let bent = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.1), Vec3::Y];
    assert!(matches!(ConvexPolygon::new(&bent), Err(PolygonError::NotPlanar { .. })));
    assert!(ConvexPolygon::with_tolerance(&bent, 0.1).is_ok());
    let dart = [Vec3::ZERO, Vec3::X, Vec3::new(0.2, 0.2, 0.0), Vec3::Y];
    assert!(matches!(ConvexPolygon::new(&dart), Err(PolygonError::NotConvex { .. })));
    let straight = [Vec3::ZERO, Vec3::X * 0.5, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    assert!(matches!(
        ConvexPolygon::new(&straight),
        Err(PolygonError::NotConvex { index: 1 })
    ));
    let repeated = [Vec3::ZERO, Vec3::X, Vec3::X, Vec3::Y];
    assert!(matches!(
        ConvexPolygon::new(&repeated),
        Err(PolygonError::NotConvex { .. })
    ));
    let flat = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 3.0];
    assert!(matches!(ConvexPolygon::new(&flat), Err(PolygonError::Degenerate)));
    let star: Vec<Vec3> = (0..5)
        .map(|i| {
            let a = i as f32 * 4.0 * std::f32::consts::PI / 5.0;
            Vec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    assert!(matches!(ConvexPolygon::new(&star), Err(PolygonError::NotConvex { .. })));
    // Counts and coordinates.
    assert!(matches!(
        ConvexPolygon::new(&square[..2]),
        Err(PolygonError::VertexCount { count: 2, .. })
    ));
    assert!(matches!(
        ConvexPolygon::new(&[Vec3::ZERO; 9]),
        Err(PolygonError::VertexCount { count: 9, .. })
    ));
    let nan = [Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 1.0, 0.0), Vec3::Y];
    assert!(matches!(
        ConvexPolygon::new(&nan),
        Err(PolygonError::NonFinite { index: 2 })
    ));
    // Any triangle is accepted, degenerate ones too, and is the triangle.
    let point = ConvexPolygon::new(&[Vec3::ONE; 3]).unwrap();
    assert_eq!(
        point.as_triangle(),
        Some(Triangle::new(Vec3::ONE, Vec3::ONE, Vec3::ONE))
    );
    assert_eq!(point.closest_point(Vec3A::ZERO), Vec3A::ONE);
}

#[test]
fn mesh_extraction_falls_back_to_the_fan() {
    let positions = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::Y,
        Vec3::new(1.0, 1.0, 0.5),
        Vec3::new(0.2, 0.2, 0.0),
    ];
    let faces = vec![vec![0, 1, 2, 3], vec![0, 1, 4, 3], vec![0, 1, 5, 3], vec![0, 1, 2]];
    let mesh = Mesh::from_faces(positions, &faces).unwrap();
    let r = mesh.extract_polygons(DEFAULT_PLANARITY_TOLERANCE);
    assert_eq!((r.polygons, r.not_planar, r.not_convex, r.triangles), (1, 1, 1, 1));
    assert_eq!(r.fan_triangulated, 2);
    assert_eq!(r.set.sources, [0, 1, 1, 2, 2, 3]);
    // The fallback pieces are exactly the fan triangles.
    let triangles = mesh.triangles();
    for i in 1..6 {
        assert_eq!(r.set.primitives[i].as_triangle(), Some(triangles.primitives[i + 1]));
    }
}

// ---------------------------------------------------------------- proptest ---

/// An exactly planar convex polygon: a lattice hull in an integer plane,
/// scaled by a power of two.
fn planar_polygon(max_shift: u32) -> impl Strategy<Value = Vec<Vec3>> {
    (
        prop::collection::vec((-6i64..=6, -6i64..=6), 3..12),
        prop::array::uniform3(-3i64..=3),
        prop::array::uniform3(-3i64..=3),
        prop::array::uniform3(-8i64..=8),
        0..=max_shift,
    )
        .prop_filter_map("degenerate", |(points, u, w, o, shift)| {
            let hull = lattice_hull(points);
            let normal = [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ];
            if hull.len() < 3 || hull.len() > MAX_POLYGON_VERTICES || normal == [0, 0, 0] {
                return None;
            }
            let scale = 1.0 / (1 << shift) as f32;
            Some(
                hull.iter()
                    .map(|&(a, b)| {
                        Vec3::from_array(std::array::from_fn(|k| (o[k] + a * u[k] + b * w[k]) as f32 * scale))
                    })
                    .collect(),
            )
        })
}

fn query_point() -> impl Strategy<Value = Vec3> {
    let coord = prop_oneof![-12.0f32..12.0, (-48i32..=48).prop_map(|v| v as f32 * 0.25)];
    (coord.clone(), coord.clone(), coord).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn int_box() -> impl Strategy<Value = Aabb> {
    (prop::array::uniform3(-12i32..=12), prop::array::uniform3(0i32..=6)).prop_map(|(min, size)| {
        let min = Vec3::from_array(min.map(|v| v as f32));
        Aabb::new(min, min + Vec3::from_array(size.map(|v| v as f32)))
    })
}

fn float_box() -> impl Strategy<Value = Aabb> {
    (
        prop::array::uniform3(-12.0f32..12.0),
        prop::array::uniform3(0.0f32..6.0),
    )
        .prop_map(|(min, size)| {
            let min = Vec3::from_array(min);
            Aabb::new(min, min + Vec3::from_array(size))
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// `closest_point` against the f64 fan oracle and dense sampling.
    #[test]
    fn closest_point_matches_the_f64_oracle(vertices in planar_polygon(3), p in query_point()) {
        let polygon = ConvexPolygon::new(&vertices).unwrap();
        let q: Vec3 = polygon.closest_point(p.into()).into();
        let scale = vertices.iter().chain([&p]).map(|v| v.abs().max_element()).fold(1.0f32, f32::max) as f64;
        let tol = scale * 2e-6;
        let expected = fan_distance(&polygon, d3(p));
        let got = dist(d3(q), d3(p));
        prop_assert!((got - expected).abs() <= tol, "distance {} vs oracle {}", got, expected);
        // The answer lies on the polygon, inside its box (up to the rounding of a point on an edge).
        prop_assert!(fan_distance(&polygon, d3(q)) <= tol);
        prop_assert!(polygon.bounds().inflate(tol as f32).contains_point(q));
        // No sampled point of the polygon is closer.
        for tri in polygon.fan_triangles() {
            for i in 0..=6 {
                for j in 0..=6 - i {
                    let s = tri.a + (tri.b - tri.a) * (i as f32 / 6.0) + (tri.c - tri.a) * (j as f32 / 6.0);
                    prop_assert!(got <= dist(d3(s), d3(p)) + tol);
                }
            }
        }
    }

    /// Bent polygons accepted at a loose tolerance stay within `2t` of the fan.
    #[test]
    fn nonplanar_polygons_stay_within_twice_the_thickness(
        vertices in planar_polygon(3),
        lift in -0.05f32..0.05,
        which in 0usize..8,
        p in query_point(),
    ) {
        let mut vertices = vertices;
        let k = which % vertices.len();
        let n = ConvexPolygon::new(&vertices).unwrap().normal();
        vertices[k] += n * lift;
        let Ok(polygon) = ConvexPolygon::with_tolerance(&vertices, 0.05) else { return Ok(()) };
        let t = polygon.thickness();
        let q: Vec3 = polygon.closest_point(p.into()).into();
        let scale = vertices.iter().chain([&p]).map(|v| v.abs().max_element()).fold(1.0f32, f32::max) as f64;
        let got = dist(d3(q), d3(p));
        let fan = fan_distance(&polygon, d3(p));
        prop_assert!((got - fan).abs() <= 2.0 * t + scale * 2e-6, "{} vs fan {}, t = {}", got, fan, t);
        // Within the box, up to the rounding of a point on an edge.
        prop_assert!(polygon.bounds().inflate(scale as f32 * 1e-6).contains_point(q));
    }

    /// Integer polygons and boxes: the exact rational oracle, exactly.
    #[test]
    fn box_overlap_matches_exact_clipping(vertices in planar_polygon(0), b in int_box()) {
        let polygon = ConvexPolygon::new(&vertices).unwrap();
        let expected = clip_oracle::<Q>(&vertices, &b);
        prop_assert_eq!(polygon.overlaps_box(&b), expected, "{:?} {:?}", vertices, b);
        if vertices.len() > 3 {
            prop_assert_eq!(PolygonBoxTest::new(&polygon).overlaps(&b), expected);
            prop_assert!(PolygonBoxTest::new(&polygon).is_planar());
        }
        // Every fan triangle says the same in union.
        prop_assert_eq!(polygon.fan_triangles().any(|t| t.overlaps_box(&b)), expected);
    }

    /// Float boxes: the f64 clipping oracle.
    #[test]
    fn box_overlap_matches_f64_clipping(vertices in planar_polygon(3), b in float_box()) {
        let polygon = ConvexPolygon::new(&vertices).unwrap();
        prop_assert_eq!(polygon.overlaps_box(&b), clip_oracle::<f64>(&vertices, &b), "{:?} {:?}", vertices, b);
    }
}

// ------------------------------------------------------------ real meshes ---

fn real_polygon_meshes() -> Vec<(String, Mesh)> {
    let Some(dir) = data_dir() else { return Vec::new() };
    ["spot_quadrangulated.obj", "beast.obj"]
        .iter()
        .map(|name| (name.to_string(), proxima::io::load(dir.join(name)).unwrap()))
        .collect()
}

fn report(name: &str, tolerance: f32, r: &PolygonExtraction) {
    println!(
        "{name}: tolerance {tolerance:e}: {} of {} polygon faces fan-triangulated ({} not planar, {} not convex, {} degenerate); {} kept, {} triangles",
        r.fan_triangulated,
        r.polygon_faces(),
        r.not_planar,
        r.not_convex,
        r.degenerate,
        r.polygons,
        r.triangles
    );
}

#[test]
fn real_meshes_trees_equal_brute_force() {
    for (name, mesh) in real_polygon_meshes() {
        for tolerance in [DEFAULT_PLANARITY_TOLERANCE, 1e-2, 1e-1] {
            let r = mesh.extract_polygons(tolerance);
            report(&name, tolerance, &r);
            assert_eq!(r.polygon_faces() + r.triangles, mesh.face_count());
            let n = (2_000_000 / r.set.len().max(1)).clamp(10, 120);
            check_tree(r.set, &queries(&mesh, n, 4));
        }
    }
}

#[test]
fn real_meshes_stay_within_twice_the_thickness_of_the_fan() {
    for (name, mesh) in real_polygon_meshes() {
        let r = mesh.extract_polygons(0.1);
        let t = r
            .set
            .primitives
            .iter()
            .map(ConvexPolygon::thickness)
            .fold(0.0, f64::max);
        println!("{name}: largest thickness accepted at 0.1: {t}");
        let polygons = LinearSearch::new(r.set);
        let triangles = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
        for p in queries(&mesh, 100, 6) {
            let a = polygons.closest(p).unwrap().distance as f64;
            let b = triangles.closest(p).unwrap().distance as f64;
            assert!(
                (a - b).abs() <= 2.0 * t + scale_of(&mesh, p) * 1e-6,
                "{name} at {p}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn real_meshes_grid_cells_equal_brute_force() {
    for (name, mesh) in real_polygon_meshes() {
        let diagonal = mesh.bounds().diagonal();
        for tolerance in [DEFAULT_PLANARITY_TOLERANCE, 1e-1] {
            let set = mesh.extract_polygons(tolerance).set;
            for cells in [40.0, 150.0] {
                let layout = GridLayout::cubic(diagonal / cells).unwrap();
                check_cells(&set.primitives, &layout);
            }
            // The grid build stores the same cells as the per-primitive visits.
            let config = GridConfig {
                insert: InsertMethod::Scanline,
                ..GridConfig::cubic(diagonal / 100.0)
            };
            let a: HashGrid<_> = HashGrid::build(set.clone(), &config).unwrap();
            let b: HashGrid<_> = HashGrid::build(set, &GridConfig::cubic(diagonal / 100.0)).unwrap();
            assert_eq!(cell_sources(&a), cell_sources(&b), "{name}");
        }
    }
}

/// Ray queries of the trees over polygons (through `RayIntersect`) equal the
/// brute-force first hit over the same polygons, on the planar meshes (whose
/// answers also equal the fan triangulation's, above) and on the real quad
/// meshes at the default and a loose tolerance; the hit point lies on the ray.
#[test]
fn tree_ray_queries_over_polygons_equal_brute_force() {
    let mut cases: Vec<(String, PrimitiveSet<ConvexPolygon>)> = planar_meshes()
        .into_iter()
        .map(|(name, mesh)| (name.to_string(), mesh.polygons()))
        .collect();
    if let Some(dir) = data_dir() {
        for file in ["spot_quadrangulated.obj", "beast.obj"] {
            let path = dir.join(file);
            if !path.exists() {
                continue;
            }
            let mesh = proxima::io::load(&path).unwrap();
            for tolerance in [DEFAULT_PLANARITY_TOLERANCE, 0.1] {
                cases.push((format!("{file} at {tolerance}"), mesh.extract_polygons(tolerance).set));
            }
        }
    }
    for (name, set) in cases {
        let bounds = set.primitives.iter().fold(Aabb::EMPTY, |b, p| b.merge(&p.bounds()));
        let tree = AabbTree::build_set(set.clone(), &BuildConfig::default()).unwrap();
        let wide = WideTree::from_tree(tree.clone());
        let mut rng = Rng::new(29);
        let mut hits = 0;
        for i in 0..600 {
            let origin = bounds.center() + (rng.in_box(&bounds) - bounds.center()) * 2.5;
            let target = match i % 2 {
                0 => set.primitives[rng.below(set.len())].vertices()[0],
                _ => rng.in_box(&bounds),
            };
            let direction = target - origin;
            let Some(ray) = WatertightRay::new(origin, direction) else {
                continue;
            };
            let expected = first_hit_polygons(&set, &ray);
            let got = tree.first_hit(origin, direction, 0.0, f32::INFINITY).unwrap();
            assert_eq!(got.map(|h| (h.t, h.source)), expected, "{name}: ray {i}");
            assert_eq!(
                wide.first_hit(origin, direction, 0.0, f32::INFINITY).unwrap(),
                got,
                "{name}: ray {i} (wide)"
            );
            assert_eq!(
                tree.any_hit(origin, direction, 0.0, f32::INFINITY).unwrap(),
                expected.is_some(),
                "{name}: ray {i} (any)"
            );
            if let Some(hit) = got {
                hits += 1;
                let on_ray = origin + direction * hit.t;
                let scale = bounds.diagonal().max(origin.abs().max_element());
                assert!(
                    hit.point.distance(on_ray) <= 1e-4 * scale,
                    "{name}: ray {i}: point {} is not on the ray at {on_ray}",
                    hit.point
                );
            }
        }
        assert!(hits > 150, "{name}: only {hits} hits");
    }
}

/// Frustum queries over polygons: the tree equals brute force over the same
/// polygons, and on the exactly planar meshes the faces seen equal those the
/// fan triangulation sees (a planar convex polygon is the union of its fan).
#[test]
fn frustum_queries_over_polygons_equal_brute_force_and_the_fan() {
    use proxima::{Frustum, FrustumOverlap};
    let faces_seen =
        |sources: &[u32], indices: &[u32]| -> BTreeSet<u32> { indices.iter().map(|&i| sources[i as usize]).collect() };
    for (name, mesh) in planar_meshes() {
        let polygons = mesh.polygons();
        let triangles = mesh.triangles();
        let polygon_tree = AabbTree::build_set(polygons.clone(), &BuildConfig::default()).unwrap();
        let triangle_tree = AabbTree::build_set(triangles.clone(), &BuildConfig::default()).unwrap();
        let b = mesh.bounds();
        let mut rng = Rng::new(41);
        let mut nonempty = 0;
        for i in 0..60 {
            let eye = b.center() + (rng.in_box(&b) - b.center()) * 3.0;
            let target = rng.in_box(&b);
            let fov = rng.range(5.0, 90.0);
            let Ok(frustum) = Frustum::look_at(eye, target, Vec3::Y, fov, rng.range(0.5, 2.0), 0.01, 100.0) else {
                continue;
            };
            let seen = polygon_tree.frustum(&frustum);
            let brute: Vec<u32> = (0..polygons.len() as u32)
                .filter(|&i| polygons.primitives[i as usize].overlaps_frustum(&frustum))
                .collect();
            assert_eq!(seen, brute, "{name}: camera {i}");
            assert_eq!(
                faces_seen(&polygons.sources, &seen),
                faces_seen(&triangles.sources, &triangle_tree.frustum(&frustum)),
                "{name}: camera {i}: faces seen differ from the fan triangulation's"
            );
            nonempty += usize::from(!seen.is_empty());
        }
        assert!(nonempty > 10, "{name}: only {nonempty} cameras saw something");
    }
}
