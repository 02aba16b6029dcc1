//! Binary glTF 2.0 (`.glb`): the triangles of a scene, with the nodes'
//! transforms applied, as one mesh.
//!
//! The container (a 12-byte header, a JSON chunk, an optional binary chunk) and
//! the accessors are read here with every offset checked; the JSON itself is
//! parsed by serde_json (depth-limited, so no input can exhaust the stack),
//! keeping only the members this reader uses: any other (`extras`, `asset`,
//! materials, animations, …) is skipped as it is parsed (serde's
//! `IgnoredAny`), whatever its size, and what is kept is counted against the
//! memory budget as it is built.
//!
//! What is read: the scene that `scene` names (else the first; with no scene,
//! the nodes that are no node's child; with no node, every mesh as it is);
//! each node's `matrix` or `translation`/`rotation`/`scale`, composed from the
//! root in f64; the primitives of mode 4 (triangles), 5 (strip) and 6 (fan),
//! their `POSITION` (float, or the integer types of `KHR_mesh_quantization`,
//! normalized or not) and `indices` (unsigned 8, 16 or 32 bits, or none);
//! `NORMAL` (turned by the node's transform, inverse transposed) and
//! `TEXCOORD_0`, kept per face corner when every primitive read has them.
//! Points and lines (modes 0 to 3) are skipped. Each primitive of each node
//! that shows it adds its own vertices (nothing is welded), so an instanced
//! mesh appears once per node, in place.
//!
//! A triangle primitive compressed with `KHR_draco_mesh_compression` (with
//! the `draco` feature, on by default) is decoded from its buffer view by
//! `io/draco.rs`: its accessors hold only counts and types, which the
//! decoded stream must meet exactly, and its `POSITION`, `NORMAL` and
//! `TEXCOORD_0` are those the extension maps to Draco attribute ids; from
//! then on it is read as any primitive (node transforms, normals turned). It
//! may decode to at most the attribute bytes the memory budget leaves once
//! the whole mesh is counted. It is decoded again for each node that shows
//! it. Refused, naming the primitive: a stream that does not decode (`…:
//! Draco data: <why>`), other counts than its accessors', an attribute
//! stored uncompressed beside the stream, no `indices`, a mode other than 4;
//! without the feature, every such primitive.
//!
//! Refused, each with a message naming the JSON element: meshopt-compressed
//! geometry (`EXT_meshopt_compression`), sparse
//! accessors, buffers outside the file (a `uri`), a node hierarchy that is not
//! a tree (a cycle is found whether a scene names the roots or not), offsets
//! or sizes past their buffer, and indices past the vertices. Scenes whose
//! instances add up to more vertices and triangles than the memory budget
//! holds (at the bytes per vertex and per triangle of [`crate::budget`],
//! counted from the accessors before anything is expanded: a small primitive
//! shown by many nodes is cheap to write and dear to read) are a
//! [`LoadErrorKind::MemoryBudget`].

