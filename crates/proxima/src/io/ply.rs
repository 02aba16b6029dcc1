//! PLY (Polygon File Format), ascii and binary of both byte orders.

use super::read::Budget;
use super::text::{
    Faces, Lines, TokenStream, check_finite, error_at, implausible, parse_f32, parse_int, parse_uint, show, syntax,
    tokens, truncated,
};
use crate::error::{LoadError, MeshError};
use crate::math::Vec3;
use crate::mesh::Mesh;
use std::path::Path;

/// A scalar property type.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &[u8]) -> Option<Self> {
        Some(match name {
            b"char" | b"int8" => Scalar::I8,
            b"uchar" | b"uint8" => Scalar::U8,
            b"short" | b"int16" => Scalar::I16,
            b"ushort" | b"uint16" => Scalar::U16,
            b"int" | b"int32" => Scalar::I32,
            b"uint" | b"uint32" => Scalar::U32,
            b"float" | b"float32" => Scalar::F32,
            b"double" | b"float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Size in bytes in binary files.
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// How the data after the header is stored.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Encoding {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

/// A property's layout.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Scalar(Scalar),
    /// `list <count type> <item type>`.
    List(Scalar, Scalar),
}

/// What a property means to us.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// A vertex value: coordinate 0, 1 or 2, normal component 3, 4 or 5
    /// (`nx ny nz`), texture coordinate 6 or 7 ([`UV_NAMES`]).
    Coordinate(usize),
    /// The index list of a face.
    Indices,
    Skip,
}

#[derive(Debug)]
struct Property<'a> {
    name: &'a [u8],
    kind: Kind,
    role: Role,
}

#[derive(Debug)]
struct Element<'a> {
    name: &'a [u8],
    count: u64,
    /// Header line that declares the element.
    line: usize,
    properties: Vec<Property<'a>>,
}

impl Element<'_> {
    /// Fewest bytes one element takes: binary, its exact minimum (lists empty);
    /// ascii, two per value (a digit and a separator; a list at least its count).
    fn min_bytes(&self, encoding: Encoding) -> u64 {
        let per_property = |p: &Property| match (encoding, p.kind) {
            (Encoding::Ascii, _) => 2,
            (_, Kind::Scalar(t) | Kind::List(t, _)) => t.size() as u64,
        };
        self.properties.iter().map(per_property).sum()
    }
}

/// The parsed header.
struct Header<'a> {
    encoding: Encoding,
    elements: Vec<Element<'a>>,
    /// Index of the vertex element in `elements`.
    vertex: usize,
    /// 1-based line where the data starts (for ascii).
    data_line: usize,
    /// The bytes after the header.
    data: &'a [u8],
}

pub(super) fn parse(bytes: &[u8], path: &Path, budget: Budget) -> Result<Mesh, LoadError> {
    let header = parse_header(bytes, path)?;
    let vertex_count = header.elements.get(header.vertex).map_or(0, |e| e.count);
    // The memory budget, before the data is read: each face is at least a triangle.
    let faces = header
        .elements
        .iter()
        .find(|e| has_role(e, |r| r == Role::Indices))
        .map_or(0, |e| e.count);
    budget
        .check(bytes.len() as u64, vertex_count, faces, false)
        .map_err(|kind| error_at(path, Some(header.data_line - 1), kind))?;
    // `parse_header` checked that the counts fit the data (so fit in memory) and
    // that the vertex count fits 32-bit indices.
    let vertex_count = usize::try_from(vertex_count).unwrap_or(usize::MAX);
    let vertex_has = |slot: usize| {
        let vertex = header.elements.get(header.vertex);
        vertex.is_some_and(|e| has_role(e, |r| r == Role::Coordinate(slot)))
    };
    let mut reader = Reader {
        path,
        vertex_count,
        positions: Vec::new(),
        normals: vertex_has(3).then(Vec::new),
        uvs: vertex_has(6).then(Vec::new),
        faces: Faces::with_capacity(0, 0),
        encoding: header.encoding,
    };
    let data_len = header.data.len() as u64;
    match header.encoding {
        Encoding::Ascii => {
            let mut tokens = TokenStream::new(header.data, header.data_line);
            for element in &header.elements {
                reader.reserve(element, data_len);
                reader.ascii_element(element, &mut tokens)?;
            }
            if let Some(token) = tokens.next_token() {
                let message = format!("unexpected `{}` after the last element", show(token));
                return Err(syntax(path, Some(tokens.line()), message));
            }
        }
        Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
            let mut pos = 0;
            for element in &header.elements {
                reader.reserve(element, data_len.saturating_sub(pos as u64));
                reader.binary_element(element, header.data, &mut pos)?;
            }
        }
    }
    let Reader {
        normals,
        uvs,
        faces,
        positions,
        ..
    } = reader;
    let mut mesh = faces.finish(positions, path)?;
    // Per-vertex values, given to each corner that uses the vertex.
    let indices: Vec<u32> = mesh.faces().flatten().copied().collect();
    if let Some(uvs) = uvs {
        let corners = indices.iter().map(|&v| uvs[v as usize]).collect();
        mesh = mesh.with_corner_uvs(corners).map_err(|e| error_at(path, None, e))?;
    }
    if let Some(normals) = normals {
        let corners = indices.iter().map(|&v| normals[v as usize]).collect();
        mesh = mesh.with_corner_normals(corners).map_err(|e| error_at(path, None, e))?;
    }
    Ok(mesh)
}

