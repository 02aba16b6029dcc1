//! Ray queries of the AABB tree, the wide tree and the ray tree (with and
//! without AVX2) against brute force (the same watertight test on every
//! triangle, smallest t, ties to the lowest index) and against the hash grid: random and degenerate soups (proptest), rays with zero direction
//! components and origins on box faces, t ranges, and every shared mesh with
//! random rays and rays aimed exactly at vertices and edge midpoints (which
//! must never slip through).

use crate::common;

use proptest::prelude::*;
use proxima::build::SplitMethod;
use proxima::grid::{FastHash, GridConfig, HashGrid};
use proxima::prelude::*;
use proxima::primitive::{RayIntersect, TriangleHit, WatertightRay};
use proxima::sample::Rng;
use proxima::{AabbTree, BuildConfig, GridError, Mesh, PrimitiveSet, RayError, RayTree, Triangle, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// The oracle: every triangle, smallest t, ties to the lowest index.
fn brute_first(set: &PrimitiveSet<Triangle>, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<RayHit> {
    let ray = WatertightRay::new(o, d).unwrap();
    let mut best: Option<RayHit> = None;
    for (i, tri) in set.primitives.iter().enumerate() {
        if let Some(h) = tri.intersect_ray(&ray, t_min, t_max)
            && best.is_none_or(|b| h.t < b.t)
        {
            best = Some(hit_of(set, i, &h));
        }
    }
    best
}

/// The answer for `h`, a hit on primitive `i` of `set`.
fn hit_of(set: &PrimitiveSet<Triangle>, i: usize, h: &TriangleHit) -> RayHit {
    RayHit {
        primitive: i as u32,
        source: set.sources[i],
        t: h.t,
        point: set.primitives[i].hit_point(h),
        u: h.u,
        v: h.v,
    }
}

fn brute_any(set: &PrimitiveSet<Triangle>, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
    let ray = WatertightRay::new(o, d).unwrap();
    set.primitives
        .iter()
        .any(|t| t.intersect_ray(&ray, t_min, t_max).is_some())
}

/// Checks that `got`, a structure's [`RayQuery::some_hit`], is a hit when
/// and only when brute force finds one (`any`), and then a real one: the
/// hit that brute force finds on that primitive, field for field.
fn check_some_hit(
    set: &PrimitiveSet<Triangle>,
    ray: (Vec3, Vec3, f32, f32),
    any: bool,
    got: Option<RayHit>,
    what: &str,
) {
    let (o, d, t_min, t_max) = ray;
    assert_eq!(got.is_some(), any, "{what}: some hit ({o}, {d}, [{t_min}, {t_max}])");
    if let Some(got) = got {
        let i = got.primitive as usize;
        let tri = &set.primitives[i];
        let h = tri
            .intersect_ray(&WatertightRay::new(o, d).unwrap(), t_min, t_max)
            .unwrap_or_else(|| panic!("{what}: some hit on triangle {i}, which the ray misses ({o}, {d})"));
        assert_eq!(
            got,
            hit_of(set, i, &h),
            "{what}: some hit ({o}, {d}, [{t_min}, {t_max}])"
        );
    }
}

fn configs() -> [BuildConfig; 3] {
    [
        BuildConfig::default(),
        BuildConfig::fast_queries(),
        BuildConfig {
            min_size: 1,
            split: SplitMethod::Median,
            ..BuildConfig::default()
        },
    ]
}

/// The structures made from one binary tree: the wide tree (holding the
/// binary one) and the ray tree, on AVX2 lanes where the CPU has them and
/// without. [`first_hit`](Self::first_hit) and [`any_hit`](Self::any_hit)
/// give the wide tree's answer once the ray tree's, both ways, are found equal.
struct Trees {
    wide: WideTree<Triangle>,
    ray: RayTree,
    portable: RayTree,
}

impl Trees {
    fn new(tree: AabbTree<Triangle>) -> Self {
        let ray = RayTree::from_tree(tree.clone());
        let mut portable = ray.clone();
        portable.set_avx2(false);
        Self {
            wide: WideTree::from_tree(tree),
            ray,
            portable,
        }
    }

    fn tree(&self) -> &AabbTree<Triangle> {
        self.wide.tree()
    }

    fn first_hit(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Result<Option<RayHit>, RayError> {
        let want = self.wide.first_hit(o, d, t_min, t_max);
        assert_eq!(
            self.ray.first_hit(o, d, t_min, t_max),
            want,
            "ray tree, ray ({o}, {d}, [{t_min}, {t_max}])"
        );
        assert_eq!(
            self.portable.first_hit(o, d, t_min, t_max),
            want,
            "ray tree without AVX2, ray ({o}, {d})"
        );
        want
    }

    fn any_hit(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Result<bool, RayError> {
        let want = self.wide.any_hit(o, d, t_min, t_max);
        assert_eq!(
            self.ray.any_hit(o, d, t_min, t_max),
            want,
            "ray tree, any hit ({o}, {d})"
        );
        assert_eq!(
            self.portable.any_hit(o, d, t_min, t_max),
            want,
            "ray tree without AVX2, any hit ({o}, {d})"
        );
        want
    }
}

/// Checks first hit and any hit of every tree against brute force; returns
/// the number of rays that hit.
fn check_rays(name: &str, set: &PrimitiveSet<Triangle>, trees: &[Trees], rays: &[(Vec3, Vec3, f32, f32)]) -> usize {
    rays.par_iter()
        .enumerate()
        .map(|(k, &(o, d, t_min, t_max))| {
            let want = brute_first(set, o, d, t_min, t_max);
            let any = brute_any(set, o, d, t_min, t_max);
            assert_eq!(any, want.is_some());
            for (c, wide) in trees.iter().enumerate() {
                let tree = wide.tree();
                let got = tree.first_hit(o, d, t_min, t_max).unwrap();
                assert_eq!(got, want, "{name}: ray {k} ({o}, {d}, [{t_min}, {t_max}]), tree {c}");
                assert_eq!(
                    tree.any_hit(o, d, t_min, t_max).unwrap(),
                    any,
                    "{name}: any hit, ray {k}, tree {c}"
                );
                let got = wide.first_hit(o, d, t_min, t_max).unwrap();
                assert_eq!(
                    got, want,
                    "{name}: ray {k} ({o}, {d}, [{t_min}, {t_max}]), wide tree {c}"
                );
                assert_eq!(
                    wide.any_hit(o, d, t_min, t_max).unwrap(),
                    any,
                    "{name}: any hit, ray {k}, wide {c}"
                );
                let ray = (o, d, t_min, t_max);
                for (what, hit) in [
                    ("binary tree", tree.some_hit(o, d, t_min, t_max)),
                    ("wide tree", wide.wide.some_hit(o, d, t_min, t_max)),
                    ("ray tree", wide.ray.some_hit(o, d, t_min, t_max)),
                    ("ray tree without AVX2", wide.portable.some_hit(o, d, t_min, t_max)),
                ] {
                    check_some_hit(set, ray, any, hit.unwrap(), &format!("{name}: ray {k}, {what} {c}"));
                }
            }
            usize::from(any)
        })
        .sum()
}

/// The structures of each build configuration, and the ray tree's own
/// (binned SAH, leaves of four).
fn trees(set: &PrimitiveSet<Triangle>) -> Vec<Trees> {
    configs()
        .iter()
        .chain([RayTree::config()].iter())
        .map(|c| Trees::new(AabbTree::build_set(set.clone(), c).unwrap()))
        .collect()
}

/// Random rays about a box: origins around it (some inside), aimed at points
/// of it, or in random directions; some axis-aligned or with zero components.
fn random_rays(bounds: &proxima::Aabb, n: usize, seed: u64) -> Vec<(Vec3, Vec3, f32, f32)> {
    let mut rng = Rng::new(seed);
    let big = bounds.inflate(bounds.diagonal() * 0.5);
    (0..n)
        .map(|k| {
            let o = if k % 5 == 0 {
                rng.in_box(bounds)
            } else {
                rng.in_box(&big)
            };
            let mut d = match k % 4 {
                0 => Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
                _ => rng.in_box(bounds) - o,
            };
            if k % 7 == 0 {
                // Zero out one or two components (signed zeros included).
                let axis = rng.below(3);
                d[axis] = if k % 2 == 0 { 0.0 } else { -0.0 };
                if k % 3 == 0 {
                    d[(axis + 1) % 3] = -0.0;
                }
            }
            if d.abs().max_element() == 0.0 {
                d = Vec3::Y;
            }
            let (t_min, t_max) = match k % 6 {
                0 => (rng.range(-1.0, 0.5), rng.range(0.5, 2.0)),
                1 => (-f32::MAX, f32::INFINITY),
                _ => (0.0, f32::INFINITY),
            };
            (o, d, t_min, t_max)
        })
        .collect()
}

#[test]
fn random_soups_match_brute_force() {
    for seed in 0..4 {
        let mesh = common::random_soup(400 + 300 * seed as usize, seed);
        let set = mesh.triangles();
        let hits = check_rays(
            "soup",
            &set,
            &trees(&set),
            &random_rays(&mesh.bounds(), 3000, seed + 10),
        );
        assert!(hits > 500, "soup {seed}: only {hits} hits");
    }
}

/// Triangles and rays on a small integer grid: many rays lie in a triangle's
/// plane, run along its edges, start on box faces or on vertices.
/// A ray on the integer grid: origin, direction, `t_min`, span of the range (6: unbounded).
type GridRay = ([i8; 3], [i8; 3], i8, i8);

fn grid_case() -> impl Strategy<Value = (Vec<[i8; 9]>, Vec<GridRay>)> {
    (
        prop::collection::vec(prop::array::uniform9(-3i8..=3), 1..40),
        prop::collection::vec(
            (
                prop::array::uniform3(-4i8..=4),
                prop::array::uniform3(-2i8..=2),
                -3i8..=1,
                0i8..=6,
            ),
            1..40,
        ),
    )
}

fn v(a: &[i8]) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn integer_grids_match_brute_force((tris, rays) in grid_case()) {
        let set = PrimitiveSet::from_primitives(
            tris.iter().map(|c| Triangle::new(v(&c[0..3]), v(&c[3..6]), v(&c[6..9]))).collect(),
        );
        let trees = trees(&set);
        for &(o, d, t_min, span) in &rays {
            let (o, d) = (v(&o), v(&d));
            if d == Vec3::ZERO {
                for wide in &trees {
                    prop_assert_eq!(wide.tree().first_hit(o, d, 0.0, 1.0).unwrap_err(), RayError::Direction);
                    prop_assert_eq!(wide.first_hit(o, d, 0.0, 1.0).unwrap_err(), RayError::Direction);
                }
                continue;
            }
            // Half-integer scales too, so hits land on edges and vertices.
            for (o, d) in [(o, d), (o * 0.5, d), (o, d * 0.5)] {
                let t_max = if span == 6 { f32::INFINITY } else { t_min as f32 + span as f32 };
                let want = brute_first(&set, o, d, t_min as f32, t_max);
                for wide in &trees {
                    let tree = wide.tree();
                    prop_assert_eq!(tree.first_hit(o, d, t_min as f32, t_max).unwrap(), want);
                    prop_assert_eq!(tree.any_hit(o, d, t_min as f32, t_max).unwrap(), want.is_some());
                    prop_assert_eq!(wide.first_hit(o, d, t_min as f32, t_max).unwrap(), want);
                    prop_assert_eq!(wide.any_hit(o, d, t_min as f32, t_max).unwrap(), want.is_some());
                }
            }
        }
    }

    #[test]
    fn random_triangles_and_rays_match_brute_force(
        coords in prop::collection::vec(prop::array::uniform9(-10.0f32..10.0), 1..60),
        rays in prop::collection::vec((prop::array::uniform3(-15.0f32..15.0), prop::array::uniform3(-1.0f32..1.0)), 1..30),
        scale in prop::sample::select(vec![1e-3f32, 1.0, 1e3]),
        offset in prop::sample::select(vec![0.0f32, 100.0, -7e3]),
    ) {
        let p = |c: &[f32]| Vec3::new(c[0], c[1], c[2]) * scale + Vec3::splat(offset);
        let set = PrimitiveSet::from_primitives(
            coords.iter().map(|c| Triangle::new(p(&c[0..3]), p(&c[3..6]), p(&c[6..9]))).collect(),
        );
        let trees = trees(&set);
        for &(o, d) in &rays {
            let (o, d) = (p(&o), Vec3::from_array(d));
            if WatertightRay::new(o, d).is_none() || d.abs().max_element() < 1e-20 {
                continue;
            }
            // Aim some rays at vertices of the soup.
            let aimed = set.primitives[(o.x.to_bits() as usize) % set.len()].b - o;
            for d in [d, aimed] {
                if d == Vec3::ZERO {
                    continue;
                }
                let want = brute_first(&set, o, d, 0.0, f32::INFINITY);
                for wide in &trees {
                    let tree = wide.tree();
                    prop_assert_eq!(tree.first_hit(o, d, 0.0, f32::INFINITY).unwrap(), want);
                    prop_assert_eq!(tree.any_hit(o, d, 0.0, f32::INFINITY).unwrap(), want.is_some());
                    prop_assert_eq!(wide.first_hit(o, d, 0.0, f32::INFINITY).unwrap(), want);
                    prop_assert_eq!(wide.any_hit(o, d, 0.0, f32::INFINITY).unwrap(), want.is_some());
                }
            }
        }
    }
}

#[test]
fn degenerate_triangles_and_boxes() {
    // Repeated and collinear vertices, a flat (zero-thickness) soup, triangles
    // sharing edges, and rays along the flat plane and through its edges.
    let mut tris = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            let (x, y) = (i as f32, j as f32);
            tris.push(Triangle::new(
                Vec3::new(x, y, 0.0),
                Vec3::new(x + 1.0, y, 0.0),
                Vec3::new(x, y + 1.0, 0.0),
            ));
            tris.push(Triangle::new(
                Vec3::new(x + 1.0, y, 0.0),
                Vec3::new(x + 1.0, y + 1.0, 0.0),
                Vec3::new(x, y + 1.0, 0.0),
            ));
        }
    }
    tris.push(Triangle::new(Vec3::ONE, Vec3::ONE, Vec3::new(2.0, 1.0, 1.0)));
    tris.push(Triangle::new(Vec3::ZERO, Vec3::ONE, Vec3::splat(2.0)));
    tris.push(Triangle::new(Vec3::splat(0.5), Vec3::splat(0.5), Vec3::splat(0.5)));
    let set = PrimitiveSet::from_primitives(tris);
    let trees = trees(&set);
    let mut rays = Vec::new();
    for i in 0..=12 {
        for j in 0..=12 {
            let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
            // Straight down through vertices, edge midpoints and centers.
            rays.push((Vec3::new(x, y, 2.0), -Vec3::Z, 0.0, f32::INFINITY));
            rays.push((Vec3::new(x, y, -2.0), Vec3::new(0.0, -0.0, 1.0), 0.0, f32::INFINITY));
            // Along the plane (and along edges): never a hit of a flat triangle.
            rays.push((Vec3::new(x, -1.0, 0.0), Vec3::Y, 0.0, f32::INFINITY));
            rays.push((Vec3::new(x, y, 0.0), Vec3::new(1.0, 1.0, 0.0), -10.0, 10.0));
            // Starting on the plane, in the box, at a vertex.
            rays.push((Vec3::new(x, y, 0.0), Vec3::new(0.3, 0.2, 1.0), 0.0, f32::INFINITY));
            rays.push((Vec3::new(x, y, 0.0), Vec3::new(0.3, 0.2, -1.0), -1.0, 0.0));
        }
    }
    let hits = check_rays("flat", &set, &trees, &rays);
    assert!(hits > 300, "{hits}");
    // No ray through the flat grid's interior slips through its shared edges.
    for i in 1..12 {
        for j in 1..12 {
            let o = Vec3::new(i as f32 * 0.5, j as f32 * 0.5, 1.0);
            for d in [-Vec3::Z, Vec3::new(0.1, 0.0, -1.0), Vec3::new(-0.1, 0.2, -1.0)] {
                assert!(trees[0].tree().any_hit(o - d * 3.0, d, 0.0, f32::INFINITY).unwrap());
                assert!(trees[0].any_hit(o - d * 3.0, d, 0.0, f32::INFINITY).unwrap());
            }
        }
    }
}

#[test]
fn empty_tree_and_errors() {
    let empty = AabbTree::build_set(PrimitiveSet::<Triangle>::default(), &Default::default()).unwrap();
    assert_eq!(empty.first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY).unwrap(), None);
    assert!(!empty.any_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY).unwrap());
    let empty = WideTree::from_tree(empty);
    assert_eq!(empty.first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY).unwrap(), None);
    assert!(!empty.any_hit(Vec3::ZERO, Vec3::X, 0.0, f32::INFINITY).unwrap());
    let tree = AabbTree::build_set(common::bumpy_sphere(8, 1).triangles(), &Default::default()).unwrap();
    assert!(
        tree.first_hit(Vec3::ZERO, Vec3::X, 0.0, 0.5).unwrap().is_none(),
        "the sphere is beyond 0.5"
    );
    assert!(tree.first_hit(Vec3::ZERO, Vec3::X, 0.0, 2.0).unwrap().is_some());
    assert!(
        tree.first_hit(Vec3::ZERO, Vec3::X, -2.0, -0.5).unwrap().is_some(),
        "behind the origin"
    );
    let cases = [
        (Vec3::ZERO, Vec3::ZERO, 0.0, 1.0, RayError::Direction),
        (Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 0.0), 0.0, 1.0, RayError::Direction),
        (
            Vec3::ZERO,
            Vec3::new(f32::INFINITY, 1.0, 0.0),
            0.0,
            1.0,
            RayError::Direction,
        ),
        (Vec3::ZERO, Vec3::splat(1e-45), 0.0, 1.0, RayError::Direction),
        (Vec3::splat(f32::NAN), Vec3::X, 0.0, 1.0, RayError::Origin),
        (
            Vec3::new(0.0, f32::NEG_INFINITY, 0.0),
            Vec3::X,
            0.0,
            1.0,
            RayError::Origin,
        ),
        (
            Vec3::ZERO,
            Vec3::X,
            1.0,
            0.0,
            RayError::Range { t_min: 1.0, t_max: 0.0 },
        ),
        (
            Vec3::ZERO,
            Vec3::X,
            f32::NEG_INFINITY,
            0.0,
            RayError::Range {
                t_min: f32::NEG_INFINITY,
                t_max: 0.0,
            },
        ),
    ];
    let wide = Trees::new(tree.clone());
    #[cfg(target_arch = "x86_64")]
    assert!(
        wide.wide.has_triangle_packets(),
        "the wide tests must cover the packet path"
    );
    for (o, d, t_min, t_max, want) in cases {
        assert_eq!(wide.first_hit(o, d, t_min, t_max).unwrap_err(), want);
        assert_eq!(wide.any_hit(o, d, t_min, t_max).unwrap_err(), want);
        assert_eq!(tree.first_hit(o, d, t_min, t_max).unwrap_err(), want);
        assert_eq!(tree.any_hit(o, d, t_min, t_max).unwrap_err(), want);
    }
    assert!(matches!(
        tree.first_hit(Vec3::ZERO, Vec3::X, 0.0, f32::NAN),
        Err(RayError::Range { .. })
    ));
    // Batches answer in input order, errors in place.
    let rays = [
        (Vec3::ZERO, Vec3::X),
        (Vec3::ZERO, Vec3::ZERO),
        (Vec3::splat(9.0), Vec3::ONE),
    ];
    let batch = tree.first_hit_batch(&rays, 0.0, f32::INFINITY);
    let any = tree.any_hit_batch(&rays, 0.0, f32::INFINITY);
    let some = tree.some_hit_batch(&rays, 0.0, f32::INFINITY);
    for (k, &(o, d)) in rays.iter().enumerate() {
        assert_eq!(batch[k], tree.first_hit(o, d, 0.0, f32::INFINITY));
        assert_eq!(any[k], tree.any_hit(o, d, 0.0, f32::INFINITY));
        assert_eq!(some[k], tree.some_hit(o, d, 0.0, f32::INFINITY));
    }
}

