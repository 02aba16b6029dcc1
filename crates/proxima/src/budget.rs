//! Memory and work budgets: how much a grid build or a voxelization may
//! allocate and how many cells it may test, whatever the sizing options ask.
//!
//! Every option that sizes work is checked before the work starts:
//!
//! - the **work** (cell tests) is bounded by the sum, over the primitives, of
//!   the cells of their bounding boxes' cell ranges — an upper bound on the
//!   cells the insertion tests and on the entries it can produce, computed
//!   from the boxes alone ([`GridConfig::max_cell_tests`](crate::grid::GridConfig),
//!   [`VoxelConfig::max_cell_tests`](crate::grid::VoxelConfig));
//! - storage of a known size (a voxelization's dense bitset) is checked
//!   against the memory budget before it is allocated;
//! - storage whose size depends on the answer (a hash grid's entries and
//!   cells, a sparse voxelization's cells) is counted as it grows, at the
//!   bytes per entry and per cell measured below, and the build stops with an
//!   error once the count would pass the budget: it never holds more.
//!
//! The default memory budget is 2 GiB, or three quarters of the memory this
//! process can still obtain when that is less ([`default_memory_budget`]):
//! the least of what the system reports available (`MemAvailable` in
//! `/proc/meminfo`), the room left under the process's address-space limit
//! (`RLIMIT_AS`, as `ulimit -v` sets it) and the room left under its cgroup's
//! `memory.max` ([`process_available_memory`]).
//!
//! Loading a mesh is counted against the same budget
//! ([`LOAD_BYTES_PER_VERTEX`], [`LOAD_BYTES_PER_TRIANGLE`], applied by
//! [`crate::io`]).
//!
//! ```
//! use proxima::budget::{DEFAULT_MEMORY_BUDGET, default_memory_budget};
//! assert!(default_memory_budget() <= DEFAULT_MEMORY_BUDGET);
//! assert!(default_memory_budget() > 0);
//! ```

use std::sync::OnceLock;

/// The memory budget when the system has plenty available: 2 GiB.
pub const DEFAULT_MEMORY_BUDGET: u64 = 2 << 30;

/// The smallest default budget, whatever the system reports: 64 MiB.
pub const MIN_DEFAULT_MEMORY_BUDGET: u64 = 64 << 20;

/// Default of the cell-test limits: 2^32 cells of cell ranges, some seconds
/// of a dense voxelization at a few nanoseconds per range cell; sparse
/// voxelizations and hash grids reach their memory budget first (figures in
/// `docs/perf-log.md`).
pub const DEFAULT_MAX_CELL_TESTS: u64 = 1 << 32;

/// Peak bytes of a hash grid build per cell–primitive pair: the replay array
/// (4 bytes, up to twice that while it grows) and the entry array (4 bytes),
/// rounded up: 12 bytes per entry were measured at the peak (with the bytes
/// per cell below; `docs/perf-log.md`).
pub const GRID_BYTES_PER_ENTRY: u64 = 16;

/// Peak bytes of a hash grid build per occupied cell: 70–72 measured;
/// budgeted for the worst moment, right after the
/// hash map doubles while its old table is still held (33-byte slots at a
/// load of 7/16 plus the old table at 7/8: about 113 bytes), plus the cell
/// key (24), count, start and cursor (4 each).
pub const GRID_BYTES_PER_CELL: u64 = 128;

/// Peak bytes of a sparse voxelization per occupied cell: 54–55 measured;
/// budgeted for the worst moment of the hash set's growth (25-byte
/// slots, old and new table) plus each chunk's sorted list and their
/// concatenation (24 bytes each).
pub const VOXEL_BYTES_PER_SPARSE_CELL: u64 = 128;

/// Bytes a loaded mesh is counted per vertex against the memory budget
/// ([`crate::io::LoadOptions::memory_budget`]): its position (12 bytes) and
/// the tree a command builds over the vertices. Measured: 94 bytes per
/// vertex at the peak of `proxima info` (and of `closest --primitives
/// vertices`) on point clouds of 1 and 4 million vertices, by difference.
pub const LOAD_BYTES_PER_VERTEX: u64 = 96;

