//! Reading an input stream into memory with bounded size, and the checks that
//! make a text format fail fast on what is not text: a NUL byte, or a line
//! longer than the limit (an endless stream such as `/dev/zero` has either).
//! Text is also counted as it arrives (OBJ `v` and `f` lines, OFF lines,
//! ascii STL facets) against the memory budget ([`Budget`]), so that a file
//! holding more than the budget stops being read as soon as the counts pass
//! it, not once it has all been inflated.

use super::Format;
// Where the parsers have always found it.
pub(super) use super::load_budget::Budget;
use super::stl;
use crate::error::{LoadError, LoadErrorKind};
use std::io::Read;
use std::path::Path;

/// The most bytes read before the checks run again: small enough that
/// `/dev/zero` or `/dev/urandom` fail within a few milliseconds.
const CHUNK_BYTES: u64 = 1 << 20;

/// What the guard checks in the bytes seen so far.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    /// Text throughout: NUL bytes and long lines are errors.
    Text,
    /// A PLY header (text), whose `format` line said ascii when `ascii`.
    PlyHeader { ascii: bool },
    /// An STL not yet known to be binary: text checks while it looks ascii.
    Stl,
    /// Binary data: nothing to check.
    Binary,
    /// Binary STL: its complete triangles before the first one not yet
    /// checked have finite corners.
    StlBinary { checked: usize },
    /// Binary STL with all its announced triangles read: stop reading.
    Done,
}

/// What a text line adds to the counts.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Count {
    /// Nothing (points files; formats counted by their parsers).
    Nothing,
    /// OBJ: a `v` line is a vertex, an `f` line of `n` references `n - 2`
    /// triangles.
    Obj,
    /// OFF: every line that is not blank or a comment is a vertex or a face,
    /// counted as a vertex (the cheaper; the header's line or two with them).
    Off,
    /// Ascii STL: a `facet` line is a triangle.
    Stl,
}

/// The text checks, fed the growing buffer of a file.
pub(super) struct TextGuard {
    mode: Mode,
    count: Count,
    /// Vertices and triangles counted so far.
    vertices: u64,
    triangles: u64,
    max_line_bytes: usize,
    /// 1-based number of the line being read.
    line: usize,
    /// Offset of the first byte of that line.
    line_start: usize,
    /// Offset of the first byte not yet checked.
    checked: usize,
}

impl TextGuard {
    pub(super) fn new(format: Format, max_line_bytes: usize) -> Self {
        let mode = match format {
            Format::Obj | Format::Off => Mode::Text,
            Format::Ply => Mode::PlyHeader { ascii: false },
            Format::Stl => Mode::Stl,
            Format::Glb => Mode::Binary,
        };
        let count = match format {
            Format::Obj => Count::Obj,
            Format::Off => Count::Off,
            Format::Stl => Count::Stl,
            Format::Ply | Format::Glb => Count::Nothing,
        };
        Self::with_mode(mode, count, max_line_bytes)
    }

    /// A guard for a binary file that is not a mesh (`.npy` points).
    pub(super) fn binary() -> Self {
        Self::with_mode(Mode::Binary, Count::Nothing, usize::MAX)
    }

    /// A guard for a text format that is not a mesh (points files).
    pub(super) fn text(max_line_bytes: usize) -> Self {
        Self::with_mode(Mode::Text, Count::Nothing, max_line_bytes)
    }

    fn with_mode(mode: Mode, count: Count, max_line_bytes: usize) -> Self {
        Self {
            mode,
            count,
            vertices: 0,
            triangles: 0,
            max_line_bytes,
            line: 1,
            line_start: 0,
            checked: 0,
        }
    }

    /// `true` once the data needed is complete (a binary STL whose announced
    /// triangles are all read: the parser ignores the bytes after them).
    pub(super) fn done(&self) -> bool {
        self.mode == Mode::Done
    }

    /// Fails when `held` bytes and the vertices and triangles counted so far
    /// pass `budget`, naming the line reached in text.
    pub(super) fn check_budget(&self, held: u64, budget: Budget, path: &Path) -> Result<(), LoadError> {
        budget
            .check(held, self.vertices, self.triangles, false)
            .map_err(|kind| {
                let text = matches!(self.mode, Mode::Text | Mode::Stl) && self.count != Count::Nothing;
                LoadError::new(path, text.then_some(self.line), kind)
            })
    }

