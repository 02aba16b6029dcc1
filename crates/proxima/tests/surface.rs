//! Where answers lie on the surface (`proxima::surface`), and the signed
//! distance's gradient, against independent oracles: a feature-by-feature
//! brute force in `f64`, analytic answers on axis-aligned triangles at and
//! within ulps of region boundaries, a per-vertex loop for normals, and
//! central finite differences for gradients.

use crate::common;

use proxima::prelude::*;
use proxima::sample::Rng;
use proxima::sdf::Sign;
use proxima::surface::{Attributes, Feature, SurfaceAnswer, SurfacePoint, vertex_normals};
use proxima::{DVec3, MeshIndex, PrimitiveKind};

/// The closest feature of triangle `t` to `p` found by trying every vertex,
/// every open edge and the open face in `f64` (no Voronoi regions): the
/// local feature (0 face, 1..=3 edge k-1, 4..=6 vertex k-4) and the margin
/// by which it beats the best other feature (0 when features tie).
fn brute_feature(t: [DVec3; 3], p: DVec3) -> (usize, f64) {
    let mut found: Vec<(f64, usize)> = Vec::new();
    for k in 0..3 {
        found.push(((t[k] - p).length(), 4 + k));
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let d = b - a;
        let s = (p - a).dot(d) / d.length_squared();
        if s > 0.0 && s < 1.0 {
            found.push(((a + d * s - p).length(), 1 + k));
        }
    }
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let q = p - n * ((p - t[0]).dot(n) / n.length_squared());
    let inside = (0..3).all(|k| (t[(k + 1) % 3] - t[k]).cross(q - t[k]).dot(n) > 0.0);
    if inside {
        found.push(((q - p).length(), 0));
    }
    found.sort_by(|x, y| x.0.total_cmp(&y.0));
    (found[0].1, found.get(1).map_or(f64::INFINITY, |s| s.0 - found[0].0))
}

/// `feature` (local to a fan triangle `corners` of a face with `sides` fan
/// triangles, `fan` its place) as the mesh feature.
fn mesh_feature(local: usize, corners: [u32; 3], fan: usize, triangles: usize) -> Feature {
    match local {
        0 => Feature::Face,
        1..=3 => {
            let k = local - 1;
            let is_edge = [fan == 0, true, fan + 1 == triangles][k];
            if is_edge {
                Feature::Edge([corners[k], corners[(k + 1) % 3]])
            } else {
                Feature::Face
            }
        }
        _ => Feature::Vertex(corners[local - 4]),
    }
}

/// Triangles and quads (most of them not planar) on a bumpy sphere: a
/// face's closest point is taken on its fan's triangles either way.
fn polygon_mesh(seed: u64) -> Mesh {
    let sphere = common::bumpy_sphere(6, seed);
    let tris = sphere.triangle_vertex_indices();
    let mut faces: Vec<Vec<u32>> = Vec::new();
    let mut i = 0;
    let mut rng = Rng::new(seed);
    while i < tris.len() {
        // Merge a triangle with its successor when they share an edge, into a quad.
        let t = tris[i];
        if i + 1 < tris.len() && rng.below(2) == 0 {
            let u = tris[i + 1];
            if let Some(extra) = u.iter().find(|v| !t.contains(v)) {
                let shared = u.iter().filter(|v| t.contains(v)).count();
                if shared == 2 {
                    // Insert `extra` between the two shared corners, in t's order.
                    for k in 0..3 {
                        let (a, b) = (t[k], t[(k + 1) % 3]);
                        if u.contains(&a) && u.contains(&b) {
                            let mut face = vec![];
                            for j in 0..3 {
                                face.push(t[(k + 1 + j) % 3]);
                            }
                            // t[k+1], t[k+2], t[k], extra: t with `extra` put into its shared edge.
                            face.push(*extra);
                            faces.push(face);
                            break;
                        }
                    }
                    i += 2;
                    continue;
                }
            }
        }
        faces.push(t.to_vec());
        i += 1;
    }
    Mesh::from_faces(sphere.positions().to_vec(), &faces).unwrap()
}

