//! Reading an input stream into memory with bounded size, and the checks that
//! make a text format fail fast on what is not text: a NUL byte, or a line
//! longer than the limit (an endless stream such as `/dev/zero` has either).

use super::Format;
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

/// The text checks, fed the growing buffer of a file.
pub(super) struct TextGuard {
    mode: Mode,
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
        Self::with_mode(mode, max_line_bytes)
    }

    /// A guard for a text format that is not a mesh (points files).
    pub(super) fn text(max_line_bytes: usize) -> Self {
        Self::with_mode(Mode::Text, max_line_bytes)
    }

    fn with_mode(mode: Mode, max_line_bytes: usize) -> Self {
        Self {
            mode,
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
/// `guard` on each chunk so that bad text fails before the memory grows.
/// `size_hint` (a regular file's size) sizes the buffer at once.
pub(super) fn read_bounded(
    mut reader: impl Read,
    limit: Limit,
    size_hint: Option<u64>,
    guard: &mut TextGuard,
    path: &Path,
) -> Result<Vec<u8>, LoadError> {
    let max = limit.bytes();
    if size_hint.is_some_and(|size| size > max) {
        return Err(LoadError::new(path, None, limit.error()));
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
            // Doubling, but never past the ceiling: the buffer stays within the limit.
            let grow = (bytes.capacity() as u64).max(64 << 10).min(ceiling - len);
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

/// The bytes the system could give this process now: `MemAvailable` of
/// `/proc/meminfo` on Linux, `None` elsewhere or when it cannot be read.
pub(super) fn memory_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}
