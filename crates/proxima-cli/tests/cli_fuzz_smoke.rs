//! A fuzz target for the command line's argument space, run as a smoke test:
//! a few hundred seeded random combinations of the options that size work
//! (resolutions, cell sizes, thread counts, step counts, query counts, k,
//! sample counts and spreads)
//! and of coordinates at the extremes (0, -0, 1e-45, 1e-30, 1e30, 3.4e38,
//! inf, nan, u64 and i64 extremes), on a tiny mesh and the embedded bunny.
//!
//! Every run must end with status 0, 1 or 2 (never a panic's 101 nor a
//! signal), print at most one line on stderr when it fails with 1, finish
//! within [`TIMEOUT`], and stay within [`MAX_PEAK_BYTES`] of memory (its
//! `VmHWM`, sampled while it runs), under a small memory budget
//! (`PROXIMA_MEMORY_BUDGET`) and cell-test limit (`PROXIMA_MAX_CELL_TESTS`).
//! `PROXIMA_CLI_FUZZ_RUNS` and `PROXIMA_CLI_FUZZ_SEED` change the number of
//! runs and the seed.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest a run may take.
const TIMEOUT: Duration = Duration::from_secs(20);
/// The memory budget given to each run.
const BUDGET: &str = "128M";
/// The cell-test limit given to each run: about 0.2 s of dense voxelization.
const MAX_CELL_TESTS: &str = "67108864";
/// The largest peak resident memory accepted: the budget, the mesh, the
/// binary and the thread stacks, with room to spare.
const MAX_PEAK_BYTES: u64 = 512 << 20;

/// xorshift64*: reproducible without a dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn pick<'a>(&mut self, values: &[&'a str]) -> &'a str {
        values[(self.next() % values.len() as u64) as usize]
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
}

const RESOLUTIONS: &[&str] = &[
    "0",
    "1",
    "2",
    "7",
    "64",
    "1000",
    "1024",
    "1025",
    "4096",
    "65536",
    "4194304",
    "1073741824",
    "4294967295",
    "4294967296",
    "-1",
];
const CELLS: &[&str] = &[
    "0",
    "-0",
    "1e-45",
    "1e-30",
    "1e-3",
    "0.01",
    "0.5",
    "1",
    "1e30",
    "3.4e38",
    "inf",
    "nan",
    "-1",
    "1e-3,1,1",
    "1,1e30,1e-30",
];
const THREADS: &[&str] = &["0", "1", "2", "3", "8", "1000", "100000", "18446744073709551615"];
const STEPS: &[&str] = &["0", "1", "16", "1000", "10000000", "10000001", "18446744073709551615"];
const QUERIES: &[&str] = &["0", "1", "5", "20", "1000", "1000000000", "18446744073709551615"];
const KS: &[&str] = &["0", "1", "3", "1000", "18446744073709551615"];
const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1e-45",
    "1e-30",
    "0.25",
    "-3",
    "1e30",
    "-1e30",
    "3.4e38",
    "-3.4e38",
    "inf",
    "nan",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
];

fn point(rng: &mut Rng) -> String {
    // Mostly ordinary coordinates, so that runs get past the parsing.
    let mut c = || {
        if rng.chance(60) {
            ["0.1", "-0.5", "2", "0", "1"][(rng.next() % 5) as usize]
        } else {
            rng.pick(NUMBERS)
        }
    };
    format!("{},{},{}", c(), c(), c())
}

/// One random command line.
fn arguments(rng: &mut Rng, meshes: &[&str]) -> Vec<String> {
    let mesh = rng.pick(meshes).to_string();
    let mut args: Vec<String> = Vec::new();
    let mut push = |a: &[&str]| args.extend(a.iter().map(|s| s.to_string()));
    match rng.next() % 6 {
        0 => {
            push(&["voxelize", &mesh, "--res", rng.pick(RESOLUTIONS)]);
            if rng.chance(50) {
                push(&["--threads", rng.pick(THREADS)]);
            }
            if rng.chance(30) {
                push(&["--insert", rng.pick(&["classic", "scanline"])]);
            }
        }
        1 => {
            let primitives = rng.pick(&["vertices", "edges", "faces", "all"]);
            push(&["grid", &mesh, "--cell", rng.pick(CELLS), "--primitives", primitives]);
            if rng.chance(30) {
                push(&["--origin", &point(rng)]);
            }
            if rng.chance(30) {
                push(&["--insert", rng.pick(&["classic", "scanline"])]);
            }
        }
        2 => {
            let (origin, dir) = (point(rng), point(rng));
            push(&[
                "traverse",
                "--origin",
                &origin,
                "--dir",
                &dir,
                "--cell",
                rng.pick(CELLS),
            ]);
            push(&["--steps", rng.pick(STEPS)]);
        }
        3 => {
            let (origin, dir) = (point(rng), point(rng));
            push(&["raycast", &mesh, "--origin", &origin, "--dir", &dir]);
            if rng.chance(60) {
                push(&["--cell", rng.pick(CELLS)]);
            }
            if rng.chance(30) {
                push(&["--any"]);
            }
        }
        4 => {
            let p = point(rng);
            push(&["closest", &mesh, "--point", &p, "-k", rng.pick(KS)]);
            if rng.chance(30) {
                push(&["--method", "linear"]);
            }
        }
        _ => {
            push(&["bench", &mesh, "--queries", rng.pick(QUERIES), "--json"]);
            push(&[
                "--threads",
                rng.pick(THREADS),
                "--primitives",
                rng.pick(&["vertices", "faces"]),
            ]);
        }
    }
    args
}