    /// Counts what the complete line `line` adds to the mesh.
    fn count_line(&mut self, line: &[u8]) {
        let line = line.trim_ascii_start();
        match self.count {
            Count::Nothing => {}
            Count::Obj => match line {
                [b'v', b' ' | b'\t', ..] => self.vertices += 1,
                [b'f', b' ' | b'\t', rest @ ..] => {
                    let corners = rest.split(u8::is_ascii_whitespace).filter(|w| !w.is_empty()).count();
                    self.triangles += (corners as u64).saturating_sub(2);
                }
                _ => {}
            },
            Count::Off => {
                if !line.is_empty() && line[0] != b'#' {
                    self.vertices += 1;
                }
            }
            Count::Stl => {
                if line.get(..5).is_some_and(|w| w.eq_ignore_ascii_case(b"facet")) {
                    self.triangles += 1;
                }
            }
        }
    }

    /// Checks `bytes[self.checked..]`, `bytes` being everything read so far.
    /// Fails with the line of a NUL byte or of an over-long line.
    pub(super) fn feed(&mut self, bytes: &[u8], path: &Path) -> Result<(), LoadError> {
        if self.mode == Mode::Stl {
            self.mode = stl_mode(bytes);
        }
        if let Mode::StlBinary { checked } = self.mode {
            // A non-finite corner is an error, whatever follows: stop reading
            // there (an endless `/dev/urandom` has one within a few triangles)
            // and let the parser say which vertex.
            self.mode = match stl::first_non_finite(bytes, checked) {
                Err(()) => Mode::Done,
                Ok(_) if stl_mode(bytes) == Mode::Done => Mode::Done,
                Ok(checked) => Mode::StlBinary { checked },
            };
        }
        if matches!(self.mode, Mode::Binary | Mode::Done | Mode::StlBinary { .. }) {
            self.checked = bytes.len();
            return Ok(());
        }
        let nul_is_error = self.mode != Mode::Stl;
        let mut i = self.checked;
        while let Some(offset) = bytes
            .get(i..)
            .and_then(|rest| rest.iter().position(|&b| b == b'\n' || b == b'\r' || b == 0))
        {
            let end = i + offset;
            self.check_length(end, path)?;
            match bytes[end] {
                0 if nul_is_error => return Err(LoadError::new(path, Some(self.line), LoadErrorKind::NotText)),
                0 => {}
                // The `\n` of a `\r\n` ends no further line.
                b'\n' if end > 0 && bytes[end - 1] == b'\r' => self.line_start = end + 1,
                _ => {
                    if let Mode::PlyHeader { ascii } = self.mode {
                        self.mode = ply_header_line(&bytes[self.line_start..end], ascii);
                    } else {
                        self.count_line(&bytes[self.line_start..end]);
                    }
                    self.line += 1;
                    self.line_start = end + 1;
                }
            }
            i = end + 1;
            if self.mode == Mode::Binary {
                break;
            }
        }
        self.checked = bytes.len();
        if self.mode != Mode::Binary {
            self.check_length(bytes.len(), path)?;
        }
        Ok(())
    }

    fn check_length(&self, end: usize, path: &Path) -> Result<(), LoadError> {
        if end.saturating_sub(self.line_start) > self.max_line_bytes {
            let kind = LoadErrorKind::LineTooLong {
                limit: self.max_line_bytes,
            };
            return Err(LoadError::new(path, Some(self.line), kind));
        }
        Ok(())
    }
}

/// The mode after a PLY header line: the data after `end_header` is text only
/// when the `format` line said `ascii`.
fn ply_header_line(line: &[u8], ascii: bool) -> Mode {
    let mut words = line.split(|b| b.is_ascii_whitespace()).filter(|w| !w.is_empty());
    match words.next() {
        Some(b"end_header") if ascii => Mode::Text,
        Some(b"end_header") => Mode::Binary,
        Some(b"format") => Mode::PlyHeader {
            ascii: words.next() == Some(b"ascii"),
        },
        _ => Mode::PlyHeader { ascii },
    }
}

