//! Mesh loading: Wavefront OBJ, PLY, STL, OFF and binary glTF, each optionally gzip-compressed.
//!
//! [`load`] reads a whole file at once, picks the format from the extension
//! (case-insensitive `.obj`, `.ply`, `.stl`, `.off`, `.glb`, each optionally followed by
//! `.gz`), decompresses gzip transparently and parses the bytes. [`parse`] does
//! the same for bytes already in memory (tests, fuzzers, embedded data).
//!
//! # Accepted forms
//!
//! - **OBJ**: `v x y z`, `v x y z w` or `v x y z r g b` (the common vertex
//!   colour extension), the numbers after `z` being checked and ignored (any
//!   other count is an error), and `f` with vertex references `a`, `a/t`, `a//n` or
//!   `a/t/n`: 1-based, or negative (relative to the vertices read so far),
//!   polygons of any size. References to vertices defined later in the file are
//!   resolved at the end. Every other statement (`vt`, `vn`, `g`, `o`, `s`,
//!   `usemtl`, `mtllib`, `l`, `p`, free-form geometry, …) is ignored, as are
//!   `#` comments and blank lines; a trailing `\` continues a
//!   line. A statement that does not start with a letter is an error. A
//!   leading UTF-8 byte order mark is skipped (also in OFF).
//! - **OFF**: an `OFF` header (optionally `ST`/`C`/`N` prefixed, as in `COFF`
//!   and `NOFF`; only the first three numbers of a vertex line are used), or no
//!   header at all; `nV nF [nE]`, possibly on the header line; one vertex per
//!   line; one face per line as `n i0 … in-1` (0-based), with anything after the
//!   indices (face colours) ignored; `#` comments. Content after the announced
//!   faces is an error. Binary OFF and 4D/nD OFF are not supported.
//! - **PLY**: `ascii 1.0`, `binary_little_endian 1.0` and `binary_big_endian 1.0`;
//!   `element vertex` with scalar properties `x`, `y`, `z` of any type (`char`,
//!   `uchar`, `short`, `ushort`, `int`, `uint`, `float`, `double` and the
//!   `int8` … `float64` aliases), other properties skipped;
//!   `element face` with a `property list <count> <index> vertex_indices` (or
//!   `vertex_index`), with integer types; any other element is skipped, in ascii
//!   and binary alike; `comment` and `obj_info` lines. Ascii data is read as
//!   whitespace-separated values; an element may be split over lines, but
//!   it ends its line (a value left over on that line is an error, blamed on
//!   that line), each value must fit its declared type, and values left over
//!   after the last element are an error.
//! - **STL**: binary (80-byte header, `u32` triangle count, 50 bytes per
//!   triangle) and ascii (`solid` … `facet normal` … `outer loop`, `vertex x y z`
//!   at least three times, `endloop`, `endfacet`, … `endsolid`; keywords are
//!   case-insensitive, several solids may follow each other, normals are
//!   ignored). A file is binary when its size is exactly `84 + 50·n` for the
//!   count `n` it announces, ascii when it otherwise starts with `solid` and
//!   has no NUL byte in its first 4 KiB (binary files often start with `solid`
//!   too, but their data nearly always holds zero bytes), and binary again,
//!   with extra bytes after the announced triangles ignored, otherwise.
//!   **STL stores no shared vertices**, so positions that are exactly equal
//!   (same `f32` bit patterns, with `-0.0` taken as `0.0`) are welded into one
//!   vertex, numbered in order of first appearance. Faces are kept as read,
//!   including ones that become degenerate after welding.
//! - **GLB** (binary glTF 2.0): the triangles of the default scene, each node's
//!   transform applied, every primitive of every node adding its own vertices
//!   (an instanced mesh appears once per node); points and lines skipped.
//!   Primitives compressed with `KHR_draco_mesh_compression` are decoded
//!   (the `draco` feature, on by default). Meshopt-compressed geometry,
//!   sparse accessors and external buffers are refused with a message naming
//!   the element. The container and
//!   the accessors are read with every offset checked; the JSON chunk is
//!   parsed by serde_json, keeping only the members the reader uses. Details
//!   in the `glb` module.
//!
//! In every text format a line ends at `\n`, `\r\n` or a lone `\r` (old Mac
//! files), and ascii PLY values must fit their declared type (`uchar 300` is
//! an error) with each element ending its line.
//!
//! Every vertex of a file is kept, including those that no face uses, in file
//! order; faces keep their polygon size (nothing is triangulated here).
//!
//! # Errors
//!
//! Errors carry the path and, for text, the 1-based line:
//! [`LoadErrorKind::Syntax`] for malformed content (bad numbers, missing
//! values, OBJ index 0, relative OBJ indices reaching before the first vertex,
//! negative PLY/OFF indices), [`LoadErrorKind::Mesh`] for content that parses
//! but breaks a mesh invariant (index out of range, face of fewer than three
//! vertices, non-finite coordinate such as `nan`, `inf` or an overflowing
//! `1e999`), [`LoadErrorKind::Truncated`] when the data ends before what the
//! header announces, and [`LoadErrorKind::Implausible`] when a header announces
//! more elements than the remaining bytes could possibly hold (binary: the exact
//! minimum size; ascii: two bytes per value), which is checked before anything
//! is allocated.
//!
//! # Bounds
//!
//! [`load_with`] and [`read_with`] stream their input and stop at the limits
//! of [`LoadOptions`]: total size ([`LoadErrorKind::InputTooLarge`],
//! [`LoadErrorKind::DecompressedTooLarge`]; by default 4 GiB or half the
//! memory this process can obtain, whichever is less), and in text, a line longer than 1 MiB
//! ([`LoadErrorKind::LineTooLong`]) or a NUL byte ([`LoadErrorKind::NotText`]),
//! which end `/dev/zero` or `/dev/urandom` read as `.obj` after the first
//! chunk. Text echoed in messages has its control characters escaped and is cut
//! to 80 characters ([`escape_for_terminal`]).
//!
//! Loading also keeps to the memory budget ([`LoadOptions::memory_budget`],
//! by default [`default_memory_budget`](crate::budget::default_memory_budget)):
//! the bytes held plus the mesh they become, at
//! [`LOAD_BYTES_PER_VERTEX`](crate::budget::LOAD_BYTES_PER_VERTEX) and
//! [`LOAD_BYTES_PER_TRIANGLE`](crate::budget::LOAD_BYTES_PER_TRIANGLE) (the
//! mesh and the trees a command builds over it), may not pass it
//! ([`LoadErrorKind::MemoryBudget`]). Text is counted as it is read (OBJ `v`
//! and `f` lines, OFF lines, ascii STL facets), so reading stops as soon as
//! the counts pass the budget; PLY and OFF headers and the binary STL count
//! are checked before their data is read, a GLB scene's instances before
//! any of them is expanded, and a GLB's JSON values as they are built. The
//! mesh made is counted once more, exactly (while reading, a face counts as
//! one triangle at least), so a mesh returned always fits the budget.
//!
//! # Why hand-written parsers
//!
//! So that every error carries its line (tobj, for one, reports none), sizes
//! announced by headers are checked against the input before anything is
//! allocated, and no input, however damaged, can make a loader panic. The
//! parsers read from one `&[u8]` holding the whole file, allocate nothing per
//! line, and size their buffers by what the remaining bytes allow. Numbers are
//! parsed with `str::parse::<f32>` (correctly rounded, so a double written in
//! the file becomes the nearest `f32`). Timings: `docs/perf-log.md`.

