//! Binary glTF reading (`io::glb`), against the OBJ reader on the same
//! geometry and hand-computed transforms; damaged and hostile files must give
//! typed errors, never a panic or an unbounded allocation.

use proptest::prelude::*;
use proxima::LoadErrorKind;
use proxima::io::{Format, parse};
use proxima::math::Vec3;
use proxima::mesh::Mesh;
use serde_json::{Value, json};

/// A GLB file: header, the JSON chunk (padded with spaces), the BIN chunk
/// (padded with zeros) when `bin` is not empty.
fn glb(document: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(document).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}

/// Builds the binary chunk and the JSON arrays that describe it.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Appends `bytes` as a buffer view and an accessor over it; returns the accessor's index.
    fn accessor(&mut self, bytes: &[u8], component: u32, kind: &str, count: usize, extra: Value) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        let mut accessor =
            json!({"bufferView": self.views.len() - 1, "componentType": component, "type": kind, "count": count});
        if let (Value::Object(a), Value::Object(e)) = (&mut accessor, extra) {
            a.extend(e);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn positions(&mut self, points: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = points.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, 5126, "VEC3", points.len(), json!({}))
    }

    /// Indices stored with `component` (5121, 5123, 5125).
    fn indices(&mut self, indices: &[u32], component: u32) -> usize {
        let bytes: Vec<u8> = match component {
            5121 => indices.iter().map(|&i| i as u8).collect(),
            5123 => indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
            _ => indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
        };
        self.accessor(&bytes, component, "SCALAR", indices.len(), json!({}))
    }

    /// The document with these meshes and nodes, and its file.
    fn file(&self, mut document: Value) -> Vec<u8> {
        document["asset"] = json!({"version": "2.0"});
        document["buffers"] = json!([{"byteLength": self.bin.len()}]);
        document["bufferViews"] = Value::Array(self.views.clone());
        document["accessors"] = Value::Array(self.accessors.clone());
        glb(&document, &self.bin)
    }
}