/// Reads the header: magic, format, elements and their properties.
fn parse_header<'a>(bytes: &'a [u8], path: &Path) -> Result<Header<'a>, LoadError> {
    let mut lines = Lines::new(bytes, 1);
    if lines.next().is_none_or(|(_, magic)| magic.trim_ascii_end() != b"ply") {
        return Err(syntax(path, Some(1), "not a PLY file: the first line must be `ply`"));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let end_line = loop {
        let Some((line, text)) = lines.next() else {
            return Err(truncated(path, Some(lines.line()), "the header has no `end_header`"));
        };
        let mut fields = tokens(text);
        let keyword = fields.next().unwrap_or_default();
        match keyword {
            b"" | b"comment" | b"obj_info" => {}
            b"end_header" => break line,
            b"format" => {
                encoding = Some(match fields.next().unwrap_or_default() {
                    b"ascii" => Encoding::Ascii,
                    b"binary_little_endian" => Encoding::BinaryLittleEndian,
                    b"binary_big_endian" => Encoding::BinaryBigEndian,
                    other => {
                        return Err(syntax(
                            path,
                            Some(line),
                            format!("unknown PLY format `{}`", show(other)),
                        ));
                    }
                });
                if fields.next().is_none() {
                    return Err(syntax(path, Some(line), "missing format version"));
                }
            }
            b"element" => {
                let (Some(name), Some(count)) = (fields.next(), fields.next()) else {
                    return Err(syntax(path, Some(line), "expected `element <name> <count>`"));
                };
                let count = parse_uint(count)
                    .ok_or_else(|| syntax(path, Some(line), format!("bad element count `{}`", show(count))))?;
                elements.push(Element {
                    name,
                    count,
                    line,
                    properties: Vec::new(),
                });
            }
            b"property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(syntax(path, Some(line), "`property` before any `element`"));
                };
                let scalar = |name: Option<&[u8]>| {
                    let name = name.unwrap_or_default();
                    Scalar::from_name(name)
                        .ok_or_else(|| syntax(path, Some(line), format!("unknown property type `{}`", show(name))))
                };
                let first = fields.next();
                let kind = if first == Some(b"list") {
                    let count = scalar(fields.next())?;
                    if !count.is_integer() {
                        return Err(syntax(path, Some(line), "a list count must have an integer type"));
                    }
                    Kind::List(count, scalar(fields.next())?)
                } else {
                    Kind::Scalar(scalar(first)?)
                };
                let Some(name) = fields.next() else {
                    return Err(syntax(path, Some(line), "missing property name"));
                };
                element.properties.push(Property {
                    name,
                    kind,
                    role: Role::Skip,
                });
            }
            other => {
                return Err(syntax(
                    path,
                    Some(line),
                    format!("unknown header keyword `{}`", show(other)),
                ));
            }
        }
    };
    let Some(encoding) = encoding else {
        return Err(syntax(path, Some(end_line), "the header has no `format` line"));
    };
    let data = lines.rest();
    let vertex = assign_roles(&mut elements, end_line, path)?;

    // Sizes, before anything is allocated.
    let available = data.len() as u128 + u128::from(encoding == Encoding::Ascii);
    let mut needed: u128 = 0;
    for element in &elements {
        needed += u128::from(element.count) * u128::from(element.min_bytes(encoding));
        if needed > available {
            let message = format!(
                "the header announces {} `{}` elements, more than the {} bytes of data can hold",
                element.count,
                show(element.name),
                data.len()
            );
            return Err(implausible(path, Some(element.line), message));
        }
    }
    if let Some(element) = elements.get(vertex).filter(|e| e.count > u64::from(u32::MAX)) {
        let error = MeshError::TooLarge {
            what: "vertices",
            count: usize::try_from(element.count).unwrap_or(usize::MAX),
        };
        return Err(error_at(path, Some(element.line), error));
    }
    Ok(Header {
        encoding,
        elements,
        vertex,
        data_line: end_line + 1,
        data,
    })
}