#[cfg(feature = "draco")]
mod draco;
mod error;
mod glb;
mod load_budget;
mod npy;
mod obj;
mod off;
mod ply;
mod points;
mod read;
mod stl;
mod text;

pub use error::{LoadError, LoadErrorKind};
pub use npy::parse_npy_points;
pub use points::{load_points, load_rays, parse_points, parse_rays};

use crate::mesh::Mesh;
use std::io::Read;
use std::path::Path;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// Polygon File Format / Stanford Triangle Format (`.ply`), ascii or binary.
    Ply,
    /// Stereolithography (`.stl`), ascii or binary.
    Stl,
    /// Object File Format (`.off`).
    Off,
    /// Binary glTF 2.0 (`.glb`): the triangles of a scene, transforms applied.
    Glb,
}

impl Format {
    /// The format named by the extension of `path` (case-insensitive), looking
    /// through a trailing `.gz`: `bunny.PLY.gz` is [`Format::Ply`]. `None` for
    /// any other extension.
    pub fn from_path(path: impl AsRef<Path>) -> Option<Format> {
        let path = path.as_ref();
        let path = if is_gzip_path(path) {
            Path::new(path.file_stem()?)
        } else {
            path
        };
        let ext = path.extension()?.to_str()?;
        [
            ("obj", Format::Obj),
            ("ply", Format::Ply),
            ("stl", Format::Stl),
            ("off", Format::Off),
            ("glb", Format::Glb),
        ]
        .into_iter()
        .find(|(name, _)| ext.eq_ignore_ascii_case(name))
        .map(|(_, format)| format)
    }