const CUBE: [[f32; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];
const CUBE_TRIANGLES: [u32; 36] = [
    0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3,
];

fn cube_obj() -> Mesh {
    let mut text = String::new();
    for p in CUBE {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in CUBE_TRIANGLES.chunks(3) {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    parse(text.as_bytes(), Format::Obj, "cube.obj".as_ref()).unwrap()
}

fn read(bytes: &[u8]) -> Result<Mesh, proxima::LoadError> {
    parse(bytes, Format::Glb, "test.glb".as_ref())
}

fn faces(mesh: &Mesh) -> Vec<Vec<u32>> {
    mesh.faces().map(<[u32]>::to_vec).collect()
}

fn one_mesh(primitive: Value) -> Value {
    json!({"scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [primitive]}]})
}

#[test]
fn triangles_with_each_index_type_equal_the_obj_reader() {
    let obj = cube_obj();
    for component in [5121, 5123, 5125] {
        let mut b = Builder::default();
        let position = b.positions(&CUBE);
        let indices = b.indices(&CUBE_TRIANGLES, component);
        let mesh = read(&b.file(one_mesh(
            json!({"attributes": {"POSITION": position}, "indices": indices}),
        )))
        .unwrap();
        assert_eq!(mesh.positions(), obj.positions(), "component type {component}");
        assert_eq!(faces(&mesh), faces(&obj), "component type {component}");
    }
    // Without indices: every three vertices a triangle, nothing welded.
    let mut b = Builder::default();
    let corners: Vec<[f32; 3]> = CUBE_TRIANGLES.iter().map(|&i| CUBE[i as usize]).collect();
    let position = b.positions(&corners);
    let mesh = read(&b.file(one_mesh(json!({"attributes": {"POSITION": position}})))).unwrap();
    assert_eq!(mesh.vertex_count(), 36);
    assert_eq!(mesh.face_count(), 12);
    for (f, face) in mesh.faces().enumerate() {
        let expected: Vec<Vec3> = obj.face(f).iter().map(|&v| obj.positions()[v as usize]).collect();
        let got: Vec<Vec3> = face.iter().map(|&v| mesh.positions()[v as usize]).collect();
        assert_eq!(got, expected);
    }
}

#[test]
fn node_transforms_compose_from_the_root() {
    let mut b = Builder::default();
    let position = b.positions(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let document = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [
            // Parent: scale 2, then translate by (1, 2, 3).
            {"translation": [1.0, 2.0, 3.0], "scale": [2.0, 2.0, 2.0], "children": [1]},
            // Child: a quarter turn about z as a column-major matrix (x -> y, y -> -x).
            {"matrix": [0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0], "children": [2]},
            // Grandchild: the same quarter turn as a quaternion (z, sin 45°, cos 45°), then the mesh.
            {"rotation": [0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::FRAC_1_SQRT_2], "mesh": 0}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]
    });
    let mesh = read(&b.file(document)).unwrap();
    // Two quarter turns map (x, y, z) to (-x, -y, z); then 2p + (1, 2, 3).
    let expected = [[-1.0, 2.0, 3.0], [1.0, 0.0, 3.0], [1.0, 2.0, 5.0]];
    for (got, want) in mesh.positions().iter().zip(expected) {
        assert!(
            (*got - Vec3::from(want)).abs().max_element() < 1e-6,
            "{got} against {want:?}"
        );
    }
}

#[test]
fn an_instanced_mesh_appears_once_per_node_and_scenes_are_chosen() {
    let mut b = Builder::default();
    let position = b.positions(&CUBE);
    let indices = b.indices(&CUBE_TRIANGLES, 5123);
    let meshes = json!([{"primitives": [{"attributes": {"POSITION": position}, "indices": indices}]}]);
    let nodes = json!([{"mesh": 0}, {"mesh": 0, "translation": [10.0, 0.0, 0.0]}, {"mesh": 0, "translation": [0.0, 10.0, 0.0]}]);
    let both = read(&b.file(json!({"scenes": [{"nodes": [0, 1]}], "nodes": nodes, "meshes": meshes}))).unwrap();
    assert_eq!((both.vertex_count(), both.face_count()), (16, 24));
    assert_eq!(both.positions()[8], Vec3::new(10.0, 0.0, 0.0));
    assert_eq!(both.face(12), &[8, 10, 9]);
    // `scene` picks the scene.
    let document = json!({"scene": 1, "scenes": [{"nodes": [0]}, {"nodes": [2]}], "nodes": nodes, "meshes": meshes});
    let second = read(&b.file(document)).unwrap();
    assert_eq!(second.vertex_count(), 8);
    assert_eq!(second.positions()[0], Vec3::new(0.0, 10.0, 0.0));
    // No scene: the nodes that are nobody's child; no node: every mesh, untransformed.
    let nodes = json!([{"mesh": 0, "children": [1]}, {"mesh": 0, "translation": [5.0, 0.0, 0.0]}, {"mesh": 0}]);
    let roots = read(&b.file(json!({"nodes": nodes, "meshes": meshes}))).unwrap();
    assert_eq!(roots.vertex_count(), 24);
    let bare = read(&b.file(json!({"meshes": meshes}))).unwrap();
    assert_eq!(bare.positions(), cube_obj().positions());
}

#[test]
fn strips_and_fans_are_triangulated_and_points_and_lines_skipped() {
    let mut b = Builder::default();
    let points: Vec<[f32; 3]> = (0..5).map(|i| [i as f32, (i % 2) as f32, 0.0]).collect();
    let position = b.positions(&points);
    let primitives = json!([
        {"attributes": {"POSITION": position}, "mode": 5},
        {"attributes": {"POSITION": position}, "mode": 6},
        {"attributes": {"POSITION": position}, "mode": 0},
        {"attributes": {"POSITION": position}, "mode": 1},
        {"attributes": {"POSITION": position}, "mode": 3}
    ]);
    let document = json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": primitives}]});
    let mesh = read(&b.file(document)).unwrap();
    assert_eq!(mesh.vertex_count(), 10);
    let strip = [[0, 1, 2], [2, 1, 3], [2, 3, 4]];
    let fan = [[5, 6, 7], [5, 7, 8], [5, 8, 9]];
    let expected: Vec<Vec<u32>> = strip.iter().chain(&fan).map(|t| t.to_vec()).collect();
    assert_eq!(faces(&mesh), expected);
}

#[test]
fn interleaved_and_quantized_positions() {
    // Float positions every 16 bytes (a normal's worth of padding between them).
    let mut b = Builder::default();
    let mut bytes = Vec::new();
    for p in &CUBE[..3] {
        bytes.extend(p.iter().flat_map(|x| x.to_le_bytes()));
        bytes.extend_from_slice(&[0xFF; 4]);
    }
    let interleaved = b.accessor(&bytes, 5126, "VEC3", 3, json!({}));
    b.views[interleaved]["byteStride"] = json!(16); // one view per accessor
    // KHR_mesh_quantization: normalized shorts (-32767 -> -1, 32767 -> 1) and plain bytes.
    let shorts: Vec<u8> = [32767i16, 0, -32767, 0, 16384, 0, -32768, 0, 0]
        .iter()
        .flat_map(|s| s.to_le_bytes())
        .collect();
    let quantized = b.accessor(&shorts, 5122, "VEC3", 3, json!({"normalized": true}));
    let small = b.accessor(&[1u8, 2, 3, 4, 5, 6, 7, 8, 9], 5121, "VEC3", 3, json!({}));
    let primitives = json!([
        {"attributes": {"POSITION": interleaved}},
        {"attributes": {"POSITION": quantized}},
        {"attributes": {"POSITION": small}}
    ]);
    let document = json!({"extensionsRequired": ["KHR_mesh_quantization"], "meshes": [{"primitives": primitives}]});
    let mesh = read(&b.file(document)).unwrap();
    let p = mesh.positions();
    assert_eq!(
        &p[..3],
        &CUBE[..3].iter().map(|&c| Vec3::from(c)).collect::<Vec<_>>()[..]
    );
    assert_eq!(p[3], Vec3::new(1.0, 0.0, -1.0));
    assert_eq!(p[4], Vec3::new(0.0, (16384.0f64 / 32767.0) as f32, 0.0));
    assert_eq!(p[5], Vec3::new(-1.0, 0.0, 0.0)); // -32768 clamps to -1
    assert_eq!(
        &p[6..],
        &[
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(4.0, 5.0, 6.0),
            Vec3::new(7.0, 8.0, 9.0)
        ]
    );
}

/// A file exercising most of the reader: a hierarchy, strips, interleaving, u8 indices.
fn rich_file() -> Vec<u8> {
    let mut b = Builder::default();
    let position = b.positions(&CUBE);
    let indices = b.indices(&CUBE_TRIANGLES, 5121);
    let document = json!({
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"translation": [1.0, 0.0, 0.0], "children": [1]}, {"scale": [2.0, 1.0, 1.0], "mesh": 0}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": position}, "indices": indices},
            {"attributes": {"POSITION": position}, "mode": 5}
        ]}]
    });
    b.file(document)
}