/// Fan-triangulated vertex indices, in the order of `Mesh::triangles`.
fn triangle_indices(mesh: &Mesh) -> Vec<[u32; 3]> {
    let mut out = Vec::with_capacity(mesh.triangle_count());
    for face in mesh.faces() {
        for w in face[1..].windows(2) {
            out.push([face[0], w[0], w[1]]);
        }
    }
    out
}

/// Rays aimed exactly at edge midpoints and vertices, each from the side its
/// incident triangles face: the ray must cross them, so a watertight test
/// hits something. Edges not shared by exactly two triangles, vertices on
/// such edges, and those with a degenerate or back-facing incident triangle
/// are skipped.
fn aimed_rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<(Vec3, Vec3, f32, f32)> {
    let p = mesh.positions();
    let tris = triangle_indices(mesh);
    let normal = |t: &[u32; 3]| {
        let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
        (b - a).cross(c - a)
    };
    let mut edge_faces: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    let mut vertex_faces: Vec<Vec<usize>> = vec![Vec::new(); p.len()];
    for (f, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edge_faces.entry((a.min(b), a.max(b))).or_default().push(f);
            vertex_faces[a as usize].push(f);
        }
    }
    // A vertex on a boundary or a non-manifold edge has no disk of faces
    // around it: a ray may pass it by without crossing anything.
    let mut open_vertex = vec![false; p.len()];
    for (&(a, b), f) in &edge_faces {
        if f.len() != 2 {
            open_vertex[a as usize] = true;
            open_vertex[b as usize] = true;
        }
    }
    let mut edges: Vec<_> = edge_faces.into_iter().filter(|(_, f)| f.len() == 2).collect();
    edges.sort_unstable();
    let reach = mesh.bounds().diagonal();
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    // Direction toward the target from the side all `faces` face, if any.
    let ray_to = |target: Vec3, faces: &[usize], rng: &mut Rng| {
        let normals: Vec<Vec3> = faces.iter().map(|&f| normal(&tris[f]).normalize_or_zero()).collect();
        let sum: Vec3 = normals.iter().sum();
        let axis = sum.normalize_or_zero();
        if axis == Vec3::ZERO || normals.iter().any(|n| n.dot(axis) < 0.05) {
            return None;
        }
        let jitter = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let side = (axis + jitter).normalize_or_zero();
        if normals.iter().any(|n| n.dot(side) < 0.02) {
            return None;
        }
        let o = target + side * reach * rng.range(0.01, 2.0);
        Some((o, target - o, 0.0, f32::INFINITY))
    };
    for _ in 0..n {
        let (&(a, b), faces) = {
            let (k, f) = &edges[rng.below(edges.len())];
            (k, f.clone())
        };
        let mid = (p[a as usize] + p[b as usize]) * 0.5;
        out.extend(ray_to(mid, &faces, &mut rng));
        let vtx = rng.below(p.len());
        if !vertex_faces[vtx].is_empty() && !open_vertex[vtx] {
            out.extend(ray_to(p[vtx], &vertex_faces[vtx].clone(), &mut rng));
        }
    }
    out
}