#[test]
fn surface_answers_reproduce_the_closest_point_and_match_brute_force_features() {
    for mesh in [
        common::bumpy_sphere(5, 3),
        polygon_mesh(7),
        common::random_soup(300, 11),
    ] {
        let index = MeshIndex::new(mesh.clone());
        let points = common::queries(&mesh, 400, 5);
        let hits = index.closest(PrimitiveKind::Faces, &points).unwrap();
        let answers = index.closest_surface(
            &points,
            &hits,
            Attributes {
                normals: true,
                uv: true,
            },
        );
        // The batch's attributes are the surface point's own, computed one at a time.
        let normals = vertex_normals(&mesh);
        assert_eq!(answers.len(), points.len());
        for answer in answers.iter().flatten() {
            let alone = SurfaceAnswer::new(
                answer.at,
                &mesh,
                &normals,
                Attributes {
                    normals: true,
                    uv: true,
                },
            );
            assert_eq!(*answer, alone);
            assert_eq!(answer.normal, answer.at.interpolated_normal(&mesh, &normals));
            assert_eq!(answer.face_normal, answer.at.face_normal(&mesh));
            assert_eq!(answer.uv, None); // these meshes have none
        }
        let at: Vec<Option<SurfacePoint>> = answers.iter().map(|a| a.map(|a| a.at)).collect();
        let diagonal = mesh.bounds().diagonal() as f64;
        let (mut compared, mut clear) = (0, 0);
        for ((p, hit), at) in points.iter().zip(&hits).zip(&at) {
            let (hit, at) = (hit.unwrap(), at.unwrap());
            assert_eq!((at.face, at.triangle), (hit.source, hit.primitive));
            assert!(at.barycentric.iter().all(|&w| (0.0..=1.0).contains(&w)), "{at:?}");
            assert!((at.barycentric.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{at:?}");
            let point = at.point(&mesh);
            assert!(
                (point - hit.point.as_dvec3()).length() <= 1e-6 * diagonal,
                "{p} {hit:?} {at:?}"
            );
            // The corners are the fan triangle's, in the face's order.
            let face = mesh.face(at.face as usize);
            let fan = at.triangle as usize - mesh.first_triangle(at.face as usize);
            assert_eq!(at.corners, [face[0], face[fan + 1], face[fan + 2]]);
            let t = at.corners.map(|v| mesh.positions()[v as usize].as_dvec3());
            if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() < 1e-12 * diagonal.powi(4) {
                continue; // degenerate: no face region to compare
            }
            let (local, margin) = brute_feature(t, p.as_dvec3());
            compared += 1;
            if margin > 1e-9 * diagonal {
                clear += 1;
                let expected = mesh_feature(local, at.corners, fan, face.len() - 2);
                assert_eq!(at.feature, expected, "{p} on {t:?}: {at:?}");
            }
        }
        assert!(clear * 10 > compared * 7, "{clear} of {compared} clear cases");
    }
}

/// The right triangle (0,0,0), (1,0,0), (0,1,0) in z = 0: its closest point
/// to (x, y, z) is known exactly near the legs and the corner at the origin.
#[test]
fn features_at_and_within_ulps_of_region_boundaries_are_exact() {
    let mesh = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    let tree = WideTree::build_set(mesh.triangles(), &Default::default()).unwrap();
    let at = |p: Vec3| SurfacePoint::closest(&mesh, &tree.closest(p).unwrap(), p);
    let ulps = |x: f32, k: i32| {
        let mut x = x;
        for _ in 0..k.abs() {
            x = if k > 0 { x.next_up() } else { x.next_down() };
        }
        x
    };
    for z in [0.0f32, 1.0, -0.25] {
        for k in -3..=3 {
            let y = ulps(0.0, k);
            // Beside the leg y = 0 at x = 0.5: on it for y <= 0, inside for y > 0.
            let a = at(Vec3::new(0.5, y, z));
            let expected = if y > 0.0 { Feature::Face } else { Feature::Edge([0, 1]) };
            assert_eq!(a.feature, expected, "y = {y:e}, z = {z}");
            assert_eq!(a.barycentric[1], 0.5);
            assert_eq!(a.barycentric[2], f64::from(y.max(0.0)));
            // Beside the corner at the origin, along the diagonal out of it.
            let b = at(Vec3::new(y, y, z));
            let expected = if y > 0.0 { Feature::Face } else { Feature::Vertex(0) };
            assert_eq!(b.feature, expected, "corner, y = {y:e}");
            // Near the corner (1, 0): its region starts at x = 1 (for y <= 0).
            let x = ulps(1.0, k);
            let c = at(Vec3::new(x, -0.5, z));
            let expected = if x >= 1.0 {
                Feature::Vertex(1)
            } else {
                Feature::Edge([0, 1])
            };
            assert_eq!(c.feature, expected, "x = {x:e}");
            assert_eq!(c.point(&mesh), DVec3::new(f64::from(x.min(1.0)), 0.0, 0.0));
        }
    }
}

#[test]
fn polygon_diagonals_are_inside_the_face() {
    let quad = Mesh::from_faces(
        vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::Y,
            Vec3::new(0.5, 1.5, 0.0),
        ],
        &[vec![0, 1, 2, 4, 3]],
    )
    .unwrap();
    let index = MeshIndex::new(quad.clone());
    // Right above the fan's diagonals 0–2 and 0–4, and above vertex 4 and edge 2–4.
    let points = [
        Vec3::new(0.5, 0.5, 1.0),
        Vec3::new(0.25, 0.75, 1.0),
        Vec3::new(0.5, 1.5, 1.0),
        Vec3::new(0.75, 1.25, 2.0),
    ];
    let hits = index.closest(PrimitiveKind::Faces, &points).unwrap();
    let at: Vec<Feature> = index
        .closest_surface(&points, &hits, Attributes::NONE)
        .iter()
        .map(|a| a.unwrap().at.feature)
        .collect();
    assert_eq!(
        at,
        [Feature::Face, Feature::Face, Feature::Vertex(4), Feature::Edge([2, 4])]
    );
}

#[test]
fn ray_hits_locate_their_points() {
    let mesh = polygon_mesh(2);
    let index = MeshIndex::new(mesh.clone());
    let tree = index.ray_tree().unwrap();
    let mut rng = Rng::new(4);
    let (mut hits, mut facing) = (0, 0);
    let mut all_hits = Vec::new();
    for _ in 0..2000 {
        let d = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X);
        let origin = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), rng.range(-0.3, 0.3));
        let found = tree.first_hit(origin, d, 0.0, f32::INFINITY).unwrap();
        all_hits.push(found);
        let Some(hit) = found else {
            continue;
        };
        hits += 1;
        let at = SurfacePoint::of_ray_hit(&mesh, &hit);
        assert_eq!((at.face, at.triangle), (hit.source, hit.primitive));
        assert!(
            (at.point(&mesh) - hit.point.as_dvec3()).length() < 1e-5,
            "{hit:?} {at:?}"
        );
        // The geometric normal is the triangle's, unit length.
        let t = at.corners.map(|v| mesh.positions()[v as usize].as_dvec3());
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        assert!((at.face_normal(&mesh) - n).length() < 1e-12);
        facing += usize::from(n.dot(d.as_dvec3()) > 0.0);
    }
    // Seen from inside the outward sphere, faces turn their backs to the rays.
    assert!(
        hits > 1900 && facing * 100 > hits * 95,
        "{hits} hits, {facing} facing away"
    );
    // The batch answers as the hits one at a time do, misses (put in
    // among them) included.
    all_hits.insert(7, None);
    let normals = vertex_normals(&mesh);
    let asked = Attributes {
        normals: true,
        uv: false,
    };
    let batch = index.ray_surface(&all_hits, asked).to_vec();
    let alone: Vec<Option<SurfaceAnswer>> = all_hits
        .iter()
        .map(|h| h.map(|h| SurfaceAnswer::new(SurfacePoint::of_ray_hit(&mesh, &h), &mesh, &normals, asked)))
        .collect();
    assert_eq!(batch, alone);
}