/// The names of a vertex's normal.
const NORMAL_NAMES: [&[u8]; 3] = [b"nx", b"ny", b"nz"];

/// The names a vertex's texture coordinates go by, in order of preference.
const UV_NAMES: [[&[u8]; 2]; 4] = [
    [b"u", b"v"],
    [b"s", b"t"],
    [b"texture_u", b"texture_v"],
    [b"texture_s", b"texture_t"],
];

/// The vertex values read: x, y, z, nx, ny, nz, u, v.
const VERTEX_VALUES: usize = 8;

/// Marks the vertex values (the first of [`UV_NAMES`] whose two scalars are
/// both there, and `nx ny nz` when all three are scalars there) and the
/// face-index properties; returns the index of the vertex element.
fn assign_roles(elements: &mut [Element], end_line: usize, path: &Path) -> Result<usize, LoadError> {
    let mut vertex = None;
    let mut face_seen = false;
    for (e, element) in elements.iter_mut().enumerate() {
        match element.name {
            b"vertex" => {
                if vertex.replace(e).is_some() {
                    return Err(syntax(path, Some(element.line), "a second `element vertex`"));
                }
                for (axis, name) in [b"x", b"y", b"z"].into_iter().enumerate() {
                    let Some(property) = element.properties.iter_mut().find(|p| p.name == name) else {
                        let message = format!("`element vertex` has no property `{}`", show(name));
                        return Err(syntax(path, Some(element.line), message));
                    };
                    if matches!(property.kind, Kind::List(..)) {
                        let message = format!("vertex property `{}` is a list", show(name));
                        return Err(syntax(path, Some(element.line), message));
                    }
                    property.role = Role::Coordinate(axis);
                }
                let optional: Vec<&[&[u8]]> = std::iter::once(&NORMAL_NAMES[..])
                    .chain(UV_NAMES.iter().map(|names| &names[..]))
                    .collect();
                let mut uv_found = false;
                for (group, names) in optional.into_iter().enumerate() {
                    if group > 0 && uv_found {
                        break;
                    }
                    let scalar = |name: &[u8]| {
                        element
                            .properties
                            .iter()
                            .position(|p| p.name == name && matches!(p.kind, Kind::Scalar(_)))
                    };
                    let found: Option<Vec<usize>> = names.iter().map(|n| scalar(n)).collect();
                    if let Some(found) = found {
                        let first = if group == 0 { 3 } else { 6 };
                        for (k, property) in found.into_iter().enumerate() {
                            element.properties[property].role = Role::Coordinate(first + k);
                        }
                        uv_found = group > 0;
                    }
                }
            }
            b"face" => {
                if std::mem::replace(&mut face_seen, true) {
                    return Err(syntax(path, Some(element.line), "a second `element face`"));
                }
                let indices = element
                    .properties
                    .iter_mut()
                    .find(|p| matches!(p.name, b"vertex_indices" | b"vertex_index"));
                let Some(property) = indices else {
                    let message = "`element face` has no `vertex_indices` (or `vertex_index`) list";
                    return Err(syntax(path, Some(element.line), message));
                };
                match property.kind {
                    Kind::List(_, item) if item.is_integer() => property.role = Role::Indices,
                    _ => {
                        let message = "`vertex_indices` must be a list of an integer type";
                        return Err(syntax(path, Some(element.line), message));
                    }
                }
            }
            _ => {}
        }
    }
    vertex.ok_or_else(|| syntax(path, Some(end_line), "the header has no `element vertex`"))
}

