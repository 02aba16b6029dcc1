//! Why a file could not be loaded: the file, the line and the kind.

use crate::error::{budget_set_by_env, human};
use crate::mesh::MeshError;
use std::fmt;
use std::path::PathBuf;

/// Why a file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadErrorKind {
    /// Reading the file failed.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The extension names no format we read.
    #[error("unknown mesh format (expected .obj, .ply, .stl, .off or .glb, optionally .gz)")]
    UnknownFormat,
    /// The content does not follow the format.
    #[error("{0}")]
    Syntax(String),
    /// The file ends before the data it announces.
    #[error("unexpected end of file: {0}")]
    Truncated(String),
    /// The file announces sizes that cannot be real (checked before allocating).
    #[error("implausible size: {0}")]
    Implausible(String),
    /// The data parses but does not make a valid mesh.
    #[error("{0}")]
    Mesh(#[from] MeshError),
    /// A compressed file expands beyond the configured limit
    /// ([`LoadOptions::max_decompressed_bytes`](crate::io::LoadOptions)).
    #[error("decompressed data exceeds the limit of {limit} bytes")]
    DecompressedTooLarge {
        /// The limit, in bytes.
        limit: u64,
    },
    /// An uncompressed input holds more bytes than the configured limit
    /// ([`LoadOptions::max_input_bytes`](crate::io::LoadOptions)); reading stops there.
    #[error("the input exceeds the limit of {limit} bytes")]
    InputTooLarge {
        /// The limit, in bytes.
        limit: u64,
    },
    /// A line of a text format longer than the limit
    /// ([`LoadOptions::max_line_bytes`](crate::io::LoadOptions)), such as an
    /// endless stream without line ends; reading stops there.
    #[error("line longer than {limit} bytes (is this a text file?)")]
    LineTooLong {
        /// The limit, in bytes.
        limit: usize,
    },
    /// A NUL byte where a text format (OBJ, OFF, a PLY header or ascii data, a
    /// points file) is expected: binary data, not text.
    #[error("a NUL byte: binary data where text is expected")]
    NotText,
    /// Text that is not valid UTF-8 where UTF-8 is required (points files).
    #[error("invalid UTF-8")]
    InvalidUtf8,
    /// What the file holds (counted while it is read, or from its header or
    /// its glTF scene before anything is expanded) would pass the memory
    /// budget ([`LoadOptions::memory_budget`](crate::io::LoadOptions)) once
    /// loaded, at the bytes per vertex and per triangle of
    /// [`crate::budget`]; reading stops there.
    #[error(
        "{what} need about {}, more than the memory budget of {}",
        human(.bytes), budget_set_by_env(.budget)
    )]
    MemoryBudget {
        /// What was counted, for the message (`at least 20000000 vertices
        /// and 0 triangles, with their trees and the 160000000 bytes read,`).
        what: String,
        /// Bytes counted so far (a lower bound of the whole when reading
        /// stopped early).
        bytes: u128,
        /// The budget, in bytes.
        budget: u64,
    },
}

/// A load failure, with the file and (for text formats) the 1-based line.
#[derive(Debug, thiserror::Error)]
pub struct LoadError {
    /// The file being read.
    pub path: PathBuf,
    /// 1-based line number, when the format is text and the place is known.
    pub line: Option<usize>,
    /// What went wrong.
    #[source]
    pub kind: LoadErrorKind,
}

impl LoadError {
    /// An error at `line` (if known) of `path`.
    pub fn new(path: impl Into<PathBuf>, line: Option<usize>, kind: impl Into<LoadErrorKind>) -> Self {
        Self {
            path: path.into(),
            line,
            kind: kind.into(),
        }
    }
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.path.display(), line, self.kind),
            None => write!(f, "{}: {}", self.path.display(), self.kind),
        }
    }
}