#[test]
fn vertex_normals_match_a_per_vertex_loop() {
    for mesh in [polygon_mesh(5), common::random_soup(200, 3)] {
        let normals = vertex_normals(&mesh);
        let p = |v: u32| mesh.positions()[v as usize].as_dvec3();
        let tris = mesh.triangle_vertex_indices();
        for v in 0..mesh.vertex_count() as u32 {
            let mut sum = DVec3::ZERO;
            for t in tris.iter().filter(|t| t.contains(&v)) {
                // A vertex repeated in a triangle: each of its corners counts.
                for k in (0..3).filter(|&j| t[j] == v) {
                    let (a, b, c) = (p(t[k]), p(t[(k + 1) % 3]), p(t[(k + 2) % 3]));
                    let n = (b - a).cross(c - a).normalize_or_zero();
                    let (u, w) = ((b - a).normalize_or_zero(), (c - a).normalize_or_zero());
                    let angle = u.dot(w).clamp(-1.0, 1.0).acos();
                    if u != DVec3::ZERO && w != DVec3::ZERO {
                        sum += n * angle;
                    }
                }
            }
            let expected = sum.normalize_or_zero().as_vec3();
            assert!(
                (normals[v as usize] - expected).length() < 1e-5,
                "vertex {v}: {} vs {expected}",
                normals[v as usize]
            );
        }
    }
    // On a closed sphere about the origin, normals point out.
    let sphere = common::bumpy_sphere(6, 1);
    for (n, p) in vertex_normals(&sphere).iter().zip(sphere.positions()) {
        assert!(n.dot(p.normalize()) > 0.8);
    }
}