/// Rays from outside the bounding sphere aimed at points of the box, and
/// rays from near the surface in random directions.
fn mesh_rays(mesh: &Mesh, n: usize, seed: u64) -> Vec<(Vec3, Vec3, f32, f32)> {
    let b = mesh.bounds();
    let mut rng = Rng::new(seed);
    let near = proxima::sample::near_surface(mesh, n / 2, 0.01, seed);
    let mut out: Vec<_> = near
        .into_iter()
        .map(|o| {
            let d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            (o, if d == Vec3::ZERO { Vec3::X } else { d }, 0.0, f32::INFINITY)
        })
        .collect();
    for _ in 0..n - n / 2 {
        let dir = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X);
        let o = b.center() + dir * b.diagonal() * rng.range(0.6, 3.0);
        out.push((o, rng.in_box(&b) - o, 0.0, f32::INFINITY));
    }
    out
}

#[test]
fn shared_meshes_match_brute_force_and_grid_and_never_leak() {
    for path in common::shared_meshes() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mesh = proxima::io::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let set = mesh.triangles();
        let n = set.len();
        let trees = trees(&set);
        // Brute force costs n per ray: about 6e7 triangle tests per mesh.
        let brute_rays = (60_000_000 / n).clamp(60, 4000);
        let mut rays = mesh_rays(&mesh, brute_rays / 2, 7);
        let aimed = aimed_rays(&mesh, brute_rays / 4, 8);
        rays.extend(aimed.iter().copied());
        let hits = check_rays(&name, &set, &trees, &rays);
        // Aimed rays never slip through.
        let (wide, tree) = (&trees[0], trees[0].tree());
        let many_aimed = aimed_rays(&mesh, 20_000, 9);
        let misses = many_aimed
            .par_iter()
            .filter(|&&(o, d, t0, t1)| {
                let first = tree.first_hit(o, d, t0, t1).unwrap();
                assert_eq!(
                    wide.first_hit(o, d, t0, t1).unwrap(),
                    first,
                    "{name}: wide tree differs"
                );
                !tree.any_hit(o, d, t0, t1).unwrap() || !wide.any_hit(o, d, t0, t1).unwrap() || first.is_none()
            })
            .count();
        assert_eq!(
            misses,
            0,
            "{name}: {misses} of {} aimed rays slipped through",
            many_aimed.len()
        );
        // The tree equals the grid on many more rays.
        let side = mesh.bounds().size().max_element();
        let grid: HashGrid<Triangle, FastHash> =
            HashGrid::build(set.clone(), &GridConfig::cubic(side / (n as f32).cbrt().max(1.0))).unwrap();
        let mut grid_rays = mesh_rays(&mesh, 20_000, 10);
        grid_rays.extend(many_aimed.iter().take(5_000));
        grid_rays.par_iter().for_each(|&(o, d, t0, t1)| {
            let got = tree.first_hit(o, d, t0, t1).unwrap();
            assert_eq!(wide.first_hit(o, d, t0, t1).unwrap(), got, "{name}: wide tree differs");
            let g = grid.first_hit(o, d, t0, t1).unwrap();
            assert_eq!(
                got.map(|h| (h.primitive, h.source, h.t, h.point, h.u, h.v)),
                g.map(|h| (h.primitive, h.source, h.t, h.point, h.u, h.v)),
                "{name}: tree and grid differ for ({o}, {d})"
            );
        });
        println!(
            "{name}: {} rays against brute force ({hits} hit), {} aimed rays never missed, {} rays tree == grid",
            rays.len(),
            many_aimed.len(),
            grid_rays.len()
        );
    }
}

