//! What the one-run benchmark binaries (`refit`, `scene`) share: a numeric
//! flag from the command line, and the time of a piece of work.

use std::time::Instant;

/// The number after `flag` in `args`, or `default` when absent. Panics on
/// a value that does not parse: these binaries are the developers' tools.
pub fn flag_value(args: &[String], flag: &str, default: f64) -> f64 {
    args.iter()
        .position(|a| a == flag)
        .map_or(default, |i| args[i + 1].parse().expect(flag))
}

/// Seconds `work` takes.
pub fn timed(work: impl FnOnce()) -> f64 {
    let start = Instant::now();
    work();
    start.elapsed().as_secs_f64()
}