/// Bytes a loaded mesh is counted per triangle (a face of `n` vertices
/// counts as `n - 2`) against the memory budget: its indices and face offset
/// (16 bytes) and the trees a command builds over its faces and edges.
/// Measured: 131 bytes per triangle at the peak of `proxima info` on meshes
/// of 1 and 4 million triangles, by difference, the vertices' share taken
/// off; `closest --primitives faces` and `raycast` hold 115–123, `sdf` about
/// 234 (its winding-number nodes are not counted here).
pub const LOAD_BYTES_PER_TRIANGLE: u64 = 136;

/// Memory the system reports available (`MemAvailable` in `/proc/meminfo`),
/// in bytes, or `None` where it is not known.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// The room left under this process's address-space limit: the soft
/// `RLIMIT_AS` (`Max address space` in `/proc/self/limits`) minus the address
/// space mapped now (`VmSize` in `/proc/self/status`); `None` when there is
/// no limit or it cannot be read. Allocations fail at this limit whatever the
/// system has free, so a budget above it ends in an abort.
pub fn address_space_room() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    // "Max address space   <soft>   <hard>   bytes": the soft limit is what applies.
    let limit: u64 = line.split_whitespace().nth(3)?.parse().ok()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let size = status.lines().find(|l| l.starts_with("VmSize:"))?;
    let kib: u64 = size.split_whitespace().nth(1)?.parse().ok()?;
    Some(limit.saturating_sub(kib.saturating_mul(1024)))
}

/// The room left under this process's cgroup memory limits: the least, over
/// its cgroup and the cgroups above it, of `memory.max` minus
/// `memory.current` (cgroup v2), or `memory.limit_in_bytes` minus
/// `memory.usage_in_bytes` (cgroup v1); `None` when no limit is set or
/// readable. A container's limit applies to the whole container, not to what
/// the system has free.
pub fn cgroup_memory_room() -> Option<u64> {
    let groups = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let mut room: Option<u64> = None;
    let number = |path: &str| std::fs::read_to_string(path).ok()?.trim().parse::<u64>().ok();
    for line in groups.lines() {
        // "0::/path" (v2) or "4:memory:/path" (v1).
        let mut parts = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next()) else {
            continue;
        };
        let (base, max_file, current_file) = if controllers.is_empty() {
            ("/sys/fs/cgroup", "memory.max", "memory.current")
        } else if controllers.split(',').any(|c| c == "memory") {
            (
                "/sys/fs/cgroup/memory",
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
            )
        } else {
            continue;
        };
        let mut dir = std::path::PathBuf::from(format!("{base}{}", path.trim_end_matches('/')));
        loop {
            let at = |file: &str| dir.join(file).to_string_lossy().into_owned();
            // "max" (no limit) does not parse: skipped.
            if let (Some(max), Some(current)) = (number(&at(max_file)), number(&at(current_file))) {
                let here = max.saturating_sub(current);
                room = Some(room.map_or(here, |r| r.min(here)));
            }
            if dir.as_os_str().len() <= base.len() || !dir.pop() {
                break;
            }
        }
    }
    room
}

/// The memory this process can still obtain: the least of
/// [`available_memory`], [`address_space_room`] and [`cgroup_memory_room`],
/// `None` when none is known.
pub fn process_available_memory() -> Option<u64> {
    [available_memory(), address_space_room(), cgroup_memory_room()]
        .into_iter()
        .flatten()
        .min()
}

/// [`DEFAULT_MEMORY_BUDGET`], or three quarters of
/// [`process_available_memory`] when that is less (but at least
/// [`MIN_DEFAULT_MEMORY_BUDGET`]). Read once per process.
pub fn default_memory_budget() -> u64 {
    static BUDGET: OnceLock<u64> = OnceLock::new();
    *BUDGET.get_or_init(|| match process_available_memory() {
        Some(available) => (available / 4 * 3).clamp(MIN_DEFAULT_MEMORY_BUDGET, DEFAULT_MEMORY_BUDGET),
        None => DEFAULT_MEMORY_BUDGET,
    })
}