/// A ray from far away (2^27 units before a mesh of size about 2) must hit
/// the same face as the same ray started near the mesh, at `t` shifted by
/// the distance: in `f32` alone the parameters near 1.3e8 (a step of 16)
/// cannot tell the near face from the far one. Origins beyond 2^30 times the
/// mesh size are refused (tree) or out of range (grid), not answered wrongly.
#[test]
fn far_origins_hit_the_near_face() {
    let mesh = common::bumpy_sphere(4, 11);
    let set = mesh.triangles();
    let tree = AabbTree::build_set(set.clone(), &BuildConfig::default()).unwrap();
    let wide = Trees::new(tree.clone());
    let grid: HashGrid<Triangle, FastHash> = HashGrid::build(set, &GridConfig::cubic(0.2)).unwrap();
    let far = (1u32 << 27) as f32;
    let mut rng = Rng::new(3);
    for _ in 0..200 {
        // Axis-aligned directions keep `near - far · d` exact in f32.
        let axis = (rng.range(0.0, 3.0) as usize).min(2);
        let sign = if rng.range(0.0, 1.0) < 0.5 { 1.0 } else { -1.0 };
        let mut d = Vec3::ZERO;
        d[axis] = sign;
        let mut near = Vec3::new(rng.range(-0.8, 0.8), rng.range(-0.8, 0.8), rng.range(-0.8, 0.8));
        near[axis] = -16.0 * sign;
        let origin = near - d * far;
        assert_eq!(origin + d * far, near, "the far origin is exact");
        let want = tree.first_hit(near, d, 0.0, f32::INFINITY).unwrap();
        let hits = [
            tree.first_hit(origin, d, 0.0, f32::INFINITY).unwrap(),
            wide.first_hit(origin, d, 0.0, f32::INFINITY).unwrap(),
            grid.first_hit(origin, d, 0.0, f32::INFINITY).unwrap().map(|h| RayHit {
                primitive: h.primitive,
                source: h.source,
                t: h.t,
                point: h.point,
                u: h.u,
                v: h.v,
            }),
        ];
        for (name, got) in ["tree", "wide", "grid"].iter().zip(hits) {
            match (want, got) {
                (None, None) => {}
                (Some(w), Some(g)) => {
                    assert_eq!(g.source, w.source, "{name}: near {near:?} dir {d:?}");
                    // t at 2^27 has a step of 16: the sum rounds once.
                    assert!(
                        (g.t as f64 - (far as f64 + w.t as f64)).abs() <= 16.0,
                        "{name}: t {} vs {}",
                        g.t,
                        w.t
                    );
                }
                _ => panic!("{name}: hit {got:?}, the near ray {want:?}"),
            }
        }
        assert_eq!(tree.any_hit(origin, d, 0.0, f32::INFINITY).unwrap(), want.is_some());
        assert_eq!(wide.any_hit(origin, d, 0.0, f32::INFINITY).unwrap(), want.is_some());
    }
    // 1e30 away: beyond what f64 can place finely.
    let (o, d) = (Vec3::new(0.1, 0.2, 1e30), -Vec3::Z);
    assert_eq!(tree.first_hit(o, d, 0.0, f32::INFINITY), Err(RayError::OriginTooFar));
    assert_eq!(wide.first_hit(o, d, 0.0, f32::INFINITY), Err(RayError::OriginTooFar));
    assert!(grid.first_hit(o, d, 0.0, f32::INFINITY).is_err());
}