/// The error kind a malformed file must give.
enum Expect {
    Syntax,
    Truncated,
}

#[test]
fn malformed_files_are_typed_errors_naming_the_element() {
    let mut b = Builder::default();
    let position = b.positions(&CUBE);
    let indices = b.indices(&CUBE_TRIANGLES, 5121);
    let good = json!({"asset": {"version": "2.0"}, "buffers": [{"byteLength": b.bin.len()}],
        "bufferViews": b.views, "accessors": b.accessors,
        "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": position}, "indices": indices}]}]});
    assert_eq!(read(&glb(&good, &b.bin)).unwrap().face_count(), 12);
    let with = |path: &[&str], value: Value| {
        let mut d = good.clone();
        let mut at = &mut d;
        for key in path {
            at = match key.parse::<usize>() {
                Ok(i) => &mut at[i],
                Err(_) => &mut at[*key],
            };
        }
        *at = value;
        glb(&d, &b.bin)
    };
    let syntax = |bytes: Vec<u8>, words: &[&str]| {
        let e = read(&bytes).unwrap_err();
        let text = e.to_string();
        assert!(words.iter().all(|w| text.contains(w)), "{text} should name {words:?}");
        assert!(text.starts_with("test.glb"), "{text}");
        e.kind
    };
    let is_syntax = |k: LoadErrorKind| assert!(matches!(k, LoadErrorKind::Syntax(_)), "{k:?}");
    let is_truncated = |k: LoadErrorKind| assert!(matches!(k, LoadErrorKind::Truncated(_)), "{k:?}");

    is_syntax(syntax(b"PK\x03\x04 not a glb at all".to_vec(), &["no 'glTF' magic"]));
    let mut v1 = glb(&good, &b.bin);
    v1[4] = 1;
    is_syntax(syntax(v1, &["version 1"]));
    let mut long = glb(&good, &b.bin);
    long[8..12].copy_from_slice(&10_000u32.to_le_bytes());
    is_truncated(syntax(long, &["announces 10000 bytes"]));
    let mut chunk = glb(&good, &b.bin);
    chunk[12..16].copy_from_slice(&1_000_000u32.to_le_bytes());
    is_truncated(syntax(chunk, &["chunk at byte 12"]));
    let mut no_json = glb(&good, &b.bin);
    no_json[16..20].copy_from_slice(b"XXXX");
    is_syntax(syntax(no_json, &["out of order"]));
    let header_only: Vec<u8> = [*b"glTF", 2u32.to_le_bytes(), 12u32.to_le_bytes()].concat();
    is_syntax(syntax(header_only, &["no JSON chunk"]));
    let mut bad_json = glb(&good, &b.bin);
    bad_json[20] = b'[';
    is_syntax(syntax(bad_json, &["JSON chunk"]));

    // Edits of the good document: the error kind, the JSON path, its new value, words the message names.
    use Expect::{Syntax, Truncated};
    let edits: Vec<(Expect, &[&str], Value, &[&str])> = vec![
        (
            Truncated,
            &["accessors", "0", "count"],
            json!(9),
            &["accessors[0]", "bufferViews[0]"],
        ),
        (
            Truncated,
            &["accessors", "0", "byteOffset"],
            json!(4),
            &["accessors[0]"],
        ),
        (
            Truncated,
            &["bufferViews", "1", "byteLength"],
            json!(1 << 20),
            &["bufferViews[1]", "binary chunk"],
        ),
        (Syntax, &["bufferViews", "0", "byteStride"], json!(4), &["byteStride"]),
        (
            Syntax,
            &["accessors", "0", "type"],
            json!("VEC2"),
            &["not a VEC3", "POSITION"],
        ),
        (
            Syntax,
            &["accessors", "1", "componentType"],
            json!(5120),
            &["indices", "SCALAR of unsigned"],
        ),
        (
            Syntax,
            &["accessors", "1", "componentType"],
            json!(1234),
            &["componentType is 1234"],
        ),
        (Syntax, &["accessors", "0", "sparse"], json!({"count": 1}), &["sparse"]),
        (
            Syntax,
            &["buffers", "0", "uri"],
            json!("cube.bin"),
            &["buffers[0] has a uri"],
        ),
        (
            Syntax,
            &["meshes", "0", "primitives", "0", "mode"],
            json!(9),
            &["mode is 9"],
        ),
        (
            Syntax,
            &["meshes", "0", "primitives", "0", "indices"],
            json!(7),
            &["accessors[7]", "does not exist"],
        ),
        (
            Syntax,
            &["meshes", "0", "primitives", "0", "attributes"],
            json!({}),
            &["no POSITION"],
        ),
        (Syntax, &["nodes", "0", "mesh"], json!(3), &["meshes[3]"]),
        (
            Syntax,
            &["nodes", "0", "children"],
            json!([0]),
            &["nodes[0] is reached twice"],
        ),
        (
            Syntax,
            &["nodes"],
            json!([{"children": [1, 1]}, {"mesh": 0}]),
            &["nodes[1] is reached twice"],
        ),
        (
            Syntax,
            &["nodes", "0", "matrix"],
            json!([1, 0, 0]),
            &["nodes[0].matrix", "16 finite numbers"],
        ),
        (
            Syntax,
            &["nodes", "0", "rotation"],
            json!([0, 0, 0, 0]),
            &["zero quaternion"],
        ),
        (Syntax, &["scene"], json!(4), &["scenes[4]"]),
        (
            Syntax,
            &["extensionsRequired"],
            json!(["EXT_meshopt_compression"]),
            &["EXT_meshopt_compression"],
        ),
    ];
    for (expect, path, value, words) in edits {
        let kind = syntax(with(path, value), words);
        match expect {
            Syntax => is_syntax(kind),
            Truncated => is_truncated(kind),
        }
    }
    // An index past the vertices.
    let mut bin = b.bin.clone();
    let index_view = b.views[1]["byteOffset"].as_u64().unwrap() as usize;
    bin[index_view] = 8;
    let e = read(&glb(&good, &bin)).unwrap_err().to_string();
    assert!(e.contains("index 0 is 8, but the primitive has 8 vertices"), "{e}");
    // A coordinate that overflows f32 once transformed.
    let e = read(&with(&["nodes", "0", "scale"], json!([1e300, 1.0, 1.0]))).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::Mesh(_)), "{e}");
}