#[test]
fn signed_distance_gradients_match_central_differences() {
    let mesh = common::bumpy_sphere(6, 9);
    let index = MeshIndex::new(mesh.clone());
    for sign in [Sign::WindingNumber, Sign::Pseudonormal] {
        let points = proxima::sample::uniform_in_box(&mesh, 300, 2);
        let answers = index.signed_distance_gradients(sign, &points).unwrap();
        let field = index.field(sign).unwrap();
        // The distance in f64 from the exact closest point on the answer's triangle set.
        let sdf = |q: DVec3| -> f64 {
            let p = q.as_vec3();
            let s = field.signed_distance(p).unwrap();
            let at = SurfacePoint::closest(&mesh, &s.closest, p);
            let d = (q - at.point(&mesh)).length();
            if s.is_inside() { -d } else { d }
        };
        let (mut checked, h) = (0, 1e-3);
        for (p, g) in points.iter().zip(&answers) {
            let g = g.unwrap();
            assert!((g.gradient.length() - 1.0).abs() < 1e-9);
            if g.distance.distance.abs() < 0.05 {
                continue;
            }
            let q = p.as_dvec3();
            let difference = |h: f64| {
                DVec3::new(
                    sdf(q + DVec3::X * h) - sdf(q - DVec3::X * h),
                    sdf(q + DVec3::Y * h) - sdf(q - DVec3::Y * h),
                    sdf(q + DVec3::Z * h) - sdf(q - DVec3::Z * h),
                ) / (2.0 * h)
            };
            let (fd, fine) = (difference(h), difference(h / 4.0));
            // Near the medial axis the steps straddle two closest points and
            // the two step sizes disagree: skip those.
            if (fd - fine).length() > 1e-3 {
                continue;
            }
            checked += 1;
            assert!((fd - g.gradient).length() < 1e-2, "{p}: {} vs {fd}", g.gradient);
        }
        assert!(checked > 200, "{checked}");
    }
}