/// A mesh with coordinates near 1e17 (inside the documented bound 2^60):
/// the watertight test's products overflow `f32` although `t` does not, and
/// the hit must still be found, with `t` scaled like the mesh.
#[test]
fn huge_coordinates_keep_their_hits() {
    let mesh = common::bumpy_sphere(3, 5);
    let scale = 1e17f32;
    let huge = Mesh::from_triangles(
        mesh.positions().iter().map(|&p| p * scale).collect(),
        &mesh.faces().map(|f| [f[0], f[1], f[2]]).collect::<Vec<_>>(),
    )
    .unwrap();
    let small_tree = AabbTree::build_set(mesh.triangles(), &BuildConfig::default()).unwrap();
    let tree = AabbTree::build_set(huge.triangles(), &BuildConfig::default()).unwrap();
    let wide = Trees::new(tree.clone());
    let grid: HashGrid<Triangle, FastHash> =
        HashGrid::build(huge.triangles(), &GridConfig::cubic(0.3 * scale)).unwrap();
    let mut rng = Rng::new(9);
    let mut hits = 0;
    for _ in 0..300 {
        let o = Vec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-3.0, 3.0));
        let aim = Vec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
        let d = aim - o;
        let Some(want) = small_tree.first_hit(o, d, 0.0, f32::INFINITY).unwrap() else {
            continue;
        };
        hits += 1;
        let got = [
            tree.first_hit(o * scale, d, 0.0, f32::INFINITY)
                .unwrap()
                .map(|h| (h.source, h.t)),
            wide.first_hit(o * scale, d, 0.0, f32::INFINITY)
                .unwrap()
                .map(|h| (h.source, h.t)),
            grid.first_hit(o * scale, d, 0.0, f32::INFINITY)
                .unwrap()
                .map(|h| (h.source, h.t)),
        ];
        for (name, g) in ["tree", "wide", "grid"].iter().zip(got) {
            let (source, t) = g.unwrap_or_else(|| panic!("{name}: no hit for {o:?} {d:?}"));
            assert_eq!(source, want.source, "{name}");
            assert!(
                t.is_finite() && ((t / scale) - want.t).abs() <= 1e-4 * want.t.max(1.0),
                "{name}: t {t} vs {}",
                want.t
            );
        }
    }
    assert!(hits > 100, "{hits} rays hit");
}