#[test]
fn instancing_beyond_the_budget_is_refused_before_allocating() {
    // A million byte-sized vertices (3 MB), shown by 100 nodes: 100M
    // vertices and 33M triangles (about 14 GB with their trees) asked for by
    // a 3 MB file. The whole scene is counted before any vertex is read.
    let mut b = Builder::default();
    let count = 999_999;
    let position = b.accessor(&vec![0u8; 3 * count], 5121, "VEC3", count, json!({}));
    let nodes: Vec<Value> = (0..100).map(|_| json!({"mesh": 0})).collect();
    let document = json!({"nodes": nodes, "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]});
    let e = read(&b.file(document)).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::MemoryBudget { .. }), "{e}");
    assert!(
        e.to_string()
            .contains("100 mesh instances (99999900 vertices and 33333300 triangles, 100 primitives)"),
        "{e}"
    );
    // Counts that 32-bit vertex numbers cannot hold are refused from the
    // JSON alone, before the accessors (which announce far more than the
    // file holds) are looked at.
    let mut b = Builder::default();
    let position = b.accessor(&[0u8; 3], 5121, "VEC3", 50_000_000, json!({}));
    let nodes: Vec<Value> = (0..100).map(|_| json!({"mesh": 0})).collect();
    let document = json!({"nodes": nodes, "meshes": [{"primitives": [{"attributes": {"POSITION": position}}]}]});
    let e = read(&b.file(document)).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::Syntax(_)), "{e}");
    assert!(
        e.to_string()
            .contains("more than 32-bit vertex numbers and face offsets can address"),
        "{e}"
    );
}