#[test]
fn gradients_on_the_surface_are_pseudonormals() {
    let mesh = common::bumpy_sphere(4, 2);
    let index = MeshIndex::new(mesh.clone());
    // Vertices and edge midpoints are on the surface (distance 0).
    let mut points: Vec<Vec3> = mesh.positions().to_vec();
    points.extend(mesh.edge_indices().iter().map(|&[a, b]| {
        let p = mesh.positions();
        (p[a as usize] + p[b as usize]) * 0.5
    }));
    let normals = vertex_normals(&mesh);
    let answers = index.signed_distance_gradients(Sign::WindingNumber, &points).unwrap();
    for (i, (p, g)) in points.iter().zip(&answers).enumerate() {
        let g = g.unwrap();
        assert!((g.gradient.length() - 1.0).abs() < 1e-9, "{p}");
        assert!(g.gradient.dot(p.normalize().as_dvec3()) > 0.8, "{p}: {}", g.gradient);
        if i < mesh.vertex_count() && g.distance.distance == 0.0 {
            // The vertex pseudonormal is the angle-weighted vertex normal.
            assert!((g.gradient - normals[i].as_dvec3()).length() < 1e-5);
        }
    }
}
/// A triangle of `random_soup` meant to be collinear, left with sin² =
/// 2.4e-15 by its f32 corners: Ericson's face weights in f64 put the closest
/// point to its own edge's midpoint 3e-3 away; the sliver path finds it.
#[test]
fn sliver_closest_points_stay_on_the_sliver() {
    let bits = [
        [1064909129u32, 1057572790, 1047650127],
        [1065635062, 1060877895, 1049897002],
        [1066390896, 1065594384, 1052572910],
    ];
    let t = bits.map(|c| Vec3::from(c.map(f32::from_bits)).as_dvec3());
    for p in [
        (t[0] + t[2]) * 0.5,
        t[0] * 0.25 + t[2] * 0.75,
        (t[0] + t[1]) * 0.5 + DVec3::Z * 0.01,
    ] {
        let (q, w) = proxima::pair::point_triangle_closest(p, &t);
        let oracle = (0..3)
            .map(|k| common::oracle::segment_distance(t[k].into(), t[(k + 1) % 3].into(), p.into()))
            .fold(f64::INFINITY, f64::min);
        assert!(
            (q - p).length() <= oracle + 1e-12,
            "{p}: {q} at {}, edges at {oracle}",
            (q - p).length()
        );
        assert!((t[0] * w[0] + t[1] * w[1] + t[2] * w[2] - q).length() < 1e-12);
    }
}

/// A unit square in z = 0 as two triangles whose UVs meet at a seam along
/// the diagonal (the corners of vertex 0 and 2 carry different UVs in each
/// face), with one normal per corner.
const SEAM_OBJ: &str = "\
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
vt 0.25 0.25
vn 0 0 1
vn 0 1 1
f 1/1/1 2/2/1 3/3/2
f 1/6/1 3/5/2 4/4/1
";