use super::read::Budget;
use super::text::{syntax, truncated};
use crate::error::{LoadError, LoadErrorKind};
use crate::math::Vec3;
use crate::mesh::Mesh;
use glam::{DMat4, DQuat, DVec3};
use serde::de::{DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::Value;
use std::borrow::Cow;
use std::cell::Cell;
use std::collections::HashMap;
use std::path::Path;

/// `glTF` in ASCII, little-endian.
const MAGIC: u32 = 0x4654_6C67;
/// Chunk types: `JSON` and `BIN\0`.
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// The most primitives a scene may show, instances counted: each costs a
/// little work even when empty, and a mesh of many primitives shown by many
/// nodes would otherwise keep the reader busy for minutes.
const MAX_PRIMITIVE_INSTANCES: u64 = 1 << 22;

/// The members of glTF objects this reader uses, at any depth; every other
/// member is skipped unread.
const KEPT_MEMBERS: &[&str] = &[
    "scene",
    "scenes",
    "nodes",
    "children",
    "mesh",
    "meshes",
    "matrix",
    "translation",
    "rotation",
    "scale",
    "primitives",
    "attributes",
    "POSITION",
    "NORMAL",
    "TEXCOORD_0",
    "indices",
    "mode",
    "extensions",
    "extensionsRequired",
    "KHR_draco_mesh_compression",
    "accessors",
    "bufferView",
    "bufferViews",
    "buffer",
    "buffers",
    "byteOffset",
    "byteLength",
    "byteStride",
    "componentType",
    "type",
    "count",
    "normalized",
    "sparse",
    "uri",
];

/// Bytes counted per JSON value kept: a `serde_json::Value` (32 bytes) and
/// as much again for the growth of the array holding it.
const JSON_BYTES_PER_VALUE: u64 = 64;
/// Bytes counted per JSON object kept: the first node of its `BTreeMap`
/// (eleven keys and values: about 630 bytes), allocated with its first member.
const JSON_BYTES_PER_OBJECT: u64 = 640;

pub(super) fn parse(bytes: &[u8], path: &Path, budget: Budget) -> Result<Mesh, LoadError> {
    let (json, bin) = chunks(bytes, path)?;
    let held = bytes.len() as u64;
    let (root, json_bytes) = parse_json(json, held, budget, path)?;
    let document = Document { root: &root, bin, path };
    document.check_extensions()?;
    let instances = document.instances()?;
    let [vertices, triangles] = document.check_instances(&instances, [held, json_bytes], budget)?;
    // What the budget leaves once the file and the whole mesh are counted:
    // the most a Draco stream may decode to, held only while its primitive
    // is copied.
    let need = Budget::need(held + json_bytes, vertices, triangles);
    let spare = u64::try_from(u128::from(budget.bytes).saturating_sub(need)).unwrap_or(u64::MAX);
    let mut out = Output::with_capacity(vertices, triangles, path)?;
    for (mesh, transform) in instances {
        document.add_mesh(mesh, &transform, spare, &mut out)?;
    }
    let Output {
        positions,
        offsets,
        indices,
        normals,
        uvs,
    } = out;
    // Per vertex, given to every corner that uses the vertex.
    let corner_normals = normals.map(|n: Vec<Vec3>| indices.iter().map(|&v| n[v as usize]).collect::<Vec<_>>());
    let corner_uvs = uvs.map(|t: Vec<[f32; 2]>| indices.iter().map(|&v| t[v as usize]).collect::<Vec<_>>());
    let mut mesh = Mesh::from_compact(positions, offsets, indices).map_err(|e| LoadError::new(path, None, e))?;
    if let Some(normals) = corner_normals {
        mesh = mesh
            .with_corner_normals(normals)
            .map_err(|e| LoadError::new(path, None, e))?;
    }
    if let Some(uvs) = corner_uvs {
        mesh = mesh.with_corner_uvs(uvs).map_err(|e| LoadError::new(path, None, e))?;
    }
    Ok(mesh)
}

/// The JSON chunk as a `Value` holding only the [`KEPT_MEMBERS`], and the
/// bytes counted for it; [`LoadErrorKind::MemoryBudget`] as soon as those
/// bytes and the `held` ones pass the budget.
fn parse_json(json: &[u8], held: u64, budget: Budget, path: &Path) -> Result<(Value, u64), LoadError> {
    let counter = Counter {
        spent: Cell::new(0),
        values: Cell::new(0),
        limit: budget.bytes.saturating_sub(held),
    };
    let mut deserializer = serde_json::Deserializer::from_slice(json);
    let parsed = Pruned(&counter)
        .deserialize(&mut deserializer)
        .and_then(|value| deserializer.end().map(|()| value));
    match parsed {
        Ok(value) => Ok((value, counter.spent.get())),
        Err(_) if counter.spent.get() > counter.limit => {
            let bytes = u128::from(held) + u128::from(counter.spent.get());
            let kind = LoadErrorKind::MemoryBudget {
                what: format!(
                    "at least {} JSON values of the members read (at {JSON_BYTES_PER_VALUE} bytes, objects \
                     {JSON_BYTES_PER_OBJECT}), with the {held} bytes of the file,",
                    counter.values.get()
                ),
                bytes,
                budget: budget.bytes,
            };
            Err(LoadError::new(path, None, kind))
        }
        Err(e) => Err(syntax(path, None, format!("JSON chunk: {e}"))),
    }
}

/// The bytes spent on the JSON values kept so far, and the most they may reach.
struct Counter {
    spent: Cell<u64>,
    values: Cell<u64>,
    limit: u64,
}

impl Counter {
    fn spend<E: serde::de::Error>(&self, bytes: u64) -> Result<(), E> {
        self.values.set(self.values.get() + 1);
        self.spent.set(self.spent.get().saturating_add(bytes));
        if self.spent.get() > self.limit {
            return Err(E::custom("the memory budget is spent"));
        }
        Ok(())
    }
}

/// Deserializes any JSON value into a `Value`, keeping in objects only the
/// members named in [`KEPT_MEMBERS`] (the others are skipped as they are
/// read, allocating nothing), and counting what it keeps.
#[derive(Clone, Copy)]
struct Pruned<'c>(&'c Counter);

impl<'de> DeserializeSeed<'de> for Pruned<'_> {
    type Value = Value;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Value, D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Pruned<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<Value, E> {
        self.0.spend(JSON_BYTES_PER_VALUE)?;
        Ok(Value::Bool(v))
    }

    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Value, E> {
        self.0.spend(JSON_BYTES_PER_VALUE)?;
        Ok(Value::from(v))
    }

    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Value, E> {
        self.0.spend(JSON_BYTES_PER_VALUE)?;
        Ok(Value::from(v))
    }

    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Value, E> {
        self.0.spend(JSON_BYTES_PER_VALUE)?;
        // serde_json reads no non-finite number: `from_f64` never gives None here.
        Ok(serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number))
    }

    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Value, E> {
        self.0.spend(JSON_BYTES_PER_VALUE + v.len() as u64)?;
        Ok(Value::String(v.to_owned()))
    }

    fn visit_unit<E: serde::de::Error>(self) -> Result<Value, E> {
        self.0.spend(JSON_BYTES_PER_VALUE)?;
        Ok(Value::Null)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        self.0.spend(JSON_BYTES_PER_VALUE)?;
        let mut items = Vec::new();
        while let Some(item) = seq.next_element_seed(self)? {
            items.push(item);
        }
        Ok(Value::Array(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        self.0.spend(JSON_BYTES_PER_OBJECT)?;
        let mut members = serde_json::Map::new();
        while let Some(key) = map.next_key_seed(MemberName)? {
            match key {
                Some(name) => {
                    let value = map.next_value_seed(self)?;
                    members.insert(name.to_owned(), value);
                }
                None => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
        }
        Ok(Value::Object(members))
    }
}

/// A member name: the entry of [`KEPT_MEMBERS`] it equals, or `None` (to be
/// skipped), read without allocating.
struct MemberName;

impl<'de> DeserializeSeed<'de> for MemberName {
    type Value = Option<&'static str>;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Self::Value, D::Error> {
        deserializer.deserialize_str(self)
    }
}

impl<'de> Visitor<'de> for MemberName {
    type Value = Option<&'static str>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a member name")
    }

    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Self::Value, E> {
        Ok(KEPT_MEMBERS.iter().copied().find(|&k| k == v))
    }
}