#[test]
fn a_cycle_is_reported_with_or_without_a_scene() {
    // nodes[0] and nodes[1] are each other's child; nodes[2] hangs under
    // nodes[1]; nodes[3] is a root of its own. Without a scene no node of the
    // cycle is a root: it used to be skipped ("the mesh is empty", or a mesh
    // without the cycle's nodes).
    let mut b = Builder::default();
    let position = b.positions(&CUBE[..3]);
    let meshes = json!([{"primitives": [{"attributes": {"POSITION": position}}]}]);
    let nodes = json!([{"mesh": 0, "children": [1]}, {"children": [0, 2]}, {"mesh": 0}, {"mesh": 0}]);
    let expected = "nodes[0] is reached twice: the node hierarchy is not a tree";
    for document in [
        json!({"nodes": nodes, "meshes": meshes}),
        json!({"scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes, "meshes": meshes}),
    ] {
        let e = read(&b.file(document)).unwrap_err();
        assert!(matches!(e.kind, LoadErrorKind::Syntax(_)), "{e}");
        assert!(e.to_string().contains(expected), "{e}");
    }
    // Entered from below the cycle, the walk up finds it all the same.
    let nodes = json!([{"children": [1]}, {"mesh": 0, "children": [2]}, {"children": [1]}]);
    let e = read(&b.file(json!({"nodes": nodes, "meshes": meshes}))).unwrap_err();
    assert!(e.to_string().contains("is reached twice"), "{e}");
    // A scene that leaves the cycle out does not read it.
    let nodes = json!([{"mesh": 0, "children": [1]}, {"children": [0]}, {"mesh": 0}]);
    let document = json!({"scene": 0, "scenes": [{"nodes": [2]}], "nodes": nodes, "meshes": meshes});
    assert_eq!(read(&b.file(document)).unwrap().face_count(), 1);
}

#[test]
fn every_truncation_of_a_valid_file_is_an_error() {
    let file = rich_file();
    let full = read(&file).unwrap();
    assert_eq!(full.face_count(), 12 + 6);
    for length in 0..file.len() {
        let e = read(&file[..length]).expect_err("a truncated file must not load");
        assert!(e.to_string().starts_with("test.glb"), "{e}");
    }
}

#[test]
fn glb_files_load_by_extension_and_gzip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("Cube.GLB");
    std::fs::write(&path, rich_file()).unwrap();
    let mesh = proxima::io::load(&path).unwrap();
    assert_eq!(mesh.face_count(), 18);
    let gz = dir.path().join("cube.glb.gz");
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut encoder, &rich_file()).unwrap();
    std::fs::write(&gz, encoder.finish().unwrap()).unwrap();
    assert_eq!(proxima::io::load(&gz).unwrap().positions(), mesh.positions());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Any bytes changed anywhere (header, JSON, binary): an answer or a typed error.
    #[test]
    fn damaged_files_never_panic(flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8)) {
        let mut file = rich_file();
        for (at, value) in flips {
            let i = at.index(file.len());
            file[i] = value;
        }
        let _ = read(&file);
    }
}