/// `bytes` as a short human-readable size (`1.5 GiB`), for messages.
pub fn human_bytes(bytes: u128) -> String {
    const UNITS: [&str; 7] = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} bytes")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// The environment variable that sets the memory budget of grids,
/// voxelizations and query sets, in bytes (a `K`, `M` or `G` suffix
/// multiplies by 2^10, 2^20, 2^30); default [`default_memory_budget`].
pub const MEMORY_BUDGET_ENV: &str = "PROXIMA_MEMORY_BUDGET";

/// The environment variable that sets the limit on cells tested by grid
/// builds and voxelizations; default [`DEFAULT_MAX_CELL_TESTS`].
pub const MAX_CELL_TESTS_ENV: &str = "PROXIMA_MAX_CELL_TESTS";

/// Parses `123`, `64K`, `512M`, `2G` (binary multiples) into a count.
///
/// ```
/// assert_eq!(proxima::budget::parse_size("512M"), Some(512 << 20));
/// assert_eq!(proxima::budget::parse_size("-1"), None);
/// ```
pub fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let (digits, shift) = match text.as_bytes().last()?.to_ascii_uppercase() {
        b'K' => (&text[..text.len() - 1], 10),
        b'M' => (&text[..text.len() - 1], 20),
        b'G' => (&text[..text.len() - 1], 30),
        _ => (text, 0),
    };
    digits.trim().parse::<u64>().ok()?.checked_mul(1 << shift)
}

/// The value of the environment variable `name` as a size
/// ([`parse_size`]), or `default` when it is not set; a one-line message
/// naming the variable when it is not a size.
pub fn env_size(name: &str, default: u64) -> Result<u64, String> {
    match std::env::var(name) {
        Ok(text) => {
            parse_size(&text).ok_or_else(|| format!("{name}: '{text}' is not a number (a K, M or G suffix is allowed)"))
        }
        Err(_) => Ok(default),
    }
}

/// The memory budget: [`MEMORY_BUDGET_ENV`] or [`default_memory_budget`].
pub fn memory_budget_from_env() -> Result<u64, String> {
    env_size(MEMORY_BUDGET_ENV, default_memory_budget())
}

/// The cell-test limit: [`MAX_CELL_TESTS_ENV`] or [`DEFAULT_MAX_CELL_TESTS`].
pub fn max_cell_tests_from_env() -> Result<u64, String> {
    env_size(MAX_CELL_TESTS_ENV, DEFAULT_MAX_CELL_TESTS)
}

/// The most worker threads a caller may ask for (the command line's
/// `--threads`, Python's `threads=`): 4 per core, at least 8. More would
/// only cost memory and scheduling.
///
/// ```
/// assert!(proxima::budget::max_threads() >= 8);
/// ```
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    (4 * cores).max(8)
}

/// What [`check_fits`] refuses.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BudgetError {
    /// `count` items of `bytes_each` bytes, sized by `option = value`, need
    /// more than the memory budget.
    #[error(
        "{option} {value}: needs about {} ({count} × {bytes_each} = {} bytes), more than the memory budget of {} \
         ({budget} bytes; set PROXIMA_MEMORY_BUDGET to change it)",
        human_bytes(self.bytes()),
        self.bytes(),
        human_bytes(u128::from(*budget))
    )]
    TooLarge {
        /// The option (argument) that sizes the work, as the caller spells it.
        option: String,
        /// Its value, as given.
        value: String,
        /// How many items it asks for.
        count: u128,
        /// Bytes each item needs at the peak.
        bytes_each: u128,
        /// The memory budget.
        budget: u64,
    },
    /// [`MEMORY_BUDGET_ENV`] is set but is not a size ([`parse_size`]).
    #[error("{0}")]
    Environment(String),
}

impl BudgetError {
    /// The bytes asked for (saturating); 0 for [`BudgetError::Environment`].
    pub fn bytes(&self) -> u128 {
        match self {
            Self::TooLarge { count, bytes_each, .. } => count.saturating_mul(*bytes_each),
            Self::Environment(_) => 0,
        }
    }
}