/// One random `sdf` command line, drawn from its own generator so that the
/// other commands' lines stay those of the seeds before `sdf` existed.
fn sdf_arguments(rng: &mut Rng, meshes: &[&str]) -> Vec<String> {
    let mesh = rng.pick(meshes).to_string();
    let mut args: Vec<String> = Vec::new();
    let mut push = |a: &[&str]| args.extend(a.iter().map(|s| s.to_string()));
    match rng.next() % 3 {
        0 => {
            let p = point(rng);
            push(&["sdf", &mesh, "--point", &p]);
            if rng.chance(30) {
                push(&["--exact"]);
            }
        }
        1 => push(&["sdf", &mesh, "--grid", rng.pick(RESOLUTIONS), "--out", "g.npy"]),
        _ => {
            push(&["sdf", &mesh, "--sample", rng.pick(QUERIES), "--out", "s.npz"]);
            if rng.chance(40) {
                push(&["--near-sigma", rng.pick(NUMBERS)]);
            }
        }
    }
    if rng.chance(30) {
        push(&["--sign", "pseudonormal"]);
    }
    if rng.chance(30) {
        push(&["--threads", rng.pick(THREADS)]);
    }
    args
}

/// The peak resident memory of a running process (`VmHWM`), in bytes.
fn peak_bytes(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<u64>().ok()? * 1024)
}

/// Runs one command line; `Err` says what went wrong.
fn run(args: &[String], dir: &Path) -> Result<(), String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .current_dir(dir)
        .env("PROXIMA_MEMORY_BUDGET", BUDGET)
        .env("PROXIMA_MAX_CELL_TESTS", MAX_CELL_TESTS)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("spawn: {e}"))?;
    // Stderr is read by a thread, so a chatty child never blocks on a full pipe.
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut text);
        text
    });
    let start = Instant::now();
    let mut peak = 0u64;
    let status = loop {
        if let Some(bytes) = peak_bytes(child.id()) {
            peak = peak.max(bytes);
        }
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {TIMEOUT:?} (killed)"));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let err = reader.join().unwrap();
    if peak > MAX_PEAK_BYTES {
        return Err(format!("peak memory {peak} bytes, more than {MAX_PEAK_BYTES}"));
    }
    match status.code() {
        Some(0 | 2) => Ok(()),
        Some(1) if err.trim_end().lines().count() == 1 && err.starts_with("proxima: ") => Ok(()),
        Some(1) => Err(format!("exit 1 without exactly one `proxima: ` line on stderr: {err}")),
        code => Err(format!("status {code:?} (signal or panic): {err}")),
    }
}

#[test]
fn cli_argument_space() {
    let runs: usize = std::env::var("PROXIMA_CLI_FUZZ_RUNS").map_or(300, |v| v.parse().unwrap());
    let seed: u64 = std::env::var("PROXIMA_CLI_FUZZ_SEED").map_or(21, |v| v.parse().unwrap());
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("sq.obj"),
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let bunny = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj");
    let meshes = ["sq.obj", "tri.obj", bunny];
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let start = Instant::now();
    let mut failures = Vec::new();
    let mut sdf_rng = Rng(seed.wrapping_mul(0xd1b5_4a32_d192_ed03) | 1);
    let lines = (0..runs)
        .map(|_| arguments(&mut rng, &meshes))
        .chain((0..runs / 5).map(|_| sdf_arguments(&mut sdf_rng, &meshes)));
    for args in lines {
        if let Err(e) = run(&args, dir.path()) {
            failures.push(format!("proxima {}: {e}", args.join(" ")));
        }
    }
    println!(
        "{} command lines in {:.1} s",
        runs + runs / 5,
        start.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {} failed:\n{}",
        failures.len(),
        runs + runs / 5,
        failures.join("\n")
    );
}
