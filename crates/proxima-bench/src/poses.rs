//! Seeded pose sets for the two-mesh benchmarks ([`crate::pairs`]): mesh `b`
//! moved against mesh `a` (unmoved) in three classes, written to a file that
//! every process and every peer reads, so that all answer the same poses.
//!
//! A pose turns `b` by a uniformly random rotation about its bounding box
//! centre and puts that centre at `a`'s centre plus an offset `s u` along a
//! random unit direction `u`. For near and far poses, `s` is first bisected
//! with proxima's exact `intersects` to the contact offset `s_c` (the
//! surfaces meet at the bisection's lower end and not at its upper end, a
//! `2^-40` fraction of the search interval apart), then moved out by a gap
//! `g`:
//!
//! - [`PoseClass::Near`]: `g` uniform in `[0, 1%]` of `a`'s diagonal, and
//!   `g = 0` (touching, within the bisection's last step) for one pose in
//!   ten;
//! - [`PoseClass::Far`]: `g` uniform in `[10%, 50%]` of the diagonal;
//! - [`PoseClass::Overlap`]: `s` uniform in `[0, 10%]` of the diagonal, no
//!   bisection (the surfaces usually cross).
//!
//! Distance is 1-Lipschitz in `s`, so a near or far pose's distance is at
//! most `g` (plus the last step); it is less where `b` comes out of contact
//! sideways. Bisecting the distance itself to `g` would be exact but costs
//! a distance query per step (tens of milliseconds on 1M-triangle meshes),
//! against well under a millisecond for `intersects`; the benchmark reports
//! the measured distances of every class.
//!
//! The file has one pose per line, the 16 numbers of the row-major 4x4
//! matrix `[R t; 0 0 0 1]` separated by spaces, each printed so that it
//! reads back to the same `f64`; lines starting with `#` are comments
//! (numpy's `loadtxt` reads the file as it is).

use anyhow::{Context, Result, bail};
use proxima::math::{DMat3, DQuat, DVec3};
use proxima::pair::{self, RigidPose};
use proxima::sample::Rng;
use proxima::{Mesh, MeshIndex};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::Path;

/// Bisection steps to the contact offset: it is then known within `2^-40`
/// of the search interval (the two meshes' diagonals).
const BISECTION_STEPS: u32 = 40;

/// Draws of rotation and direction a near or far pose may take before the
/// class is declared out of reach for the pair of meshes (their surfaces
/// never meet at offset 0: `b` inside a hollow `a`, or around it).
const MAX_DRAWS: u32 = 64;

/// The three pose classes of the issue-36 workloads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PoseClass {
    /// Surfaces apart by at most 1% of `a`'s diagonal, or touching.
    Near,
    /// Surfaces apart by 10% to 50% of `a`'s diagonal.
    Far,
    /// Bounding box centres within 10% of `a`'s diagonal.
    Overlap,
}

impl PoseClass {
    /// Every class, in the order the benchmark reports them.
    pub const ALL: [PoseClass; 3] = [PoseClass::Near, PoseClass::Far, PoseClass::Overlap];

    /// The class's name in file names and tables (`near`, `far`, `overlap`).
    pub fn name(self) -> &'static str {
        match self {
            PoseClass::Near => "near",
            PoseClass::Far => "far",
            PoseClass::Overlap => "overlap",
        }
    }
}

/// A uniformly random rotation: a normalized 4D gaussian as a quaternion.
fn random_rotation(rng: &mut Rng) -> DMat3 {
    loop {
        let q = DQuat::from_xyzw(rng.gaussian(), rng.gaussian(), rng.gaussian(), rng.gaussian());
        // A quaternion of tiny norm has no reliable direction: draw again.
        if q.length() > 1e-6 {
            return DMat3::from_quat(q.normalize());
        }
    }
}

/// A uniformly random unit vector.
fn random_direction(rng: &mut Rng) -> DVec3 {
    loop {
        let v = DVec3::new(rng.gaussian(), rng.gaussian(), rng.gaussian());
        if v.length() > 1e-6 {
            return v.normalize();
        }
    }
}

/// The generator of pose `index` of `class`: its own stream, so that a set
/// is the same whatever the number of threads that made it.
fn pose_rng(seed: u64, class: PoseClass, index: usize) -> Rng {
    let mut mix = Rng::new(seed ^ ((class as u64 + 1) << 56) ^ index as u64);
    Rng::new(mix.next_u64())
}

/// The pose that turns `b` by `rotation` about `centre_b` and puts that
/// centre at `centre_a + offset`.
fn placed(rotation: DMat3, centre_a: DVec3, centre_b: DVec3, offset: DVec3) -> Result<RigidPose> {
    Ok(RigidPose::new(rotation, centre_a + offset - rotation * centre_b)?)
}