/// The JSON chunk and the binary chunk (empty when absent) of a GLB file.
fn chunks<'a>(bytes: &'a [u8], path: &Path) -> Result<(&'a [u8], &'a [u8]), LoadError> {
    fn word(bytes: &[u8], at: usize) -> Option<u32> {
        let b = bytes.get(at..at.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    let (Some(magic), Some(version), Some(length)) = (word(bytes, 0), word(bytes, 4), word(bytes, 8)) else {
        if bytes.len() >= 4 && word(bytes, 0) != Some(MAGIC) {
            return Err(syntax(path, None, "not a binary glTF file (no 'glTF' magic)"));
        }
        return Err(truncated(
            path,
            None,
            format!("{} bytes: a GLB file has a 12-byte header", bytes.len()),
        ));
    };
    if magic != MAGIC {
        return Err(syntax(path, None, "not a binary glTF file (no 'glTF' magic)"));
    }
    if version != 2 {
        return Err(syntax(
            path,
            None,
            format!("glTF version {version}: only version 2 is read"),
        ));
    }
    let length = length as usize;
    if length > bytes.len() {
        let message = format!("the header announces {length} bytes, the file has {}", bytes.len());
        return Err(truncated(path, None, message));
    }
    let bytes = &bytes[..length];
    let (mut json, mut bin) = (None, None);
    let mut at = 12usize;
    while at < bytes.len() {
        let (Some(size), Some(kind)) = (word(bytes, at), word(bytes, at + 4)) else {
            return Err(truncated(path, None, format!("a chunk header at byte {at}")));
        };
        let start = at + 8;
        let end = start
            .checked_add(size as usize)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| truncated(path, None, format!("the chunk at byte {at} announces {size} bytes")))?;
        match kind {
            CHUNK_JSON if json.is_none() => json = Some(&bytes[start..end]),
            CHUNK_BIN if json.is_some() && bin.is_none() => bin = Some(&bytes[start..end]),
            CHUNK_JSON | CHUNK_BIN => {
                return Err(syntax(
                    path,
                    None,
                    format!("the chunk at byte {at} is out of order (JSON first, then at most one BIN)"),
                ));
            }
            _ => {} // Chunks of other types are to be ignored.
        }
        // Chunks are padded to 4 bytes, but a lenient writer may not pad the last.
        at = end.checked_add(3).map_or(usize::MAX, |e| e & !3);
    }
    let json = json.ok_or_else(|| syntax(path, None, "no JSON chunk"))?;
    Ok((json, bin.unwrap_or(&[])))
}

/// The mesh being gathered, in the layout of [`Mesh::from_compact`], its
/// room reserved once from the counts.
struct Output {
    positions: Vec<Vec3>,
    offsets: Vec<u32>,
    indices: Vec<u32>,
    /// Per vertex, while every primitive so far has had them.
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<[f32; 2]>>,
}

impl Output {
    /// Room for `vertices` and `triangles` exactly, or an error (not an
    /// abort) when the allocator refuses.
    fn with_capacity(vertices: u64, triangles: u64, path: &Path) -> Result<Self, LoadError> {
        let mut out = Output {
            positions: Vec::new(),
            offsets: Vec::new(),
            indices: Vec::new(),
            normals: Some(Vec::new()),
            uvs: Some(Vec::new()),
        };
        let refused = |_| {
            let error = std::io::Error::new(
                std::io::ErrorKind::OutOfMemory,
                format!("cannot allocate a mesh of {vertices} vertices and {triangles} triangles"),
            );
            LoadError::new(path, None, error)
        };
        // Both below 2^32 (checked by the caller): they fit usize.
        let (vertices, triangles) = (vertices as usize, triangles as usize);
        out.positions.try_reserve_exact(vertices).map_err(refused)?;
        out.offsets.try_reserve_exact(triangles + 1).map_err(refused)?;
        out.indices.try_reserve_exact(3 * triangles).map_err(refused)?;
        out.offsets.push(0);
        Ok(out)
    }

    fn push_triangle(&mut self, triangle: [u32; 3]) {
        self.indices.extend_from_slice(&triangle);
        self.offsets.push(self.indices.len() as u32);
    }
}

struct Document<'a> {
    root: &'a Value,
    bin: &'a [u8],
    path: &'a Path,
}

/// A component type of an accessor.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Component {
    I8,
    U8,
    I16,
    U16,
    U32,
    F32,
}

impl Component {
    fn from_code(code: u64) -> Option<Self> {
        Some(match code {
            5120 => Self::I8,
            5121 => Self::U8,
            5122 => Self::I16,
            5123 => Self::U16,
            5125 => Self::U32,
            5126 => Self::F32,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::U32 | Self::F32 => 4,
        }
    }

    /// The component at the start of `b` (at least `size()` bytes), as f64;
    /// `normalized` maps integers to [-1, 1] or [0, 1] as glTF specifies.
    fn read(self, b: &[u8], normalized: bool) -> f64 {
        let (value, scale) = match self {
            Self::I8 => (f64::from(b[0] as i8), 127.0),
            Self::U8 => (f64::from(b[0]), 255.0),
            Self::I16 => (f64::from(i16::from_le_bytes([b[0], b[1]])), 32767.0),
            Self::U16 => (f64::from(u16::from_le_bytes([b[0], b[1]])), 65535.0),
            Self::U32 => (f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])), 4294967295.0),
            Self::F32 => return f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        };
        if normalized { (value / scale).max(-1.0) } else { value }
    }
}

/// An accessor resolved to checked bytes: element `i` starts at
/// `data[i * stride]` and holds `components` values of `component`. The
/// bytes are the file's, or those of a decoded Draco stream.
struct Elements<'a> {
    data: Cow<'a, [u8]>,
    stride: usize,
    count: usize,
    components: usize,
    component: Component,
    normalized: bool,
}

/// What a primitive's triangles are made from, in accessors or decoded:
/// `indices` with the accessor that names them in messages.
struct Geometry<'a> {
    positions: Elements<'a>,
    normals: Option<Elements<'a>>,
    uvs: Option<Elements<'a>>,
    indices: Option<(u64, Elements<'a>)>,
}