/// The parse state shared by the ascii and binary readers.
struct Reader<'p> {
    path: &'p Path,
    vertex_count: usize,
    positions: Vec<Vec3>,
    /// Per vertex, when the header names them.
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<[f32; 2]>>,
    faces: Faces,
    encoding: Encoding,
}

impl Reader<'_> {
    /// Reserves room for `element` if it is the vertex or face element, by what
    /// the `remaining` bytes allow.
    fn reserve(&mut self, element: &Element, remaining: u64) {
        let capacity = |min_bytes: u64| {
            let fits = remaining / min_bytes.max(1);
            usize::try_from(element.count.min(fits)).unwrap_or(usize::MAX)
        };
        let min_bytes = element.min_bytes(self.encoding);
        if has_role(element, |r| matches!(r, Role::Coordinate(_))) {
            self.positions.reserve_exact(capacity(min_bytes));
        } else if has_role(element, |r| r == Role::Indices) {
            // Typical faces are triangles: 3 indices more than the minimum.
            let per_face = match (self.encoding, indices_kind(element)) {
                (Encoding::Ascii, _) => 6,
                (_, Some(Kind::List(_, item))) => 3 * item.size() as u64,
                _ => 0,
            };
            let faces = capacity(min_bytes + per_face);
            self.faces = Faces::with_capacity(faces, faces.saturating_mul(3));
        }
    }

    /// Reads all `element`s of an ascii file.
    fn ascii_element<'a>(&mut self, element: &Element, tokens: &mut TokenStream<'a>) -> Result<(), LoadError> {
        if element.properties.is_empty() {
            return Ok(());
        }
        let is_vertex = has_role(element, |r| matches!(r, Role::Coordinate(_)));
        for i in 0..element.count {
            let mut xyz = [0.0f32; VERTEX_VALUES];
            for property in &element.properties {
                let next = |tokens: &mut TokenStream<'a>| next_value(tokens, element, i, self.path);
                match (property.kind, property.role) {
                    (Kind::Scalar(t), Role::Coordinate(axis)) => {
                        let token = next(tokens)?;
                        let value = ascii_value(t, token, "number")
                            .map_err(|message| syntax(self.path, Some(tokens.line()), message))?;
                        if let Some(slot) = xyz.get_mut(axis) {
                            *slot = value;
                        }
                    }
                    (Kind::Scalar(t), _) => {
                        let token = next(tokens)?;
                        ascii_value(t, token, "number")
                            .map_err(|message| syntax(self.path, Some(tokens.line()), message))?;
                    }
                    (Kind::List(count, item), role) => {
                        let token = next(tokens)?;
                        let line = tokens.line();
                        let len = ascii_integer(count, token, "list length")
                            .and_then(|n| u64::try_from(n).map_err(|_| format!("bad list length `{}`", show(token))))
                            .map_err(|message| syntax(self.path, Some(line), message))?;
                        for _ in 0..len {
                            let token = tokens.next_token().ok_or_else(|| {
                                let message = format!("a list of {len} values ends early");
                                truncated(self.path, Some(tokens.line()), message)
                            })?;
                            if role == Role::Indices {
                                let index = ascii_integer(item, token, "vertex index")
                                    .map_err(|message| syntax(self.path, Some(tokens.line()), message))?;
                                self.push_index(index, Some(tokens.line()))?;
                            } else {
                                ascii_value(item, token, "number")
                                    .map_err(|message| syntax(self.path, Some(tokens.line()), message))?;
                            }
                        }
                        if role == Role::Indices {
                            self.faces.close().map_err(|e| error_at(self.path, Some(line), e))?;
                        }
                    }
                }
            }
            // An element ends its line: a value left over means the header and
            // the data disagree, and the line to blame is this one.
            let line = tokens.line();
            if let Some(extra) = super::text::tokens(tokens.rest_of_line()).next() {
                let message = format!(
                    "unexpected `{}` after the {} values of `{}` element number {}",
                    show(extra),
                    element.properties.len(),
                    show(element.name),
                    i + 1
                );
                return Err(syntax(self.path, Some(line), message));
            }
            if is_vertex {
                self.vertex(xyz, Some(line))?;
            }
        }
        Ok(())
    }

    /// Reads all `element`s of a binary file from `data[*pos..]`.
    fn binary_element(&mut self, element: &Element, data: &[u8], pos: &mut usize) -> Result<(), LoadError> {
        if element.properties.is_empty() {
            return Ok(());
        }
        let big_endian = self.encoding == Encoding::BinaryBigEndian;
        let is_vertex = has_role(element, |r| matches!(r, Role::Coordinate(_)));
        for i in 0..element.count {
            let ended = |pos: usize| {
                let message = format!(
                    "the header announces {} `{}` elements, but the data ends in number {} (byte {} of the data)",
                    element.count,
                    show(element.name),
                    i + 1,
                    pos
                );
                truncated(self.path, None, message)
            };
            let mut xyz = [0.0f32; VERTEX_VALUES];
            for property in &element.properties {
                match (property.kind, property.role) {
                    (Kind::Scalar(t), Role::Coordinate(axis)) => {
                        let value = read_f64(data, pos, t, big_endian).ok_or_else(|| ended(*pos))?;
                        if let Some(slot) = xyz.get_mut(axis) {
                            *slot = value as f32;
                        }
                    }
                    (Kind::Scalar(t), _) => {
                        skip(data, pos, t.size() as u64).ok_or_else(|| ended(*pos))?;
                    }
                    (Kind::List(count, item), role) => {
                        let len = read_int(data, pos, count, big_endian).ok_or_else(|| ended(*pos))?;
                        let len = u64::try_from(len).map_err(|_| {
                            syntax(
                                self.path,
                                None,
                                format!("negative list length {len} in element {}", i + 1),
                            )
                        })?;
                        if role == Role::Indices {
                            if len.saturating_mul(item.size() as u64) > (data.len() - *pos) as u64 {
                                return Err(ended(*pos));
                            }
                            for _ in 0..len {
                                let index = read_int(data, pos, item, big_endian).ok_or_else(|| ended(*pos))?;
                                self.push_index(index, None)?;
                            }
                            self.faces.close().map_err(|e| error_at(self.path, None, e))?;
                        } else {
                            skip(data, pos, len.saturating_mul(item.size() as u64)).ok_or_else(|| ended(*pos))?;
                        }
                    }
                }
            }
            if is_vertex {
                self.vertex(xyz, None)?;
            }
        }
        Ok(())
    }

    /// Keeps a vertex's values: its position, and its normal and texture
    /// coordinates when the header has them.
    fn vertex(&mut self, values: [f32; VERTEX_VALUES], line: Option<usize>) -> Result<(), LoadError> {
        let p = Vec3::new(values[0], values[1], values[2]);
        self.positions
            .push(check_finite(p, self.positions.len(), self.path, line)?);
        let index = self.positions.len() - 1;
        let not_finite = |what: &str| syntax(self.path, line, format!("vertex {index}: {what} is not finite"));
        if let Some(normals) = &mut self.normals {
            let n = Vec3::new(values[3], values[4], values[5]);
            if !n.is_finite() {
                return Err(not_finite("its normal"));
            }
            normals.push(n);
        }
        if let Some(uvs) = &mut self.uvs {
            if !(values[6].is_finite() && values[7].is_finite()) {
                return Err(not_finite("its texture coordinate"));
            }
            uvs.push([values[6], values[7]]);
        }
        Ok(())
    }

    /// Adds a vertex index to the face being read, checking its range.
    #[inline]
    fn push_index(&mut self, index: i64, line: Option<usize>) -> Result<(), LoadError> {
        if index < 0 {
            return Err(syntax(self.path, line, format!("negative vertex index {index}")));
        }
        match u32::try_from(index) {
            Ok(i) if (i as usize) < self.vertex_count => {
                self.faces.push(i);
                Ok(())
            }
            _ => {
                let error = MeshError::IndexOutOfRange {
                    face: self.faces.count(),
                    vertex: index as u64,
                    vertex_count: self.vertex_count,
                };
                Err(error_at(self.path, line, error))
            }
        }
    }
}