/// The ray tree's batches (walks interleaved; random rays in Morton order,
/// a camera's rays row by row as they come) give each ray the answer
/// `first_hit` (`any_hit`, `some_hit`) gives it alone, errors included, in
/// input order, with and without AVX2 (deep trees, which take their rays one
/// at a time, are tested in the crate: `ray_tree`'s unit tests).
#[test]
fn ray_tree_batches_equal_single_rays() {
    let cases = [
        ("sphere", common::bumpy_sphere(40, 3).triangles()),
        ("soup", common::random_soup(3000, 4).triangles()),
    ];
    for (name, set) in cases {
        for config in configs().iter().chain([RayTree::config()].iter()) {
            let tree = RayTree::build_set(set.clone(), config).unwrap();
            let bounds = tree.bounds();
            let random: Vec<(Vec3, Vec3)> = random_rays(&bounds, 3000, 21).iter().map(|r| (r.0, r.1)).collect();
            for (order, mut rays) in [("random", random), ("camera", camera_rays(&bounds, 56))] {
                let name = &format!("{name}, {order} rays");
                // Errors in place: zero and non-finite directions, an origin too far.
                rays.insert(7, (Vec3::ZERO, Vec3::ZERO));
                rays.insert(1500, (Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 1.0)));
                rays.insert(2000, (Vec3::splat(1e37), -Vec3::ONE));
                let mut portable = tree.clone();
                portable.set_avx2(false);
                // The camera's window cuts through the middle of the box.
                let diagonal = bounds.size().length();
                let window = match order {
                    "random" => (-1.0, 2.5),
                    _ => (1.6 * diagonal, 2.1 * diagonal),
                };
                for t_range in [(0.0, f32::INFINITY), window] {
                    let batch = tree.first_hit_batch(&rays, t_range.0, t_range.1);
                    assert_eq!(batch, portable.first_hit_batch(&rays, t_range.0, t_range.1), "{name}");
                    let any = tree.any_hit_batch(&rays, t_range.0, t_range.1);
                    assert_eq!(any, portable.any_hit_batch(&rays, t_range.0, t_range.1), "{name}");
                    let some = tree.some_hit_batch(&rays, t_range.0, t_range.1);
                    assert_eq!(some, portable.some_hit_batch(&rays, t_range.0, t_range.1), "{name}");
                    let mut hits = 0;
                    for (k, &(o, d)) in rays.iter().enumerate() {
                        let single = tree.first_hit(o, d, t_range.0, t_range.1);
                        assert_eq!(batch[k], single, "{name}, {config:?}, ray {k} ({o}, {d})");
                        assert_eq!(
                            any[k],
                            tree.any_hit(o, d, t_range.0, t_range.1),
                            "{name}: any hit, ray {k}"
                        );
                        assert_eq!(
                            some[k],
                            tree.some_hit(o, d, t_range.0, t_range.1),
                            "{name}: some hit, ray {k}"
                        );
                        hits += usize::from(matches!(single, Ok(Some(_))));
                    }
                    assert!(batch[7].is_err() && batch[1500].is_err() && batch[2000].is_err());
                    assert!(hits > 300, "{name}: only {hits} hits");
                }
            }
        }
    }
}