/// Files written by another library (trimesh 4, `fuzz/seeds/*.glb`): a unit box,
/// and a scene of two subdivided icospheres, the second moved by (2, 0, 0).
#[test]
fn files_written_by_trimesh_load() {
    let seeds = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/seeds"));
    let cube = proxima::io::load(seeds.join("box.glb")).unwrap();
    assert_eq!((cube.vertex_count(), cube.face_count()), (8, 12));
    assert_eq!(cube.bounds().min, Vec3::splat(-0.5));
    assert_eq!(cube.bounds().max, Vec3::splat(0.5));
    let spheres = proxima::io::load(seeds.join("two_spheres.glb")).unwrap();
    assert_eq!((spheres.vertex_count(), spheres.face_count()), (84, 160));
    let (first, second) = spheres.positions().split_at(42);
    for (a, b) in first.iter().zip(second) {
        assert!((*b - *a - Vec3::new(2.0, 0.0, 0.0)).abs().max_element() < 1e-6);
        assert!((a.length() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn many_instances_of_many_primitives_are_refused_at_once() {
    // 3,000 empty primitives shown by 3,000 nodes: 9M primitive instances
    // from a file of about 100 KB, refused by counting, not by walking them.
    let primitives: Vec<Value> = (0..3000).map(|_| json!({"attributes": {}})).collect();
    let nodes: Vec<Value> = (0..3000).map(|_| json!({"mesh": 0})).collect();
    let document = json!({"nodes": nodes, "meshes": [{"primitives": primitives}]});
    let e = read(&glb(&document, &[])).unwrap_err().to_string();
    assert!(e.contains("9000000 primitives"), "{e}"); // the count, made before any primitive is read
}