    /// The usual extension of the format, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Obj => "obj",
            Format::Ply => "ply",
            Format::Stl => "stl",
            Format::Off => "off",
            Format::Glb => "glb",
        }
    }
}

/// `true` when the extension of `path` is `.gz` (case-insensitive).
fn is_gzip_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"))
}

/// The ceiling of [`LoadOptions::max_decompressed_bytes`] and
/// [`LoadOptions::max_input_bytes`]: 4 GiB, far above any real mesh (the
/// ascii dragon is 33 MB) and below what a gzip bomb expands to.
pub const DEFAULT_MAX_DECOMPRESSED_BYTES: u64 = 4 << 30;

/// Default of [`LoadOptions::max_line_bytes`]: 1 MiB, some ten thousand times
/// the longest line of a real mesh file (an OBJ face of a few thousand vertices).
pub const DEFAULT_MAX_LINE_BYTES: usize = 1 << 20;

/// The default input size limit: 4 GiB, or half the memory this process can
/// obtain now, whichever is less: the least of what the system has available
/// (`MemAvailable`), the room under the process's address-space limit
/// (`RLIMIT_AS`) and under its cgroup's `memory.max`
/// ([`process_available_memory`](crate::budget::process_available_memory)).
/// A file is held whole while it is parsed and the mesh takes about as much
/// again, so an input beyond half of that would fail later, in swap, by the
/// out-of-memory killer or in an aborting allocation, instead of with an
/// error. (The memory budget, [`LoadOptions::memory_budget`], applies besides.)
pub fn default_max_input_bytes() -> u64 {
    let half_available = crate::budget::process_available_memory().map_or(u64::MAX, |bytes| bytes / 2);
    DEFAULT_MAX_DECOMPRESSED_BYTES.min(half_available)
}

/// Limits applied while loading.
///
/// ```
/// use proxima::io::LoadOptions;
/// let strict = LoadOptions { max_decompressed_bytes: 64 << 20, ..LoadOptions::default() };
/// assert!(strict.max_decompressed_bytes <= 64 << 20);
/// assert!(LoadOptions::default().max_input_bytes <= 4 << 30);
/// assert_eq!(LoadOptions::default().memory_budget, proxima::budget::default_memory_budget());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// A `.gz` file that decompresses to more bytes than this fails with
    /// [`LoadErrorKind::DecompressedTooLarge`] (decompression stops there).
    /// Default: [`default_max_input_bytes`].
    pub max_decompressed_bytes: u64,
    /// An uncompressed file (or stream) of more bytes than this fails with
    /// [`LoadErrorKind::InputTooLarge`] (reading stops there; a regular file
    /// is refused from its size, before any byte is read). Default:
    /// [`default_max_input_bytes`].
    pub max_input_bytes: u64,
    /// A line of a text format longer than this fails with
    /// [`LoadErrorKind::LineTooLong`], as soon as it has been read that far.
    /// Default: [`DEFAULT_MAX_LINE_BYTES`].
    pub max_line_bytes: usize,
    /// The bytes loading may count: the input held and the mesh it becomes,
    /// at [`LOAD_BYTES_PER_VERTEX`](crate::budget::LOAD_BYTES_PER_VERTEX) and
    /// [`LOAD_BYTES_PER_TRIANGLE`](crate::budget::LOAD_BYTES_PER_TRIANGLE)
    /// (the mesh and the trees built over it). Past it, reading stops with
    /// [`LoadErrorKind::MemoryBudget`]. Default:
    /// [`default_memory_budget`](crate::budget::default_memory_budget).
    pub memory_budget: u64,
}

