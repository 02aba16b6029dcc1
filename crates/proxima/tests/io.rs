//! Mesh loaders: every format against meshes written here with known content,
//! every error path with its kind and line, robustness against truncated and
//! corrupted input, and the real meshes of `../shared/data` against the counts
//! and bounding boxes in its README.

use flate2::Compression;
use flate2::write::GzEncoder;
use proxima::io::{Format, load, parse};
use proxima::{LoadError, LoadErrorKind, Mesh, MeshError, Vec3};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------

/// A file in its own fresh temporary directory, removed on drop.
/// A file in a fresh temporary directory (`tempfile`), removed when dropped.
struct TempFile {
    _dir: tempfile::TempDir,
    path: PathBuf,
}

impl TempFile {
    fn new(name: &str, bytes: &[u8]) -> Self {
        let dir = tempfile::Builder::new().prefix("proxima-io-test-").tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        Self { _dir: dir, path }
    }
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = GzEncoder::new(Vec::new(), Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

fn parse_as(bytes: &[u8], format: Format) -> Result<Mesh, LoadError> {
    parse(bytes, format, Path::new("test-input"))
}

fn parse_err(bytes: &[u8], format: Format) -> LoadError {
    match parse_as(bytes, format) {
        Ok(mesh) => panic!(
            "expected an error, got a mesh of {} vertices and {} faces",
            mesh.vertex_count(),
            mesh.face_count()
        ),
        Err(e) => e,
    }
}

/// Checks that `e` is at `line` and that its kind satisfies `kind`.
#[track_caller]
fn assert_error(e: &LoadError, line: Option<usize>, kind: impl Fn(&LoadErrorKind) -> bool) {
    assert!(kind(&e.kind), "unexpected error kind: {e} ({:?})", e.kind);
    assert_eq!(e.line, line, "wrong line for: {e}");
    assert_eq!(e.path, Path::new("test-input"), "wrong path for: {e}");
}

/// A predicate on error kinds.
type KindCheck = fn(&LoadErrorKind) -> bool;
/// Input, expected line, expected kind.
type Case = (String, Option<usize>, KindCheck);

fn is_syntax(k: &LoadErrorKind) -> bool {
    matches!(k, LoadErrorKind::Syntax(_))
}
fn is_truncated(k: &LoadErrorKind) -> bool {
    matches!(k, LoadErrorKind::Truncated(_))
}
fn is_implausible(k: &LoadErrorKind) -> bool {
    matches!(k, LoadErrorKind::Implausible(_))
}
fn is_out_of_range(k: &LoadErrorKind) -> bool {
    matches!(k, LoadErrorKind::Mesh(MeshError::IndexOutOfRange { .. }))
}
fn is_too_small(k: &LoadErrorKind) -> bool {
    matches!(k, LoadErrorKind::Mesh(MeshError::FaceTooSmall { .. }))
}
fn is_non_finite(k: &LoadErrorKind) -> bool {
    matches!(k, LoadErrorKind::Mesh(MeshError::NonFiniteVertex { .. }))
}

/// Compares two meshes vertex by vertex (bitwise) and face by face.
#[track_caller]
fn assert_same_mesh(got: &Mesh, expected: &Mesh, what: &str) {
    assert_eq!(got.vertex_count(), expected.vertex_count(), "{what}: vertex count");
    for (i, (g, e)) in got.positions().iter().zip(expected.positions()).enumerate() {
        assert_eq!(
            g.to_array().map(f32::to_bits),
            e.to_array().map(f32::to_bits),
            "{what}: vertex {i}: {g} vs {e}"
        );
    }
    assert_eq!(got.face_count(), expected.face_count(), "{what}: face count");
    for (f, (g, e)) in got.faces().zip(expected.faces()).enumerate() {
        assert_eq!(g, e, "{what}: face {f}");
    }
    assert_eq!(got, expected, "{what}");
}

/// A mesh as plain data, for the writers below.
struct Data {
    positions: Vec<[f32; 3]>,
    faces: Vec<Vec<u32>>,
}

impl Data {
    fn mesh(&self) -> Mesh {
        Mesh::from_faces(
            self.positions.iter().map(|&p| Vec3::from_array(p)).collect(),
            &self.faces,
        )
        .unwrap()
    }

    /// The triangles of a fan triangulation of every face.
    fn triangles(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        for face in &self.faces {
            for k in 1..face.len() - 1 {
                out.push([face[0], face[k], face[k + 1]]);
            }
        }
        out
    }

    /// What an STL of `triangles()` must load to: corners welded by exact
    /// position, numbered by first use, unused vertices gone.
    fn welded_triangles(&self) -> Mesh {
        let mut positions: Vec<[f32; 3]> = Vec::new();
        let mut faces = Vec::new();
        for t in self.triangles() {
            let face = t.map(|v| {
                let p = self.positions[v as usize].map(|c| if c == 0.0 { 0.0 } else { c });
                match positions.iter().position(|&q| q == p) {
                    Some(i) => i as u32,
                    None => {
                        positions.push(p);
                        positions.len() as u32 - 1
                    }
                }
            });
            faces.push(face.to_vec());
        }
        Data { positions, faces }.mesh()
    }
}

/// A box of 10 vertices (one in the middle of an edge, one unused) and 7 faces:
/// quads, pentagons and triangles, with coordinates that are not round numbers.
fn reference() -> Data {
    let (x0, x1, y0, y1, z0, z1) = (-1.5f32, 2.5, 0.1, 3.7, -0.333, 2.25);
    Data {
        positions: vec![
            [x0, y0, z1],
            [x1, y0, z1],
            [x1, y1, z1],
            [x0, y1, z1],
            [x0, y0, z0],
            [x1, y0, z0],
            [x1, y1, z0],
            [x0, y1, z0],
            [x1, y0, 0.9585],     // 8: middle of edge 1-5
            [1e-3, -7e5, 12.125], // 9: used by no face
        ],
        faces: vec![
            vec![0, 1, 2, 3],
            vec![5, 4, 7, 6],
            vec![4, 5, 8, 1, 0],
            vec![3, 2, 6],
            vec![3, 6, 7],
            vec![4, 0, 3, 7],
            vec![1, 8, 5, 6, 2],
        ],
    }
}

// ---------------------------------------------------------------------------
// Writers (independent of the loaders; each exercises optional syntax)
// ---------------------------------------------------------------------------

fn obj_plain(d: &Data) -> String {
    let mut s = String::new();
    for p in &d.positions {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in &d.faces {
        s += "f";
        for v in f {
            s += &format!(" {}", v + 1);
        }
        s += "\n";
    }
    s
}

/// OBJ with every optional feature: comments, ignored statements, `w` and colour
/// components, all four vertex-reference forms, negative indices, `\r\n`, a
/// continued line, trailing comments.
fn obj_fancy(d: &Data) -> String {
    let n = d.positions.len() as i64;
    let mut s = String::from("# exported for a test\r\nmtllib box.mtl\r\no box\r\n\r\n");
    for (i, p) in d.positions.iter().enumerate() {
        match i % 3 {
            0 => s += &format!("v {} {} {}\r\n", p[0], p[1], p[2]),
            1 => s += &format!("v  {}\t{} {} 1.0\r\n", p[0], p[1], p[2]),
            _ => s += &format!("v {} {} {} 0.5 0.25 1 # coloured\r\n", p[0], p[1], p[2]),
        }
        s += &format!("vt 0.{i} 0.5\r\nvn 0 0 1\r\n");
    }
    s += "g sides\r\nusemtl red\r\ns off\r\n";
    for (k, f) in d.faces.iter().enumerate() {
        s += "f";
        for (j, &v) in f.iter().enumerate() {
            let a = if (k + j) % 2 == 0 {
                (v as i64 + 1).to_string()
            } else {
                (v as i64 - n).to_string()
            };
            s += &match (k + j) % 4 {
                0 => format!(" {a}"),
                1 => format!(" {a}/{}", j + 1),
                2 => format!(" {a}//{}", j + 1),
                _ => format!(" {a}/{}/{}", j + 1, j + 1),
            };
            if k == 2 && j == 1 {
                s += " \\\r\n  "; // continued on the next line
            }
        }
        s += "\r\n";
    }
    s += "l 1 2\r\np 3\r\n# end\r\n";
    s
}

fn off_plain(d: &Data) -> String {
    let mut s = format!("OFF\n# a comment\n\n{} {} 0\n", d.positions.len(), d.faces.len());
    for p in &d.positions {
        s += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    for (k, f) in d.faces.iter().enumerate() {
        s += &f.len().to_string();
        for v in f {
            s += &format!(" {v}");
        }
        if k % 2 == 1 {
            s += " 255 0 0"; // a face colour
        }
        s += "\n";
    }
    s
}

/// COFF with counts on the header line, vertex colours, `\r\n` and end-of-line
/// comments.
fn off_coff(d: &Data) -> String {
    let mut s = format!("COFF {} {} 12 # counts here\r\n", d.positions.len(), d.faces.len());
    for p in &d.positions {
        s += &format!("{} {} {} 0.1 0.2 0.3 1.0\r\n", p[0], p[1], p[2]);
    }
    for f in &d.faces {
        s += &format!(
            "{}  {}\r\n",
            f.len(),
            f.iter().map(|v| v.to_string()).collect::<Vec<_>>().join("  ")
        );
    }
    s
}

/// OFF without its optional header keyword.
fn off_headerless(d: &Data) -> String {
    off_plain(d).replacen("OFF\n", "", 1)
}

/// Ascii PLY: coordinates not first, a double, extra vertex properties, a face
/// property before the list, an extra element, trailing spaces.
fn ply_ascii(d: &Data) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment written by a test\nobj_info nothing\nelement vertex {}\n\
         property float nx\nproperty float x\nproperty double y\nproperty float z\nproperty uchar red\n\
         element face {}\nproperty uchar flags\nproperty list uchar int vertex_indices\n\
         element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n",
        d.positions.len(),
        d.faces.len()
    );
    for p in &d.positions {
        s += &format!("0.5 {} {} {} 255 \n", p[0], p[1], p[2]);
    }
    for f in &d.faces {
        s += &format!("7 {}", f.len());
        for v in f {
            s += &format!(" {v}");
        }
        s += " \n";
    }
    s += "0 1\n1 2\n";
    s
}

struct Bin {
    out: Vec<u8>,
    big_endian: bool,
}

impl Bin {
    fn bytes<const N: usize>(&mut self, le: [u8; N], be: [u8; N]) {
        self.out.extend_from_slice(if self.big_endian { &be } else { &le });
    }
    fn f32(&mut self, v: f32) {
        self.bytes(v.to_le_bytes(), v.to_be_bytes());
    }
    fn f64(&mut self, v: f64) {
        self.bytes(v.to_le_bytes(), v.to_be_bytes());
    }
    fn u8(&mut self, v: u8) {
        self.out.push(v);
    }
    fn i8(&mut self, v: i8) {
        self.out.push(v as u8);
    }
    fn i16(&mut self, v: i16) {
        self.bytes(v.to_le_bytes(), v.to_be_bytes());
    }
    fn u16(&mut self, v: u16) {
        self.bytes(v.to_le_bytes(), v.to_be_bytes());
    }
    fn i32(&mut self, v: i32) {
        self.bytes(v.to_le_bytes(), v.to_be_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.bytes(v.to_le_bytes(), v.to_be_bytes());
    }
}

/// Binary little-endian PLY: float coordinates, colour and confidence
/// properties, an extra element with lists between vertices and faces,
/// `list uchar int` faces.
fn ply_binary_le(d: &Data) -> Vec<u8> {
    let header = format!(
        "ply\r\nformat binary_little_endian 1.0\r\nelement vertex {}\r\nproperty float x\r\nproperty float y\r\n\
         property float z\r\nproperty uchar red\r\nproperty uint8 green\r\nproperty uchar blue\r\n\
         property float confidence\r\nelement material 2\r\nproperty list uint8 float32 values\r\n\
         element face {}\r\nproperty list uchar int vertex_indices\r\nend_header\r\n",
        d.positions.len(),
        d.faces.len()
    );
    let mut b = Bin {
        out: header.into_bytes(),
        big_endian: false,
    };
    for p in &d.positions {
        p.iter().for_each(|&c| b.f32(c));
        b.u8(1);
        b.u8(2);
        b.u8(3);
        b.f32(0.75);
    }
    for m in 0..2u8 {
        b.u8(m + 2);
        (0..m + 2).for_each(|k| b.f32(k as f32));
    }
    for f in &d.faces {
        b.u8(f.len() as u8);
        f.iter().for_each(|&v| b.i32(v as i32));
    }
    b.out
}

/// Binary big-endian PLY: double coordinates interleaved with other types, a
/// list property on vertices, a face property before `list ushort uint
/// vertex_index`, an extra element after the faces.
fn ply_binary_be(d: &Data) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_big_endian 1.0\nelement vertex {}\nproperty float64 x\nproperty ushort tag\n\
         property double y\nproperty double z\nproperty list uchar float extras\nelement face {}\n\
         property int32 id\nproperty list uint16 uint32 vertex_index\nelement edge 1\nproperty int8 a\n\
         property int16 b\nend_header\n",
        d.positions.len(),
        d.faces.len()
    );
    let mut b = Bin {
        out: header.into_bytes(),
        big_endian: true,
    };
    for (i, p) in d.positions.iter().enumerate() {
        b.f64(p[0] as f64);
        b.u16(0xBEEF);
        b.f64(p[1] as f64);
        b.f64(p[2] as f64);
        b.u8((i % 3) as u8);
        (0..i % 3).for_each(|k| b.f32(k as f32));
    }
    for (k, f) in d.faces.iter().enumerate() {
        b.i32(-(k as i32));
        b.u16(f.len() as u16);
        f.iter().for_each(|&v| b.u32(v));
    }
    b.i8(-1);
    b.i16(-2);
    b.out
}

/// Binary STL of the fan triangulation; the header starts with `solid` (as many
/// exporters write) to check that the size decides.
fn stl_binary(d: &Data) -> Vec<u8> {
    let triangles = d.triangles();
    let mut out = b"solid but binary".to_vec();
    out.resize(80, b' ');
    out.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        out.extend_from_slice(&[0u8; 12]);
        for v in t {
            for c in d.positions[v as usize] {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

fn stl_ascii(d: &Data) -> String {
    let mut s = String::from("solid test mesh\n");
    for t in d.triangles() {
        s += "  facet normal 0 0 1\n    outer loop\n";
        for v in t {
            let p = d.positions[v as usize];
            s += &format!("      vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        s += "    endloop\n  endfacet\n";
    }
    s += "endsolid test mesh\n";
    s
}

// ---------------------------------------------------------------------------
// Content of each format
// ---------------------------------------------------------------------------

#[test]
fn every_format_loads_the_reference_mesh() {
    let d = reference();
    let expected = d.mesh();
    assert_eq!(expected.vertex_count(), 10);
    assert_eq!(expected.face_count(), 7);
    assert_eq!(expected.triangle_count(), 14);
    let cases: Vec<(&str, Format, Vec<u8>)> = vec![
        ("obj plain", Format::Obj, obj_plain(&d).into_bytes()),
        ("obj fancy", Format::Obj, obj_fancy(&d).into_bytes()),
        ("off plain", Format::Off, off_plain(&d).into_bytes()),
        ("off coff", Format::Off, off_coff(&d).into_bytes()),
        ("off headerless", Format::Off, off_headerless(&d).into_bytes()),
        ("ply ascii", Format::Ply, ply_ascii(&d).into_bytes()),
        ("ply binary le", Format::Ply, ply_binary_le(&d)),
        ("ply binary be", Format::Ply, ply_binary_be(&d)),
    ];
    for (what, format, bytes) in &cases {
        let mesh = parse_as(bytes, *format).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_same_mesh(&mesh, &expected, what);
    }
    // STL has no shared vertices: corners are welded by position.
    let welded = d.welded_triangles();
    assert_eq!(welded.vertex_count(), 9, "the unused vertex is gone");
    assert_eq!(welded.face_count(), 14);
    for (what, bytes) in [
        ("stl binary", stl_binary(&d)),
        ("stl ascii", stl_ascii(&d).into_bytes()),
    ] {
        let mesh = parse_as(&bytes, Format::Stl).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_same_mesh(&mesh, &welded, what);
    }
}

#[test]
fn load_picks_the_format_by_extension_and_gunzips() {
    let d = reference();
    let expected = d.mesh();
    let welded = d.welded_triangles();
    let files: Vec<(&str, Vec<u8>, &Mesh)> = vec![
        ("box.obj", obj_fancy(&d).into_bytes(), &expected),
        ("box.OBJ", obj_plain(&d).into_bytes(), &expected),
        ("box.off", off_plain(&d).into_bytes(), &expected),
        ("box.ply", ply_ascii(&d).into_bytes(), &expected),
        ("box.Ply", ply_binary_le(&d), &expected),
        ("box.ply", ply_binary_be(&d), &expected),
        ("box.stl", stl_binary(&d), &welded),
        ("box.STL", stl_ascii(&d).into_bytes(), &welded),
    ];
    for (name, bytes, expected) in &files {
        let plain = TempFile::new(name, bytes);
        assert_same_mesh(&load(&plain.path).unwrap_or_else(|e| panic!("{e}")), expected, name);
        for suffix in [".gz", ".GZ"] {
            let gz_name = format!("{name}{suffix}");
            let compressed = TempFile::new(&gz_name, &gzip(bytes));
            assert_same_mesh(
                &load(&compressed.path).unwrap_or_else(|e| panic!("{e}")),
                expected,
                &gz_name,
            );
        }
    }
    // Several gzip members are read as one stream.
    let text = obj_plain(&d);
    let (a, b) = text.split_at(text.len() / 2);
    let mut two_members = gzip(a.as_bytes());
    two_members.extend(gzip(b.as_bytes()));
    let file = TempFile::new("two.obj.gz", &two_members);
    assert_same_mesh(&load(&file.path).unwrap(), &expected, "two gzip members");
}

#[test]
fn format_from_path() {
    assert_eq!(Format::from_path("a/b/mesh.obj"), Some(Format::Obj));
    assert_eq!(Format::from_path("mesh.PLY"), Some(Format::Ply));
    assert_eq!(Format::from_path("mesh.stl.gz"), Some(Format::Stl));
    assert_eq!(Format::from_path("mesh.v2.Off.Gz"), Some(Format::Off));
    assert_eq!(Format::from_path("mesh.gz"), None);
    assert_eq!(Format::from_path("mesh.gltf"), None);
    assert_eq!(Format::from_path("mesh.obj.zip"), None);
    assert_eq!(Format::from_path("obj"), None);
    for format in [Format::Obj, Format::Ply, Format::Stl, Format::Off] {
        assert_eq!(Format::from_path(format!("x.{}", format.extension())), Some(format));
    }
}

#[test]
fn load_errors_name_the_path() {
    let missing = std::env::temp_dir().join("proxima-io-test-surely-missing/nothing.obj");
    let e = load(&missing).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::Io(_)), "{e}");
    assert_eq!(e.path, missing);
    assert!(e.to_string().contains("nothing.obj"), "{e}");

    let file = TempFile::new("mesh.gltf", b"{}");
    let e = load(&file.path).unwrap_err();
    assert!(matches!(e.kind, LoadErrorKind::UnknownFormat), "{e}");
    assert_eq!(e.path, file.path);

    // A corrupt gzip stream, a truncated one, and plain text named .gz.
    let good = gzip(obj_plain(&reference()).as_bytes());
    let mut corrupt = good.clone();
    let middle = corrupt.len() / 2;
    corrupt[middle..middle + 8].copy_from_slice(b"\xff\x00\xff\x00garb");
    let truncated = good[..good.len() - 20].to_vec();
    for (name, bytes) in [
        ("c.obj.gz", corrupt),
        ("t.obj.gz", truncated),
        ("p.obj.gz", b"v 0 0 0\n".to_vec()),
    ] {
        let file = TempFile::new(name, &bytes);
        match load(&file.path) {
            Err(e) => {
                assert_eq!(e.path, file.path, "{e}");
                assert!(e.to_string().contains(name), "{e}");
            }
            Ok(_) => panic!("{name}: a damaged gzip file loaded"),
        }
    }

    // Display is `path:line: message`.
    let file = TempFile::new("bad.obj", b"v 0 0 0\nv 1 zero 0\n");
    let e = load(&file.path).unwrap_err();
    assert_eq!(e.to_string(), format!("{}:2: bad number `zero`", file.path.display()));
}

// ---------------------------------------------------------------------------
// OBJ
// ---------------------------------------------------------------------------

#[test]
fn obj_negative_indices_are_relative_to_the_vertices_so_far() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\nvt 0 0\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0\nf 2/1 -1//3 3/1/1\n";
    let mesh = parse_as(text.as_bytes(), Format::Obj).unwrap();
    let faces: Vec<&[u32]> = mesh.faces().collect();
    assert_eq!(faces, [&[0, 1, 2][..], &[1, 3, 2], &[1, 3, 2]]);
}

#[test]
fn obj_forward_references_resolve_at_the_end() {
    let mesh = parse_as(b"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", Format::Obj).unwrap();
    assert_eq!(mesh.face(0), &[0, 1, 2]);
    // The first face whose reference stays unresolved is reported.
    let e = parse_err(
        b"f 1 2 3\nf 1 2 9\nf 1 2 5\nf 1 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\n",
        Format::Obj,
    );
    assert_error(&e, Some(2), is_out_of_range);
    assert!(matches!(
        e.kind,
        LoadErrorKind::Mesh(MeshError::IndexOutOfRange {
            face: 1,
            vertex: 8,
            vertex_count: 4
        })
    ));
}

#[test]
fn obj_unused_vertices_extra_components_and_empty_files() {
    let mesh = parse_as(b"v 1 2 3 4\nv 5 6 7 0.1 0.2 0.3\n", Format::Obj).unwrap();
    assert_eq!(mesh.positions(), &[Vec3::new(1.0, 2.0, 3.0), Vec3::new(5.0, 6.0, 7.0)]);
    assert_eq!(mesh.face_count(), 0);
    let bom = parse_as(b"\xEF\xBB\xBFv 1 2 3\n", Format::Obj).unwrap();
    assert_eq!(bom.positions(), &[Vec3::new(1.0, 2.0, 3.0)]);
    let empty = parse_as(b"", Format::Obj).unwrap();
    assert!(empty.is_empty());
    let comments = parse_as(b"# nothing\n\n   \n# more\n", Format::Obj).unwrap();
    assert!(comments.is_empty());
}

#[test]
fn obj_errors_carry_kind_and_line() {
    let head = "# header\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"; // lines 1-4; line 5 is the bad one
    let cases: [(&str, KindCheck); 16] = [
        ("v 1 x 3\n", is_syntax),       // bad number
        ("v 1 2\n", is_syntax),         // missing coordinate
        ("v\n", is_syntax),             // no coordinates at all
        ("v 1 2 3e\n", is_syntax),      // malformed exponent
        ("f 1 2 0\n", is_syntax),       // index 0
        ("f 1 2 x\n", is_syntax),       // not an index
        ("f 1 2 /3\n", is_syntax),      // empty vertex reference
        ("f 1 2 5\n", is_out_of_range), // beyond the last vertex
        ("f 1 2 99999999999\n", is_out_of_range),
        ("f -1 -2 -4\n", is_syntax), // relative index before the first vertex
        ("f 1 2\n", is_too_small),
        ("f\n", is_too_small),
        ("v nan 0 0\n", is_non_finite),
        ("v 0 -inf 0\n", is_non_finite),
        ("v 0 0 1e999\n", is_non_finite), // overflows f32
        ("1 2 3\n", is_syntax),           // not a statement
    ];
    for (bad, kind) in cases {
        let text = format!("{head}{bad}v 5 5 5\nf 1 2 3\n");
        let e = parse_err(text.as_bytes(), Format::Obj);
        assert_error(&e, Some(5), kind);
    }
    let e = parse_err(format!("{head}v inf 0 0\n").as_bytes(), Format::Obj);
    assert!(
        matches!(e.kind, LoadErrorKind::Mesh(MeshError::NonFiniteVertex { index: 3 })),
        "{e}"
    );
    let e = parse_err(format!("{head}f 1 2 3\nf 3 1\n").as_bytes(), Format::Obj);
    assert!(
        matches!(e.kind, LoadErrorKind::Mesh(MeshError::FaceTooSmall { face: 1, len: 2 })),
        "{e}"
    );
    // Line numbers count `\r\n` lines, and a continued line reports its first line.
    let e = parse_err(b"v 0 0 0\r\nv 1 0 0\r\nf 1 \\\r\n 2 \\\r\n 3\r\n", Format::Obj);
    assert_error(&e, Some(3), is_out_of_range);
    let e = parse_err(b"v 0 0 0\r\n\r\n\r\nv 1 0 q\r\n", Format::Obj);
    assert_error(&e, Some(4), is_syntax);
}

// ---------------------------------------------------------------------------
// OFF
// ---------------------------------------------------------------------------

#[test]
fn off_errors_carry_kind_and_line() {
    let long = "0.000000000 0.000000000 0.000000000"; // long lines keep the size check quiet
    let cases: Vec<Case> = vec![
        ("PLY\n3 1 0\n".into(), Some(1), is_syntax),
        ("4OFF\n3 1 0\n".into(), Some(1), is_syntax),
        ("OFF BINARY\n3 1 0\n".into(), Some(1), is_syntax),
        ("OFF\n3\n".into(), Some(2), is_syntax),
        ("OFF\n3 x 0\n".into(), Some(2), is_syntax),
        ("OFF\n-3 1 0\n".into(), Some(2), is_syntax),
        ("".into(), Some(1), is_truncated),
        ("OFF\n# only a header\n".into(), Some(2), is_truncated),
        // Too few vertices / faces: the error is at the last line of the file.
        (format!("OFF\n3 1 0\n{long}\n{long}\n"), Some(4), is_truncated),
        (
            format!("OFF\n3 2 0\n{long}\n{long}\n{long}\n3 0 1 2\n\n"),
            Some(7),
            is_truncated,
        ),
        // Header counts the remaining bytes cannot hold.
        ("OFF\n1000000000000 1 0\n0 0 0\n".into(), Some(2), is_implausible),
        (
            "OFF\n3 99999999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".into(),
            Some(2),
            is_implausible,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n0 1 y\n{long}\n3 0 1 2\n"),
            Some(4),
            is_syntax,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n0 1\n{long}\n3 0 1 2\n"),
            Some(4),
            is_syntax,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n0 nan 0\n3 0 1 2\n"),
            Some(5),
            is_non_finite,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n{long}\n3 0 1 3\n"),
            Some(6),
            is_out_of_range,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n{long}\n3 0 -1 2\n"),
            Some(6),
            is_syntax,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n{long}\n2 0 1\n"),
            Some(6),
            is_too_small,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n{long}\n4 0 1 2\n"),
            Some(6),
            is_syntax,
        ),
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n{long}\nx 0 1 2\n"),
            Some(6),
            is_syntax,
        ),
        // More faces than announced.
        (
            format!("OFF\n3 1 0\n{long}\n{long}\n{long}\n3 0 1 2\n3 0 1 2\n"),
            Some(7),
            is_syntax,
        ),
    ];
    for (text, line, kind) in &cases {
        let e = parse_err(text.as_bytes(), Format::Off);
        assert_error(&e, *line, kind);
    }
    // Trailing blank lines and comments are fine.
    let mesh = parse_as(
        format!("OFF\n3 1 0\n{long}\n{long}\n{long}\n3 0 1 2\n\n# done\n  \n").as_bytes(),
        Format::Off,
    );
    assert_eq!(mesh.unwrap().face_count(), 1);
}

// ---------------------------------------------------------------------------
// PLY
// ---------------------------------------------------------------------------

const PLY_ASCII_HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                              property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

#[test]
fn ply_integer_coordinates_and_no_faces() {
    let text = "ply\nformat ascii 1.0\nelement vertex 2\nproperty short x\nproperty uint16 y\nproperty char z\n\
                end_header\n-3 65535 -128\n1 2 3\n";
    let mesh = parse_as(text.as_bytes(), Format::Ply).unwrap();
    assert_eq!(
        mesh.positions(),
        &[Vec3::new(-3.0, 65535.0, -128.0), Vec3::new(1.0, 2.0, 3.0)]
    );
    let mut b = Bin {
        out: text
            .replace("ascii", "binary_big_endian")
            .split_inclusive("end_header\n")
            .next()
            .unwrap()
            .as_bytes()
            .to_vec(),
        big_endian: true,
    };
    for (x, y, z) in [(-3i16, 65535u16, -128i8), (1, 2, 3)] {
        b.i16(x);
        b.u16(y);
        b.i8(z);
    }
    assert_same_mesh(
        &parse_as(&b.out, Format::Ply).unwrap(),
        &mesh,
        "binary integer coordinates",
    );
    // Elements split over lines are read as one; but each ends its line, so
    // that a value too many is blamed on its own line, not on a later one.
    let split = format!("{PLY_ASCII_HEAD}0 0\n0\n1 0\n0\n0 1 0\n3 0 1\n2\n");
    assert_eq!(parse_as(split.as_bytes(), Format::Ply).unwrap().face(0), &[0, 1, 2]);
    let shared = format!("{PLY_ASCII_HEAD}0 0\n0 1 0 0 0\n1\n0 3 0 1\n2\n");
    let e = parse_as(shared.as_bytes(), Format::Ply).unwrap_err();
    assert_eq!(e.line, Some(11), "{e}");
}

#[test]
fn ply_errors_carry_kind_and_line() {
    let data = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"; // lines 10-13
    let header = |replace: &str, with: &str| PLY_ASCII_HEAD.replacen(replace, with, 1);
    let cases: Vec<Case> = vec![
        (format!("plx\n{}", &PLY_ASCII_HEAD[4..]), Some(1), is_syntax),
        (header("ascii", "binary_middle_endian"), Some(2), is_syntax),
        (header("format ascii 1.0", "format ascii"), Some(2), is_syntax),
        (header("format ascii 1.0\n", ""), Some(8), is_syntax),
        (header("float y", "float3 y"), Some(5), is_syntax),
        (header("property float x\n", ""), Some(3), is_syntax),
        (
            header("element vertex 3\n", "property int q\nelement vertex 3\n"),
            Some(3),
            is_syntax,
        ),
        (
            header("element vertex 3\n", "element vertex three\n"),
            Some(3),
            is_syntax,
        ),
        (header("element vertex 3\n", "element vertex -3\n"), Some(3), is_syntax),
        (header("list uchar int", "list float int"), Some(8), is_syntax),
        (header("list uchar int", "list uchar float"), Some(7), is_syntax),
        (header("vertex_indices", "vertices"), Some(7), is_syntax),
        (header("end_header", "end_header_please"), Some(9), is_syntax),
        (header("end_header\n", ""), Some(8), is_truncated),
        (
            header(
                "element face 1\n",
                "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n",
            ),
            Some(7),
            is_syntax,
        ),
        // Data errors, on the line of the offending value.
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0x\n0 1 0\n3 0 1 2\n"),
            Some(11),
            is_syntax,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"),
            Some(12),
            is_non_finite,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
            Some(13),
            is_out_of_range,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
            Some(13),
            is_syntax,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 one 2\n"),
            Some(13),
            is_syntax,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
            Some(13),
            is_too_small,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n"),
            Some(13),
            is_syntax,
        ),
        (
            format!("{PLY_ASCII_HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n"),
            Some(13),
            is_syntax,
        ),
        (
            format!("{PLY_ASCII_HEAD}0.000000000 0.000000000 0.0000000000\n1 0 0\n0 1 0\n\n"),
            Some(13),
            is_truncated,
        ),
        (
            format!("{PLY_ASCII_HEAD}0.000000000 0.000000000 0.0000000000\n1 0 0\n0 1 0\n3 0 1"),
            Some(13),
            is_truncated,
        ),
        (format!("{PLY_ASCII_HEAD}0 0 0\n"), Some(3), is_implausible),
    ];
    for (text, line, kind) in &cases {
        let e = parse_err(text.as_bytes(), Format::Ply);
        assert_error(&e, *line, kind);
    }
    assert!(parse_as(format!("{PLY_ASCII_HEAD}{data}").as_bytes(), Format::Ply).is_ok());
}

#[test]
fn ply_binary_errors() {
    let d = reference();
    let le = ply_binary_le(&d);
    let header_len = le.windows(12).position(|w| w == b"end_header\r\n").unwrap() + 12;
    // Cut anywhere in the data: Truncated (or Implausible when the remaining bytes
    // cannot even hold the minimum sizes), never a panic or a mesh.
    for cut in header_len..le.len() {
        let e = parse_err(&le[..cut], Format::Ply);
        match e.kind {
            LoadErrorKind::Truncated(_) => assert_eq!(e.line, None, "binary data has no lines"),
            LoadErrorKind::Implausible(_) => assert!(e.line.is_some(), "the line of the element"),
            _ => panic!("cut at {cut}: {e}"),
        }
    }
    // The last face's last index cut off: the sizes pass, the data ends early.
    let e = parse_err(&le[..le.len() - 1], Format::Ply);
    assert_error(&e, None, is_truncated);

    // An index out of range and a negative one.
    let mut bad = le.clone();
    let last = bad.len() - 4;
    bad[last..].copy_from_slice(&10i32.to_le_bytes());
    assert_error(&parse_err(&bad, Format::Ply), None, is_out_of_range);
    bad[last..].copy_from_slice(&(-1i32).to_le_bytes());
    assert_error(&parse_err(&bad, Format::Ply), None, is_syntax);
    // A NaN coordinate.
    let mut bad = le.clone();
    bad[header_len..header_len + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_error(&parse_err(&bad, Format::Ply), None, is_non_finite);
    // A list length beyond the data.
    let be = ply_binary_be(&d);
    let header_len = be.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let mut bad = be.clone();
    bad[header_len + 8 + 2 + 16] = 200; // the extras list of vertex 0
    assert_error(&parse_err(&bad, Format::Ply), None, is_truncated);
}

#[test]
fn ply_huge_counts_fail_fast_without_allocating() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 0 0\n";
    let binary = ascii.replace("ascii", "binary_little_endian");
    let faces = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\nend_header\n";
    let max_count = "ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\n\
                   property double x\nproperty double y\nproperty double z\nend_header\n";
    let mut faces = faces.as_bytes().to_vec();
    faces.extend_from_slice(&[0; 36 + 20]); // the vertices and a few bytes
    for (text, line) in [
        (ascii.as_bytes(), 3),
        (binary.as_bytes(), 3),
        (&faces, 7),
        (max_count.as_bytes(), 3),
    ] {
        let start = Instant::now();
        let e = parse_err(text, Format::Ply);
        assert!(
            start.elapsed() < Duration::from_millis(100),
            "took {:?}",
            start.elapsed()
        );
        assert_error(&e, Some(line), is_implausible);
    }
    // Counts that are exactly what the data holds are fine, even empty ones.
    let empty = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                 property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
    assert!(parse_as(empty.as_bytes(), Format::Ply).unwrap().is_empty());
    // An element without properties takes no bytes, however many there are.
    let nothing = format!(
        "{}element nothing 1000000000000\nend_header\n",
        &empty[..empty.len() - 11]
    );
    assert!(parse_as(nothing.as_bytes(), Format::Ply).unwrap().is_empty());
}

// ---------------------------------------------------------------------------
// STL
// ---------------------------------------------------------------------------

#[test]
fn stl_welds_exactly_equal_positions_only() {
    // Two triangles sharing an edge; the second writes 0.0 as -0.0, and a third
    // triangle has a corner one ulp away from a shared one.
    let p = |x: f32, y: f32| format!("vertex {x:?} {y:?} 0\n");
    let text = format!(
        "solid s\nfacet normal 0 0 1\nouter loop\n{}{}{}endloop\nendfacet\n\
         facet normal 0 0 1\nouter loop\n{}{}{}endloop\nendfacet\n\
         facet normal 0 0 1\nouter loop\n{}{}{}endloop\nendfacet\nendsolid s\n",
        p(0.0, 0.0),
        p(1.0, 0.0),
        p(0.0, 1.0),
        p(1.0, -0.0),
        p(1.0, 1.0),
        p(-0.0, 1.0),
        p(1.0, 1.0),
        p(f32::from_bits(1.0f32.to_bits() + 1), 1.0),
        p(1.0, 2.0),
    );
    let mesh = parse_as(text.as_bytes(), Format::Stl).unwrap();
    assert_eq!(mesh.vertex_count(), 6);
    let faces: Vec<&[u32]> = mesh.faces().collect();
    assert_eq!(faces, [&[0, 1, 2][..], &[1, 3, 2], &[3, 4, 5]]);
    assert_eq!(mesh.positions()[1].y.to_bits(), 0, "the first spelling (+0.0) is kept");
}

#[test]
fn stl_ascii_variants() {
    // Upper-case keywords, several solids, nameless endsolid, a quad loop.
    let text = "SOLID a\nFACET NORMAL 0 0 0\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\nVERTEX 0 1 0\nENDLOOP\nENDFACET\n\
                ENDSOLID\nsolid b\nfacet normal nan nan nan\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n\
                vertex 0 1 0\nendloop\nendfacet\nendsolid b";
    let mesh = parse_as(text.as_bytes(), Format::Stl).unwrap();
    let faces: Vec<&[u32]> = mesh.faces().collect();
    assert_eq!(faces, [&[0, 1, 2][..], &[0, 1, 3, 2]]);
    assert_eq!(
        parse_as(b"solid empty\nendsolid empty\n", Format::Stl)
            .unwrap()
            .vertex_count(),
        0
    );
}

#[test]
fn stl_errors() {
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let cases: Vec<Case> = vec![
        (format!("solid x\n{facet}"), Some(8), is_truncated),
        (format!("solid x\n{}", &facet[..facet.len() - 9]), Some(7), is_truncated),
        (
            format!("solid x\n{}endsolid\n", facet.replace("outer", "inner")),
            Some(3),
            is_syntax,
        ),
        (
            format!("solid x\n{}endsolid\n", facet.replace("1 0 0", "1 zero 0")),
            Some(5),
            is_syntax,
        ),
        (
            format!("solid x\n{}endsolid\n", facet.replace("1 0 0", "1 inf 0")),
            Some(5),
            is_non_finite,
        ),
        (
            format!("solid x\n{}endsolid\n", facet.replace("vertex 0 1 0\n", "")),
            Some(3),
            is_too_small,
        ),
        (
            format!("solid x\n{}endsolid\n", facet.replace("vertex 0 1 0", "vortex 0 1 0")),
            Some(6),
            is_syntax,
        ),
        (format!("solid x\n{facet}endsolid\nfacet\n"), Some(10), is_syntax),
        (format!("solid x\n{facet}facets\n"), Some(9), is_syntax),
        // Short of the binary header.
        ("solo".to_string(), None, is_truncated),
        (String::new(), None, is_truncated),
    ];
    for (text, line, kind) in &cases {
        assert_error(&parse_err(text.as_bytes(), Format::Stl), *line, kind);
    }
    // Binary: a count beyond the data, and a NaN corner.
    let good = stl_binary(&reference());
    let mut more = good.clone();
    more[80..84].copy_from_slice(&1000u32.to_le_bytes());
    assert_error(&parse_err(&more, Format::Stl), None, is_truncated);
    more[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_error(&parse_err(&more, Format::Stl), None, is_truncated);
    // Starts with "solid" but holds NUL bytes: still binary.
    assert_error(&parse_err(&good[..good.len() - 1], Format::Stl), None, is_truncated);
    let mut binary = good.clone();
    binary.extend_from_slice(b"padding");
    assert_eq!(
        parse_as(&binary, Format::Stl).unwrap().face_count(),
        14,
        "extra bytes after the triangles"
    );
    let mut nan = good.clone();
    nan[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_error(&parse_err(&nan, Format::Stl), None, is_non_finite);
}

// ---------------------------------------------------------------------------
// Robustness: nothing panics on damaged input
// ---------------------------------------------------------------------------

#[test]
fn truncated_and_corrupted_inputs_never_panic() {
    let d = reference();
    let inputs: Vec<(Format, Vec<u8>)> = vec![
        (Format::Obj, obj_fancy(&d).into_bytes()),
        (Format::Off, off_coff(&d).into_bytes()),
        (Format::Ply, ply_ascii(&d).into_bytes()),
        (Format::Ply, ply_binary_le(&d)),
        (Format::Ply, ply_binary_be(&d)),
        (Format::Stl, stl_binary(&d)),
        (Format::Stl, stl_ascii(&d).into_bytes()),
    ];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut random = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for (format, bytes) in &inputs {
        for cut in 0..bytes.len() {
            let _ = parse_as(&bytes[..cut], *format);
        }
        for _ in 0..2000 {
            let mut damaged = bytes.clone();
            for _ in 0..1 + random() % 4 {
                let at = (random() % damaged.len() as u64) as usize;
                damaged[at] = match random() % 4 {
                    0 => random() as u8,
                    1 => b"0123456789-"[(random() % 11) as usize],
                    2 => b' ',
                    _ => 0xff,
                };
            }
            if let Ok(mesh) = parse_as(&damaged, *format) {
                // Whatever loads satisfies the mesh invariants.
                assert!(mesh.positions().iter().all(|p| p.is_finite()));
                assert!(
                    mesh.faces()
                        .all(|f| f.len() >= 3 && f.iter().all(|&v| (v as usize) < mesh.vertex_count()))
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Real meshes
// ---------------------------------------------------------------------------

/// File, vertices, faces, triangles, bounding box min and max, from `../shared/data/README.md`.
#[allow(clippy::type_complexity)]
const REAL: [(&str, usize, usize, usize, [f32; 3], [f32; 3]); 12] = [
    (
        "bunny-npm.obj",
        1839,
        3674,
        3674,
        [-4.95847, -0.003149, -3.72983],
        [4.94885, 9.65475, 3.81064],
    ),
    (
        "spot_quadrangulated.obj",
        2930,
        2928,
        5856,
        [-0.471552, -0.736784, -0.668909],
        [0.471552, 0.953646, 1.049],
    ),
    (
        "spot_triangulated.obj",
        2930,
        5856,
        5856,
        [-0.471552, -0.736784, -0.668909],
        [0.471552, 0.953646, 1.049],
    ),
    ("teapot.obj", 3644, 6320, 6320, [-3.0, 0.0, -2.0], [3.434, 3.15, 2.0]),
    (
        "fandisk.obj",
        6475,
        12946,
        12946,
        [0.0, 12.6055, -2.68026],
        [4.8279, 17.85, 0.0],
    ),
    (
        "blade.off",
        8231,
        16222,
        16222,
        [-5.98992, 12.9959, 1.43743],
        [4.0083, 142.182, 2.08567],
    ),
    (
        "rocker-arm.obj",
        10044,
        20088,
        20088,
        [-0.151733, -0.257456, -0.5],
        [0.151733, 0.257456, 0.5],
    ),
    (
        "beast.obj",
        32311,
        32364,
        64618,
        [-136.888, -0.869426, -29.6748],
        [136.888, 251.326, 86.8523],
    ),
    (
        "stanford-bunny.obj",
        35947,
        69451,
        69451,
        [-0.09469, 0.032987, -0.061874],
        [0.061009, 0.187321, 0.0588],
    ),
    (
        "nefertiti.obj",
        49971,
        99938,
        99938,
        [-119.323, -181.293, -247.268],
        [119.363, 181.241, 247.337],
    ),
    (
        "dragon_vrip_res2.ply",
        100250,
        202520,
        202520,
        [-0.108188, 0.0527392, -0.0503454],
        [0.0964062, 0.197139, 0.0411367],
    ),
    (
        "dragon_vrip.ply.gz",
        437645,
        871414,
        871414,
        [-0.108324, 0.0527295, -0.0504143],
        [0.0965662, 0.197173, 0.0412075],
    ),
];

#[test]
fn real_meshes_match_the_readme() {
    // `PROXIMA_DATA_DIR` when set, else ../shared/data beside the checkout.
    let dir = std::env::var_os("PROXIMA_DATA_DIR").map_or_else(
        || PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/data")),
        PathBuf::from,
    );
    if !dir.is_dir() {
        println!("skipped: ../shared/data not found");
        return;
    }
    for (name, vertices, faces, triangles, min, max) in REAL {
        let path = dir.join(name);
        let start = Instant::now();
        let mesh = load(&path).unwrap_or_else(|e| panic!("{e}"));
        println!(
            "{name}: {} vertices, {} faces in {:?}",
            mesh.vertex_count(),
            mesh.face_count(),
            start.elapsed()
        );
        assert_eq!(mesh.vertex_count(), vertices, "{name}: vertices");
        assert_eq!(mesh.face_count(), faces, "{name}: faces");
        assert_eq!(mesh.triangle_count(), triangles, "{name}: triangles");
        let bounds = mesh.bounds();
        let (min, max) = (Vec3::from_array(min), Vec3::from_array(max));
        // The README rounds to 6 significant digits; compare relative to the box size.
        let tolerance = 1e-4 * (max - min).max_element();
        for (got, expected) in [(bounds.min, min), (bounds.max, max)] {
            assert!(
                (got - expected).abs().max_element() <= tolerance,
                "{name}: bounds {bounds:?}, expected {min} – {max}"
            );
        }
    }
}
