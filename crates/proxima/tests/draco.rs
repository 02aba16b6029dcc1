//! Draco-compressed GLB primitives (`KHR_draco_mesh_compression`, io/draco.rs):
//! meshes encoded in the test with draco-core's encoder, wrapped in a GLB
//! written here, must load as the same triangles as the mesh they were made
//! from (compared as sets: Draco renumbers points and reorders faces), with
//! their normals and texture coordinates within the quantization step; node
//! transforms apply as to an uncompressed primitive; damaged streams are
//! errors naming the primitive, never a panic.

// Without the feature only the refusal is tested, with the same fixtures.
#![cfg_attr(not(feature = "draco"), allow(dead_code, unused_imports))]

use crate::common;

use crate::common::glb_writer::glb;
use draco_core::{
    DataType, EncoderBuffer, EncoderOptions, GeometryAttributeType, Mesh as DracoMesh, MeshEncoder, PointAttribute,
};
use glam::{DMat4, DQuat, DVec3};
use proxima::io::{Format, parse};
use proxima::math::Vec3;
use proxima::mesh::Mesh;
use serde_json::{Value, json};
use std::collections::HashMap;

/// A triangle mesh with a normal and texture coordinates per corner: what
/// is encoded, and the oracle the loaded mesh is compared with.
struct Source {
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    /// Per corner, three a triangle.
    normals: Vec<Vec3>,
    uvs: Vec<[f32; 2]>,
}

/// Quantization bits of the encoded positions, normals and texture coordinates.
const BITS: [i32; 3] = [30, 16, 20];

/// A torus of `n` × `m` quads (two triangles each), with its exact normals
/// and a texture seam along each of its two circles (the grid's first row
/// and column repeat at u = 1 and v = 1), so that Draco splits points.
fn torus(n: u32, m: u32) -> Source {
    let (big, small) = (2.0f64, 0.5f64);
    let at = |i: u32, j: u32| {
        let (a, b) = (
            std::f64::consts::TAU * f64::from(i % n) / f64::from(n),
            std::f64::consts::TAU * f64::from(j % m) / f64::from(m),
        );
        let normal = DVec3::new(a.cos() * b.cos(), a.sin() * b.cos(), b.sin());
        let center = DVec3::new(a.cos() * big, a.sin() * big, 0.0);
        (center + small * normal, normal)
    };
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..m {
            positions.push(at(i, j).0.as_vec3());
        }
    }
    let index = |i: u32, j: u32| (i % n) * m + j % m;
    let mut source = Source {
        positions,
        triangles: Vec::new(),
        normals: Vec::new(),
        uvs: Vec::new(),
    };
    for i in 0..n {
        for j in 0..m {
            let quad = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            for t in [[0, 1, 2], [0, 2, 3]] {
                let corners = t.map(|k| quad[k]);
                source.triangles.push(corners.map(|(i, j)| index(i, j)));
                for (i, j) in corners {
                    source.normals.push(at(i, j).1.as_vec3());
                    source.uvs.push([i as f32 / n as f32, j as f32 / m as f32]);
                }
            }
        }
    }
    source
}

/// A real mesh from the shared folder with its area-weighted vertex normals
/// and its texture coordinates (or, for a mesh without, the position's x and
/// y, which makes no seam).
fn real(name: &str) -> Option<Source> {
    let mesh = proxima::io::load(common::data_dir()?.join(name)).unwrap();
    let positions = mesh.positions().to_vec();
    let triangles: Vec<[u32; 3]> = mesh.faces().map(|f| [f[0], f[1], f[2]]).collect();
    let mut vertex_normals = vec![DVec3::ZERO; positions.len()];
    for t in &triangles {
        let [a, b, c] = t.map(|v| positions[v as usize].as_dvec3());
        for v in t {
            vertex_normals[*v as usize] += (b - a).cross(c - a);
        }
    }
    let corners = triangles.iter().flatten();
    let normals = corners
        .clone()
        .map(|&v| vertex_normals[v as usize].normalize_or_zero().as_vec3())
        .collect();
    let uvs = match mesh.corner_uvs() {
        Some(uvs) => uvs.to_vec(),
        None => corners
            .map(|&v| [positions[v as usize].x, positions[v as usize].y])
            .collect(),
    };
    Some(Source {
        positions,
        triangles,
        normals,
        uvs,
    })
}

/// A Draco stream of `source`, and what its glTF accessors state.
struct Encoded {
    stream: Vec<u8>,
    points: usize,
    faces: usize,
    /// Draco unique ids of the position, normal and texture attributes.
    ids: [u32; 3],
}