/// The rays of a `size` × `size` pinhole camera two diagonals from the
/// centre of `bounds`, looking at it, row after row (as an image is cast).
fn camera_rays(bounds: &Aabb, size: usize) -> Vec<(Vec3, Vec3)> {
    let centre = bounds.center();
    let diagonal = bounds.size().length();
    let eye = centre + Vec3::new(0.3, 0.2, 1.0).normalize() * 2.0 * diagonal;
    let forward = (centre - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half = 0.3;
    (0..size * size)
        .map(|k| {
            let s = |i: usize| ((i as f32 + 0.5) / size as f32 * 2.0 - 1.0) * half;
            (eye, forward + right * s(k % size) + up * s(k / size))
        })
        .collect()
}

/// A mesh whose triangles all sit on one point has no area: every ray
/// misses it, from near or from far, and none is refused as starting too far
/// from a mesh of no size (tree, wide tree, ray tree, brute force, batches).
/// The oracle is the point's lack of area; brute force agrees. The trees'
/// boxes are widened by a few ulps of their coordinates, so a point away
/// from 0 has a size for them: rays up to 2^30 times its coordinates away
/// are answered (beyond, f64 cannot place a ray within f32's spacing there).
#[test]
fn point_sized_meshes_are_missed_from_anywhere() {
    for point in [Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), Vec3::new(-1e6, 5e5, 1e3)] {
        let set = PrimitiveSet::from_primitives(vec![Triangle::new(point, point, point); 1000]);
        let linear = LinearSearch::new(set.clone());
        let trees = trees(&set);
        let mut rays = Vec::new();
        let distances: &[f32] = if point == Vec3::ZERO {
            &[0.0, 1.0, 1e4, 1e9, 1e15, 1e30, 3e38]
        } else {
            &[0.0, 1.0, 1e4, 1e9]
        };
        for &distance in distances {
            for d in [-Vec3::Z, Vec3::new(0.3, -0.2, -1.0), Vec3::new(1e-30, 0.0, -1.0)] {
                // Aimed straight at the point, and past it.
                rays.push((point - d * distance, d));
                rays.push((point - d * distance + Vec3::X, d));
            }
        }
        for &(o, d) in &rays {
            let what = format!("point {point}, ray ({o}, {d})");
            assert_eq!(brute_first(&set, o, d, 0.0, f32::INFINITY), None, "{what}");
            assert_eq!(linear.first_hit(o, d, 0.0, f32::INFINITY), Ok(None), "{what}: linear");
            assert_eq!(linear.any_hit(o, d, 0.0, f32::INFINITY), Ok(false), "{what}: linear");
            for t in &trees {
                assert_eq!(t.tree().first_hit(o, d, 0.0, f32::INFINITY), Ok(None), "{what}: tree");
                assert_eq!(t.tree().any_hit(o, d, 0.0, f32::INFINITY), Ok(false), "{what}: tree");
                assert_eq!(
                    t.first_hit(o, d, 0.0, f32::INFINITY),
                    Ok(None),
                    "{what}: wide and ray trees"
                );
                assert_eq!(
                    t.any_hit(o, d, 0.0, f32::INFINITY),
                    Ok(false),
                    "{what}: wide and ray trees"
                );
                assert_eq!(t.ray.some_hit(o, d, 0.0, f32::INFINITY), Ok(None), "{what}: ray tree");
            }
        }
        for t in &trees {
            let misses = |answers: Vec<Result<Option<RayHit>, RayError>>| answers.iter().all(|a| *a == Ok(None));
            assert!(
                misses(t.ray.first_hit_batch(&rays, 0.0, f32::INFINITY)),
                "point {point}: ray tree batch"
            );
            assert!(
                misses(t.wide.first_hit_batch(&rays, 0.0, f32::INFINITY)),
                "point {point}: wide batch"
            );
            let any = t.ray.any_hit_batch(&rays, 0.0, f32::INFINITY);
            assert!(
                any.iter().all(|a| *a == Ok(false)),
                "point {point}: ray tree any-hit batch"
            );
        }
    }
}