/// The next value of element number `i` (0-based) of `element`.
#[inline]
fn next_value<'a>(tokens: &mut TokenStream<'a>, element: &Element, i: u64, path: &Path) -> Result<&'a [u8], LoadError> {
    tokens.next_token().ok_or_else(|| {
        let message = format!(
            "the header announces {} `{}` elements, but the data ends in number {}",
            element.count,
            show(element.name),
            i + 1
        );
        truncated(path, Some(tokens.line()), message)
    })
}

/// An ascii value of type `t` as a coordinate: an integer type takes an
/// integer within its range (`uchar 300` is an error), a float type any number
/// `f32` parsing accepts (the caller checks finiteness).
fn ascii_value(t: Scalar, token: &[u8], what: &str) -> Result<f32, String> {
    if t.is_integer() {
        ascii_integer(t, token, what).map(|v| v as f32)
    } else {
        parse_f32(token).ok_or_else(|| format!("bad {what} `{}`", show(token)))
    }
}

/// An ascii integer of type `t`, within its range.
fn ascii_integer(t: Scalar, token: &[u8], what: &str) -> Result<i64, String> {
    let (min, max, name) = match t {
        Scalar::I8 => (i8::MIN.into(), i8::MAX.into(), "char"),
        Scalar::U8 => (0, u8::MAX.into(), "uchar"),
        Scalar::I16 => (i16::MIN.into(), i16::MAX.into(), "short"),
        Scalar::U16 => (0, u16::MAX.into(), "ushort"),
        Scalar::I32 => (i32::MIN.into(), i32::MAX.into(), "int"),
        Scalar::U32 => (0, u32::MAX.into(), "uint"),
        Scalar::F32 | Scalar::F64 => return Err(format!("a {what} must have an integer type")),
    };
    let value = parse_int(token).ok_or_else(|| format!("bad {what} `{}`", show(token)))?;
    if !(min..=max).contains(&value) {
        return Err(format!(
            "{what} {value} is out of the range of its type `{name}` ({min} to {max})"
        ));
    }
    Ok(value)
}

