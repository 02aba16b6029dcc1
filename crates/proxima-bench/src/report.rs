//! What every benchmark shares: the measured row ([`Record`]), timing,
//! progress bars, the linear row's budget, and the table printed from the
//! rows. The benchmarks use this module; it uses none of them.

use indicatif::{ProgressBar, ProgressStyle};
use std::time::Instant;

/// One measured row.
pub struct Record {
    /// Primitive type.
    pub primitives: &'static str,
    /// `linear`, `tree` (binary tree, per query in input order), `tree-wide`
    /// (4-wide SIMD tree, per query), `tree-batch` (4-wide tree, Morton-ordered
    /// batch), `sphere-tree` (bounding spheres, per query in input order) or,
    /// for faces, `parry3d` (the peer library, per query in input order).
    pub method: &'static str,
    /// Build time of the structure (0 for linear).
    pub build_seconds: f64,
    /// Number of queries answered.
    pub queries: usize,
    /// Time for all of them.
    pub seconds: f64,
    /// `true` when the distances equal the reference's: for linear search and
    /// the binary tree, each other's on the shared queries; for the other
    /// structures of proxima, the binary tree's; for the peer, ours within
    /// its tolerance.
    pub agree: bool,
    /// Why the row answered fewer queries than the set, when it did for a
    /// reason of its own (the linear row's budget is said once, after the
    /// table): a structure that searched like a linear scan, a peer that
    /// spent its time budget.
    pub note: Option<String>,
}

impl Record {
    /// Queries answered per second.
    pub fn queries_per_second(&self) -> f64 {
        self.queries as f64 / self.seconds.max(1e-12)
    }
}

/// Primitive tests the linear scan may spend, so big meshes still finish
/// quickly ([`LINEAR_BUDGET_ENV`] sets it).
const LINEAR_BUDGET: u64 = 100_000_000;

/// The environment variable that sets the linear row's budget of primitive
/// tests (a positive whole number), which also bounds the rows of
/// structures that search like a linear scan.
pub const LINEAR_BUDGET_ENV: &str = "PROXIMA_BENCH_LINEAR_BUDGET";

/// The primitive tests the linear row may spend: [`LINEAR_BUDGET_ENV`] or
/// 10^8.
pub fn linear_budget() -> anyhow::Result<u64> {
    match std::env::var_os(LINEAR_BUDGET_ENV) {
        None => Ok(LINEAR_BUDGET),
        Some(value) => {
            let text = value.to_string_lossy();
            text.trim()
                .parse::<u64>()
                .ok()
                .filter(|&budget| budget > 0)
                .ok_or_else(|| {
                    anyhow::anyhow!("{LINEAR_BUDGET_ENV}: '{text}' is not a positive whole number of primitive tests")
                })
        }
    }
}

/// The queries of a row that the linear row's budget allows on `primitives`
/// primitives: at least 20 (when there are that many), at most all.
///
/// ```
/// use proxima_bench::report::linear_queries;
/// assert_eq!(linear_queries(1_000, 10, 10_000), 100);
/// assert_eq!(linear_queries(1_000, 1_000, 10_000), 20);
/// assert_eq!(linear_queries(1_000, 1, 50), 50);
/// ```
pub fn linear_queries(budget: u64, primitives: usize, total: usize) -> usize {
    usize::try_from(budget / primitives.max(1) as u64)
        .unwrap_or(usize::MAX)
        .max(20)
        .min(total)
}

/// Runs `f`, returning its value and its time in seconds.
pub fn timed<R>(f: impl FnOnce() -> R) -> (R, f64) {
    let start = Instant::now();
    let value = f();
    (value, start.elapsed().as_secs_f64())
}

/// A progress bar on standard error, or a hidden one when not `enabled`.
pub fn bar(enabled: bool, len: usize, message: &str) -> ProgressBar {
    if !enabled {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg:>16} {wide_bar} {pos}/{len} {eta}").unwrap_or(ProgressStyle::default_bar()),
    );
    bar.set_message(message.to_string());
    bar
}

/// Prints each row's note once (the wide tree's rows share theirs), in
/// parentheses after the table, naming the primitive type.
pub fn print_notes(records: &[Record]) -> std::io::Result<()> {
    let mut printed: Vec<(&str, &str)> = Vec::new();
    for r in records {
        if let Some(note) = &r.note
            && !printed.contains(&(r.primitives, note.as_str()))
        {
            printed.push((r.primitives, note));
            outln!("({}: {note})", r.primitives);
        }
    }
    Ok(())
}

/// Prints the records as a table: one row each, with its rate against the
/// linear row of the same primitive type.
pub fn print_table(records: &[Record]) -> std::io::Result<()> {
    outln!(
        "{:<10} {:<14} {:>10} {:>8} {:>10} {:>12} {:>10} {:>9}",
        "primitives",
        "method",
        "build ms",
        "queries",
        "seconds",
        "queries/s",
        "vs linear",
        "agree"
    );
    for r in records {
        let linear = records
            .iter()
            .find(|l| l.primitives == r.primitives && l.method == "linear");
        let speedup = linear.map_or(1.0, |l| r.queries_per_second() / l.queries_per_second());
        outln!(
            "{:<10} {:<14} {:>10.3} {:>8} {:>10.4} {:>12.0} {:>9.1}x {:>9}",
            r.primitives,
            r.method,
            r.build_seconds * 1e3,
            r.queries,
            r.seconds,
            r.queries_per_second(),
            speedup,
            if r.agree { "yes" } else { "NO" }
        );
    }
    Ok(())
}