impl Elements<'_> {
    /// Decoded f32 values, `components` to an element.
    #[cfg(feature = "draco")]
    fn floats(values: &[f32], components: usize) -> Elements<'static> {
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        Elements {
            data: Cow::Owned(data),
            stride: 4 * components,
            count: values.len() / components,
            components,
            component: Component::F32,
            normalized: false,
        }
    }

    /// Decoded indices, one to an element.
    #[cfg(feature = "draco")]
    fn indices(values: &[u32]) -> Elements<'static> {
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        Elements {
            data: Cow::Owned(data),
            stride: 4,
            count: values.len(),
            components: 1,
            component: Component::U32,
            normalized: false,
        }
    }

    fn get(&self, i: usize, c: usize) -> f64 {
        let at = i * self.stride + c * self.component.size();
        self.component.read(&self.data[at..], self.normalized)
    }
}

impl<'a> Document<'a> {
    fn error(&self, message: impl Into<String>) -> LoadError {
        syntax(self.path, None, message)
    }

    /// `root[key]` as an array (absent: empty).
    fn array(&self, value: &'a Value, key: &str, at: &str) -> Result<&'a [Value], LoadError> {
        match value.get(key) {
            None => Ok(&[]),
            Some(Value::Array(items)) => Ok(items),
            Some(_) => Err(self.error(format!("{at}.{key} is not an array"))),
        }
    }

    /// `value[key]` as a non-negative integer, `None` when absent.
    fn integer(&self, value: &Value, key: &str, at: &str) -> Result<Option<u64>, LoadError> {
        match value.get(key) {
            None => Ok(None),
            Some(v) => v
                .as_u64()
                .map(Some)
                .ok_or_else(|| self.error(format!("{at}.{key} is not a non-negative integer: {v}"))),
        }
    }

    /// Element `index` of the top-level array `kind`.
    fn item(&self, kind: &str, index: u64, from: &str) -> Result<&'a Value, LoadError> {
        let items = self.array(self.root, kind, "the document")?;
        usize::try_from(index)
            .ok()
            .and_then(|i| items.get(i))
            .filter(|v| v.is_object())
            .ok_or_else(|| self.error(format!("{from} refers to {kind}[{index}], which does not exist")))
    }

    fn numbers<const N: usize>(&self, value: &Value, key: &str, at: &str) -> Result<Option<[f64; N]>, LoadError> {
        let Some(v) = value.get(key) else { return Ok(None) };
        let bad = || self.error(format!("{at}.{key} is not {N} finite numbers"));
        let items = v.as_array().filter(|a| a.len() == N).ok_or_else(bad)?;
        let mut out = [0.0; N];
        for (o, item) in out.iter_mut().zip(items) {
            *o = item.as_f64().filter(|x| x.is_finite()).ok_or_else(bad)?;
        }
        Ok(Some(out))
    }

    fn check_extensions(&self) -> Result<(), LoadError> {
        for extension in self.array(self.root, "extensionsRequired", "the document")? {
            let name = extension.as_str().unwrap_or("");
            if name == "EXT_meshopt_compression" {
                return Err(self.error(format!(
                    "geometry compressed with {name} is not read; decompress it first (for example `gltf-transform copy`)"
                )));
            }
            if name == "KHR_draco_mesh_compression" && !cfg!(feature = "draco") {
                return Err(self.error(format!(
                    "geometry compressed with {name} is not read by this build (proxima's `draco` feature is off); \
                     decompress it first (for example `gltf-transform copy`)"
                )));
            }
        }
        Ok(())
    }

    /// Every mesh to add, with its node's world transform.
    fn instances(&self) -> Result<Vec<(u64, DMat4)>, LoadError> {
        let nodes = self.array(self.root, "nodes", "the document")?;
        let scenes = self.array(self.root, "scenes", "the document")?;
        let from_scene = !scenes.is_empty() || self.root.get("scene").is_some();
        // With no scene, the roots are the nodes that are no node's child;
        // `parent` keeps one parent of each child, to find a cycle's nodes.
        let mut parent = vec![usize::MAX; if from_scene { 0 } else { nodes.len() }];
        let roots: Vec<u64> = if from_scene {
            let index = self.integer(self.root, "scene", "the document")?.unwrap_or(0);
            let scene = self.item("scenes", index, "scene")?;
            let at = format!("scenes[{index}]");
            let mut roots = Vec::new();
            for (i, node) in self.array(scene, "nodes", &at)?.iter().enumerate() {
                roots.push(
                    node.as_u64()
                        .ok_or_else(|| self.error(format!("{at}.nodes[{i}] is not a node index")))?,
                );
            }
            roots
        } else if !nodes.is_empty() {
            for (n, node) in nodes.iter().enumerate() {
                for child in self.array(node, "children", &format!("nodes[{n}]"))? {
                    if let Some(p) = child.as_u64().and_then(|c| parent.get_mut(c as usize)) {
                        *p = n;
                    }
                }
            }
            (0..nodes.len())
                .filter(|&n| parent[n] == usize::MAX)
                .map(|n| n as u64)
                .collect()
        } else {
            let meshes = self.array(self.root, "meshes", "the document")?;
            return Ok((0..meshes.len() as u64).map(|m| (m, DMat4::IDENTITY)).collect());
        };
        let mut visited = vec![false; nodes.len()];
        let mut out = Vec::new();
        self.walk(roots, &mut visited, &mut out)?;
        if let Some(unreached) = visited.iter().position(|&v| !v).filter(|_| !from_scene) {
            // Every node that is no node's child is a root, and the children
            // of the nodes walked were walked: this node and its parents lie
            // under a cycle. Going up from it as many times as there are
            // nodes lands on the cycle, which a walk from there reports as a
            // scene's walk does.
            let mut at = unreached;
            for _ in 0..nodes.len() {
                at = match parent.get(at) {
                    Some(&p) if p != usize::MAX => p,
                    _ => break,
                };
            }
            self.walk(vec![at as u64], &mut visited, &mut out)?;
        }
        Ok(out)
    }

