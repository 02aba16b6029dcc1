//! The Draco stream of a GLB primitive compressed with
//! `KHR_draco_mesh_compression`, decoded by the pure-Rust `draco-core` into
//! plain arrays that `glb` then reads as it reads accessors (node transforms,
//! normals and texture coordinates follow the same path).
//!
//! What is read: the triangles, and the attributes that the extension's
//! `attributes` map names by their Draco unique ids (`POSITION`, and `NORMAL`
//! and `TEXCOORD_0` when named), widened to f32: quantized attributes come
//! out of the decoder dequantized, normalized integer ones are mapped to
//! [-1, 1] or [0, 1] as glTF specifies. The decoder's own ceilings, checked
//! from the stream's header before it allocates for them, are the triangles
//! the glTF accessors state and the bytes left in the memory budget (for the
//! attribute values, so they bound the points too); the caller then checks
//! that the decoded counts are exactly the accessors' (the decoder applies
//! its point ceiling to point clouds only).
//!
//! Refused, as a message that the caller prefixes with the primitive: a
//! stream that does not decode (truncated, corrupt, a point cloud, a
//! bitstream version or method this decoder lacks), a unique id with no
//! attribute or with the wrong number of components, a face whose corner is
//! past the points, a point whose value index is past its attribute's
//! values, and a value that is not finite.

use draco_core::{DataType, DecodeLimits, DecoderBuffer, Mesh, MeshDecoder, PointAttribute, PointIndex};

/// The Draco unique ids of the attributes read, from the extension's
/// `attributes` map.
pub(super) struct AttributeIds {
    pub(super) position: u32,
    pub(super) normal: Option<u32>,
    pub(super) uv: Option<u32>,
}

/// The most a decode may produce: the glTF accessors' counts and the memory
/// budget's spare bytes.
pub(super) struct Limits {
    pub(super) points: u64,
    pub(super) faces: u64,
    pub(super) bytes: u64,
}

/// A decoded primitive: `points` vertices, each with 3 position components
/// (and 3 normal and 2 texture components when asked for), and three corners
/// a face, each below `points`.
pub(super) struct Decoded {
    pub(super) points: usize,
    pub(super) positions: Vec<f32>,
    pub(super) normals: Option<Vec<f32>>,
    pub(super) uvs: Option<Vec<f32>>,
    pub(super) corners: Vec<u32>,
}

/// Decodes `stream`, a Draco mesh, keeping the attributes of `ids`; an error
/// is a message saying why, without the primitive's name.
pub(super) fn decode(stream: &[u8], ids: &AttributeIds, limits: &Limits) -> Result<Decoded, String> {
    let ceilings = DecodeLimits::default()
        .with_max_points(limits.points)
        .with_max_faces(limits.faces)
        .with_max_decoded_bytes(limits.bytes);
    let mut buffer = DecoderBuffer::new(stream).with_limits(ceilings);
    let mut mesh = Mesh::new();
    MeshDecoder::new()
        .decode(&mut buffer, &mut mesh)
        .map_err(|e| e.to_string())?;
    let points = mesh.num_points();
    let faces = mesh.faces();
    // A point-cloud stream decodes to no face, a mesh stream to at least one
    // (the decoder refuses an empty one).
    if faces.is_empty() {
        return Err("the stream holds no triangles (a point cloud?)".into());
    }
    let mut corners = Vec::new();
    corners
        .try_reserve_exact(faces.len() * 3)
        .map_err(|_| format!("cannot allocate {} triangles", faces.len()))?;
    for (f, face) in faces.iter().enumerate() {
        for PointIndex(v) in face {
            if *v as usize >= points {
                return Err(format!("face {f} uses point {v}, but the stream has {points} points"));
            }
            corners.push(*v);
        }
    }
    let read = |name: &str, id: u32, components: usize| -> Result<Vec<f32>, String> {
        let attribute = mesh
            .attribute_by_unique_id(id)
            .ok_or_else(|| format!("{name} names attribute id {id}, which the stream does not hold"))?;
        values(attribute, points, components).map_err(|why| format!("{name} (attribute id {id}): {why}"))
    };
    Ok(Decoded {
        points,
        positions: read("POSITION", ids.position, 3)?,
        normals: ids.normal.map(|id| read("NORMAL", id, 3)).transpose()?,
        uvs: ids.uv.map(|id| read("TEXCOORD_0", id, 2)).transpose()?,
        corners,
    })
}

/// The `components` values of each of `points` points, as f32.
fn values(attribute: &PointAttribute, points: usize, components: usize) -> Result<Vec<f32>, String> {
    if usize::from(attribute.num_components()) != components {
        return Err(format!("{} components, not {components}", attribute.num_components()));
    }
    // `read_f32s` gives zeros for a point mapped past the values: corrupt
    // data, refused rather than read as the origin.
    let size = attribute.size();
    if let Some(p) = (0..points).find(|&p| attribute.mapped_index(PointIndex(p as u32)).0 as usize >= size) {
        return Err(format!("point {p} maps past the {size} values"));
    }
    // What glTF's `normalized` integer types mean; quantized attributes are
    // already floats again, and plain integers are read as they are.
    let scale = match attribute.data_type() {
        _ if !attribute.normalized() => None,
        DataType::Int8 => Some(127.0),
        DataType::Uint8 => Some(255.0),
        DataType::Int16 => Some(32767.0),
        DataType::Uint16 => Some(65535.0),
        DataType::Uint32 => Some(4294967295.0),
        _ => None,
    };
    let mut values = attribute.read_f32s(points, components);
    if let Some(scale) = scale {
        for v in &mut values {
            *v = (f64::from(*v) / scale).max(-1.0) as f32;
        }
    }
    // Damaged float data decodes to anything; refused here, where the
    // message can name the primitive.
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(format!("the value of point {} is not finite", i / components));
    }
    Ok(values)
}
