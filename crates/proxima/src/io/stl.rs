//! STL, binary and ascii, with exactly-equal positions welded into shared vertices.

use super::load_budget::Budget;
use super::text::{Faces, TokenStream, check_finite, error_at, parse_f32, show, syntax, truncated};
use crate::error::{LoadError, MeshError};
use crate::math::Vec3;
use crate::mesh::Mesh;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};
use std::path::Path;

/// Binary header: 80 bytes of anything, then the `u32` triangle count.
const HEADER_BYTES: u64 = 84;
/// Binary triangle: normal, three corners (12 `f32`), 2 attribute bytes.
const TRIANGLE_BYTES: u64 = 50;
/// How far to look for NUL bytes when telling binary from ascii.
pub(super) const SNIFF_BYTES: usize = 4096;

pub(super) fn parse(bytes: &[u8], path: &Path, budget: Budget) -> Result<Mesh, LoadError> {
    if binary_size(bytes) == Some(bytes.len() as u64) {
        return parse_binary(bytes, path, budget);
    }
    // Many binary files also start with `solid`; text never holds NUL bytes, while
    // binary data nearly always does (zero normals, attribute bytes, 0.0).
    let text = bytes.trim_ascii_start();
    let looks_ascii = text.get(..5).is_some_and(|head| head.eq_ignore_ascii_case(b"solid")) && may_be_ascii(bytes);
    if looks_ascii {
        parse_ascii(bytes, path)
    } else {
        parse_binary(bytes, path, budget)
    }
}

/// The size of a binary STL whose header is at the start of `bytes`: 84 bytes
/// and 50 per announced triangle. `None` before the 84 bytes of the header.
pub(super) fn binary_size(bytes: &[u8]) -> Option<u64> {
    let announced = bytes.get(80..84)?.try_into().ok().map(u32::from_le_bytes)?;
    Some(HEADER_BYTES + TRIANGLE_BYTES * u64::from(announced))
}

/// `false` once the first bytes of a file show it is not an ascii STL: they
/// start (after white space) with something other than `solid`, or hold a NUL
/// byte within the first 4 KiB. `true` for a prefix of one that does.
pub(super) fn may_be_ascii(bytes: &[u8]) -> bool {
    let text = bytes.trim_ascii_start();
    let head = text.get(..5).unwrap_or(text);
    let solid = b"solid".get(..head.len()).is_some_and(|s| s.eq_ignore_ascii_case(head));
    solid && !bytes.iter().take(SNIFF_BYTES).any(|&b| b == 0)
}

/// Binary STL: the size must hold the announced triangles; bytes after them are
/// ignored.
fn parse_binary(bytes: &[u8], path: &Path, budget: Budget) -> Result<Mesh, LoadError> {
    let Some(count) = bytes
        .get(80..84)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes)
    else {
        let message = format!("{} bytes: a binary STL has an 84-byte header", bytes.len());
        return Err(truncated(path, None, message));
    };
    let needed = HEADER_BYTES + TRIANGLE_BYTES * u64::from(count);
    let data = bytes.get(HEADER_BYTES as usize..).unwrap_or_default();
    // The triangles that are there are read first, so that a bad coordinate
    // is reported before the truncation: a stream stops being read at its
    // first non-finite corner (see `first_non_finite`).
    let present = (count as usize).min(data.len() / TRIANGLE_BYTES as usize);
    // The memory budget, before the triangles are read (how many vertices
    // they weld into is not known yet: none are counted).
    budget
        .check(bytes.len() as u64, 0, present as u64, true)
        .map_err(|kind| error_at(path, None, kind))?;
    let mut welder = Welder::with_capacity(present / 2 + 3);
    let mut faces = Faces::with_capacity(present, present * 3);
    for triangle in data.chunks_exact(TRIANGLE_BYTES as usize).take(present) {
        // Skip the normal (12 bytes); read three corners.
        for corner in triangle.get(12..48).unwrap_or_default().chunks_exact(12) {
            let mut xyz = [0.0f32; 3];
            for (value, bytes) in xyz.iter_mut().zip(corner.chunks_exact(4)) {
                *value = bytes.try_into().map_or(0.0, f32::from_le_bytes);
            }
            let index = welder.index(Vec3::from_array(xyz), path, None)?;
            faces.push(index);
        }
        faces.close().map_err(|e| error_at(path, None, e))?;
    }
    if needed > bytes.len() as u64 {
        let message = format!(
            "the header announces {count} triangles, which need {needed} bytes, but the file has {}",
            bytes.len()
        );
        return Err(truncated(path, None, message));
    }
    faces.finish(welder.positions, path)
}

/// Whether one of the complete binary triangles numbered `from..` in `bytes`
/// has a non-finite corner (which the parser refuses), and the number of
/// complete triangles checked so far otherwise.
pub(super) fn first_non_finite(bytes: &[u8], from: usize) -> Result<usize, ()> {
    let data = bytes.get(HEADER_BYTES as usize..).unwrap_or_default();
    let complete = data.len() / TRIANGLE_BYTES as usize;
    for triangle in data.chunks_exact(TRIANGLE_BYTES as usize).take(complete).skip(from) {
        let corners = triangle.get(12..48).unwrap_or_default();
        if corners
            .chunks_exact(4)
            .any(|b| !b.try_into().map_or(0.0, f32::from_le_bytes).is_finite())
        {
            return Err(());
        }
    }
    Ok(complete.max(from))
}