/// `true` when some property of `element` has a role matching `f`.
fn has_role(element: &Element, f: impl Fn(Role) -> bool) -> bool {
    element.properties.iter().any(|p| f(p.role))
}

/// The layout of the face-index list of `element`, if it has one.
fn indices_kind(element: &Element) -> Option<Kind> {
    element
        .properties
        .iter()
        .find(|p| p.role == Role::Indices)
        .map(|p| p.kind)
}

/// Advances `pos` by `n` bytes, or `None` when fewer remain.
#[inline]
fn skip(data: &[u8], pos: &mut usize, n: u64) -> Option<()> {
    let end = u64::try_from(*pos).ok()?.checked_add(n)?;
    if end > data.len() as u64 {
        return None;
    }
    *pos = end as usize;
    Some(())
}

/// The `N` bytes at `*pos`, advancing `pos`.
#[inline]
fn take<const N: usize>(data: &[u8], pos: &mut usize) -> Option<[u8; N]> {
    let bytes = data.get(*pos..pos.checked_add(N)?)?;
    *pos += N;
    bytes.try_into().ok()
}

/// Reads a scalar of type `t` as `f64` (exact for every type).
#[inline]
fn read_f64(data: &[u8], pos: &mut usize, t: Scalar, big_endian: bool) -> Option<f64> {
    macro_rules! read {
        ($ty:ty) => {{
            let bytes = take(data, pos)?;
            if big_endian {
                <$ty>::from_be_bytes(bytes)
            } else {
                <$ty>::from_le_bytes(bytes)
            }
        }};
    }
    Some(match t {
        Scalar::I8 => f64::from(read!(i8)),
        Scalar::U8 => f64::from(read!(u8)),
        Scalar::I16 => f64::from(read!(i16)),
        Scalar::U16 => f64::from(read!(u16)),
        Scalar::I32 => f64::from(read!(i32)),
        Scalar::U32 => f64::from(read!(u32)),
        Scalar::F32 => f64::from(read!(f32)),
        Scalar::F64 => read!(f64),
    })
}

/// Reads an integer scalar of type `t`; `None` at the end of the data or for a
/// float type (the header checks rule that out for counts and indices).
#[inline]
fn read_int(data: &[u8], pos: &mut usize, t: Scalar, big_endian: bool) -> Option<i64> {
    macro_rules! read {
        ($ty:ty) => {{
            let bytes = take(data, pos)?;
            i64::from(if big_endian {
                <$ty>::from_be_bytes(bytes)
            } else {
                <$ty>::from_le_bytes(bytes)
            })
        }};
    }
    Some(match t {
        Scalar::I8 => read!(i8),
        Scalar::U8 => read!(u8),
        Scalar::I16 => read!(i16),
        Scalar::U16 => read!(u16),
        Scalar::I32 => read!(i32),
        Scalar::U32 => read!(u32),
        Scalar::F32 | Scalar::F64 => return None,
    })
}