    /// Walks the hierarchy down from `roots`, adding the meshes met to `out`
    /// with their world transforms; a node reached twice is an error.
    fn walk(&self, roots: Vec<u64>, visited: &mut [bool], out: &mut Vec<(u64, DMat4)>) -> Result<(), LoadError> {
        // The stack holds a node and the index of its parent's transform (16
        // bytes, not a matrix per node waiting: roots and children lists come
        // from the JSON, two bytes an entry); one transform per node walked.
        let mut transforms = vec![DMat4::IDENTITY];
        let mut stack: Vec<(u64, usize)> = roots.into_iter().rev().map(|n| (n, 0)).collect();
        while let Some((index, parent)) = stack.pop() {
            let node = self.item("nodes", index, "a scene or a node's children")?;
            let seen = &mut visited[index as usize];
            if *seen {
                return Err(self.error(format!(
                    "nodes[{index}] is reached twice: the node hierarchy is not a tree (a cycle, or a shared child)"
                )));
            }
            *seen = true;
            let at = format!("nodes[{index}]");
            let transform = transforms[parent] * self.local_transform(node, &at)?;
            if let Some(mesh) = self.integer(node, "mesh", &at)? {
                out.push((mesh, transform));
            }
            let children = self.array(node, "children", &at)?;
            if children.is_empty() {
                continue;
            }
            transforms.push(transform);
            let slot = transforms.len() - 1;
            for (i, child) in children.iter().enumerate().rev() {
                let child = child
                    .as_u64()
                    .ok_or_else(|| self.error(format!("{at}.children[{i}] is not a node index")))?;
                stack.push((child, slot));
            }
        }
        Ok(())
    }

    fn local_transform(&self, node: &Value, at: &str) -> Result<DMat4, LoadError> {
        if let Some(matrix) = self.numbers::<16>(node, "matrix", at)? {
            return Ok(DMat4::from_cols_array(&matrix));
        }
        let translation = self.numbers::<3>(node, "translation", at)?.unwrap_or([0.0; 3]);
        let scale = self.numbers::<3>(node, "scale", at)?.unwrap_or([1.0; 3]);
        let rotation = match self.numbers::<4>(node, "rotation", at)? {
            None => DQuat::IDENTITY,
            Some(q) => {
                let q = DQuat::from_array(q);
                if q.length() < 1e-6 {
                    return Err(self.error(format!("{at}.rotation is not a rotation (a zero quaternion)")));
                }
                q.normalize()
            }
        };
        Ok(DMat4::from_scale_rotation_translation(
            DVec3::from(scale),
            rotation,
            DVec3::from(translation),
        ))
    }

    /// The vertices and triangles of the scene's instances (accessor counts
    /// over every instance: each mesh is counted once, then weighed by its
    /// instances), checked before anything is read against the 32-bit vertex
    /// numbers, [`MAX_PRIMITIVE_INSTANCES`] and the memory budget, the bytes
    /// `held` (the file, and the JSON values kept) included.
    fn check_instances(
        &self,
        instances: &[(u64, DMat4)],
        held: [u64; 2],
        budget: Budget,
    ) -> Result<[u64; 2], LoadError> {
        let mut per_mesh: HashMap<u64, [u64; 3]> = HashMap::new();
        let mut total = [0u64; 3]; // vertices, triangles, primitives
        for &(mesh, _) in instances {
            let counts = match per_mesh.get(&mesh) {
                Some(&counts) => counts,
                None => {
                    let counts = self.mesh_counts(mesh)?;
                    per_mesh.insert(mesh, counts);
                    counts
                }
            };
            for (t, c) in total.iter_mut().zip(counts) {
                *t = t.saturating_add(c);
            }
        }
        let [vertices, triangles, primitives] = total;
        let [file, json] = held;
        let bytes = Budget::need(file + json, vertices, triangles);
        let described = || {
            format!(
                "the scene's {} mesh instances ({vertices} vertices and {triangles} triangles, {primitives} primitives)",
                instances.len()
            )
        };
        // Vertex numbers and face offsets are u32.
        if vertices > u64::from(u32::MAX) || triangles.saturating_mul(3) > u64::from(u32::MAX) {
            return Err(self.error(format!(
                "{} are more than 32-bit vertex numbers and face offsets can address",
                described()
            )));
        }
        if primitives > MAX_PRIMITIVE_INSTANCES {
            return Err(self.error(format!(
                "{} show more than {MAX_PRIMITIVE_INSTANCES} primitives",
                described()
            )));
        }
        if bytes > u128::from(budget.bytes) {
            let kind = LoadErrorKind::MemoryBudget {
                what: format!(
                    "{}, with their trees ({} and {} bytes each), the file ({file} bytes) and its JSON values ({json} \
                     bytes),",
                    described(),
                    crate::budget::LOAD_BYTES_PER_VERTEX,
                    crate::budget::LOAD_BYTES_PER_TRIANGLE
                ),
                bytes,
                budget: budget.bytes,
            };
            return Err(LoadError::new(self.path, None, kind));
        }
        Ok([vertices, triangles])
    }

