//! Object File Format: header, counts, one vertex per line, one face per line.

use super::read::Budget;
use super::text::{
    Faces, Lines, check_finite, error_at, implausible, parse_f32, parse_int, parse_uint, show, strip_comment, syntax,
    tokens, truncated,
};
use crate::error::{LoadError, MeshError};
use crate::math::Vec3;
use crate::mesh::Mesh;
use std::path::Path;

/// Fewest bytes a vertex line can take: `0 0 0\n`.
const MIN_VERTEX_BYTES: usize = 6;
/// Fewest bytes a face line can take: `3 0 1 2\n`.
const MIN_FACE_BYTES: usize = 8;

/// The next line holding something other than whitespace and comments, with
/// the comment removed.
fn next_content<'a>(lines: &mut Lines<'a>) -> Option<(usize, &'a [u8])> {
    lines.find_map(|(number, line)| {
        let line = strip_comment(line);
        (!line.trim_ascii().is_empty()).then_some((number, line))
    })
}

/// Checks an `OFF` header keyword: `[ST][C][N]OFF`. `Err` holds a message.
fn check_header(keyword: &[u8]) -> Result<(), String> {
    let mut rest = keyword;
    for prefix in [&b"ST"[..], b"C", b"N"] {
        rest = rest.strip_prefix(prefix).unwrap_or(rest);
    }
    match rest {
        b"OFF" => Ok(()),
        b"4OFF" | b"nOFF" | b"4nOFF" => Err(format!("`{}`: only 3D OFF is supported", show(keyword))),
        _ => Err(format!("expected an `OFF` header, found `{}`", show(keyword))),
    }
}

/// Parses a count token.
fn count(token: Option<&[u8]>, what: &str, line: usize, path: &Path) -> Result<usize, LoadError> {
    let token = token.ok_or_else(|| syntax(path, Some(line), format!("missing {what} count")))?;
    parse_uint(token)
        .map(|n| usize::try_from(n).unwrap_or(usize::MAX))
        .ok_or_else(|| syntax(path, Some(line), format!("bad {what} count `{}`", show(token))))
}

pub(super) fn parse(bytes: &[u8], path: &Path, budget: Budget) -> Result<Mesh, LoadError> {
    let mut lines = Lines::new(bytes, 1);
    let Some((mut line, mut text)) = next_content(&mut lines) else {
        return Err(truncated(
            path,
            Some(lines.line().max(1)),
            "empty file: expected an `OFF` header",
        ));
    };
    // The header keyword is optional: a first line starting with a number holds the counts.
    let mut fields = tokens(text);
    if let Some(first) = tokens(text).next().filter(|t| parse_int(t).is_none()) {
        check_header(first).map_err(|m| syntax(path, Some(line), m))?;
        fields.next();
        if let Some(extra) = tokens(text).nth(1).filter(|t| parse_int(t).is_none()) {
            let message = format!("`{}` OFF is not supported (only ascii OFF)", show(extra));
            return Err(syntax(path, Some(line), message));
        }
        if tokens(text).nth(1).is_none() {
            (line, text) = next_content(&mut lines)
                .ok_or_else(|| truncated(path, Some(lines.line()), "expected the vertex and face counts"))?;
            fields = tokens(text);
        }
    }
    let vertex_count = count(fields.next(), "vertex", line, path)?;
    let face_count = count(fields.next(), "face", line, path)?;
    let remaining = lines.rest().len();
    // Every vertex and face takes at least 2 bytes (a value and a separator).
    if vertex_count.saturating_add(face_count).saturating_mul(2) > remaining.saturating_add(1) {
        let message = format!(
            "the header announces {vertex_count} vertices and {face_count} faces, but only {remaining} bytes follow"
        );
        return Err(implausible(path, Some(line), message));
    }
    // The memory budget, before the data is read: each face is at least a triangle.
    budget
        .check(bytes.len() as u64, vertex_count as u64, face_count as u64, false)
        .map_err(|kind| error_at(path, Some(line), kind))?;

    if vertex_count > u32::MAX as usize {
        let error = MeshError::TooLarge {
            what: "vertices",
            count: vertex_count,
        };
        return Err(error_at(path, Some(line), error));
    }
    let mut positions = Vec::with_capacity(vertex_count.min(remaining / MIN_VERTEX_BYTES));
    for index in 0..vertex_count {
        let Some((line, text)) = next_content(&mut lines) else {
            let message = format!("the header announces {vertex_count} vertices, but the file has {index}");
            return Err(truncated(path, Some(lines.line()), message));
        };
        let mut fields = tokens(text);
        let mut xyz = [0.0f32; 3];
        for (axis, value) in xyz.iter_mut().enumerate() {
            let Some(token) = fields.next() else {
                return Err(syntax(
                    path,
                    Some(line),
                    format!("vertex has {axis} coordinates; it needs 3"),
                ));
            };
            *value =
                parse_f32(token).ok_or_else(|| syntax(path, Some(line), format!("bad number `{}`", show(token))))?;
        }
        positions.push(check_finite(Vec3::from_array(xyz), index, path, Some(line))?);
    }

    let remaining = lines.rest().len();
    let capacity = face_count.min(remaining / MIN_FACE_BYTES);
    let mut faces = Faces::with_capacity(capacity, capacity.saturating_mul(3));
    for face in 0..face_count {
        let Some((line, text)) = next_content(&mut lines) else {
            let message = format!("the header announces {face_count} faces, but the file has {face}");
            return Err(truncated(path, Some(lines.line()), message));
        };
        let mut fields = tokens(text);
        let size = fields.next().unwrap_or_default();
        let size = parse_int(size)
            .and_then(|n| usize::try_from(n).ok())
            .ok_or_else(|| syntax(path, Some(line), format!("bad face size `{}`", show(size))))?;
        for listed in 0..size {
            let Some(token) = fields.next() else {
                let message = format!("face announces {size} vertices but lists {listed}");
                return Err(syntax(path, Some(line), message));
            };
            let index = parse_int(token)
                .ok_or_else(|| syntax(path, Some(line), format!("bad vertex index `{}`", show(token))))?;
            if index < 0 {
                return Err(syntax(path, Some(line), format!("negative vertex index {index}")));
            }
            if index as u64 >= vertex_count as u64 {
                let error = MeshError::IndexOutOfRange {
                    face,
                    vertex: index as u64,
                    vertex_count,
                };
                return Err(error_at(path, Some(line), error));
            }
            faces.push(index as u32);
        }
        faces.close().map_err(|e| error_at(path, Some(line), e))?;
    }
    if let Some((line, text)) = next_content(&mut lines) {
        let message = format!(
            "unexpected `{}` after the {face_count} faces the header announces",
            show(tokens(text).next().unwrap_or_default())
        );
        return Err(syntax(path, Some(line), message));
    }
    faces.finish(positions, path)
}
