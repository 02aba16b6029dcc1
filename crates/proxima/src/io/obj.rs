//! Wavefront OBJ: `v`, `vt`, `vn` and `f` statements; everything else is
//! ignored. Texture coordinates and normals are kept per face corner when
//! every corner of every face names one (`a/t`, `a/t/n`, `a//n`); a file
//! where only some do keeps none of that kind.

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
    uvs: CornerData<[f32; 2]>,
    normals: CornerData<Vec3>,
}

/// One kind of per-corner data: the `vt` or `vn` values, and each corner's
/// index into them while every corner so far has named one.
struct CornerData<T> {
    what: &'static str,
    values: Vec<T>,
    /// One per corner; emptied, and `complete` cleared, at the first corner
    /// without one.
    corners: Vec<u32>,
    complete: bool,
    /// As [`Obj::forward`]: references beyond the values defined so far.
    forward: Vec<ForwardRef>,
}

impl<T: Copy> CornerData<T> {
    fn new(what: &'static str) -> Self {
        Self {
            what,
            values: Vec::new(),
            corners: Vec::new(),
            complete: true,
            forward: Vec::new(),
        }
    }

    /// Records the reference `token` (the `t` or `n` of `a/t/n`, empty when
    /// absent) of corner `corner` of face `face`.
    fn corner(&mut self, token: Option<&[u8]>, line: usize, face: usize, path: &Path) -> Result<(), LoadError> {
        let Some(token) = token.filter(|t| !t.is_empty()) else {
            self.complete = false;
            self.corners = Vec::new();
            return Ok(());
        };
        let bad = || syntax(path, Some(line), format!("bad {} index `{}`", self.what, show(token)));
        let index = parse_int(token).ok_or_else(bad)?;
        let defined = self.values.len();
        let index = match index {
            0 => {
                return Err(syntax(
                    path,
                    Some(line),
                    format!("{} index 0 (OBJ indices start at 1)", self.what),
                ));
            }
            i if i > 0 => u32::try_from(i - 1).map_err(|_| bad())?,
            i => {
                let resolved = i64::try_from(defined).unwrap_or(i64::MAX).saturating_add(i);
                u32::try_from(resolved).map_err(|_| {
                    let message = format!(
                        "relative {} index {i} reaches before the first one ({defined} defined so far)",
                        self.what
                    );
                    syntax(path, Some(line), message)
                })?
            }
        };
        if index as usize >= defined && self.forward.last().is_none_or(|f| index > f.vertex) {
            self.forward.push(ForwardRef {
                line,
                face,
                vertex: index,
            });
        }
        if self.complete {
            self.corners.push(index);
        }
        Ok(())
    }

    /// The values per corner, when every corner named one; an error naming
    /// the first line that names one never defined.
    fn finish(self, path: &Path) -> Result<Option<Vec<T>>, LoadError> {
        let count = self.values.len();
        if let Some(bad) = self.forward.iter().find(|f| f.vertex as usize >= count) {
            let message = format!(
                "face {} refers to {} {}, but the file defines {count}",
                bad.face,
                self.what,
                u64::from(bad.vertex) + 1
            );
            return Err(syntax(path, Some(bad.line), message));
        }
        if !self.complete || self.corners.is_empty() {
            return Ok(None);
        }
        Ok(Some(self.corners.iter().map(|&i| self.values[i as usize]).collect()))
    }
}

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<Mesh, LoadError> {
    // Rough guesses from typical line lengths; the vectors grow if needed.
    let mut obj = Obj {
        path,
        positions: Vec::with_capacity(bytes.len() / 80),
        faces: Faces::with_capacity(bytes.len() / 40, bytes.len() / 13),
        forward: Vec::new(),
        uvs: CornerData::new("texture coordinate"),
        normals: CornerData::new("normal"),
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
    let uvs = obj.uvs.finish(path)?;
    let normals = obj.normals.finish(path)?;
    let mut mesh = obj.faces.finish(obj.positions, path)?;
    if let Some(uvs) = uvs {
        mesh = mesh.with_corner_uvs(uvs).map_err(|e| error_at(path, None, e))?;
    }
    if let Some(normals) = normals {
        mesh = mesh.with_corner_normals(normals).map_err(|e| error_at(path, None, e))?;
    }
    Ok(mesh)
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
            b"vt" => self.texture_coordinate(line, tokens),
            b"vn" => self.normal(line, tokens),
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

    /// The numbers of a `vt` or `vn` statement: at least `least`, at most
    /// `most` (the rest 0).
    fn numbers<'t>(
        &self,
        line: usize,
        tokens: impl Iterator<Item = &'t [u8]>,
        (least, most): (usize, usize),
        what: &str,
    ) -> Result<[f32; 3], LoadError> {
        let mut out = [0.0f32; 3];
        let mut count = 0;
        for token in tokens {
            let value = parse_f32(token)
                .ok_or_else(|| syntax(self.path, Some(line), format!("bad number `{}`", show(token))))?;
            if !value.is_finite() {
                return Err(syntax(
                    self.path,
                    Some(line),
                    format!("{what} `{}` is not finite", show(token)),
                ));
            }
            if count < 3 {
                out[count] = value;
            }
            count += 1;
        }
        if !(least..=most).contains(&count) {
            let message = format!("{what} has {count} numbers; expected {least} to {most}");
            return Err(syntax(self.path, Some(line), message));
        }
        Ok(out)
    }

    /// `vt u [v [w]]`: `w` is checked, then ignored.
    fn texture_coordinate<'t>(&mut self, line: usize, tokens: impl Iterator<Item = &'t [u8]>) -> Result<(), LoadError> {
        let [u, v, _] = self.numbers(line, tokens, (1, 3), "texture coordinate")?;
        self.uvs.values.push([u, v]);
        Ok(())
    }

    /// `vn x y z`.
    fn normal<'t>(&mut self, line: usize, tokens: impl Iterator<Item = &'t [u8]>) -> Result<(), LoadError> {
        let n = self.numbers(line, tokens, (3, 3), "normal")?;
        self.normals.values.push(Vec3::from_array(n));
        Ok(())
    }

    /// `f v1 v2 v3 ...`, each `v` being `a`, `a/t`, `a//n` or `a/t/n`.
    fn face<'t>(&mut self, line: usize, tokens: impl Iterator<Item = &'t [u8]>) -> Result<(), LoadError> {
        let face = self.faces.count();
        let defined = self.positions.len();
        for token in tokens {
            let mut parts = token.split(|&b| b == b'/');
            let reference = parts.next().unwrap_or(token);
            self.uvs.corner(parts.next(), line, face, self.path)?;
            self.normals.corner(parts.next(), line, face, self.path)?;
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
