//! `proxima collide A B [--pose-a M] [--pose-b M | --poses FILE] [--pairs]
//! [--within D] [--threads T] [--json]`: whether two placed meshes' surfaces
//! meet (touching counts), per pose of B, as CSV `pose,intersects`; with
//! `--pairs` the face pairs that meet, with `--within D` those at distance
//! at most D, as CSV `pose,face_a,face_b`; or JSON.

use crate::common::note;
use crate::two_meshes::{Placement, TwoMeshes};
use anyhow::Result;
use proxima::pair::{self, FacePair, RigidPose};
use serde_json::json;
use std::io::{BufWriter, Write};
use std::time::Instant;

/// Arguments of `proxima collide`.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pair: TwoMeshes,
    /// List the pairs of faces that meet (face of A, face of B), decided
    /// exactly, instead of yes or no.
    #[arg(long)]
    pairs: bool,
    /// List the pairs of faces at distance at most D instead (D = 0 is
    /// --pairs).
    #[arg(long, value_name = "D", value_parser = parse_within, allow_hyphen_values = true)]
    within: Option<f64>,
}

/// Parses `--within`: a finite number of at least 0 (an infinite margin
/// would list every pair of faces).
fn parse_within(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(d) if d.is_finite() && d >= 0.0 => Ok(d),
        _ => Err(format!("'{text}' is not a finite number >= 0")),
    }
}

/// Runs `proxima collide`.
pub fn run(args: Args) -> Result<()> {
    let listing = args.pairs || args.within.is_some();
    // Yes/no answers are held for every pose; pair lists one pose at a time.
    let bytes_per_pose = size_of::<RigidPose>() + if listing { 0 } else { 1 };
    let inputs = args.pair.inputs(bytes_per_pose)?;
    let (a, b) = (&inputs.a, &inputs.b);
    let json = args.pair.json;
    let mut out = BufWriter::new(std::io::stdout().lock());
    let start = Instant::now();
    let count = inputs.placement.len();
    // How many poses meet (or have pairs within the distance), and how many pairs.
    let (mut meeting, mut pair_count) = (0usize, 0usize);
    if listing {
        let d = args.within.unwrap_or(0.0);
        let pairs_at = |pose_a: &RigidPose, pose_b: &RigidPose| -> Result<Vec<FacePair>> {
            Ok(inputs.pool.install(|| pair::pairs_within(a, pose_a, b, pose_b, d))?)
        };
        if json {
            write!(out, "{{\n  \"answers\": [")?;
        } else {
            writeln!(out, "pose,face_a,face_b")?;
        }
        for i in 0..count {
            let pairs = match &inputs.placement {
                Placement::One(pose_a, pose_b) => pairs_at(pose_a, pose_b)?,
                Placement::Many(poses) => pairs_at(&RigidPose::IDENTITY, &poses[i])?,
            };
            meeting += usize::from(!pairs.is_empty());
            pair_count += pairs.len();
            if json {
                let separator = if i == 0 { "" } else { "," };
                write!(out, "{separator}\n    {}", json!({"pose": i, "pairs": pairs}))?;
            } else {
                for [fa, fb] in pairs {
                    writeln!(out, "{i},{fa},{fb}")?;
                }
            }
        }
        if json {
            write!(out, "\n  ],")?;
        }
    } else {
        let answers: Vec<bool> = inputs.pool.install(|| match &inputs.placement {
            Placement::One(pose_a, pose_b) => pair::intersects(a, pose_a, b, pose_b).map(|yes| vec![yes]),
            Placement::Many(poses) => pair::intersects_batch(a, b, poses),
        })?;
        meeting = answers.iter().filter(|&&yes| yes).count();
        if json {
            write!(out, "{{\n  \"answers\": {},", json!(answers))?;
        } else {
            writeln!(out, "pose,intersects")?;
            for (i, yes) in answers.iter().enumerate() {
                writeln!(out, "{i},{}", u8::from(*yes))?;
            }
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    if json {
        let summary = json!({
            "mesh_a": args.pair.a.display().to_string(),
            "mesh_b": args.pair.b.display().to_string(),
            "faces_a": a.mesh().face_count(),
            "faces_b": b.mesh().face_count(),
            "poses": count,
            "meeting": meeting,
            "pairs": listing.then_some(pair_count),
            "within": args.within,
            "threads": inputs.pool.current_num_threads(),
            "seconds": seconds,
        });
        let summary = serde_json::to_string_pretty(&summary)?;
        writeln!(out, "{}", summary.trim_start_matches('{'))?;
    }
    out.flush()?;
    if !json {
        let what = match (listing, args.within) {
            (false, _) => format!("{meeting} of {count} poses meet"),
            (true, None) => format!("{pair_count} face pairs meet, at {meeting} of {count} poses"),
            (true, Some(d)) => format!("{pair_count} face pairs within {d}, at {meeting} of {count} poses"),
        };
        note(&format!("{}; {what}; {seconds:.3} s", args.pair.describe(&inputs)));
    }
    Ok(())
}