fn attribute(kind: GeometryAttributeType, values: &[f32], components: u8) -> PointAttribute {
    let points = values.len() / components as usize;
    let mut attribute = PointAttribute::new();
    attribute.init(kind, components, DataType::Float32, false, points);
    let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
    attribute.buffer_mut().write(0, &bytes);
    attribute
}

/// Encodes `source` as Draco does a glTF primitive: one point per corner,
/// then the points whose position, normal and texture coordinates are all
/// equal merged (so a seam keeps its points apart), at [`BITS`].
fn encode(source: &Source) -> Encoded {
    let corners: Vec<Vec3> = source
        .triangles
        .iter()
        .flatten()
        .map(|&v| source.positions[v as usize])
        .collect();
    let flat = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
    let mut mesh = DracoMesh::new();
    mesh.set_num_points(corners.len());
    let ids = [
        mesh.add_attribute(attribute(GeometryAttributeType::Position, &flat(&corners), 3)),
        mesh.add_attribute(attribute(GeometryAttributeType::Normal, &flat(&source.normals), 3)),
        mesh.add_attribute(attribute(
            GeometryAttributeType::TexCoord,
            &source.uvs.iter().flatten().copied().collect::<Vec<_>>(),
            2,
        )),
    ];
    let faces: Vec<u32> = (0..corners.len() as u32).collect();
    mesh.set_num_faces(source.triangles.len());
    mesh.set_faces_from_flat_indices(&faces);
    mesh.deduplicate_attribute_values().unwrap();
    mesh.deduplicate_point_ids();
    let unique = ids.map(|id| mesh.attribute(id).unique_id());
    let mut options = EncoderOptions::new();
    for (id, bits) in ids.iter().zip(BITS) {
        options.set_attribute_quantization(*id, bits);
    }
    let mut encoder = MeshEncoder::new();
    encoder.set_mesh(mesh);
    let mut out = EncoderBuffer::new();
    let info = encoder.encode_with_info(&options, &mut out).unwrap();
    Encoded {
        stream: out.data().to_vec(),
        points: info.num_encoded_points,
        faces: info.num_encoded_faces,
        ids: unique,
    }
}

/// A GLB file whose primitive is `encoded`, shown by `nodes`; `with_uvs`
/// names the texture coordinates too.
fn draco_glb(encoded: &Encoded, nodes: Value, with_uvs: bool) -> Vec<u8> {
    let [position, normal, uv] = encoded.ids;
    let accessor =
        |kind: &str, count: usize, component: u32| json!({"componentType": component, "type": kind, "count": count});
    let mut attributes = json!({"POSITION": 0, "NORMAL": 1});
    let mut ids = json!({"POSITION": position, "NORMAL": normal});
    if with_uvs {
        attributes["TEXCOORD_0"] = json!(2);
        ids["TEXCOORD_0"] = json!(uv);
    }
    let document = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_draco_mesh_compression"],
        "extensionsRequired": ["KHR_draco_mesh_compression"],
        "buffers": [{"byteLength": encoded.stream.len()}],
        "bufferViews": [{"buffer": 0, "byteLength": encoded.stream.len()}],
        "accessors": [
            accessor("VEC3", encoded.points, 5126),
            accessor("VEC3", encoded.points, 5126),
            accessor("VEC2", encoded.points, 5126),
            accessor("SCALAR", 3 * encoded.faces, 5125)
        ],
        "meshes": [{"primitives": [{
            "attributes": attributes,
            "indices": 3,
            "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": ids}}
        }]}],
        "nodes": nodes,
    });
    glb(&document.to_string(), &encoded.stream)
}

/// The same primitive uncompressed: `source`'s corners as plain float
/// accessors, one vertex per corner.
fn plain_glb(source: &Source, nodes: Value) -> Vec<u8> {
    let corners = source.triangles.iter().flatten().map(|&v| source.positions[v as usize]);
    let mut bin: Vec<u8> = corners.flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
    let normals_at = bin.len();
    bin.extend(
        source
            .normals
            .iter()
            .flat_map(|n| n.to_array())
            .flat_map(f32::to_le_bytes),
    );
    let count = source.normals.len();
    let document = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteLength": normals_at},
            {"buffer": 0, "byteOffset": normals_at, "byteLength": bin.len() - normals_at}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": count},
            {"bufferView": 1, "componentType": 5126, "type": "VEC3", "count": count}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
        "nodes": nodes,
    });
    glb(&document.to_string(), &bin)
}