/// `count` poses of `class` for `b` against `a` (unmoved), made from `seed`,
/// on the current rayon pool (the same set on any number of threads).
/// Fails when a mesh has no faces, or when a near or far pose finds no
/// contact in [`MAX_DRAWS`] draws.
pub fn generate(a: &MeshIndex, b: &MeshIndex, class: PoseClass, count: usize, seed: u64) -> Result<Vec<RigidPose>> {
    // Build both trees once, before the threads race for them.
    pair::intersects(a, &RigidPose::IDENTITY, b, &RigidPose::IDENTITY)?;
    let (box_a, box_b) = (a.mesh().bounds(), b.mesh().bounds());
    let diagonal = f64::from(box_a.diagonal());
    let centre_a = box_a.center().as_dvec3();
    let centre_b = box_b.center().as_dvec3();
    // Beyond this offset the bounding spheres about the box centres are
    // apart: no contact.
    let reach = 0.5 * (diagonal + f64::from(box_b.diagonal())) * (1.0 + 1e-6);
    (0..count)
        .into_par_iter()
        .map(|index| {
            let mut rng = pose_rng(seed, class, index);
            let gap = match class {
                PoseClass::Overlap => {
                    let rotation = random_rotation(&mut rng);
                    let offset = random_direction(&mut rng) * (0.1 * diagonal * rng.unit());
                    return placed(rotation, centre_a, centre_b, offset);
                }
                // One near pose in ten touches: the gap is 0.
                PoseClass::Near if rng.below(10) == 0 => 0.0,
                PoseClass::Near => 0.01 * diagonal * rng.unit(),
                PoseClass::Far => diagonal * (0.1 + 0.4 * rng.unit()),
            };
            for _ in 0..MAX_DRAWS {
                let rotation = random_rotation(&mut rng);
                let direction = random_direction(&mut rng);
                let at = |s: f64| placed(rotation, centre_a, centre_b, direction * s);
                let meets = |s: f64| -> Result<bool> { Ok(pair::intersects(a, &RigidPose::IDENTITY, b, &at(s)?)?) };
                if !meets(0.0)? {
                    continue;
                }
                // Invariant: the surfaces meet at `lo` and not at `hi`.
                let (mut lo, mut hi) = (0.0, reach);
                for _ in 0..BISECTION_STEPS {
                    let mid = 0.5 * (lo + hi);
                    if meets(mid)? {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return at(hi + gap);
            }
            bail!(
                "no {} pose: b's surface did not meet a's at offset 0 in {MAX_DRAWS} draws (is b inside a hollow a?)",
                class.name()
            )
        })
        .collect()
}

/// `mesh` scaled about its bounding box centre so that its diagonal is
/// `diagonal` (the icosphere fitted to the dragon's size, so that the two
/// meet when their centres are close).
pub fn scaled_to(mesh: &Mesh, diagonal: f32) -> Result<Mesh> {
    let bounds = mesh.bounds();
    let factor = f64::from(diagonal) / f64::from(bounds.diagonal());
    let centre = bounds.center().as_dvec3();
    let positions = mesh
        .positions()
        .iter()
        .map(|p| (centre + (p.as_dvec3() - centre) * factor).as_vec3())
        .collect();
    let faces: Vec<Vec<u32>> = mesh.faces().map(<[u32]>::to_vec).collect();
    Ok(Mesh::from_faces(positions, &faces)?)
}

/// The text of a pose file: `header` lines as `#` comments, then one pose per line.
pub fn format_poses(poses: &[RigidPose], header: &[String]) -> String {
    let mut text = String::new();
    for line in header {
        let _ = writeln!(text, "# {line}");
    }
    for pose in poses {
        let numbers: Vec<String> = pose.to_rows().iter().flatten().map(|x| format!("{x:?}")).collect();
        let _ = writeln!(text, "{}", numbers.join(" "));
    }
    text
}

/// Reads the poses of a pose file (see the module's documentation); the
/// error names the line and why (not 16 numbers, not a rigid pose).
pub fn parse_poses(text: &str) -> Result<Vec<RigidPose>> {
    let mut poses = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let context = || format!("line {}", number + 1);
        let values = line
            .split_whitespace()
            .map(str::parse::<f64>)
            .collect::<Result<Vec<f64>, _>>()
            .with_context(context)?;
        let Ok(values) = <[f64; 16]>::try_from(values.as_slice()) else {
            bail!(
                "line {}: {} numbers, not the 16 of a 4x4 matrix",
                number + 1,
                values.len()
            );
        };
        let rows = [0, 1, 2, 3].map(|i| [values[4 * i], values[4 * i + 1], values[4 * i + 2], values[4 * i + 3]]);
        poses.push(RigidPose::from_rows(rows).with_context(context)?);
    }
    Ok(poses)
}

/// Reads a pose file; errors name the file.
pub fn read_poses(path: &Path) -> Result<Vec<RigidPose>> {
    let text = std::fs::read_to_string(path).with_context(|| path.display().to_string())?;
    parse_poses(&text).with_context(|| path.display().to_string())
}

/// `mesh` as binary little-endian PLY (its positions as stored, its faces
/// fanned into triangles as proxima fans them): the one copy of a mesh that
/// the Python peers read, so that all see the same `f32` coordinates.
pub fn ply_bytes(mesh: &Mesh) -> Vec<u8> {
    let triangles = mesh.triangle_vertex_indices();
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.positions().len(),
        triangles.len()
    )
    .into_bytes();
    for p in mesh.positions() {
        for x in p.to_array() {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    for t in triangles {
        out.push(3);
        for i in t {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proxima::Vec3;
    use proxima::pair::triangle_distance;

    /// The distance by brute force over every pair of triangles, `b` placed
    /// by `pose`: the oracle of the classes.
    fn brute_distance(a: &Mesh, b: &Mesh, pose: &RigidPose) -> f64 {
        let place = |mesh: &Mesh, pose: &RigidPose| -> Vec<[DVec3; 3]> {
            let p = mesh.positions();
            mesh.triangle_vertex_indices()
                .iter()
                .map(|t| t.map(|i| pose.apply(p[i as usize])))
                .collect()
        };
        let (ta, tb) = (place(a, &RigidPose::IDENTITY), place(b, pose));
        let mut best = f64::INFINITY;
        for x in &ta {
            for y in &tb {
                best = best.min(triangle_distance(x, y).distance);
            }
        }
        best
    }

    fn sphere() -> Mesh {
        proxima::mesh::generate::noisy_icosphere(3, 7)
    }

    /// Near and far poses are apart, by at most their class's gap (plus the
    /// bisection's last step) and at least 0; overlap poses have their
    /// centres within 10% of the diagonal; all by brute force.
    #[test]
    fn classes_meet_their_definitions() {
        let a = sphere();
        // Of a's size: two bumpy spheres about one centre cross at their bumps.
        let b = scaled_to(&proxima::mesh::generate::noisy_icosphere(2, 3), a.bounds().diagonal()).unwrap();
        let (ia, ib) = (MeshIndex::new(a.clone()), MeshIndex::new(b.clone()));
        let diagonal = f64::from(a.bounds().diagonal());
        let step = 4.0 * diagonal * 2f64.powi(-(BISECTION_STEPS as i32));
        for (class, hi) in [(PoseClass::Near, 0.01), (PoseClass::Far, 0.5)] {
            let poses = generate(&ia, &ib, class, 12, 5).unwrap();
            let distances: Vec<f64> = poses.iter().map(|pose| brute_distance(&a, &b, pose)).collect();
            for &d in &distances {
                assert!(
                    d > 0.0 && d <= hi * diagonal + step,
                    "{class:?}: {d} not in (0, {hi}] of {diagonal}"
                );
            }
            if class == PoseClass::Far {
                // Coming out sideways shortens a gap, never all of them.
                assert!(distances.iter().any(|&d| d >= 0.1 * diagonal), "{distances:?}");
            }
        }
        let centre_b = b.bounds().center().as_dvec3();
        for pose in generate(&ia, &ib, PoseClass::Overlap, 12, 5).unwrap() {
            let moved = pose.apply_f64(centre_b);
            assert!((moved - a.bounds().center().as_dvec3()).length() <= 0.1 * diagonal * (1.0 + 1e-12));
        }
    }

    /// The same seed makes the same poses on one thread and on several.
    #[test]
    fn a_seed_names_a_pose_set() {
        let index = MeshIndex::new(sphere());
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let serial = one.install(|| generate(&index, &index, PoseClass::Near, 8, 9).unwrap());
        assert_eq!(serial, generate(&index, &index, PoseClass::Near, 8, 9).unwrap());
        assert_ne!(serial, generate(&index, &index, PoseClass::Near, 8, 10).unwrap());
    }

    /// Written and read back, every pose is the same `f64` for `f64`; bad
    /// lines are refused with their line number.
    #[test]
    fn pose_files_read_back_exactly() {
        let index = MeshIndex::new(sphere());
        let poses = generate(&index, &index, PoseClass::Overlap, 20, 1).unwrap();
        let text = format_poses(&poses, &["a test".to_string()]);
        assert!(text.starts_with("# a test\n"));
        assert_eq!(parse_poses(&text).unwrap(), poses);
        let error = |text: &str| format!("{:#}", parse_poses(text).unwrap_err());
        assert!(error("1 0 0 0\n").contains("line 1: 4 numbers"));
        assert!(error("# c\n1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 x\n").starts_with("line 2"));
        let scaled = "2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";
        assert!(error(scaled).contains("not a rotation"), "{}", error(scaled));
        let edge = format!("1 0 0 {} 0 1 0 0 0 0 1 0 0 0 0 1", f64::MAX);
        assert!(
            parse_poses(&edge).is_ok(),
            "a finite translation is a pose; the queries bound it"
        );
    }

    /// The PLY copy loads back to the same positions and triangles.
    #[test]
    fn ply_copy_is_the_mesh() {
        let mesh = Mesh::from_faces(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1f32.next_up(), 0.0),
            ],
            &[vec![0, 1, 2, 3]],
        )
        .unwrap();
        let back = proxima::io::parse(&ply_bytes(&mesh), proxima::io::Format::Ply, Path::new("x.ply")).unwrap();
        assert_eq!(back.positions(), mesh.positions());
        assert_eq!(back.triangle_vertex_indices(), mesh.triangle_vertex_indices());
    }
}
