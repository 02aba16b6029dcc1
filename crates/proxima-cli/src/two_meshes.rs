//! What `distance` and `collide` share: two meshes, where they stand (one
//! pose each, or mesh B at each pose of a file), the threads and `--json`.

use crate::common::{load_mesh, require_primitives, thread_count};
use crate::poses::{Rows, option_pose, parse_rows, read_poses};
use anyhow::{Context, Result};
use proxima::index::MeshIndex;
use proxima::pair::RigidPose;
use proxima::prelude::*;
use std::path::PathBuf;

/// The options of a query between two meshes.
#[derive(clap::Args)]
pub struct TwoMeshes {
    /// The first mesh (A).
    pub a: PathBuf,
    /// The second mesh (B).
    pub b: PathBuf,
    /// Where A stands: a 4x4 matrix [R t; 0 0 0 1] as 16 numbers by rows
    /// (M00,M01,…,M33); R must be a rotation. Default: the identity.
    #[arg(long, value_name = "M00,…,M33", value_parser = parse_rows, allow_hyphen_values = true, conflicts_with = "poses")]
    pub pose_a: Option<Rows>,
    /// Where B stands, as --pose-a. Default: the identity.
    #[arg(long, value_name = "M00,…,M33", value_parser = parse_rows, allow_hyphen_values = true, conflicts_with = "poses")]
    pub pose_b: Option<Rows>,
    /// A file of poses of B (A unmoved), one answer each: one pose per line,
    /// 16 numbers by rows separated by commas or white space; `#` comments and
    /// blank lines are skipped.
    #[arg(long, value_name = "FILE")]
    pub poses: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 4 per core, at least 8).
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
    /// Print one JSON object instead of CSV and the summary line.
    #[arg(long)]
    pub json: bool,
}

/// Where the meshes stand.
pub enum Placement {
    /// A at the first pose, B at the second.
    One(RigidPose, RigidPose),
    /// A unmoved, B at each pose (`--poses FILE`), in the file's order.
    Many(Vec<RigidPose>),
}

impl Placement {
    /// How many answers: one per pose of B.
    pub fn len(&self) -> usize {
        match self {
            Self::One(..) => 1,
            Self::Many(poses) => poses.len(),
        }
    }
}

/// The two meshes indexed, where they stand and the pool to answer on.
pub struct Inputs {
    /// Mesh A.
    pub a: MeshIndex,
    /// Mesh B.
    pub b: MeshIndex,
    /// Their poses.
    pub placement: Placement,
    /// The worker threads.
    pub pool: rayon::ThreadPool,
}

impl TwoMeshes {
    /// Checks the options, reads the poses (counted against the memory
    /// budget at `bytes_per_pose`), loads both meshes and refuses one
    /// without faces, naming its file.
    pub fn inputs(&self, bytes_per_pose: usize) -> Result<Inputs> {
        let threads = self.threads.map_or(Ok(0), thread_count)?;
        let placement = match &self.poses {
            Some(file) => Placement::Many(read_poses(file, bytes_per_pose)?),
            None => Placement::One(
                option_pose(self.pose_a.as_ref(), "--pose-a")?,
                option_pose(self.pose_b.as_ref(), "--pose-b")?,
            ),
        };
        let load = |path: &PathBuf| -> Result<MeshIndex> {
            let mesh = load_mesh(path)?;
            require_primitives(&mesh, PrimitiveKind::Faces, path)?;
            Ok(MeshIndex::new(mesh))
        };
        let (a, b) = (load(&self.a)?, load(&self.b)?);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .context("thread pool")?;
        Ok(Inputs { a, b, placement, pool })
    }

    /// The stderr summary's description of the meshes and poses.
    pub fn describe(&self, inputs: &Inputs) -> String {
        let poses = match &self.poses {
            Some(file) => format!("{} poses of B from {}", inputs.placement.len(), file.display()),
            None => "1 pose".to_string(),
        };
        format!(
            "A {} ({} faces), B {} ({} faces), {poses}",
            self.a.display(),
            inputs.a.mesh().face_count(),
            self.b.display(),
            inputs.b.mesh().face_count()
        )
    }
}