/// A small mesh far from 0 is resolved by `f32` only to the spacing of its
/// coordinates: an origin farther than 2^30 of its diagonals but within 2^30
/// of its coordinates is placed near it within that spacing and answered,
/// at the face the same ray started near the mesh hits; beyond 2^30 times
/// its coordinates it is refused.
#[test]
fn far_origins_are_measured_against_the_mesh_size_and_coordinates() {
    let mesh = common::bumpy_sphere(3, 5);
    let offset = Vec3::new(1e6, -2e6, 5e5);
    let moved = Mesh::from_triangles(
        mesh.positions().iter().map(|&p| p + offset).collect(),
        &triangle_indices(&mesh),
    )
    .unwrap();
    let set = moved.triangles();
    let trees = trees(&set);
    let linear = LinearSearch::new(set.clone());
    let centre = moved.bounds().center();
    // 2^40 (1.1e12) is beyond 2^30 diagonals (about 4e9) and within 2^30 times
    // the coordinates (2.1e15).
    let far = (1u64 << 40) as f32;
    let mut rng = Rng::new(9);
    let mut hits = 0;
    for _ in 0..100 {
        let axis = (rng.range(0.0, 3.0) as usize).min(2);
        let mut d = Vec3::ZERO;
        d[axis] = if rng.range(0.0, 1.0) < 0.5 { 1.0 } else { -1.0 };
        let mut near = centre + Vec3::new(rng.range(-0.8, 0.8), rng.range(-0.8, 0.8), rng.range(-0.8, 0.8));
        near[axis] = centre[axis] - 4.0 * d[axis];
        let origin = near - d * far;
        let want = brute_first(&set, near, d, 0.0, f32::INFINITY);
        let got = [
            linear.first_hit(origin, d, 0.0, f32::INFINITY).unwrap(),
            trees[0].tree().first_hit(origin, d, 0.0, f32::INFINITY).unwrap(),
            trees[1].first_hit(origin, d, 0.0, f32::INFINITY).unwrap(),
        ];
        for g in got {
            assert_eq!(g.map(|h| h.source), want.map(|h| h.source), "near {near}, dir {d}");
        }
        hits += usize::from(want.is_some());
    }
    assert!(hits > 50, "{hits} of 100 rays hit the sphere");
    let too_far = centre - Vec3::Z * 1e22;
    assert_eq!(
        trees[0].tree().first_hit(too_far, Vec3::Z, 0.0, f32::INFINITY),
        Err(RayError::OriginTooFar)
    );
    assert_eq!(
        linear.first_hit(too_far, Vec3::Z, 0.0, f32::INFINITY),
        Err(RayError::OriginTooFar)
    );
}

/// The hash grid answers rays through `RayQuery`, as the trees do: its own
/// `first_hit` (with `GridError`s) and the trait's `first_hit`, `any_hit`,
/// `some_hit` and batches equal brute force on random soups, and the errors
/// are the ray's, wrapped.
#[test]
fn the_grid_answers_every_ray_query() {
    for seed in 0..3 {
        let mesh = common::random_soup(300, seed);
        let set = mesh.triangles();
        let grid: HashGrid<Triangle> = HashGrid::build(set.clone(), &GridConfig::cubic(0.15)).unwrap();
        let rays = random_rays(&mesh.bounds(), 600, seed);
        let mut hits = 0;
        for &(o, d, t_min, t_max) in &rays {
            let want = brute_first(&set, o, d, t_min, t_max);
            hits += want.is_some() as usize;
            assert_eq!(
                grid.first_hit(o, d, t_min, t_max),
                Ok(want),
                "({o}, {d}, [{t_min}, {t_max}])"
            );
            assert_eq!(RayQuery::first_hit(&grid, o, d, t_min, t_max), Ok(want));
            let any = brute_any(&set, o, d, t_min, t_max);
            assert_eq!(
                grid.any_hit(o, d, t_min, t_max),
                Ok(any),
                "({o}, {d}, [{t_min}, {t_max}])"
            );
            check_some_hit(
                &set,
                (o, d, t_min, t_max),
                any,
                grid.some_hit(o, d, t_min, t_max).unwrap(),
                "grid",
            );
        }
        assert!(hits > 100, "only {hits} hits");
        let pairs: Vec<(Vec3, Vec3)> = rays.iter().map(|&(o, d, ..)| (o, d)).collect();
        let first = grid.first_hit_batch(&pairs, 0.0, f32::INFINITY);
        let any = grid.any_hit_batch(&pairs, 0.0, f32::INFINITY);
        for (k, &(o, d)) in pairs.iter().enumerate() {
            assert_eq!(first[k], Ok(brute_first(&set, o, d, 0.0, f32::INFINITY)), "ray {k}");
            assert_eq!(any[k], Ok(brute_any(&set, o, d, 0.0, f32::INFINITY)), "ray {k}");
        }
    }
    let grid: HashGrid<Triangle> =
        HashGrid::build(common::random_soup(10, 0).triangles(), &GridConfig::cubic(0.5)).unwrap();
    for (o, d, t_min, t_max, want) in [
        (Vec3::ZERO, Vec3::ZERO, 0.0, 1.0, RayError::Direction),
        (Vec3::splat(f32::NAN), Vec3::X, 0.0, 1.0, RayError::Origin),
        (
            Vec3::ZERO,
            Vec3::X,
            2.0,
            1.0,
            RayError::Range { t_min: 2.0, t_max: 1.0 },
        ),
    ] {
        assert_eq!(RayQuery::first_hit(&grid, o, d, t_min, t_max), Err(want));
        assert_eq!(grid.first_hit(o, d, t_min, t_max), Err(GridError::Ray(want)));
        assert_eq!(
            grid.first_hit(o, d, t_min, t_max).unwrap_err().to_string(),
            want.to_string()
        );
    }
    // Too far to tell front from back: the trees' error through the trait,
    // out of the grid's range through its own method.
    let far = Vec3::new(0.5, 0.5, 1e30);
    assert_eq!(
        RayQuery::first_hit(&grid, far, -Vec3::Z, 0.0, f32::INFINITY),
        Err(RayError::OriginTooFar)
    );
    assert_eq!(
        grid.first_hit(far, -Vec3::Z, 0.0, f32::INFINITY),
        Err(GridError::OutOfRange)
    );
}
