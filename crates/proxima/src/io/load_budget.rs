//! The memory budget of loading, on its own so that the parsers and the
//! bounded reader (`read.rs`, which sniffs STL through `stl.rs`) can all use
//! it without importing one another.

use crate::budget::{LOAD_BYTES_PER_TRIANGLE, LOAD_BYTES_PER_VERTEX};
use crate::error::LoadErrorKind;

/// The memory budget of loading: the bytes held (the input read so far) and
/// the mesh it becomes, counted at [`LOAD_BYTES_PER_VERTEX`] and
/// [`LOAD_BYTES_PER_TRIANGLE`], may not pass `bytes`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Budget {
    pub(super) bytes: u64,
}

impl Budget {
    /// The bytes counted for `input` bytes held and a mesh of `vertices`
    /// vertices and `triangles` triangles.
    pub(super) fn need(input: u64, vertices: u64, triangles: u64) -> u128 {
        u128::from(input)
            + u128::from(vertices) * u128::from(LOAD_BYTES_PER_VERTEX)
            + u128::from(triangles) * u128::from(LOAD_BYTES_PER_TRIANGLE)
    }

    /// [`LoadErrorKind::MemoryBudget`] when the counts pass the budget;
    /// `complete` when they are the whole file's, not those read so far.
    pub(super) fn check(self, input: u64, vertices: u64, triangles: u64, complete: bool) -> Result<(), LoadErrorKind> {
        let bytes = Self::need(input, vertices, triangles);
        if bytes <= u128::from(self.bytes) {
            return Ok(());
        }
        let what = if vertices == 0 && triangles == 0 {
            format!("{input} bytes of input{}", if complete { "" } else { " (so far)" })
        } else {
            format!(
                "{}{vertices} vertices and {triangles} triangles, with their trees ({LOAD_BYTES_PER_VERTEX} and \
                 {LOAD_BYTES_PER_TRIANGLE} bytes each) and the {input} bytes of input,",
                if complete { "" } else { "at least " }
            )
        };
        Err(LoadErrorKind::MemoryBudget {
            what,
            bytes,
            budget: self.bytes,
        })
    }
}