/// What an STL of which `bytes` have been read is, as far as can be told.
fn stl_mode(bytes: &[u8]) -> Mode {
    // The first 4 KiB decide (a file of white space alone is not rescanned
    // whole on every chunk): what follows cannot make them look ascii or not.
    if stl::may_be_ascii(bytes.get(..stl::SNIFF_BYTES).unwrap_or(bytes)) {
        return Mode::Stl;
    }
    // Binary: once the announced triangles are read, the rest is ignored, and
    // one byte more tells the parser the file is not exactly that size.
    match stl::binary_size(bytes) {
        Some(size) if bytes.len() as u64 > size => Mode::Done,
        _ => Mode::StlBinary { checked: 0 },
    }
}

/// What exceeding the size limit is called.
#[derive(Clone, Copy)]
pub(super) enum Limit {
    /// An uncompressed input: [`LoadErrorKind::InputTooLarge`].
    Input(u64),
    /// Decompressed gzip output: [`LoadErrorKind::DecompressedTooLarge`].
    Decompressed(u64),
}

impl Limit {
    fn bytes(self) -> u64 {
        match self {
            Limit::Input(n) | Limit::Decompressed(n) => n,
        }
    }

    fn error(self) -> LoadErrorKind {
        match self {
            Limit::Input(limit) => LoadErrorKind::InputTooLarge { limit },
            Limit::Decompressed(limit) => LoadErrorKind::DecompressedTooLarge { limit },
        }
    }
}

/// Reads `reader` to its end into memory, at most `limit` bytes, running
/// `guard` on each chunk so that bad text fails before the memory grows, and
/// counting the bytes held and what the guard counted against `budget`.
/// `size_hint` (a regular file's size) sizes the buffer at once.
pub(super) fn read_bounded(
    mut reader: impl Read,
    limit: Limit,
    size_hint: Option<u64>,
    guard: &mut TextGuard,
    budget: Budget,
    path: &Path,
) -> Result<Vec<u8>, LoadError> {
    let max = limit.bytes();
    if size_hint.is_some_and(|size| size > max) {
        return Err(LoadError::new(path, None, limit.error()));
    }
    if let Some(size) = size_hint {
        budget
            .check(size, 0, 0, true)
            .map_err(|kind| LoadError::new(path, None, kind))?;
    }
    // One byte past the limit tells "exactly at the limit" from "beyond it".
    let ceiling = max.saturating_add(1);
    let first = size_hint.map_or(64 << 10, |size| size.saturating_add(1)).min(ceiling);
    let mut bytes: Vec<u8> = Vec::new();
    reserve(&mut bytes, first, path)?;
    loop {
        let len = bytes.len() as u64;
        if len >= ceiling {
            return Err(LoadError::new(path, None, limit.error()));
        }
        if bytes.len() == bytes.capacity() {
            // Doubling, but never past the ceiling nor the budget: the buffer
            // is memory held too.
            let capacity = bytes.capacity() as u64;
            let counted = Budget::need(capacity, guard.vertices, guard.triangles);
            let room = u64::try_from(u128::from(budget.bytes).saturating_sub(counted)).unwrap_or(u64::MAX);
            let grow = capacity.max(64 << 10).min(ceiling - len).min(room);
            if grow == 0 {
                guard.check_budget(capacity + 1, budget, path)?;
            }
            reserve(&mut bytes, grow, path)?;
        }
        // Reads no more than the free capacity, so `read_to_end` never reallocates.
        let room = (bytes.capacity() - bytes.len()) as u64;
        let read = reader
            .by_ref()
            .take(room.min(CHUNK_BYTES))
            .read_to_end(&mut bytes)
            .map_err(|e| LoadError::new(path, None, e))?;
        guard.feed(&bytes, path)?;
        guard.check_budget(bytes.len() as u64, budget, path)?;
        if read == 0 || guard.done() {
            break;
        }
    }
    Ok(bytes)
}

/// Reserves room for `additional` more bytes, as an error rather than an
/// abort when the allocator refuses.
fn reserve(bytes: &mut Vec<u8>, additional: u64, path: &Path) -> Result<(), LoadError> {
    let additional = usize::try_from(additional).unwrap_or(usize::MAX);
    bytes.try_reserve_exact(additional).map_err(|_| {
        let error = std::io::Error::new(
            std::io::ErrorKind::OutOfMemory,
            format!("cannot allocate {additional} bytes to read the file"),
        );
        LoadError::new(path, None, error)
    })
}