/// The one memory check of every front end: fails unless `count` items of
/// `bytes_each` bytes fit the memory budget of the environment
/// ([`memory_budget_from_env`]: [`MEMORY_BUDGET_ENV`], or
/// [`default_memory_budget`] when it is not set). The error names `option`
/// and `value`, the bytes needed and the budget, and how to change it; a
/// malformed [`MEMORY_BUDGET_ENV`] is [`BudgetError::Environment`].
///
/// ```
/// use proxima::budget::{check_fits, BudgetError};
/// assert_eq!(check_fits("--grid", 4, 64, 4), Ok(()));
/// let e = check_fits("--grid", 100_000, 100_000u128.pow(3), 4).unwrap_err();
/// assert!(matches!(e, BudgetError::TooLarge { .. }));
/// assert!(e.to_string().starts_with("--grid 100000: needs about 3.6 PiB"), "{e}");
/// assert!(e.to_string().contains("PROXIMA_MEMORY_BUDGET"));
/// ```
pub fn check_fits(
    option: &str,
    value: impl std::fmt::Display,
    count: u128,
    bytes_each: u128,
) -> Result<(), BudgetError> {
    let budget = memory_budget_from_env().map_err(BudgetError::Environment)?;
    check_fits_in(budget, option, value, count, bytes_each)
}

/// [`check_fits`] against an explicit `budget` instead of the environment's.
pub fn check_fits_in(
    budget: u64,
    option: &str,
    value: impl std::fmt::Display,
    count: u128,
    bytes_each: u128,
) -> Result<(), BudgetError> {
    if count.saturating_mul(bytes_each) <= u128::from(budget) {
        return Ok(());
    }
    Err(BudgetError::TooLarge {
        option: option.to_string(),
        value: value.to_string(),
        count,
        bytes_each,
        budget,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("123"), Some(123));
        assert_eq!(parse_size(" 64k "), Some(64 << 10));
        assert_eq!(parse_size("512M"), Some(512 << 20));
        assert_eq!(parse_size("2G"), Some(2 << 30));
        assert_eq!(parse_size("G"), None);
        assert_eq!(parse_size(""), None);
        assert_eq!(parse_size("-1"), None);
        assert_eq!(parse_size("18446744073709551615G"), None);
    }

    #[test]
    fn human_sizes() {
        assert_eq!(human_bytes(0), "0 bytes");
        assert_eq!(human_bytes(1023), "1023 bytes");
        assert_eq!(human_bytes(1536), "1.5 KiB");
        assert_eq!(human_bytes(2 << 30), "2.0 GiB");
        assert_eq!(human_bytes(3 << 40), "3.0 TiB");
        assert_eq!(
            human_bytes(u128::MAX),
            format!("{:.1} EiB", u128::MAX as f64 / (1u64 << 60) as f64)
        );
    }

    #[test]
    fn fits_up_to_the_budget_and_names_the_option_past_it() {
        assert_eq!(check_fits_in(1000, "n", 250, 250, 4), Ok(()));
        let e = check_fits_in(1000, "n", 251, 251, 4).unwrap_err();
        assert_eq!(
            e,
            BudgetError::TooLarge {
                option: "n".into(),
                value: "251".into(),
                count: 251,
                bytes_each: 4,
                budget: 1000
            }
        );
        assert_eq!(e.bytes(), 1004);
        assert_eq!(
            e.to_string(),
            "n 251: needs about 1004 bytes (251 × 4 = 1004 bytes), more than the memory budget of 1000 bytes \
             (1000 bytes; set PROXIMA_MEMORY_BUDGET to change it)"
        );
        // Counts whose product passes u128 saturate instead of wrapping into a small number.
        let e = check_fits_in(u64::MAX, "k", "huge", u128::MAX, 48).unwrap_err();
        assert_eq!(e.bytes(), u128::MAX);
    }

    #[test]
    fn the_thread_cap_is_four_per_core_at_least_eight() {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        assert_eq!(max_threads(), (4 * cores).max(8));
    }

    #[test]
    fn the_default_budget_is_bounded() {
        let budget = default_memory_budget();
        assert!((MIN_DEFAULT_MEMORY_BUDGET..=DEFAULT_MEMORY_BUDGET).contains(&budget));
    }
}
