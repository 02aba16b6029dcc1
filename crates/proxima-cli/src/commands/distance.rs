//! `proxima distance A B [--pose-a M] [--pose-b M | --poses FILE]
//! [--max-distance D] [--threads T] [--json]`: the distance between two
//! placed meshes and its nearest points and faces, one answer per pose of B,
//! as CSV `pose,distance,ax,ay,az,bx,by,bz,face_a,face_b` or JSON.

use crate::common::note;
use crate::two_meshes::{Placement, TwoMeshes};
use anyhow::Result;
use proxima::pair::{self, PairDistance, RigidPose};
use serde_json::{Value, json};
use std::io::{BufWriter, Write};
use std::time::Instant;

/// Arguments of `proxima distance`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pair: TwoMeshes,
    /// Only distances below D: at D or beyond the answer is `none` (`null`
    /// in JSON), found without opening farther parts of the meshes.
    #[arg(long, value_name = "D", value_parser = parse_max_distance, allow_hyphen_values = true)]
    max_distance: Option<f64>,
}

/// The CSV header.
pub const CSV_HEADER: &str = "pose,distance,ax,ay,az,bx,by,bz,face_a,face_b";

/// Parses `--max-distance`: a number of at least 0 (`inf` is no bound).
fn parse_max_distance(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(d) if d >= 0.0 => Ok(d),
        _ => Err(format!("'{text}' is not a number >= 0")),
    }
}

/// Bytes held per pose of a poses file: the pose and its answer.
const BYTES_PER_POSE: usize = size_of::<RigidPose>() + size_of::<Option<PairDistance>>();

/// Runs `proxima distance`.
pub fn run(args: Args) -> Result<()> {
    let inputs = args.pair.inputs(BYTES_PER_POSE)?;
    let (a, b) = (&inputs.a, &inputs.b);
    let start = Instant::now();
    let answers: Vec<Option<PairDistance>> = inputs.pool.install(|| -> Result<_> {
        let d_max = args.max_distance.unwrap_or(f64::INFINITY);
        Ok(match &inputs.placement {
            Placement::One(pose_a, pose_b) => vec![pair::distance_below(a, pose_a, b, pose_b, d_max)?],
            Placement::Many(poses) => pair::distance_below_batch(a, b, poses, d_max)?,
        })
    })?;
    let seconds = start.elapsed().as_secs_f64();

    let mut out = BufWriter::new(std::io::stdout().lock());
    if args.pair.json {
        let head = json!({
            "mesh_a": args.pair.a.display().to_string(),
            "mesh_b": args.pair.b.display().to_string(),
            "faces_a": a.mesh().face_count(),
            "faces_b": b.mesh().face_count(),
            "poses": answers.len(),
            "max_distance": args.max_distance,
            "threads": inputs.pool.current_num_threads(),
            "seconds": seconds,
        });
        // The answers are written one by one after the summary's keys.
        let head = serde_json::to_string_pretty(&head)?;
        write!(
            out,
            "{},\n  \"answers\": [",
            head.trim_end().trim_end_matches('}').trim_end()
        )?;
        for (i, answer) in answers.iter().enumerate() {
            let separator = if i == 0 { "" } else { "," };
            write!(out, "{separator}\n    {}", answer_json(i, answer.as_ref()))?;
        }
        writeln!(out, "\n  ]\n}}")?;
    } else {
        writeln!(out, "{CSV_HEADER}")?;
        for (i, answer) in answers.iter().enumerate() {
            match answer {
                Some(d) => writeln!(
                    out,
                    "{i},{},{},{},{},{},{},{},{},{}",
                    d.distance,
                    d.point_a.x,
                    d.point_a.y,
                    d.point_a.z,
                    d.point_b.x,
                    d.point_b.y,
                    d.point_b.z,
                    d.face_a,
                    d.face_b
                )?,
                None => writeln!(out, "{i},none,,,,,,,,")?,
            }
        }
    }
    out.flush()?;
    if !args.pair.json {
        let beyond = answers.iter().filter(|a| a.is_none()).count();
        let beyond = match args.max_distance {
            Some(d) => format!(", {beyond} beyond --max-distance {d}"),
            None => String::new(),
        };
        note(&format!("{}{beyond}; {seconds:.3} s", args.pair.describe(&inputs)));
    }
    Ok(())
}

/// One answer as a JSON object on one line (`distance: null` beyond
/// `--max-distance`).
fn answer_json(pose: usize, answer: Option<&PairDistance>) -> Value {
    match answer {
        Some(d) => json!({
            "pose": pose,
            "distance": d.distance,
            "point_a": d.point_a.to_array(),
            "point_b": d.point_b.to_array(),
            "face_a": d.face_a,
            "face_b": d.face_b,
        }),
        None => json!({"pose": pose, "distance": null}),
    }
}
