//! Wavefront OBJ: `v` and `f` statements; everything else is ignored.

use super::text::{Faces, Lines, check_finite, error_at, parse_f32, parse_int, show, strip_comment, syntax, tokens};
use crate::error::{LoadError, MeshError};
use crate::math::Vec3;
use crate::mesh::Mesh;
use std::path::Path;

/// A face that refers to a vertex not yet defined when the face was read.
struct ForwardRef {
    line: usize,
    face: usize,
    vertex: u32,
}

/// The parser state: what has been read so far.
struct Obj<'p> {
    path: &'p Path,
    positions: Vec<Vec3>,
    faces: Faces,
    /// Forward references with strictly increasing `vertex`, so the first one
    /// beyond the final vertex count is the first offending face in the file.
    forward: Vec<ForwardRef>,
}

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<Mesh, LoadError> {
    // Rough guesses from typical line lengths; the vectors grow if needed.
    let mut obj = Obj {
        path,
        positions: Vec::with_capacity(bytes.len() / 80),
        faces: Faces::with_capacity(bytes.len() / 40, bytes.len() / 13),
        forward: Vec::new(),
    };
    let mut lines = Lines::new(bytes, 1);
    // A logical line made of several physical ones joined by a trailing `\`.
    let mut joined: Vec<u8> = Vec::new();
    let mut joined_line = 0;
    for (number, line) in &mut lines {
        let line = strip_comment(line).trim_ascii_end();
        if let Some(head) = line.strip_suffix(b"\\") {
            if joined.is_empty() {
                joined_line = number;
            }
            joined.extend_from_slice(head);
            joined.push(b' ');
            continue;
        }
        if joined.is_empty() {
            obj.statement(number, line)?;
        } else {
            joined.extend_from_slice(line);
            obj.statement(joined_line, &joined)?;
            joined.clear();
        }
    }
    if !joined.is_empty() {
        obj.statement(joined_line, &joined)?;
    }
    let count = obj.positions.len();
    if let Some(bad) = obj.forward.iter().find(|f| f.vertex as usize >= count) {
        let error = MeshError::IndexOutOfRange {
            face: bad.face,
            vertex: u64::from(bad.vertex),
            vertex_count: count,
        };
        return Err(error_at(path, Some(bad.line), error));
    }
    obj.faces.finish(obj.positions, path)
}

impl Obj<'_> {
    /// Handles one logical line (comments already removed).
    #[inline]
    fn statement(&mut self, line: usize, text: &[u8]) -> Result<(), LoadError> {
        let mut tokens = tokens(text);
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        match keyword {
            b"v" => self.vertex(line, tokens),
            b"f" => self.face(line, tokens),
            _ if keyword.first().is_some_and(u8::is_ascii_alphabetic) => Ok(()),
            _ => Err(syntax(
                self.path,
                Some(line),
                format!("unknown statement `{}`", show(keyword)),
            )),
        }
    }

    /// `v x y z`, `v x y z w` or `v x y z r g b`.
    fn vertex<'t>(&mut self, line: usize, mut tokens: impl Iterator<Item = &'t [u8]>) -> Result<(), LoadError> {
        let mut xyz = [0.0f32; 3];
        for (axis, value) in xyz.iter_mut().enumerate() {
            let Some(token) = tokens.next() else {
                let message = format!("vertex has {axis} coordinates; it needs 3");
                return Err(syntax(self.path, Some(line), message));
            };
            *value = parse_f32(token)
                .ok_or_else(|| syntax(self.path, Some(line), format!("bad number `{}`", show(token))))?;
        }
        // `w`, or the `r g b` of the vertex-colour extension: checked, then ignored.
        let mut extra = 0;
        for token in tokens {
            parse_f32(token).ok_or_else(|| syntax(self.path, Some(line), format!("bad number `{}`", show(token))))?;
            extra += 1;
        }
        if !matches!(extra, 0 | 1 | 3) {
            let message = format!(
                "vertex has {} numbers; expected 3 (x y z), 4 (x y z w) or 6 (x y z r g b)",
                3 + extra
            );
            return Err(syntax(self.path, Some(line), message));
        }
        let p = check_finite(Vec3::from_array(xyz), self.positions.len(), self.path, Some(line))?;
        self.positions.push(p);
        Ok(())
    }

    /// `f v1 v2 v3 ...`, each `v` being `a`, `a/t`, `a//n` or `a/t/n`.
    fn face<'t>(&mut self, line: usize, tokens: impl Iterator<Item = &'t [u8]>) -> Result<(), LoadError> {
        let face = self.faces.count();
        let defined = self.positions.len();
        for token in tokens {
            let reference = token.split(|&b| b == b'/').next().unwrap_or(token);
            let Some(index) = parse_int(reference) else {
                return Err(syntax(
                    self.path,
                    Some(line),
                    format!("bad vertex index `{}`", show(token)),
                ));
            };
            let index = if index > 0 {
                let index = index - 1;
                let Ok(index) = u32::try_from(index) else {
                    let error = MeshError::IndexOutOfRange {
                        face,
                        vertex: index as u64,
                        vertex_count: defined,
                    };
                    return Err(error_at(self.path, Some(line), error));
                };
                if index as usize >= defined && self.forward.last().is_none_or(|f| index > f.vertex) {
                    self.forward.push(ForwardRef {
                        line,
                        face,
                        vertex: index,
                    });
                }
                index
            } else if index < 0 {
                // -1 is the last vertex defined so far.
                let resolved = i64::try_from(defined).unwrap_or(i64::MAX).saturating_add(index);
                match u32::try_from(resolved) {
                    Ok(resolved) => resolved,
                    Err(_) => {
                        let message = format!(
                            "relative vertex index {index} reaches before the first vertex ({defined} defined so far)"
                        );
                        return Err(syntax(self.path, Some(line), message));
                    }
                }
            } else {
                return Err(syntax(self.path, Some(line), "vertex index 0 (OBJ indices start at 1)"));
            };
            self.faces.push(index);
        }
        self.faces.close().map_err(|e| error_at(self.path, Some(line), e))
    }
}