    /// A mesh's vertices, triangles and primitives, from the accessors'
    /// `count` alone (their bounds are checked when read): the primitives of
    /// points and lines add none.
    fn mesh_counts(&self, mesh: u64) -> Result<[u64; 3], LoadError> {
        let value = self.item("meshes", mesh, "a node")?;
        let primitives = self.array(value, "primitives", &format!("meshes[{mesh}]"))?;
        let mut counts = [0u64, 0, primitives.len() as u64];
        for primitive in primitives {
            let count = |index: Option<&Value>| {
                let accessor = index
                    .and_then(Value::as_u64)
                    .and_then(|i| self.item("accessors", i, "").ok());
                accessor
                    .and_then(|a| a.get("count"))
                    .and_then(Value::as_u64)
                    .unwrap_or(0)
            };
            let positions = count(primitive.get("attributes").and_then(|a| a.get("POSITION")));
            let corners = match primitive.get("indices") {
                Some(indices) => count(Some(indices)),
                None => positions,
            };
            // A mode that is not 4, 5 or 6 adds nothing (or is an error when read).
            let triangles = match primitive.get("mode").map_or(Some(4), Value::as_u64) {
                Some(4) => corners / 3,
                Some(5 | 6) => corners.saturating_sub(2),
                _ => continue,
            };
            counts[0] = counts[0].saturating_add(positions);
            counts[1] = counts[1].saturating_add(triangles);
        }
        Ok(counts)
    }