/// Ascii STL.
fn parse_ascii(bytes: &[u8], path: &Path) -> Result<Mesh, LoadError> {
    let mut tokens = TokenStream::new(bytes, 1);
    expect(&mut tokens, "solid", path)?;
    tokens.rest_of_line();
    // Roughly 250 bytes per facet; grows if needed.
    let mut welder = Welder::with_capacity(bytes.len() / 500);
    let mut faces = Faces::with_capacity(bytes.len() / 250, bytes.len() / 250 * 3);
    loop {
        let Some(keyword) = tokens.next_token() else {
            return Err(truncated(path, Some(tokens.line()), "missing `endsolid`"));
        };
        if keyword.eq_ignore_ascii_case(b"facet") {
            facet(&mut tokens, &mut welder, &mut faces, path)?;
        } else if keyword.eq_ignore_ascii_case(b"endsolid") {
            tokens.rest_of_line();
            match tokens.next_token() {
                None => break,
                Some(next) if next.eq_ignore_ascii_case(b"solid") => {
                    tokens.rest_of_line();
                }
                Some(other) => {
                    let message = format!("expected `solid` or the end of the file, found `{}`", show(other));
                    return Err(syntax(path, Some(tokens.line()), message));
                }
            }
        } else {
            let message = format!("expected `facet` or `endsolid`, found `{}`", show(keyword));
            return Err(syntax(path, Some(tokens.line()), message));
        }
    }
    faces.finish(welder.positions, path)
}

/// The rest of a facet after `facet`: `normal nx ny nz outer loop (vertex x y z)+
/// endloop endfacet`.
fn facet(tokens: &mut TokenStream, welder: &mut Welder, faces: &mut Faces, path: &Path) -> Result<(), LoadError> {
    expect(tokens, "normal", path)?;
    for _ in 0..3 {
        next(tokens, "a normal component", path)?; // normals are recomputed by users; not checked
    }
    expect(tokens, "outer", path)?;
    expect(tokens, "loop", path)?;
    let line = tokens.line();
    loop {
        let keyword = next(tokens, "`vertex` or `endloop`", path)?;
        if keyword.eq_ignore_ascii_case(b"endloop") {
            break;
        }
        if !keyword.eq_ignore_ascii_case(b"vertex") {
            let message = format!("expected `vertex` or `endloop`, found `{}`", show(keyword));
            return Err(syntax(path, Some(tokens.line()), message));
        }
        let mut xyz = [0.0f32; 3];
        for value in &mut xyz {
            let token = next(tokens, "a coordinate", path)?;
            *value = parse_f32(token)
                .ok_or_else(|| syntax(path, Some(tokens.line()), format!("bad number `{}`", show(token))))?;
        }
        let index = welder.index(Vec3::from_array(xyz), path, Some(tokens.line()))?;
        faces.push(index);
    }
    faces.close().map_err(|e| error_at(path, Some(line), e))?;
    expect(tokens, "endfacet", path)
}

/// The next token, or a truncation error naming `what` was expected.
fn next<'a>(tokens: &mut TokenStream<'a>, what: &str, path: &Path) -> Result<&'a [u8], LoadError> {
    tokens
        .next_token()
        .ok_or_else(|| truncated(path, Some(tokens.line()), format!("expected {what}")))
}

/// Consumes the keyword `word` (case-insensitive).
fn expect(tokens: &mut TokenStream, word: &str, path: &Path) -> Result<(), LoadError> {
    let token = next(tokens, &format!("`{word}`"), path)?;
    if token.eq_ignore_ascii_case(word.as_bytes()) {
        Ok(())
    } else {
        Err(syntax(
            path,
            Some(tokens.line()),
            format!("expected `{word}`, found `{}`", show(token)),
        ))
    }
}

/// Assigns one vertex index per distinct position, in order of first appearance.
struct Welder {
    positions: Vec<Vec3>,
    map: HashMap<Key, u32, BuildHasherDefault<KeyHasher>>,
}

impl Welder {
    fn with_capacity(capacity: usize) -> Self {
        Self {
            positions: Vec::with_capacity(capacity),
            map: HashMap::with_capacity_and_hasher(capacity, Default::default()),
        }
    }

    /// The index of position `p`, new if `p` was not seen before.
    #[inline]
    fn index(&mut self, p: Vec3, path: &Path, line: Option<usize>) -> Result<u32, LoadError> {
        let next = self.positions.len();
        let p = check_finite(p, next, path, line)?;
        // -0.0 == 0.0 but their bits differ: weld them.
        let bits = p.to_array().map(|v| if v == 0.0 { 0 } else { v.to_bits() });
        let Ok(next) = u32::try_from(next) else {
            return Err(error_at(
                path,
                line,
                MeshError::TooLarge {
                    what: "vertices",
                    count: next,
                },
            ));
        };
        let index = *self.map.entry(Key(bits)).or_insert(next);
        if index == next {
            self.positions.push(p);
        }
        Ok(index)
    }
}

/// The bit patterns of a position.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Key([u32; 3]);

impl Hash for Key {
    #[inline]
    fn hash<H: Hasher>(&self, state: &mut H) {
        let [x, y, z] = self.0.map(u64::from);
        state.write_u64(
            x.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ y.wrapping_mul(0xC2B2_AE3D_27D4_EB4F) ^ z.rotate_left(32),
        );
    }
}

/// A fast hasher for [`Key`]: the key mixes its words, this finishes with the
/// murmur3 64-bit finalizer so that every output bit depends on every input bit.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3);
        }
    }

    #[inline]
    fn write_u64(&mut self, value: u64) {
        self.0 ^= value;
    }

    #[inline]
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        h ^= h >> 33;
        h = h.wrapping_mul(0xC4CE_B9FE_1A85_EC53);
        h ^ (h >> 33)
    }
}
