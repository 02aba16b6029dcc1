//! Helpers shared by the parsers: line and token scanning, number parsing,
//! error construction and the face accumulator.

use crate::error::{LoadError, LoadErrorKind, MeshError};
use crate::math::Vec3;
use crate::mesh::Mesh;
use std::path::Path;

/// The lines of `bytes` with their 1-based numbers, without the `\n`, `\r\n` or
/// lone `\r` (old Mac line end) that ends them. A final line end does not start
/// another (empty) line.
pub(super) struct Lines<'a> {
    rest: &'a [u8],
    line: usize,
}

impl<'a> Lines<'a> {
    /// The lines of `bytes`, the first being line `first`.
    pub(super) fn new(bytes: &'a [u8], first: usize) -> Self {
        Self {
            rest: bytes,
            line: first.saturating_sub(1),
        }
    }

    /// Number of the last line returned (0 before the first), which is the last
    /// line of the input once the iterator is exhausted.
    pub(super) fn line(&self) -> usize {
        self.line
    }

    /// The bytes not yet returned.
    pub(super) fn rest(&self) -> &'a [u8] {
        self.rest
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n' || b == b'\r') {
            Some(i) => {
                let end = if self.rest[i] == b'\r' && self.rest.get(i + 1) == Some(&b'\n') {
                    i + 2
                } else {
                    i + 1
                };
                (&self.rest[..i], &self.rest[end..])
            }
            None => (self.rest, &self.rest[self.rest.len()..]),
        };
        self.rest = rest;
        self.line += 1;
        Some((self.line, line))
    }
}

/// `line` up to its first `#`.
#[inline]
pub(super) fn strip_comment(line: &[u8]) -> &[u8] {
    match line.iter().position(|&b| b == b'#') {
        Some(i) => &line[..i],
        None => line,
    }
}

/// The whitespace-separated tokens of `line`.
#[inline]
pub(super) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace()).filter(|t| !t.is_empty())
}

/// A stream of whitespace-separated tokens over many lines, tracking the line
/// of the current token.
pub(super) struct TokenStream<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> TokenStream<'a> {
    /// Tokens of `bytes`, whose first line is line `first_line`.
    pub(super) fn new(bytes: &'a [u8], first_line: usize) -> Self {
        Self {
            bytes,
            pos: 0,
            line: first_line,
        }
    }

    /// The line of the last token returned, or of the end of the input once it is
    /// reached.
    pub(super) fn line(&self) -> usize {
        self.line
    }

    /// The next token, or `None` at the end of the input.
    #[inline]
    pub(super) fn next_token(&mut self) -> Option<&'a [u8]> {
        let rest = self.bytes.get(self.pos..)?;
        let mut skip = 0;
        let mut previous = self.pos.checked_sub(1).and_then(|i| self.bytes.get(i)).copied();
        for &b in rest {
            // `\r\n` ends one line, a lone `\r` one too.
            if b == b'\r' || (b == b'\n' && previous != Some(b'\r')) {
                self.line += 1;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            previous = Some(b);
            skip += 1;
        }
        let rest = rest.get(skip..).unwrap_or_default();
        if rest.is_empty() {
            // End of input: report the last line, not the empty one after a final line end.
            if skip > 0 && matches!(self.bytes.last(), Some(b'\n' | b'\r')) {
                self.line -= 1;
            }
            self.pos = self.bytes.len();
            return None;
        }
        let len = rest.iter().position(|b| b.is_ascii_whitespace()).unwrap_or(rest.len());
        self.pos += skip + len;
        rest.get(..len)
    }

    /// Skips the rest of the current line (its line end stays, so the line count
    /// is unchanged) and returns it.
    pub(super) fn rest_of_line(&mut self) -> &'a [u8] {
        let rest = self.bytes.get(self.pos..).unwrap_or_default();
        let len = rest
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .unwrap_or(rest.len());
        self.pos += len;
        rest.get(..len).unwrap_or_default()
    }
}

/// Parses a float token (anything `str::parse::<f32>` accepts, including `nan`
/// and `inf`; the caller checks finiteness).
#[inline]
pub(super) fn parse_f32(token: &[u8]) -> Option<f32> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Parses a decimal integer token with an optional sign. `None` when the token is
/// not an integer or does not fit in an `i64`.
#[inline]
pub(super) fn parse_int(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token.split_first()? {
        (b'-', rest) => (true, rest),
        (b'+', rest) => (false, rest),
        _ => (false, token),
    };
    if digits.is_empty() {
        return None;
    }
    let mut value: i64 = 0;
    for &b in digits {
        let digit = b.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_add(i64::from(digit))?;
    }
    Some(if negative { -value } else { value })
}

