//! The two-mesh benchmark of issue 36 (see `proxima_bench::pairs`).
//!
//! ```text
//! pairs poses A B --out DIR [--fit] [--count N] [--seed S]   # the workload folder: a.ply, b.ply, {near,far,overlap}.poses
//! pairs run DIR [--class C]... [--limit N] [--peer-poses N] [--dump FILE]   # proxima and parry3d rows, JSON on stdout
//! pairs judge DIR PEER.json                                  # a peer's answers (coal, ...) against proxima's
//! pairs self MESH [--threads T] [--reps R] [--dump FILE]     # proxima's self-intersections
//! pairs judge-self MESH OURS.json THEIRS.json                # face pairs only one side reports, decided exactly
//! ```
//!
//! A and B are mesh files or `ico1m` / `ico100k`; `--fit` scales B about its
//! centre to A's bounding box diagonal. Exits 1 with one line on stderr on
//! bad input.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use proxima::MeshIndex;
use proxima_bench::poses::{PoseClass, format_poses, generate, ply_bytes, scaled_to};
use serde_json::{Value, json};
use std::path::PathBuf;
use std::process::ExitCode;

/// Two meshes under rigid motion: distance, collision, self-intersections.
#[derive(Parser)]
#[command(name = "pairs", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Writes a workload folder: both meshes as binary PLY and the seeded
    /// poses of B against A in each class.
    Poses {
        /// The unmoved mesh (file, `ico1m` or `ico100k`).
        a: String,
        /// The moved mesh.
        b: String,
        /// The folder to write.
        #[arg(long)]
        out: PathBuf,
        /// Scale B about its centre to A's bounding box diagonal.
        #[arg(long)]
        fit: bool,
        /// Poses per class.
        #[arg(long, default_value_t = 10_000)]
        count: usize,
        /// The seed of the pose sets.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Times proxima's rows (and parry3d's on the first --peer-poses poses)
    /// on a workload folder; prints JSON.
    Run {
        /// The workload folder.
        dir: PathBuf,
        /// The classes (default: all three).
        #[arg(long, value_enum)]
        class: Vec<PoseClass>,
        /// At most this many poses per class.
        #[arg(long)]
        limit: Option<usize>,
        /// proxima's distance rows on the first this many poses of each class.
        #[arg(long, default_value_t = 1_000)]
        distance_poses: usize,
        /// parry3d's intersection test on the first this many poses of each class (0: no parry3d rows).
        #[arg(long, default_value_t = 100)]
        peer_poses: usize,
        /// parry3d's distance on the first this many poses of each class.
        #[arg(long, default_value_t = 3)]
        peer_distance_poses: usize,
        /// Writes proxima's answers per pose (JSON) for the Python peers.
        #[arg(long)]
        dump: Option<PathBuf>,
    },
    /// Judges a peer's answers (JSON) against proxima's on the same poses.
    Judge {
        /// The workload folder.
        dir: PathBuf,
        /// The peer's answers.
        peer: PathBuf,
    },
    /// Times proxima's self-intersections of a mesh; prints JSON.
    #[command(name = "self")]
    SelfIntersections {
        /// The mesh (file, `ico1m` or `ico100k`).
        mesh: String,
        /// Threads.
        #[arg(long, default_value_t = 1)]
        threads: usize,
        /// Timed runs.
        #[arg(long, default_value_t = 3)]
        reps: usize,
        /// Writes the face pairs (JSON list of [i, j]).
        #[arg(long)]
        dump: Option<PathBuf>,
    },
    /// Face pairs that only proxima or only the peer reports as
    /// self-intersecting, each decided by proxima's exact test.
    JudgeSelf {
        /// The mesh (as given to `self`).
        mesh: String,
        /// proxima's pairs (`self --dump`).
        ours: PathBuf,
        /// The peer's pairs (JSON list of [i, j], face = triangle indices).
        theirs: PathBuf,
    },
}

fn load(name: &str) -> Result<proxima::Mesh> {
    proxima_bench::load_named(name).map_err(|e| anyhow::anyhow!("{name}: {e}"))
}

fn read_pairs(path: &PathBuf) -> Result<Vec<[u32; 2]>> {
    let text = std::fs::read_to_string(path).with_context(|| path.display().to_string())?;
    serde_json::from_str(&text).with_context(|| path.display().to_string())
}

fn run(command: Command) -> Result<Value> {
    match command {
        Command::Poses {
            a,
            b,
            out,
            fit,
            count,
            seed,
        } => {
            let mesh_a = load(&a)?;
            let mut mesh_b = load(&b)?;
            if fit {
                mesh_b = scaled_to(&mesh_b, mesh_a.bounds().diagonal())?;
            }
            std::fs::create_dir_all(&out).with_context(|| out.display().to_string())?;
            std::fs::write(out.join("a.ply"), ply_bytes(&mesh_a))?;
            std::fs::write(out.join("b.ply"), ply_bytes(&mesh_b))?;
            let (ia, ib) = (MeshIndex::new(mesh_a), MeshIndex::new(mesh_b));
            let mut made = Vec::new();
            for class in PoseClass::ALL {
                let (poses, seconds) = proxima_bench::report::timed(|| generate(&ia, &ib, class, count, seed));
                let header = [
                    format!(
                        "poses of b ({b}{}) against a ({a}), class {}",
                        if fit { ", fitted" } else { "" },
                        class.name()
                    ),
                    format!("seed {seed}, {count} poses; rows of [R t; 0 0 0 1], row-major"),
                ];
                std::fs::write(
                    out.join(format!("{}.poses", class.name())),
                    format_poses(&poses?, &header),
                )?;
                made.push(json!({ "class": class.name(), "poses": count, "seconds": seconds }));
            }
            Ok(json!(made))
        }
        Command::Run {
            dir,
            class,
            limit,
            distance_poses,
            peer_poses,
            peer_distance_poses,
            dump,
        } => proxima_bench::pairs::run(&proxima_bench::pairs::Options {
            dir: &dir,
            classes: if class.is_empty() {
                PoseClass::ALL.to_vec()
            } else {
                class
            },
            limit,
            distance_poses,
            peer_poses,
            peer_distance_poses,
            dump: dump.as_deref(),
        }),
        Command::Judge { dir, peer } => proxima_bench::pairs::judge_file(&dir, &peer),
        Command::SelfIntersections {
            mesh,
            threads,
            reps,
            dump,
        } => {
            let index = MeshIndex::new(load(&mesh)?);
            let (pairs, seconds) = proxima_bench::pairs::self_intersections(&index, threads, reps)?;
            if let Some(path) = &dump {
                std::fs::write(path, serde_json::to_string(&pairs)?).with_context(|| path.display().to_string())?;
            }
            Ok(json!({
                "mesh": mesh, "triangles": index.mesh().triangle_count(), "threads": threads,
                "pairs": pairs.len(), "seconds": seconds,
            }))
        }
        Command::JudgeSelf { mesh, ours, theirs } => {
            let mesh = load(&mesh)?;
            let counts = proxima_bench::pairs::judge_self(&mesh, &read_pairs(&ours)?, &read_pairs(&theirs)?)?;
            Ok(json!({
                "only_proxima": counts[0], "only_proxima_meeting": counts[1],
                "only_peer": counts[2], "only_peer_meeting": counts[3],
            }))
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse().command) {
        Ok(value) => {
            println!("{value:#}");
            ExitCode::SUCCESS
        }
        Err(error) => {
            proxima_bench::input::note(&format!("{error:#}").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