    fn add_mesh(&self, mesh: u64, transform: &DMat4, spare: u64, out: &mut Output) -> Result<(), LoadError> {
        let value = self.item("meshes", mesh, "a node")?;
        let at = format!("meshes[{mesh}]");
        for (p, primitive) in self.array(value, "primitives", &at)?.iter().enumerate() {
            let at = format!("{at}.primitives[{p}]");
            let mode = self.integer(primitive, "mode", &at)?.unwrap_or(4);
            if mode <= 3 {
                continue; // points and lines: no surface
            }
            if mode > 6 {
                return Err(self.error(format!("{at}.mode is {mode}, not a glTF primitive mode")));
            }
            let draco = primitive
                .get("extensions")
                .and_then(|e| e.get("KHR_draco_mesh_compression"));
            let geometry = match draco {
                Some(extension) => self.draco_geometry(primitive, extension, mode, &at, spare)?,
                None => self.accessor_geometry(primitive, &at)?,
            };
            let Geometry {
                positions,
                normals,
                uvs,
                indices,
            } = geometry;
            // Within u32 and the budget: check_instances counted these very
            // accessors (a Draco primitive's decoded counts were checked
            // equal to them), and reserved their room.
            let first = out.positions.len() as u32;
            let vertices = positions.count as u64;
            for i in 0..positions.count {
                let p = DVec3::new(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2));
                out.positions.push(transform.transform_point3(p).as_vec3());
            }
            self.add_vertex_attributes(normals, uvs, &at, positions.count, transform, out)?;
            if let Some((index, elements)) = &indices {
                // Every index checked first, in order, so that the first
                // bad one is named whatever the mode.
                for i in 0..elements.count {
                    let v = elements.get(i, 0) as u64;
                    if v >= vertices {
                        return Err(self.error(format!(
                            "accessors[{index}] (indices of {at}): index {i} is {v}, but the primitive has {vertices} vertices"
                        )));
                    }
                }
            }
            let indices = indices.map(|(_, elements)| elements);
            let corners = indices.as_ref().map_or(positions.count, |e| e.count);
            // Read again where used, rather than gathered: no list of corners is held.
            let corner = |i: usize| first + indices.as_ref().map_or(i as u32, |e| e.get(i, 0) as u32);
            match mode {
                4 => {
                    if !corners.is_multiple_of(3) {
                        return Err(self.error(format!("{at}: {corners} indices do not make whole triangles")));
                    }
                    for t in 0..corners / 3 {
                        out.push_triangle([corner(3 * t), corner(3 * t + 1), corner(3 * t + 2)]);
                    }
                }
                5 => {
                    for i in 0..corners.saturating_sub(2) {
                        // Every other triangle of a strip is reversed to keep one orientation.
                        out.push_triangle(if i % 2 == 0 {
                            [corner(i), corner(i + 1), corner(i + 2)]
                        } else {
                            [corner(i + 1), corner(i), corner(i + 2)]
                        });
                    }
                }
                _ => {
                    for i in 1..corners.saturating_sub(1) {
                        out.push_triangle([corner(0), corner(i), corner(i + 1)]);
                    }
                }
            }
        }
        Ok(())
    }

    /// The geometry of a primitive stored in accessors: `POSITION` (a VEC3),
    /// `NORMAL` and `TEXCOORD_0` of as many elements, and `indices` (a
    /// SCALAR of unsigned integers).
    fn accessor_geometry(&self, primitive: &Value, at: &str) -> Result<Geometry<'a>, LoadError> {
        let attributes = primitive.get("attributes").unwrap_or(&Value::Null);
        let position = self
            .integer(attributes, "POSITION", &format!("{at}.attributes"))?
            .ok_or_else(|| self.error(format!("{at} has no POSITION attribute")))?;
        let positions = self.elements(position, &format!("{at}.attributes.POSITION"))?;
        if positions.components != 3 {
            return Err(self.error(format!("accessors[{position}] (POSITION of {at}) is not a VEC3")));
        }
        let vertices = positions.count;
        let read = |name: &str, components: usize| -> Result<Option<Elements<'a>>, LoadError> {
            let Some(index) = self.integer(attributes, name, &format!("{at}.attributes"))? else {
                return Ok(None);
            };
            let elements = self.elements(index, &format!("{at}.attributes.{name}"))?;
            if elements.components != components || elements.count != vertices {
                return Err(self.error(format!(
                    "accessors[{index}] ({name} of {at}) is not {vertices} elements of {components} components"
                )));
            }
            Ok(Some(elements))
        };
        let normals = read("NORMAL", 3)?;
        let uvs = read("TEXCOORD_0", 2)?;
        let indices = match self.integer(primitive, "indices", at)? {
            None => None,
            Some(indices) => {
                let elements = self.elements(indices, &format!("{at}.indices"))?;
                if elements.components != 1
                    || !matches!(elements.component, Component::U8 | Component::U16 | Component::U32)
                {
                    return Err(self.error(format!(
                        "accessors[{indices}] (indices of {at}) is not a SCALAR of unsigned bytes, shorts or ints"
                    )));
                }
                Some((indices, elements))
            }
        };
        Ok(Geometry {
            positions,
            normals,
            uvs,
            indices,
        })
    }

    /// The geometry of a primitive compressed with
    /// `KHR_draco_mesh_compression` (the `extension` object), decoded by
    /// [`super::draco`] from its buffer view with at most `spare` bytes of
    /// attributes. Its accessors hold no data, only the counts and types the
    /// decoded stream must have; the attributes read must all be in the stream.
    #[cfg(feature = "draco")]
    fn draco_geometry(
        &self,
        primitive: &Value,
        extension: &Value,
        mode: u64,
        at: &str,
        spare: u64,
    ) -> Result<Geometry<'a>, LoadError> {
        use super::draco::{AttributeIds, Limits, decode};
        let ext_at = format!("{at}.extensions.KHR_draco_mesh_compression");
        if mode != 4 {
            return Err(self.error(format!(
                "{at}.mode is {mode}: a primitive compressed with KHR_draco_mesh_compression is read as triangles (mode 4) only"
            )));
        }
        let attributes = primitive.get("attributes").unwrap_or(&Value::Null);
        let ids = extension.get("attributes").unwrap_or(&Value::Null);
        // The accessor of attribute `name` (its count and components checked)
        // and the Draco id the extension gives it; `None` when the primitive
        // has no such attribute.
        let attribute = |name: &str, components: usize| -> Result<Option<(u64, u32)>, LoadError> {
            let Some(index) = self.integer(attributes, name, &format!("{at}.attributes"))? else {
                return Ok(None);
            };
            let (count, found) = self.accessor_shape(index, &format!("{at}.attributes.{name}"))?;
            if found != components {
                return Err(self.error(format!(
                    "accessors[{index}] ({name} of {at}) does not have {components} components"
                )));
            }
            let id = self
                .integer(ids, name, &format!("{ext_at}.attributes"))?
                .ok_or_else(|| {
                    self.error(format!(
                        "{at}.attributes.{name} is not in the Draco stream ({ext_at}.attributes has no {name}): \
                         uncompressed attributes beside a Draco stream are not read"
                    ))
                })?;
            let id = u32::try_from(id)
                .map_err(|_| self.error(format!("{ext_at}.attributes.{name} is {id}, not a Draco attribute id")))?;
            Ok(Some((count, id)))
        };
        let (points, position) =
            attribute("POSITION", 3)?.ok_or_else(|| self.error(format!("{at} has no POSITION attribute")))?;
        let normal = attribute("NORMAL", 3)?;
        let uv = attribute("TEXCOORD_0", 2)?;
        for (name, found) in [("NORMAL", &normal), ("TEXCOORD_0", &uv)] {
            if let Some((count, _)) = found.filter(|&(count, _)| count != points) {
                return Err(self.error(format!(
                    "{at}.attributes.{name} states {count} elements, POSITION {points}"
                )));
            }
        }
        let index = self.integer(primitive, "indices", at)?.ok_or_else(|| {
            self.error(format!(
                "{at} is compressed with KHR_draco_mesh_compression but has no indices"
            ))
        })?;
        let (corners, components) = self.accessor_shape(index, &format!("{at}.indices"))?;
        if components != 1 || !corners.is_multiple_of(3) {
            return Err(self.error(format!(
                "accessors[{index}] (indices of {at}) is not a SCALAR of whole triangles"
            )));
        }
        let view = self
            .integer(extension, "bufferView", &ext_at)?
            .ok_or_else(|| self.error(format!("{ext_at} has no bufferView")))?;
        let (_, stream) = self.view(view, &ext_at)?;
        let ids = AttributeIds {
            position,
            normal: normal.map(|(_, id)| id),
            uv: uv.map(|(_, id)| id),
        };
        let limits = Limits {
            points,
            faces: corners / 3,
            bytes: spare,
        };
        let decoded = decode(stream, &ids, &limits).map_err(|why| self.error(format!("{at}: Draco data: {why}")))?;
        if decoded.points as u64 != points || decoded.corners.len() as u64 != corners {
            return Err(self.error(format!(
                "{at}: the Draco stream decodes {} points and {} indices, but its accessors state {points} and {corners}",
                decoded.points,
                decoded.corners.len()
            )));
        }
        Ok(Geometry {
            positions: Elements::floats(&decoded.positions, 3),
            normals: decoded.normals.map(|n| Elements::floats(&n, 3)),
            uvs: decoded.uvs.map(|t| Elements::floats(&t, 2)),
            indices: Some((index, Elements::indices(&decoded.corners))),
        })
    }

    /// Without the `draco` feature, a compressed primitive is refused.
    #[cfg(not(feature = "draco"))]
    fn draco_geometry(&self, _: &Value, _: &Value, _: u64, at: &str, _: u64) -> Result<Geometry<'a>, LoadError> {
        Err(self.error(format!(
            "{at} is compressed with KHR_draco_mesh_compression, which this build does not read (proxima's `draco` \
             feature is off); decompress it first"
        )))
    }

    /// The `NORMAL` and `TEXCOORD_0` of a primitive's `vertices` vertices,
    /// added to `out` while every primitive has had them (the first without
    /// drops that kind). Normals are turned by the inverse transpose of the
    /// node's transform and normalized; values that are not finite are
    /// refused naming the primitive.
    fn add_vertex_attributes(
        &self,
        normals: Option<Elements<'_>>,
        uvs: Option<Elements<'_>>,
        at: &str,
        vertices: usize,
        transform: &DMat4,
        out: &mut Output,
    ) -> Result<(), LoadError> {
        let not_finite = |name: &str, i: usize| self.error(format!("{at}: {name} of vertex {i} is not finite"));
        match (normals, &mut out.normals) {
            (Some(normals), Some(list)) => {
                let turn = glam::DMat3::from_mat4(*transform).inverse().transpose();
                for i in 0..vertices {
                    let n = DVec3::new(normals.get(i, 0), normals.get(i, 1), normals.get(i, 2));
                    if !n.is_finite() {
                        return Err(not_finite("NORMAL", i));
                    }
                    list.push((turn * n).normalize_or_zero().as_vec3());
                }
            }
            (None, _) => out.normals = None,
            (Some(_), None) => {}
        }
        match (uvs, &mut out.uvs) {
            (Some(uvs), Some(list)) => {
                for i in 0..vertices {
                    let uv = [uvs.get(i, 0) as f32, uvs.get(i, 1) as f32];
                    if !uv.iter().all(|c| c.is_finite()) {
                        return Err(not_finite("TEXCOORD_0", i));
                    }
                    list.push(uv);
                }
            }
            (None, _) => out.uvs = None,
            (Some(_), None) => {}
        }
        Ok(())
    }

    /// The components of an accessor's elements, from its `type`.
    fn components(&self, accessor: &Value, at: &str) -> Result<usize, LoadError> {
        Ok(match accessor.get("type").and_then(Value::as_str) {
            Some("SCALAR") => 1,
            Some("VEC2") => 2,
            Some("VEC3") => 3,
            Some("VEC4") | Some("MAT2") => 4,
            Some("MAT3") => 9,
            Some("MAT4") => 16,
            other => return Err(self.error(format!("{at}.type is {other:?}, not a glTF accessor type"))),
        })
    }

    /// The `count` and components of accessor `index`, which may hold no
    /// data (those of a Draco-compressed primitive).
    #[cfg_attr(not(feature = "draco"), allow(dead_code))]
    fn accessor_shape(&self, index: u64, from: &str) -> Result<(u64, usize), LoadError> {
        let accessor = self.item("accessors", index, from)?;
        let at = format!("accessors[{index}]");
        let components = self.components(accessor, &at)?;
        Ok((self.integer(accessor, "count", &at)?.unwrap_or(0), components))
    }

    /// Buffer view `index` and its bytes, checked to lie inside the binary
    /// chunk (the one buffer a GLB file holds).
    fn view(&self, index: u64, from: &str) -> Result<(&'a Value, &'a [u8]), LoadError> {
        let view = self.item("bufferViews", index, from)?;
        let view_at = format!("bufferViews[{index}]");
        let buffer = self.integer(view, "buffer", &view_at)?.unwrap_or(0);
        let buffer_value = self.item("buffers", buffer, &view_at)?;
        if buffer_value.get("uri").is_some() {
            return Err(self.error(format!(
                "buffers[{buffer}] has a uri: only the GLB file's own binary chunk is read"
            )));
        }
        if buffer != 0 {
            return Err(self.error(format!(
                "{view_at} refers to buffers[{buffer}]; a GLB file's binary chunk is buffers[0]"
            )));
        }
        let view_offset = self.integer(view, "byteOffset", &view_at)?.unwrap_or(0);
        let view_length = self.integer(view, "byteLength", &view_at)?.unwrap_or(0);
        let view_end = view_offset
            .checked_add(view_length)
            .filter(|&end| end <= self.bin.len() as u64);
        let Some(view_end) = view_end else {
            return Err(truncated(
                self.path,
                None,
                format!(
                    "{view_at} spans bytes {view_offset}..{} of a binary chunk of {} bytes",
                    view_offset.saturating_add(view_length),
                    self.bin.len()
                ),
            ));
        };
        Ok((view, &self.bin[view_offset as usize..view_end as usize]))
    }

    /// Accessor `index`, checked to lie inside its buffer view and buffer.
    fn elements(&self, index: u64, from: &str) -> Result<Elements<'a>, LoadError> {
        let accessor = self.item("accessors", index, from)?;
        let at = format!("accessors[{index}]");
        if accessor.get("sparse").is_some() {
            return Err(self.error(format!("{at} ({from}) is sparse, which is not read")));
        }
        let code = self.integer(accessor, "componentType", &at)?.unwrap_or(0);
        let component = Component::from_code(code)
            .ok_or_else(|| self.error(format!("{at}.componentType is {code}, not a glTF component type")))?;
        let components = self.components(accessor, &at)?;
        let count = self.integer(accessor, "count", &at)?.unwrap_or(0);
        let normalized = accessor.get("normalized").and_then(Value::as_bool).unwrap_or(false);
        let element = (components * component.size()) as u64;
        if count == 0 {
            return Ok(Elements {
                data: Cow::Borrowed(&[]),
                stride: 0,
                count: 0,
                components,
                component,
                normalized,
            });
        }
        let view_index = self.integer(accessor, "bufferView", &at)?.ok_or_else(|| {
            self.error(format!(
                "{at} has no bufferView (an all-zero accessor), which is not read"
            ))
        })?;
        let (view, bytes) = self.view(view_index, &at)?;
        let view_at = format!("bufferViews[{view_index}]");
        let view_length = bytes.len() as u64;
        let stride = self.integer(view, "byteStride", &view_at)?.unwrap_or(element);
        if stride < element {
            return Err(self.error(format!(
                "{view_at}.byteStride is {stride}, less than {at}'s {element}-byte elements"
            )));
        }
        let offset = self.integer(accessor, "byteOffset", &at)?.unwrap_or(0);
        // The last element's end, in u64 so that no count can overflow it.
        let end = (count - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(offset))
            .and_then(|x| x.checked_add(element))
            .filter(|&end| end <= view_length);
        if end.is_none() {
            return Err(truncated(
                self.path,
                None,
                format!(
                    "{at}: {count} elements of {element} bytes every {stride} from byte {offset} pass the {view_length} bytes of {view_at}"
                ),
            ));
        }
        let data = &bytes[offset as usize..];
        Ok(Elements {
            data: Cow::Borrowed(data),
            stride: stride as usize,
            count: count as usize,
            components,
            component,
            normalized,
        })
    }
}