/// Parses an unsigned decimal integer token (an optional `+`, then digits).
/// `None` when the token is not one or does not fit in a `u64`.
#[inline]
pub(super) fn parse_uint(token: &[u8]) -> Option<u64> {
    let digits = token.strip_prefix(b"+").unwrap_or(token);
    if digits.is_empty() {
        return None;
    }
    let mut value: u64 = 0;
    for &b in digits {
        let digit = b.wrapping_sub(b'0');
        if digit > 9 {
            return None;
        }
        value = value.checked_mul(10)?.checked_add(u64::from(digit))?;
    }
    Some(value)
}

/// A token for an error message: lossy UTF-8, control characters escaped (so
/// no escape sequence of a hostile file reaches the terminal), cut to
/// [`SHOWN_CHARS`] characters and an ellipsis.
pub(super) fn show(token: &[u8]) -> String {
    // Decoding more than the characters shown would only cost time on a huge line.
    let head = token.get(..SHOWN_CHARS * 4).unwrap_or(token);
    let text = String::from_utf8_lossy(head);
    let mut shown = crate::io::escape_for_terminal(&text, SHOWN_CHARS);
    if head.len() < token.len() && !shown.ends_with('…') {
        shown.push('…');
    }
    shown
}

/// The most characters of a file's text an error message echoes.
pub(super) const SHOWN_CHARS: usize = 80;

/// An error of `kind` at `line` of `path`.
pub(super) fn error_at(path: &Path, line: Option<usize>, kind: impl Into<LoadErrorKind>) -> LoadError {
    LoadError::new(path, line, kind)
}

/// A syntax error at `line` of `path`.
pub(super) fn syntax(path: &Path, line: Option<usize>, message: impl Into<String>) -> LoadError {
    LoadError::new(path, line, LoadErrorKind::Syntax(message.into()))
}

/// A truncation error at `line` of `path`.
pub(super) fn truncated(path: &Path, line: Option<usize>, message: impl Into<String>) -> LoadError {
    LoadError::new(path, line, LoadErrorKind::Truncated(message.into()))
}

/// An implausible-size error at `line` of `path`.
pub(super) fn implausible(path: &Path, line: Option<usize>, message: impl Into<String>) -> LoadError {
    LoadError::new(path, line, LoadErrorKind::Implausible(message.into()))
}

/// The non-finite-vertex error for vertex `index` (0-based) when `p` is not finite.
#[inline]
pub(super) fn check_finite(p: Vec3, index: usize, path: &Path, line: Option<usize>) -> Result<Vec3, LoadError> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(error_at(path, line, MeshError::NonFiniteVertex { index }))
    }
}

/// Faces accumulated in the compact layout of [`Mesh::from_compact`].
pub(super) struct Faces {
    offsets: Vec<u32>,
    indices: Vec<u32>,
}

impl Faces {
    /// Room for `faces` faces and `indices` indices (callers cap these by what the
    /// input size allows).
    pub(super) fn with_capacity(faces: usize, indices: usize) -> Self {
        let mut offsets = Vec::with_capacity(faces.saturating_add(1));
        offsets.push(0);
        Self {
            offsets,
            indices: Vec::with_capacity(indices),
        }
    }

    /// Number of complete faces.
    #[inline]
    pub(super) fn count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Adds an index to the face being built.
    #[inline]
    pub(super) fn push(&mut self, index: u32) {
        self.indices.push(index);
    }

    /// Ends the face being built: fails when it has fewer than three vertices or
    /// when the indices no longer fit 32-bit offsets.
    #[inline]
    pub(super) fn close(&mut self) -> Result<(), MeshError> {
        let start = self.offsets.last().map_or(0, |&s| s as usize);
        let len = self.indices.len() - start;
        if len < 3 {
            return Err(MeshError::FaceTooSmall {
                face: self.count(),
                len,
            });
        }
        let end = u32::try_from(self.indices.len()).map_err(|_| MeshError::TooLarge {
            what: "face indices",
            count: self.indices.len(),
        })?;
        self.offsets.push(end);
        Ok(())
    }

    /// The mesh of `positions` and these faces. The parsers have checked the
    /// invariants already; anything left becomes a [`LoadErrorKind::Mesh`] error.
    pub(super) fn finish(self, positions: Vec<Vec3>, path: &Path) -> Result<Mesh, LoadError> {
        if positions.len() > u32::MAX as usize {
            let count = positions.len();
            return Err(error_at(
                path,
                None,
                MeshError::TooLarge {
                    what: "vertices",
                    count,
                },
            ));
        }
        Mesh::from_compact(positions, self.offsets, self.indices).map_err(|e| error_at(path, None, e))
    }
}