fn read(bytes: &[u8]) -> Result<Mesh, proxima::LoadError> {
    parse(bytes, Format::Glb, "test.glb".as_ref())
}

/// One corner of a triangle: its position's class (equal positions are one
/// class), and its normal and texture coordinates.
type Corner = (u32, Vec3, [f32; 2]);

/// The triangles of a mesh as corners, each triangle rotated to start at its
/// least class, sorted: two meshes with the same triangles give the same
/// classes in the same order whatever their numbering. Positions are put in
/// classes by `classes` (the oracle's, or the nearest oracle position).
fn triangle_set(mesh: &Mesh, class: &dyn Fn(Vec3) -> u32) -> Vec<[Corner; 3]> {
    let normals = mesh.corner_normals();
    let uvs = mesh.corner_uvs();
    let mut set: Vec<[Corner; 3]> = mesh
        .faces()
        .enumerate()
        .map(|(f, face)| {
            let mut corners: [Corner; 3] = std::array::from_fn(|k| {
                let c = 3 * f + k;
                (
                    class(mesh.positions()[face[k] as usize]),
                    normals.map_or(Vec3::ZERO, |n| n[c]),
                    uvs.map_or([0.0; 2], |t| t[c]),
                )
            });
            let least = (0..3).min_by_key(|&k| corners[k].0).unwrap();
            corners.rotate_left(least);
            corners
        })
        .collect();
    set.sort_by_key(|t| t.map(|c| c.0));
    set
}

/// Asserts that `got` holds the triangles of `oracle`: positions within
/// `tolerance[0]` of the oracle's (each matched to the one oracle position
/// that near), normals within `tolerance[1]`, texture coordinates within
/// `tolerance[2]` (a negative one: not compared).
fn assert_same_triangles(got: &Mesh, oracle: &Mesh, tolerance: [f32; 3]) {
    let mut classes: HashMap<[u32; 3], u32> = HashMap::new();
    for p in oracle.positions() {
        let next = classes.len() as u32;
        classes.entry(p.to_array().map(f32::to_bits)).or_insert(next);
    }
    // Nearest oracle position by a grid of cells twice the tolerance.
    let cell = 2.0 * tolerance[0];
    let key = |p: Vec3| (p / cell).floor().as_ivec3();
    let mut grid: HashMap<glam::IVec3, Vec<Vec3>> = HashMap::new();
    for p in oracle.positions() {
        grid.entry(key(*p)).or_default().push(*p);
    }
    let exact = |p: Vec3| classes[&p.to_array().map(f32::to_bits)];
    let nearest = |p: Vec3| {
        let k = key(p);
        let mut near: Vec<Vec3> = Vec::new();
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let cell = grid.get(&(k + glam::IVec3::new(dx, dy, dz)));
                    near.extend(
                        cell.into_iter()
                            .flatten()
                            .filter(|&&q| (q - p).abs().max_element() <= tolerance[0]),
                    );
                }
            }
        }
        near.sort_by_key(|q| exact(*q));
        near.dedup();
        assert_eq!(
            near.len(),
            1,
            "{p} has {} oracle positions within {}",
            near.len(),
            tolerance[0]
        );
        exact(near[0])
    };
    let want = triangle_set(oracle, &exact);
    let have = triangle_set(got, &nearest);
    assert_eq!(have.len(), want.len());
    let (mut normal_error, mut uv_error) = (0.0f32, 0.0f32);
    for (h, w) in have.iter().zip(&want) {
        assert_eq!(h.map(|c| c.0), w.map(|c| c.0), "the triangle sets differ");
        for (a, b) in h.iter().zip(w) {
            normal_error = normal_error.max((a.1 - b.1).abs().max_element());
            uv_error = uv_error.max((a.2[0] - b.2[0]).abs().max((a.2[1] - b.2[1]).abs()));
        }
    }
    assert!(normal_error <= tolerance[1], "normals differ by {normal_error}");
    if tolerance[2] >= 0.0 {
        assert!(uv_error <= tolerance[2], "texture coordinates differ by {uv_error}");
    }
}

/// The oracle as proxima holds it: the source's triangles with its corner
/// normals and texture coordinates.
fn oracle(source: &Source) -> Mesh {
    let offsets = (0..=source.triangles.len() as u32).map(|t| 3 * t).collect();
    let indices = source.triangles.iter().flatten().copied().collect();
    Mesh::from_compact(source.positions.clone(), offsets, indices)
        .unwrap()
        .with_corner_normals(source.normals.clone())
        .unwrap()
        .with_corner_uvs(source.uvs.clone())
        .unwrap()
}