/// The environment variable that lowers (or raises) the decompression cap of
/// `.gz` meshes, in bytes (default [`default_max_input_bytes`]).
pub const MAX_DECOMPRESSED_ENV: &str = "PROXIMA_MAX_DECOMPRESSED_BYTES";

/// The environment variable that lowers (or raises) the size cap of
/// uncompressed meshes and points files, in bytes (default
/// [`default_max_input_bytes`]).
pub const MAX_INPUT_ENV: &str = "PROXIMA_MAX_INPUT_BYTES";

impl LoadOptions {
    /// The defaults, with the limits that [`MAX_DECOMPRESSED_ENV`] and
    /// [`MAX_INPUT_ENV`] set (plain numbers of bytes) and the budget that
    /// [`MEMORY_BUDGET_ENV`](crate::budget::MEMORY_BUDGET_ENV) sets (a K, M
    /// or G suffix allowed); a one-line message naming the variable when one
    /// is not a number.
    pub fn from_env() -> Result<Self, String> {
        let mut options = Self::default();
        let bytes = |name: &str, default: u64| match std::env::var(name) {
            Ok(text) => text
                .trim()
                .parse()
                .map_err(|_| format!("{name}: '{text}' is not a number of bytes")),
            Err(_) => Ok(default),
        };
        options.max_decompressed_bytes = bytes(MAX_DECOMPRESSED_ENV, options.max_decompressed_bytes)?;
        options.max_input_bytes = bytes(MAX_INPUT_ENV, options.max_input_bytes)?;
        options.memory_budget = crate::budget::memory_budget_from_env()?;
        Ok(options)
    }

    /// The memory budget, as the readers count it.
    fn budget(&self) -> read::Budget {
        read::Budget {
            bytes: self.memory_budget,
        }
    }
}

impl Default for LoadOptions {
    fn default() -> Self {
        let max = default_max_input_bytes();
        Self {
            max_decompressed_bytes: max,
            max_input_bytes: max,
            max_line_bytes: DEFAULT_MAX_LINE_BYTES,
            memory_budget: crate::budget::default_memory_budget(),
        }
    }
}

/// Loads a mesh, choosing the format by the file extension (see [`Format::from_path`])
/// and decompressing a `.gz` file on the way, with the default [`LoadOptions`].
///
/// Fails with [`LoadErrorKind::UnknownFormat`] for an extension it does not know,
/// [`LoadErrorKind::Io`] when the file cannot be read or its gzip stream is
/// corrupt, [`LoadErrorKind::DecompressedTooLarge`] for a gzip stream that
/// expands beyond the limit, [`LoadErrorKind::InputTooLarge`] for a file
/// beyond it, [`LoadErrorKind::MemoryBudget`] for one holding more than the
/// memory budget, and the errors of [`read_with`] otherwise; every error names `path`.
///
/// ```no_run
/// let mesh = proxima::io::load("dragon_vrip.ply.gz")?;
/// println!("{} vertices, {} faces", mesh.vertex_count(), mesh.face_count());
/// # Ok::<(), proxima::LoadError>(())
/// ```
pub fn load(path: impl AsRef<Path>) -> Result<Mesh, LoadError> {
    load_with(path, &LoadOptions::default())
}