#[test]
fn obj_corner_uvs_and_normals_survive_seams() {
    let dir = common::temp_dir("obj_corner_uvs");
    let path = dir.join("seam.obj");
    std::fs::write(&path, SEAM_OBJ).unwrap();
    let mesh = proxima::io::load(&path).unwrap();
    let uvs = mesh.corner_uvs().unwrap();
    assert_eq!(
        uvs,
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.25, 0.25], [0.5, 0.5], [0.0, 1.0]]
    );
    let normals = mesh.corner_normals().unwrap();
    assert_eq!(normals[2], Vec3::new(0.0, 1.0, 1.0));
    let index = MeshIndex::new(mesh.clone());
    // Above the point (0.75, 0.25), in face 0: u, v interpolate its corners' UVs.
    let points = [Vec3::new(0.75, 0.25, 1.0), Vec3::new(0.25, 0.75, 1.0)];
    let hits = index.closest(PrimitiveKind::Faces, &points).unwrap();
    let answers = index
        .closest_surface(
            &points,
            &hits,
            Attributes {
                normals: true,
                uv: true,
            },
        )
        .to_vec();
    let at: Vec<Option<SurfacePoint>> = answers.iter().map(|a| a.map(|a| a.at)).collect();
    let first = at[0].unwrap();
    assert_eq!(first.face, 0);
    let uv = first.uv(&mesh).unwrap();
    assert_eq!(answers[0].unwrap().uv, Some(uv));
    // Face 0's UVs equal the positions' x, y.
    assert!((uv[0] - 0.75).abs() < 1e-12 && (uv[1] - 0.25).abs() < 1e-12, "{uv:?}");
    // Face 1: (x, y) = w0·(0,0) + w1·(1,1) + w2·(0,1); UVs w0·(.25,.25) + w1·(.5,.5) + w2·(0,1).
    let second = at[1].unwrap();
    let w = second.barycentric;
    let expected = [0.25 * w[0] + 0.5 * w[1], 0.25 * w[0] + 0.5 * w[1] + w[2]];
    let uv = second.uv(&mesh).unwrap();
    assert!((uv[0] - expected[0]).abs() < 1e-12 && (uv[1] - expected[1]).abs() < 1e-12);
    // The file's normals, interpolated: corner 2 of face 0 leans to +y.
    let n = first.interpolated_normal(&mesh, &[]);
    let raw = DVec3::Z * first.barycentric[0]
        + DVec3::Z * first.barycentric[1]
        + DVec3::new(0.0, 1.0, 1.0) * first.barycentric[2];
    assert!((n - raw.normalize()).length() < 1e-12);
    assert_eq!(answers[0].unwrap().normal, n);
}

#[test]
fn obj_attributes_need_every_corner_and_defined_indices() {
    let dir = common::temp_dir("obj_attribute_rules");
    let load = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        proxima::io::load(&path)
    };
    // Only some corners name a UV: none kept, no error.
    let mixed = load("mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3\n").unwrap();
    assert!(mixed.corner_uvs().is_none() && mixed.corner_normals().is_none());
    // Relative indices count back from the last defined.
    let relative = load(
        "relative.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n",
    )
    .unwrap();
    assert_eq!(relative.corner_uvs().unwrap(), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    // An index past the ones defined names the face's line.
    let error = load("beyond.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n\nf 1/1 2/1 3/7\n").unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("beyond.obj:6") && text.contains("texture coordinate 7"),
        "{text}"
    );
    let error = load("normal0.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//0 3//1\n").unwrap_err();
    assert!(error.to_string().contains("normal0.obj:5"), "{error}");
    let error = load("nan.obj", "v 0 0 0\nvn 0 nan 1\n").unwrap_err();
    assert!(error.to_string().contains("nan.obj:2"), "{error}");
}

#[test]
fn ply_vertex_normals_and_uvs_become_corner_values() {
    let dir = common::temp_dir("ply_attributes");
    let ascii = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                 property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n\
                 element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                 0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 1 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";
    let path = dir.join("quad.ply");
    std::fs::write(&path, ascii).unwrap();
    let mesh = proxima::io::load(&path).unwrap();
    assert_eq!(
        mesh.corner_uvs().unwrap(),
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    );
    assert_eq!(mesh.corner_normals().unwrap()[2], Vec3::new(0.0, 1.0, 1.0));
    // The same file in binary: the same mesh.
    let mut binary = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                       property float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float s\n\
                       property float t\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        .to_vec();
    for row in [
        [0.0f32, 0., 0., 0., 0., 1., 0., 0.],
        [1., 0., 0., 0., 0., 1., 1., 0.],
        [1., 1., 0., 0., 1., 1., 1., 1.],
        [0., 1., 0., 0., 0., 1., 0., 1.],
    ] {
        binary.extend(row.iter().flat_map(|x| x.to_le_bytes()));
    }
    binary.push(4);
    binary.extend([0i32, 1, 2, 3].iter().flat_map(|x| x.to_le_bytes()));
    let path = dir.join("quad_binary.ply");
    std::fs::write(&path, binary).unwrap();
    assert_eq!(proxima::io::load(&path).unwrap(), mesh);
    // A normal that is not finite names the vertex.
    let path = dir.join("nan.ply");
    std::fs::write(&path, ascii.replace("1 1 0 0 1 1 1 1", "1 1 0 0 nan 1 1 1")).unwrap();
    let error = proxima::io::load(&path).unwrap_err().to_string();
    assert!(error.contains("vertex 2") && error.contains("normal"), "{error}");
}