/// The quantization steps of [`BITS`] for `source`, with f32 rounding:
/// positions over the largest extent of the box (Draco's range), unit
/// normals on an octahedron (two steps a component), coordinates over
/// theirs.
fn tolerances(source: &Source) -> [f32; 3] {
    let extent = |values: &mut dyn Iterator<Item = f32>| {
        let (lo, hi) = values.fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
        (hi - lo, lo.abs().max(hi.abs()))
    };
    let step = |range: f32, bits: i32| range / ((1u64 << bits) - 1) as f32;
    let (range, largest) = (0..3)
        .map(|k| extent(&mut source.positions.iter().map(|p| p[k])))
        .fold((0.0f32, 0.0f32), |(r, l), (r2, l2)| (r.max(r2), l.max(l2)));
    let (uv_range, uv_largest) = (0..2)
        .map(|k| extent(&mut source.uvs.iter().map(|t| t[k])))
        .fold((0.0f32, 0.0f32), |(r, l), (r2, l2)| (r.max(r2), l.max(l2)));
    [
        step(range, BITS[0]) + 4.0 * f32::EPSILON * largest,
        2.0 * step(2.0, BITS[1]) + 4.0 * f32::EPSILON,
        step(uv_range, BITS[2]) + 4.0 * f32::EPSILON * uv_largest,
    ]
}

#[cfg(feature = "draco")]
#[test]
fn a_torus_with_seams_loads_as_its_triangles_normals_and_coordinates() {
    let source = torus(24, 12);
    let encoded = encode(&source);
    // The seams split points: more points than positions.
    assert!(encoded.points > source.positions.len(), "{} points", encoded.points);
    let mesh = read(&draco_glb(&encoded, json!([{"mesh": 0}]), true)).unwrap();
    assert_eq!(
        (mesh.vertex_count(), mesh.face_count()),
        (encoded.points, source.triangles.len())
    );
    assert_same_triangles(&mesh, &oracle(&source), tolerances(&source));
}

#[cfg(feature = "draco")]
#[test]
fn real_meshes_load_as_their_triangles() {
    for name in ["bunny-npm.obj", "spot_triangulated.obj"] {
        let Some(source) = real(name) else { return };
        let encoded = encode(&source);
        let mesh = read(&draco_glb(&encoded, json!([{"mesh": 0}]), true)).unwrap();
        println!(
            "{name}: {} triangles, Draco stream of {} bytes ({} points)",
            mesh.face_count(),
            encoded.stream.len(),
            encoded.points
        );
        assert_same_triangles(&mesh, &oracle(&source), tolerances(&source));
    }
}

#[cfg(feature = "draco")]
#[test]
fn node_transforms_apply_as_to_an_uncompressed_primitive() {
    let source = torus(16, 8);
    let encoded = encode(&source);
    // A parent scaling unevenly (normals turn by the inverse transpose), a
    // child turned and moved; the mesh shown by both.
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let nodes = json!([
        {"scale": [2.0, 1.0, 0.5], "children": [1], "mesh": 0},
        {"rotation": rotation.to_array(), "translation": [3.0, -1.0, 4.0], "mesh": 0}
    ]);
    let draco = read(&draco_glb(&encoded, nodes.clone(), false)).unwrap();
    let plain = read(&plain_glb(&source, nodes)).unwrap();
    assert_eq!(draco.face_count(), 2 * source.triangles.len());
    // The positions of the uncompressed file are the source's, transformed
    // as the reader does (in f64, then to f32); the normals too.
    let parent = DMat4::from_scale(DVec3::new(2.0, 1.0, 0.5));
    let child = parent * DMat4::from_rotation_translation(rotation, DVec3::new(3.0, -1.0, 4.0));
    assert_eq!(
        plain.positions()[0],
        parent.transform_point3(plain_corner(&source, 0)).as_vec3()
    );
    let half = 3 * source.triangles.len();
    assert_eq!(
        plain.positions()[half],
        child.transform_point3(plain_corner(&source, 0)).as_vec3()
    );
    // Scaled by up to 2 and turned: twice the tolerance of the source.
    let [p, n, _] = tolerances(&source);
    assert_same_triangles(&draco, &plain, [2.0 * p + 1e-6, 2.0 * n, -1.0]);
}

fn plain_corner(source: &Source, c: usize) -> DVec3 {
    source.positions[source.triangles[c / 3][c % 3] as usize].as_dvec3()
}