/// [`load`] with explicit limits. The file is streamed: a gzip file is
/// decompressed as it is read, and neither it nor its output is ever held
/// beyond the limits, whatever it is (a gzip bomb, `/dev/zero`, `/dev/urandom`).
pub fn load_with(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Mesh, LoadError> {
    let path = path.as_ref();
    let format = Format::from_path(path).ok_or_else(|| LoadError::new(path, None, LoadErrorKind::UnknownFormat))?;
    let file = std::fs::File::open(path).map_err(|e| LoadError::new(path, None, e))?;
    let metadata = file.metadata().map_err(|e| LoadError::new(path, None, e))?;
    let mut guard = read::TextGuard::new(format, options.max_line_bytes);
    let bytes = if is_gzip_path(path) {
        let decoder = flate2::read::MultiGzDecoder::new(std::io::BufReader::new(file));
        let limit = read::Limit::Decompressed(options.max_decompressed_bytes);
        read::read_bounded(decoder, limit, None, &mut guard, options.budget(), path)?
    } else {
        // Devices and pipes report a size of 0: only a regular file's size is known.
        let size = metadata.is_file().then_some(metadata.len());
        read::read_bounded(
            file,
            read::Limit::Input(options.max_input_bytes),
            size,
            &mut guard,
            options.budget(),
            path,
        )?
    };
    parse_checked(&bytes, format, path, options.budget())
}

/// Reads a mesh in `format` from `reader` (a file, a pipe, a decompressor, …)
/// to its end and parses it, within the limits of `options`:
/// [`LoadErrorKind::InputTooLarge`] past [`LoadOptions::max_input_bytes`],
/// [`LoadErrorKind::LineTooLong`] and [`LoadErrorKind::NotText`] (with the
/// line) as soon as text that is not text arrives, so an endless stream of
/// zeros fails after its first chunk; then the errors of [`parse`].
/// `path_for_errors` only labels errors.
///
/// ```
/// use proxima::io::{Format, LoadOptions, read_with};
/// use proxima::LoadErrorKind;
/// // An endless stream of zeros: a NUL byte on line 1, found in the first chunk.
/// let e = read_with(std::io::repeat(0), Format::Obj, "zeros.obj".as_ref(), &LoadOptions::default()).unwrap_err();
/// assert!(matches!(e.kind, LoadErrorKind::NotText));
/// assert_eq!(e.line, Some(1));
/// ```
pub fn read_with(
    reader: impl Read,
    format: Format,
    path_for_errors: &Path,
    options: &LoadOptions,
) -> Result<Mesh, LoadError> {
    let mut guard = read::TextGuard::new(format, options.max_line_bytes);
    let limit = read::Limit::Input(options.max_input_bytes);
    let bytes = read::read_bounded(reader, limit, None, &mut guard, options.budget(), path_for_errors)?;
    parse_checked(&bytes, format, path_for_errors, options.budget())
}

/// Decompresses every gzip member of `bytes`, failing with
/// [`LoadErrorKind::DecompressedTooLarge`] as soon as the output would exceed
/// `max_bytes` (so a gzip bomb costs at most `max_bytes` of memory), and with
/// [`LoadErrorKind::Io`] for a corrupt stream.
///
/// ```
/// use std::io::Write;
/// let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
/// encoder.write_all(&vec![b' '; 1 << 20]).unwrap();
/// let bomb = encoder.finish().unwrap();
/// assert!(proxima::io::gunzip(&bomb, 1 << 20).is_ok());
/// assert!(matches!(
///     proxima::io::gunzip(&bomb, 1000),
///     Err(proxima::LoadErrorKind::DecompressedTooLarge { limit: 1000 })
/// ));
/// ```
pub fn gunzip(bytes: &[u8], max_bytes: u64) -> Result<Vec<u8>, LoadErrorKind> {
    // A guess only (text meshes compress about 4:1), capped; the vector grows as needed.
    let guess = (bytes.len() as u64).saturating_mul(4).min(1 << 28).min(max_bytes);
    let mut out = Vec::with_capacity(guess as usize);
    // One byte past the limit tells "exactly at the limit" from "beyond it".
    flate2::read::MultiGzDecoder::new(bytes)
        .take(max_bytes.saturating_add(1))
        .read_to_end(&mut out)?;
    if out.len() as u64 > max_bytes {
        return Err(LoadErrorKind::DecompressedTooLarge { limit: max_bytes });
    }
    Ok(out)
}

/// Parses the (uncompressed) content of a mesh file in `format`. `path_for_errors`
/// is only used to label errors.
///
/// Never panics, and allocates in proportion to the size of `bytes`, whatever
/// its headers announce. See the [module documentation](self) for the accepted forms and
/// the errors.
///
/// ```
/// use proxima::io::{parse, Format};
/// let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
/// let mesh = parse(obj, Format::Obj, "inline.obj".as_ref())?;
/// assert_eq!(mesh.face(0), &[0, 1, 2]);
///
/// let err = parse(b"v 0 0 0\nf 1 2 0\n", Format::Obj, "bad.obj".as_ref()).unwrap_err();
/// assert_eq!(err.line, Some(2));
/// # Ok::<(), proxima::LoadError>(())
/// ```
pub fn parse(bytes: &[u8], format: Format, path_for_errors: &Path) -> Result<Mesh, LoadError> {
    parse_with(bytes, format, path_for_errors, &LoadOptions::default())
}

/// [`parse`] within the memory budget and the line length of `options`
/// (its size limits concern reading, which the bytes have passed).
///
/// ```
/// use proxima::io::{parse_with, Format, LoadOptions};
/// use proxima::LoadErrorKind;
/// let small = LoadOptions { memory_budget: 1000, ..LoadOptions::default() };
/// let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".repeat(10);
/// let e = parse_with(&obj, Format::Obj, "many.obj".as_ref(), &small).unwrap_err();
/// assert!(matches!(e.kind, LoadErrorKind::MemoryBudget { budget: 1000, .. }));
/// ```
pub fn parse_with(
    bytes: &[u8],
    format: Format,
    path_for_errors: &Path,
    options: &LoadOptions,
) -> Result<Mesh, LoadError> {
    // The same checks as a streamed file gets, so both give the same errors.
    let mut guard = read::TextGuard::new(format, options.max_line_bytes);
    guard.feed(bytes, path_for_errors)?;
    guard.check_budget(bytes.len() as u64, options.budget(), path_for_errors)?;
    parse_checked(bytes, format, path_for_errors, options.budget())
}

/// [`parse`] of bytes the text checks have passed.
fn parse_checked(
    bytes: &[u8],
    format: Format,
    path_for_errors: &Path,
    budget: read::Budget,
) -> Result<Mesh, LoadError> {
    // Text written by some Windows tools starts with a UTF-8 byte order mark.
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mesh = match format {
        Format::Obj => obj::parse(text, path_for_errors),
        Format::Ply => ply::parse(bytes, path_for_errors, budget),
        Format::Stl => stl::parse(bytes, path_for_errors, budget),
        Format::Off => off::parse(text, path_for_errors, budget),
        Format::Glb => glb::parse(bytes, path_for_errors, budget),
    }?;
    // The counts made while reading are lower bounds (a face counted as one
    // triangle, an OBJ face continued on the next line): the mesh made is
    // counted once more, exactly, so that a mesh returned always fits.
    budget
        .check(
            bytes.len() as u64,
            mesh.vertex_count() as u64,
            mesh.triangle_count() as u64,
            true,
        )
        .map_err(|kind| LoadError::new(path_for_errors, None, kind))?;
    Ok(mesh)
}

/// `text` made safe to print on a terminal, cut to `max_chars` characters
/// (and an ellipsis): control characters (escape sequences, carriage
/// returns, …) and bidirectional-text overrides are written as `\u{…}`
/// escapes, so what a hostile file holds cannot move the cursor, recolour
/// the terminal or reorder what is shown.
///
/// ```
/// assert_eq!(proxima::io::escape_for_terminal("a\x1b[31mb", 80), "a\\u{1b}[31mb");
/// assert_eq!(proxima::io::escape_for_terminal("abcdef", 3), "abc…");
/// ```
pub fn escape_for_terminal(text: &str, max_chars: usize) -> String {
    let mut out = String::with_capacity(text.len().min(max_chars.saturating_mul(4)));
    for (n, c) in text.chars().enumerate() {
        if n == max_chars {
            out.push('…');
            break;
        }
        let bidi = matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}');
        if c.is_control() || bidi {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    out
}