#[test]
fn corner_attributes_are_checked() {
    let mesh = Mesh::from_triangles(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0, 1, 2]]).unwrap();
    assert!(mesh.clone().with_corner_uvs(vec![[0.0, 0.0]; 2]).is_err());
    assert!(
        mesh.clone()
            .with_corner_normals(vec![Vec3::Z, Vec3::Z, Vec3::NAN])
            .is_err()
    );
    let with = mesh
        .clone()
        .with_corner_uvs(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
        .unwrap();
    assert_eq!(with.corner_count(), 3);
    assert!(mesh.corner_uvs().is_none());
}

/// A GLB triangle with NORMAL and TEXCOORD_0, shown by a node scaled
/// (2, 1, 1): the normals turn by the inverse transpose; a second primitive
/// without them drops that kind for the whole mesh.
#[test]
fn glb_normals_and_uvs_become_corner_values() {
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut bin = floats(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]); // positions, 36 bytes
    let s = std::f32::consts::FRAC_1_SQRT_2;
    bin.extend(floats(&[s, s, 0., s, s, 0., 0., 0., 1.])); // normals, 36 bytes
    bin.extend(floats(&[0., 0., 1., 0., 0., 1.])); // uvs, 24 bytes
    let document = |second_primitive: &str| {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":96}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":36}},{{"buffer":0,"byteOffset":72,"byteLength":24}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}},{{"bufferView":1,"componentType":5126,"count":3,"type":"VEC3"}},{{"bufferView":2,"componentType":5126,"count":3,"type":"VEC2"}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}}}}{second_primitive}]}}],
            "nodes":[{{"mesh":0,"scale":[2,1,1]}}]}}"#
        )
    };
    let dir = common::temp_dir("glb_attributes");
    let path = dir.join("t.glb");
    std::fs::write(&path, common::glb_writer::glb(&document(""), &bin)).unwrap();
    let mesh = proxima::io::load(&path).unwrap();
    assert_eq!(mesh.positions()[1], Vec3::new(2.0, 0.0, 0.0));
    assert_eq!(mesh.corner_uvs().unwrap(), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let n = mesh.corner_normals().unwrap();
    assert!(
        (n[0] - Vec3::new(0.5, 1.0, 0.0).normalize()).length() < 1e-6,
        "{:?}",
        n[0]
    );
    assert_eq!(n[2], Vec3::Z);
    // The same triangle again, with UVs only: no normals kept.
    std::fs::write(
        &path,
        common::glb_writer::glb(&document(r#",{"attributes":{"POSITION":0,"TEXCOORD_0":2}}"#), &bin),
    )
    .unwrap();
    let mesh = proxima::io::load(&path).unwrap();
    assert!(mesh.corner_normals().is_none());
    assert_eq!(mesh.corner_uvs().unwrap().len(), 6);
    // A NORMAL accessor of the wrong type is named.
    std::fs::write(
        &path,
        common::glb_writer::glb(&document("").replace(r#""NORMAL":1"#, r#""NORMAL":2"#), &bin),
    )
    .unwrap();
    let error = proxima::io::load(&path).unwrap_err().to_string();
    assert!(error.contains("NORMAL") && error.contains("accessors[2]"), "{error}");
}