/// Deterministic bytes for the damage loops.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
}

#[cfg(feature = "draco")]
#[test]
fn damaged_streams_are_errors_naming_the_primitive() {
    let encoded = encode(&torus(12, 6));
    let file = draco_glb(&encoded, json!([{"mesh": 0}]), true);
    read(&file).unwrap();
    let start = file.len() - encoded.stream.len().next_multiple_of(4);
    let check = |bytes: &[u8], what: &str| {
        if let Err(e) = read(bytes) {
            let text = e.to_string();
            assert!(
                text.starts_with("test.glb") && text.contains("meshes[0].primitives[0]"),
                "{what}: {text}"
            );
        }
    };
    // Every truncation of the stream (the view made shorter with it).
    for length in 0..encoded.stream.len() {
        let mut short = encoded.stream.clone();
        short.truncate(length);
        let shorter = Encoded {
            stream: short,
            ..encode_copy(&encoded)
        };
        let e = read(&draco_glb(&shorter, json!([{"mesh": 0}]), true));
        let e = e.expect_err("a truncated stream must not load").to_string();
        assert!(
            e.contains("meshes[0].primitives[0]: Draco data: "),
            "{length} bytes: {e}"
        );
    }
    // Every byte of the stream set to four other values, then many bytes at once.
    let mut random = Lcg(7);
    for at in 0..encoded.stream.len() {
        for value in [0x00, 0xFF, file[start + at] ^ 0x01, file[start + at] ^ 0x80] {
            let mut damaged = file.clone();
            damaged[start + at] = value;
            check(&damaged, &format!("byte {at} set to {value}"));
        }
    }
    for round in 0..4000 {
        let mut damaged = file.clone();
        for _ in 0..1 + random.next() % 8 {
            let at = start + random.next() as usize % encoded.stream.len();
            damaged[at] = random.next() as u8;
        }
        check(&damaged, &format!("round {round}"));
    }
}

fn encode_copy(encoded: &Encoded) -> Encoded {
    Encoded {
        stream: encoded.stream.clone(),
        ..*encoded
    }
}

#[cfg(feature = "draco")]
#[test]
fn accessors_and_ids_that_disagree_with_the_stream_are_refused() {
    let encoded = encode(&torus(8, 4));
    let nodes = json!([{"mesh": 0}]);
    let error = |encoded: &Encoded, with_uvs: bool| {
        read(&draco_glb(encoded, nodes.clone(), with_uvs))
            .unwrap_err()
            .to_string()
    };
    // Fewer triangles than the stream has: the decoder's own ceiling, from
    // the stream's header, refuses it before decoding them.
    let fewer = Encoded {
        faces: encoded.faces - 1,
        ..encode_copy(&encoded)
    };
    let e = error(&fewer, false);
    assert!(
        e.contains("meshes[0].primitives[0]: Draco data: ") && e.contains("ceiling"),
        "{e}"
    );
    // Fewer or more points, or more triangles, than it has: the counts
    // compared once decoded.
    for other in [
        Encoded {
            points: encoded.points - 1,
            ..encode_copy(&encoded)
        },
        Encoded {
            points: encoded.points + 1,
            ..encode_copy(&encoded)
        },
        Encoded {
            faces: encoded.faces + 1,
            ..encode_copy(&encoded)
        },
    ] {
        let e = error(&other, false);
        assert!(e.contains("meshes[0].primitives[0]: the Draco stream decodes"), "{e}");
    }
    // An attribute id the stream does not hold, or of the wrong kind.
    let wrong = Encoded {
        ids: [encoded.ids[0], 99, encoded.ids[2]],
        ..encode_copy(&encoded)
    };
    let e = error(&wrong, false);
    assert!(e.contains("NORMAL names attribute id 99"), "{e}");
    let swapped = Encoded {
        ids: [encoded.ids[0], encoded.ids[2], encoded.ids[1]],
        ..encode_copy(&encoded)
    };
    let e = error(&swapped, true);
    assert!(
        e.contains("NORMAL (attribute id") && e.contains("2 components, not 3"),
        "{e}"
    );
}

#[cfg(not(feature = "draco"))]
#[test]
fn without_the_feature_draco_primitives_are_refused() {
    let encoded = encode(&torus(8, 4));
    let e = read(&draco_glb(&encoded, json!([{"mesh": 0}]), true))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("KHR_draco_mesh_compression") && e.contains("`draco` feature is off"),
        "{e}"
    );
}
