//! The two-mesh benchmark (issue 36): proxima's `pair::distance` and
//! `pair::intersects` per pose on one thread, their batches on 1 and 2
//! threads, and (feature `peers`) parry3d's `query::distance` and
//! `query::intersection_test` on `TriMesh`es, all on the poses of a
//! workload folder ([`crate::poses`]); every answer compared with proxima's,
//! disagreements judged by the triangle pair concerned. Also the
//! self-intersections of one mesh, and the judging of a peer's answers
//! written by another process (the Python peers: coal, MeshLib).
//!
//! A workload folder holds `a.ply`, `b.ply` (binary, the exact `f32`
//! coordinates every process reads) and `near.poses`, `far.poses`,
//! `overlap.poses` (poses of `b`; `a` stays unmoved).

use crate::poses::{PoseClass, read_poses};
use crate::report::timed;
use anyhow::{Context, Result, bail};
use proxima::math::DVec3;
use proxima::pair::{self, PairDistance, RigidPose, triangle_distance};
use proxima::{Mesh, MeshIndex};
use serde_json::{Value, json};
use std::path::Path;

/// Where two distances are taken as equal: within this fraction of `a`'s
/// bounding box diagonal (peers compute in `f32`, whose rounding of
/// coordinates alone is about 1e-7 of it).
pub const DISTANCE_TOLERANCE: f64 = 1e-6;

/// One timed row.
#[derive(Clone, Debug)]
pub struct Row {
    /// The pose class.
    pub class: &'static str,
    /// `distance` or `intersects`.
    pub query: &'static str,
    /// `proxima`, `proxima-batch` or `parry3d`.
    pub method: &'static str,
    /// Threads of the pool the row ran on.
    pub threads: usize,
    /// Poses answered.
    pub poses: usize,
    /// Time for all of them.
    pub seconds: f64,
    /// The CPU time the process spent meanwhile (all threads), when known:
    /// over `seconds`, the cores the row actually had on a shared machine.
    pub cpu_seconds: Option<f64>,
}

impl Row {
    /// Poses answered per second.
    pub fn per_second(&self) -> f64 {
        self.poses as f64 / self.seconds.max(1e-12)
    }

    fn to_json(&self) -> Value {
        json!({
            "class": self.class, "query": self.query, "method": self.method, "threads": self.threads,
            "poses": self.poses, "seconds": self.seconds, "per_second": self.per_second(),
            "cpu_seconds": self.cpu_seconds,
        })
    }
}

/// The two meshes of a workload folder and their trees (built, untimed).
pub struct Workload {
    /// The unmoved mesh.
    pub a: MeshIndex,
    /// The moved mesh.
    pub b: MeshIndex,
    /// `a`'s triangles' corners (input order), for judging.
    pub corners_a: Vec<[DVec3; 3]>,
    /// `b`'s, unmoved.
    pub corners_b: Vec<[DVec3; 3]>,
    /// `a`'s bounding box diagonal.
    pub diagonal: f64,
}

/// The triangles of `mesh` as `f64` corners, in [`Mesh::triangles`] order.
fn corners(mesh: &Mesh) -> Vec<[DVec3; 3]> {
    let p = mesh.positions();
    mesh.triangle_vertex_indices()
        .iter()
        .map(|t| t.map(|i| p[i as usize].as_dvec3()))
        .collect()
}

impl Workload {
    /// Loads `a.ply` and `b.ply` of `dir` and builds both face trees.
    pub fn load(dir: &Path) -> Result<Self> {
        let a = crate::input::load_mesh(&dir.join("a.ply"))?;
        let b = crate::input::load_mesh(&dir.join("b.ply"))?;
        let (corners_a, corners_b) = (corners(&a), corners(&b));
        let diagonal = f64::from(a.bounds().diagonal());
        let (a, b) = (MeshIndex::new(a), MeshIndex::new(b));
        pair::distance(&a, &RigidPose::IDENTITY, &b, &RigidPose::IDENTITY)?;
        Ok(Self {
            a,
            b,
            corners_a,
            corners_b,
            diagonal,
        })
    }

    /// The distance between triangle `ta` of `a` and triangle `tb` of `b`
    /// placed by `pose`, in `f64` (the oracle of a disagreement: one pair).
    pub fn pair_distance(&self, ta: usize, tb: usize, pose: &RigidPose) -> Option<f64> {
        let a = self.corners_a.get(ta)?;
        let b = self.corners_b.get(tb)?.map(|p| pose.apply_f64(p));
        Some(triangle_distance(a, &b).distance)
    }
}

/// The CPU time of this process so far (user and system, every thread),
/// from `/proc/self/stat` at Linux's 100 ticks per second; `None` where
/// that file is not.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command name's closing parenthesis start at the
    // third; utime and stime are the 14th and 15th.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// [`timed`] with the CPU time the process spent meanwhile.
fn timed_cpu<R>(f: impl FnOnce() -> R) -> (R, f64, Option<f64>) {
    let before = cpu_seconds();
    let (value, seconds) = timed(f);
    (value, seconds, before.zip(cpu_seconds()).map(|(b, a)| a - b))
}

/// A pool of `threads` threads.
fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    Ok(rayon::ThreadPoolBuilder::new().num_threads(threads).build()?)
}

/// proxima's answers on one class: per pose on one thread, then the batches.
struct ProximaAnswers {
    distances: Vec<PairDistance>,
    intersects: Vec<bool>,
    rows: Vec<Row>,
    /// Batch answers that differ from the per-pose ones (a bug when not 0).
    batch_mismatches: usize,
    /// Poses where `intersects` is not `distance == 0` (a bug when not 0).
    inconsistent: usize,
}

/// proxima's rows on one class: `intersects` on every pose, `distance` on
/// the first `distance_count`.
fn proxima_rows(w: &Workload, class: &'static str, all: &[RigidPose], distance_count: usize) -> Result<ProximaAnswers> {
    let identity = RigidPose::IDENTITY;
    let poses = &all[..distance_count.min(all.len())];
    let row = |query, method, threads, count, (seconds, cpu_seconds)| Row {
        class,
        query,
        method,
        threads,
        poses: count,
        seconds,
        cpu_seconds,
    };
    let one = pool(1)?;
    let (distances, s_distance, c_distance) = one.install(|| {
        timed_cpu(|| {
            poses
                .iter()
                .map(|pose| pair::distance(&w.a, &identity, &w.b, pose))
                .collect::<Result<Vec<_>, _>>()
        })
    });
    let distances = distances?;
    let (intersects, s_intersects, c_intersects) = one.install(|| {
        timed_cpu(|| {
            all.iter()
                .map(|pose| pair::intersects(&w.a, &identity, &w.b, pose))
                .collect::<Result<Vec<_>, _>>()
        })
    });
    let intersects = intersects?;
    let mut rows = vec![
        row("distance", "proxima", 1, poses.len(), (s_distance, c_distance)),
        row("intersects", "proxima", 1, all.len(), (s_intersects, c_intersects)),
    ];
    let mut batch_mismatches = 0;
    for threads in [1, 2] {
        let p = pool(threads)?;
        let (batch, seconds, cpu) = p.install(|| timed_cpu(|| pair::distance_batch(&w.a, &w.b, poses)));
        batch_mismatches += batch?.iter().zip(&distances).filter(|(x, y)| x != y).count();
        rows.push(row("distance", "proxima-batch", threads, poses.len(), (seconds, cpu)));
        let (batch, seconds, cpu) = p.install(|| timed_cpu(|| pair::intersects_batch(&w.a, &w.b, all)));
        batch_mismatches += batch?.iter().zip(&intersects).filter(|(x, y)| x != y).count();
        rows.push(row("intersects", "proxima-batch", threads, all.len(), (seconds, cpu)));
    }
    let inconsistent = distances
        .iter()
        .zip(&intersects)
        .filter(|(d, i)| (d.distance == 0.0) != **i)
        .count();
    Ok(ProximaAnswers {
        distances,
        intersects,
        rows,
        batch_mismatches,
        inconsistent,
    })
}

/// A peer's answer on one pose, as [`judge`] takes it.
#[derive(Clone, Debug, Default)]
pub struct PeerAnswer {
    /// The pose's index in its class's file.
    pub pose: usize,
    /// The peer's distance, when it measured one.
    pub distance: Option<f64>,
    /// The triangles the peer says its distance is between.
    pub triangles: Option<[usize; 2]>,
    /// The peer's witness points (on `a`, on placed `b`), when it gave them.
    pub points: Option<[DVec3; 2]>,
    /// The peer's collision answer, when it gave one.
    pub intersects: Option<bool>,
}

/// How a peer's answers compare with proxima's on one class, and who is
/// right where they differ.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Verdicts {
    /// Distances compared.
    pub distances: usize,
    /// Within 1e-6 of proxima's distance, relative to it.
    pub within_relative: usize,
    /// Within [`DISTANCE_TOLERANCE`] of the diagonal (f32 rounding).
    pub within_tolerance: usize,
    /// Disagreements where the peer's own triangle pair is closer than
    /// proxima's distance (beyond the tolerance): proxima is wrong.
    pub proxima_wrong: usize,
    /// Disagreements where the peer's pair is no closer than proxima's
    /// distance and the peer's distance is above proxima's: the peer missed
    /// the nearest pair.
    pub peer_above: usize,
    /// Disagreements where the peer's pair is no closer than proxima's
    /// distance yet the peer's distance is below proxima's: a value no pair
    /// of triangles has.
    pub peer_below: usize,
    /// Disagreements the peer gave no triangle pair for.
    pub undecided: usize,
    /// Witness points farther than the tolerance from the peer's triangles
    /// or whose distance apart is not the peer's distance.
    pub bad_witnesses: usize,
    /// The largest `|peer - proxima|` over the diagonal.
    pub max_relative_difference: f64,
    /// Collision answers compared.
    pub collisions: usize,
    /// Collision answers equal to proxima's.
    pub collisions_equal: usize,
    /// proxima says they meet, the peer says not.
    pub only_proxima_meets: usize,
    /// The peer says they meet, proxima says not, with proxima's distance
    /// within the `f32` rounding tolerance (neither can be faulted at the
    /// peer's precision).
    pub only_peer_meets_within_rounding: usize,
    /// The peer says they meet, proxima's distance is beyond the tolerance:
    /// the peer is wrong.
    pub only_peer_meets_apart: usize,
}

impl Verdicts {
    /// As JSON, with the class's name.
    pub fn to_json(&self, class: &str, peer: &str) -> Value {
        json!({
            "class": class, "peer": peer, "distances": self.distances,
            "within_1e-6_relative": self.within_relative,
            "within_1e-6_diagonal": self.within_tolerance, "proxima_wrong": self.proxima_wrong,
            "peer_above": self.peer_above, "peer_below": self.peer_below, "undecided": self.undecided, "bad_witnesses": self.bad_witnesses,
            "max_difference_over_diagonal": self.max_relative_difference,
            "collisions": self.collisions, "collisions_equal": self.collisions_equal,
            "only_proxima_meets": self.only_proxima_meets,
            "only_peer_meets_within_rounding": self.only_peer_meets_within_rounding,
            "only_peer_meets_apart": self.only_peer_meets_apart,
        })
    }
}

/// Judges `answers` of a peer against proxima's `distances` (of the first
/// poses) and `intersects` (indexed by pose) on `poses`: equal within the
/// tolerances, or who is right, by the `f64` distance of the peer's own
/// triangle pair and of its witness points to that pair. A collision
/// disagreement beyond `distances` is decided by a distance query.
pub fn judge(
    w: &Workload,
    poses: &[RigidPose],
    distances: &[PairDistance],
    intersects: &[bool],
    answers: &[PeerAnswer],
) -> Result<Verdicts> {
    let tolerance = DISTANCE_TOLERANCE * w.diagonal;
    let mut v = Verdicts::default();
    for answer in answers {
        let (Some(pose), Some(&ours_meet)) = (poses.get(answer.pose), intersects.get(answer.pose)) else {
            bail!(
                "peer answer for pose {} of {}",
                answer.pose,
                poses.len().min(intersects.len())
            );
        };
        let ours = match distances.get(answer.pose) {
            Some(ours) => Some(*ours),
            None if answer.intersects.is_some_and(|meets| meets != ours_meet) => {
                Some(pair::distance(&w.a, &RigidPose::IDENTITY, &w.b, pose)?)
            }
            None => None,
        };
        if let Some(d) = answer.distance {
            let Some(ours) = ours else {
                bail!(
                    "peer distance for pose {}, beyond proxima's {}",
                    answer.pose,
                    distances.len()
                );
            };
            v.distances += 1;
            let difference = (d - ours.distance).abs();
            v.max_relative_difference = v.max_relative_difference.max(difference / w.diagonal);
            if difference <= 1e-6 * ours.distance {
                v.within_relative += 1;
            }
            if difference <= tolerance {
                v.within_tolerance += 1;
            } else {
                match answer.triangles.and_then(|[ta, tb]| w.pair_distance(ta, tb, pose)) {
                    None => v.undecided += 1,
                    Some(theirs) if theirs < ours.distance - tolerance => v.proxima_wrong += 1,
                    Some(_) if d > ours.distance => v.peer_above += 1,
                    Some(_) => v.peer_below += 1,
                }
            }
            if let (Some([pa, pb]), Some([ta, tb])) = (answer.points, answer.triangles) {
                let on = |p: DVec3, t: Option<[DVec3; 3]>| {
                    t.is_some_and(|t| (pair::point_triangle_closest(p, &t).0 - p).length() <= tolerance)
                };
                let placed_b = w.corners_b.get(tb).map(|t| t.map(|p| pose.apply_f64(p)));
                let apart = ((pa - pb).length() - d).abs() <= tolerance;
                if !(on(pa, w.corners_a.get(ta).copied()) && on(pb, placed_b) && apart) {
                    v.bad_witnesses += 1;
                }
            }
        }
        if let Some(meets) = answer.intersects {
            v.collisions += 1;
            match (ours_meet, meets) {
                (x, y) if x == y => v.collisions_equal += 1,
                (true, false) => v.only_proxima_meets += 1,
                _ if ours.is_some_and(|o| o.distance <= tolerance) => v.only_peer_meets_within_rounding += 1,
                _ => v.only_peer_meets_apart += 1,
            }
        }
    }
    Ok(v)
}

/// parry3d's rows on one class: its intersection test on `poses` and its
/// distance on the first `distance_count` of them, between the two
/// `TriMesh`es, each pose converted to its `f32` pose; and its answers as a
/// peer's.
#[cfg(feature = "peers")]
fn parry_rows(
    trimeshes: &(parry3d::shape::TriMesh, parry3d::shape::TriMesh),
    class: &'static str,
    poses: &[RigidPose],
    distance_count: usize,
) -> Result<(Vec<Row>, Vec<PeerAnswer>)> {
    use parry3d::math::{Pose, Rotation, Vector};
    let to_parry = |pose: &RigidPose| {
        let q = proxima::math::DQuat::from_mat3(&pose.rotation()).normalize();
        let t = pose.translation();
        Pose::from_parts(
            Vector::new(t.x as f32, t.y as f32, t.z as f32),
            Rotation::from_xyzw(q.x as f32, q.y as f32, q.z as f32, q.w as f32),
        )
    };
    let (ta, tb) = trimeshes;
    let converted: Vec<Pose> = poses.iter().map(to_parry).collect();
    let one = pool(1)?;
    let (found, s_distance) = one.install(|| {
        timed(|| {
            converted[..distance_count.min(poses.len())]
                .iter()
                .map(|p| parry3d::query::distance(&Pose::IDENTITY, ta, p, tb))
                .collect::<Result<Vec<_>, _>>()
        })
    });
    let found = found.map_err(|e| anyhow::anyhow!("parry3d distance: {e:?}"))?;
    let (meets, s_meets) = one.install(|| {
        timed(|| {
            converted
                .iter()
                .map(|p| parry3d::query::intersection_test(&Pose::IDENTITY, ta, p, tb))
                .collect::<Result<Vec<_>, _>>()
        })
    });
    let meets = meets.map_err(|e| anyhow::anyhow!("parry3d intersection_test: {e:?}"))?;
    let row = |query, count, seconds| Row {
        class,
        query,
        method: "parry3d",
        threads: 1,
        poses: count,
        seconds,
        cpu_seconds: None,
    };
    let answers = meets
        .iter()
        .enumerate()
        .map(|(pose, m)| {
            let d = found.get(pose);
            PeerAnswer {
                pose,
                distance: d.map(|d| f64::from(d.distance)),
                // A distance of 0 names no pair to judge by.
                triangles: d
                    .filter(|d| d.distance > 0.0)
                    .map(|d| [d.subshape1 as usize, d.subshape2 as usize]),
                points: None,
                intersects: Some(m.intersecting),
            }
        })
        .collect();
    Ok((
        vec![
            row("distance", found.len(), s_distance),
            row("intersects", meets.len(), s_meets),
        ],
        answers,
    ))
}

/// What [`run`] measures.
pub struct Options<'a> {
    /// The workload folder.
    pub dir: &'a Path,
    /// The classes, in order.
    pub classes: Vec<PoseClass>,
    /// At most this many poses per class for proxima (all when `None`).
    pub limit: Option<usize>,
    /// proxima's distance rows on the first this many poses of each class.
    pub distance_poses: usize,
    /// parry3d's intersection test on the first this many poses of each
    /// class (0: no parry3d rows).
    pub peer_poses: usize,
    /// parry3d's distance on the first this many poses of each class.
    pub peer_distance_poses: usize,
    /// Where to write proxima's answers per pose (JSON), for the Python peers.
    pub dump: Option<&'a Path>,
}

/// Runs the rows of `options` on every class; returns the JSON report
/// (rows, verdicts, proxima's internal checks).
pub fn run(options: &Options) -> Result<Value> {
    let w = Workload::load(options.dir)?;
    #[cfg(feature = "peers")]
    let trimeshes = (options.peer_poses > 0).then(|| {
        (
            crate::peers::parry_trimesh(w.a.mesh()),
            crate::peers::parry_trimesh(w.b.mesh()),
        )
    });
    let mut rows = Vec::new();
    // Filled by the parry3d rows only (feature `peers`).
    #[cfg_attr(not(feature = "peers"), allow(unused_mut))]
    let mut verdicts: Vec<Value> = Vec::new();
    let mut checks = Vec::new();
    let mut dump = serde_json::Map::new();
    for &class in &options.classes {
        let path = options.dir.join(format!("{}.poses", class.name()));
        let mut poses = read_poses(&path)?;
        poses.truncate(options.limit.unwrap_or(usize::MAX));
        let ours = proxima_rows(&w, class.name(), &poses, options.distance_poses)
            .with_context(|| path.display().to_string())?;
        rows.extend(ours.rows.iter().cloned());
        checks.push(json!({
            "class": class.name(), "batch_mismatches": ours.batch_mismatches,
            "intersects_not_distance_zero": ours.inconsistent,
            "meeting": ours.intersects.iter().filter(|&&m| m).count(), "poses": poses.len(),
            "distance_over_diagonal": quantiles(&ours.distances, w.diagonal),
        }));
        #[cfg(feature = "peers")]
        if let Some(trimeshes) = &trimeshes {
            let subset = &poses[..options.peer_poses.min(poses.len())];
            let (peer_rows, answers) = parry_rows(trimeshes, class.name(), subset, options.peer_distance_poses)?;
            rows.extend(peer_rows);
            let v = judge(&w, &poses, &ours.distances, &ours.intersects, &answers)?;
            verdicts.push(v.to_json(class.name(), "parry3d"));
        }
        if options.dump.is_some() {
            dump.insert(
                class.name().to_string(),
                dump_answers(&ours.distances, &ours.intersects),
            );
        }
    }
    if let Some(path) = options.dump {
        let text = serde_json::to_string(&json!({ "diagonal": w.diagonal, "classes": dump }))?;
        std::fs::write(path, text).with_context(|| path.display().to_string())?;
    }
    Ok(json!({
        "dir": options.dir.display().to_string(),
        "triangles": [w.corners_a.len(), w.corners_b.len()],
        "diagonal": w.diagonal,
        "rows": rows.iter().map(Row::to_json).collect::<Vec<_>>(),
        "verdicts": verdicts,
        "checks": checks,
    }))
}

/// The minimum, median and maximum of the distances over `diagonal`.
fn quantiles(distances: &[PairDistance], diagonal: f64) -> Value {
    let mut d: Vec<f64> = distances.iter().map(|d| d.distance / diagonal).collect();
    d.sort_by(f64::total_cmp);
    match (d.first(), d.get(d.len() / 2), d.last()) {
        (Some(min), Some(median), Some(max)) => json!({ "min": min, "median": median, "max": max }),
        _ => Value::Null,
    }
}

/// proxima's answers per pose as columns of JSON arrays.
fn dump_answers(distances: &[PairDistance], intersects: &[bool]) -> Value {
    let point = |p: DVec3| [p.x, p.y, p.z];
    json!({
        "distance": distances.iter().map(|d| d.distance).collect::<Vec<_>>(),
        "triangle_a": distances.iter().map(|d| d.triangle_a).collect::<Vec<_>>(),
        "triangle_b": distances.iter().map(|d| d.triangle_b).collect::<Vec<_>>(),
        "point_a": distances.iter().map(|d| point(d.point_a)).collect::<Vec<_>>(),
        "point_b": distances.iter().map(|d| point(d.point_b)).collect::<Vec<_>>(),
        "intersects": intersects,
    })
}

/// Reads a peer's answers on one class from its JSON (`{"pose": [...],
/// "distance": [...], "triangle_a": [...], "triangle_b": [...], "point_a":
/// [[x, y, z], ...], "point_b": ..., "intersects": [...]}`; every column
/// but `pose` optional; `null` entries are answers not given).
pub fn parse_peer_answers(class: &Value) -> Result<Vec<PeerAnswer>> {
    let column = |name: &str| class.get(name).and_then(Value::as_array);
    let Some(poses) = column("pose") else {
        bail!("a peer's class has no \"pose\" column");
    };
    let at = |name: &str, i: usize| column(name).and_then(|c| c.get(i));
    let point = |name: &str, i: usize| -> Option<DVec3> {
        let p = at(name, i)?.as_array()?;
        Some(DVec3::new(
            p.first()?.as_f64()?,
            p.get(1)?.as_f64()?,
            p.get(2)?.as_f64()?,
        ))
    };
    poses
        .iter()
        .enumerate()
        .map(|(i, pose)| {
            let pose = pose.as_u64().context("a pose index that is not a whole number")? as usize;
            let triangle = |name| at(name, i).and_then(Value::as_u64).map(|t| t as usize);
            Ok(PeerAnswer {
                pose,
                distance: at("distance", i).and_then(Value::as_f64),
                triangles: triangle("triangle_a").zip(triangle("triangle_b")).map(|(a, b)| [a, b]),
                points: point("point_a", i).zip(point("point_b", i)).map(|(a, b)| [a, b]),
                intersects: at("intersects", i).and_then(Value::as_bool),
            })
        })
        .collect()
}

/// Judges the answers of peers (JSON `{"peer": NAME, "classes": {CLASS:
/// columns}}`, see [`parse_peer_answers`], or `{"peers": [such, ...]}`) on
/// the poses of `dir`: proxima answers each pose the peer answered, on all
/// threads.
pub fn judge_file(dir: &Path, peer: &Path) -> Result<Value> {
    let text = std::fs::read_to_string(peer).with_context(|| peer.display().to_string())?;
    let file: Value = serde_json::from_str(&text).with_context(|| peer.display().to_string())?;
    let peers = match file.get("peers").and_then(Value::as_array) {
        Some(peers) => peers.clone(),
        None => vec![file],
    };
    let w = Workload::load(dir)?;
    let mut out = Vec::new();
    for peer_json in &peers {
        out.extend(judge_peer(dir, &w, peer_json).with_context(|| peer.display().to_string())?);
    }
    Ok(json!(out))
}

/// [`judge_file`] for one peer.
fn judge_peer(dir: &Path, w: &Workload, peer_json: &Value) -> Result<Vec<Value>> {
    let name = peer_json
        .get("peer")
        .and_then(Value::as_str)
        .unwrap_or("peer")
        .to_string();
    let mut out = Vec::new();
    for class in PoseClass::ALL {
        let Some(columns) = peer_json.get("classes").and_then(|c| c.get(class.name())) else {
            continue;
        };
        let answers = parse_peer_answers(columns).with_context(|| format!("{name}: {}", class.name()))?;
        let poses = read_poses(&dir.join(format!("{}.poses", class.name())))?;
        let last = |f: fn(&PeerAnswer) -> bool| answers.iter().filter(|a| f(a)).map(|a| a.pose + 1).max();
        let measured = last(|a| a.distance.is_some()).unwrap_or(0).min(poses.len());
        let collided = last(|a| a.intersects.is_some()).unwrap_or(0).min(poses.len());
        let distances = pair::distance_batch(&w.a, &w.b, &poses[..measured])?;
        let intersects = pair::intersects_batch(&w.a, &w.b, &poses[..measured.max(collided)])?;
        out.push(judge(w, &poses, &distances, &intersects, &answers)?.to_json(class.name(), &name));
    }
    Ok(out)
}

/// proxima's self-intersections of `mesh` on `threads` threads: the face
/// pairs and the seconds of each of `reps` runs.
pub fn self_intersections(mesh: &MeshIndex, threads: usize, reps: usize) -> Result<(Vec<[u32; 2]>, Vec<f64>)> {
    let p = pool(threads)?;
    // The tree is built once, untimed.
    mesh.tree::<proxima::Triangle>()?;
    let mut seconds = Vec::new();
    let mut pairs = Vec::new();
    for _ in 0..reps.max(1) {
        let (found, s) = p.install(|| timed(|| pair::self_intersections(mesh)));
        pairs = found?;
        seconds.push(s);
    }
    Ok((pairs, seconds))
}

/// Judges a peer's self-intersecting face pairs against proxima's: pairs
/// only one of them reports, each decided by the exact test of the two
/// faces (shared vertices by [`pair::neighbours_intersect`]). Returns
/// `(only proxima, of which the exact test says meet; only the peer, of
/// which meet)`.
pub fn judge_self(mesh: &Mesh, ours: &[[u32; 2]], theirs: &[[u32; 2]]) -> Result<[usize; 4]> {
    use std::collections::HashSet;
    let norm = |p: &[u32; 2]| [p[0].min(p[1]), p[0].max(p[1])];
    let ours: HashSet<[u32; 2]> = ours.iter().map(norm).collect();
    let theirs: HashSet<[u32; 2]> = theirs.iter().map(norm).collect();
    let index = mesh.triangle_vertex_indices();
    let placed = corners(mesh);
    let meets = |&[i, j]: &[u32; 2]| -> Result<bool> {
        let (Some(a), Some(b)) = (placed.get(i as usize), placed.get(j as usize)) else {
            bail!("face pair [{i}, {j}] beyond the mesh's {} triangles", placed.len());
        };
        let (ia, ib) = (index[i as usize], index[j as usize]);
        Ok(if ia.iter().any(|v| ib.contains(v)) {
            pair::neighbours_intersect(a, ia, b, ib)
        } else {
            pair::triangles_intersect(a, b)
        })
    };
    let mut counts = [0; 4];
    for p in ours.difference(&theirs) {
        counts[0] += 1;
        counts[1] += usize::from(meets(p)?);
    }
    for p in theirs.difference(&ours) {
        counts[2] += 1;
        counts[3] += usize::from(meets(p)?);
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::poses::{format_poses, generate, ply_bytes};

    /// A workload folder of two small icospheres and a few poses per class.
    fn folder() -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        let a = proxima::mesh::generate::noisy_icosphere(4, 1);
        let b =
            crate::poses::scaled_to(&proxima::mesh::generate::noisy_icosphere(3, 2), a.bounds().diagonal()).unwrap();
        std::fs::write(dir.path().join("a.ply"), ply_bytes(&a)).unwrap();
        std::fs::write(dir.path().join("b.ply"), ply_bytes(&b)).unwrap();
        let (ia, ib) = (MeshIndex::new(a), MeshIndex::new(b));
        for class in PoseClass::ALL {
            let poses = generate(&ia, &ib, class, 6, 3).unwrap();
            std::fs::write(
                dir.path().join(format!("{}.poses", class.name())),
                format_poses(&poses, &[]),
            )
            .unwrap();
        }
        dir
    }

    /// Brute force over every triangle pair: the oracle of proxima's rows.
    fn brute(w: &Workload, pose: &RigidPose) -> f64 {
        (0..w.corners_a.len())
            .flat_map(|i| (0..w.corners_b.len()).map(move |j| (i, j)))
            .map(|(i, j)| w.pair_distance(i, j, pose).unwrap())
            .fold(f64::INFINITY, f64::min)
    }

    /// Every row ran every pose; the batches equal the single queries; the
    /// dumped distances equal brute force; parry3d's answers are judged.
    #[test]
    fn rows_and_dump_match_brute_force() {
        let dir = folder();
        let dump = dir.path().join("dump.json");
        let report = run(&Options {
            dir: dir.path(),
            classes: PoseClass::ALL.to_vec(),
            limit: None,
            distance_poses: 6,
            peer_poses: if cfg!(feature = "peers") { 6 } else { 0 },
            peer_distance_poses: 3,
            dump: Some(&dump),
        })
        .unwrap();
        for check in report["checks"].as_array().unwrap() {
            assert_eq!(check["batch_mismatches"], 0);
            assert_eq!(check["intersects_not_distance_zero"], 0);
        }
        for r in report["rows"].as_array().unwrap() {
            let parry_distance = r["method"] == "parry3d" && r["query"] == "distance";
            assert_eq!(r["poses"], if parry_distance { 3 } else { 6 }, "{r}");
        }
        let w = Workload::load(dir.path()).unwrap();
        let dumped: Value = serde_json::from_str(&std::fs::read_to_string(&dump).unwrap()).unwrap();
        for class in PoseClass::ALL {
            let poses = read_poses(&dir.path().join(format!("{}.poses", class.name()))).unwrap();
            let column = &dumped["classes"][class.name()];
            for (i, pose) in poses.iter().enumerate() {
                // The descent takes each triangle's corners from its tree's
                // leaves, the oracle from the mesh: the same points, but
                // the pair distance may round differently in the last bit.
                let (d, expected) = (column["distance"][i].as_f64().unwrap(), brute(&w, pose));
                assert!(
                    (d - expected).abs() <= 1e-12 * w.diagonal,
                    "{class:?} {i}: {d} against {expected}"
                );
                assert_eq!(column["intersects"][i].as_bool().unwrap(), expected == 0.0);
            }
        }
        #[cfg(feature = "peers")]
        for v in report["verdicts"].as_array().unwrap() {
            assert_eq!(v["proxima_wrong"], 0, "{v}");
        }
    }

    /// The judge: an equal answer agrees; a peer pair closer than proxima's
    /// distance faults proxima; a larger one faults the peer; bad witnesses
    /// and collision disagreements are counted on the right side.
    #[test]
    fn judge_sides_with_the_closer_pair() {
        let dir = folder();
        let w = Workload::load(dir.path()).unwrap();
        let poses = read_poses(&dir.path().join("far.poses")).unwrap();
        let d = pair::distance(&w.a, &RigidPose::IDENTITY, &w.b, &poses[0]).unwrap();
        let pair_ = [d.triangle_a as usize, d.triangle_b as usize];
        let exact = PeerAnswer {
            pose: 0,
            distance: Some(d.distance),
            triangles: Some(pair_),
            points: Some([d.point_a, d.point_b]),
            intersects: Some(false),
        };
        let v = judge(&w, &poses, &[d], &[false], std::slice::from_ref(&exact)).unwrap();
        assert_eq!(
            (
                v.within_relative,
                v.within_tolerance,
                v.bad_witnesses,
                v.collisions_equal
            ),
            (1, 1, 0, 1)
        );
        // proxima claims too much: the peer's (true) pair is closer.
        let mut inflated = d;
        inflated.distance += 0.1;
        let v = judge(&w, &poses, &[inflated], &[false], std::slice::from_ref(&exact)).unwrap();
        assert_eq!((v.proxima_wrong, v.peer_above, v.peer_below), (1, 0, 0));
        // The peer claims less than its pair's distance, and says they meet.
        let short = PeerAnswer {
            distance: Some(d.distance * 0.5),
            points: Some([d.point_a, d.point_a]),
            intersects: Some(true),
            ..exact.clone()
        };
        let v = judge(&w, &poses, &[d], &[false], &[short]).unwrap();
        assert_eq!(
            (v.proxima_wrong, v.peer_above, v.peer_below, v.bad_witnesses),
            (0, 0, 1, 1)
        );
        assert_eq!(v.only_peer_meets_apart, 1);
        assert!(judge(&w, &poses, &[d], &[false], &[PeerAnswer { pose: 99, ..exact }]).is_err());
    }

    /// The process's CPU time over a busy loop never goes back and stays
    /// within what the test binary's threads could spend in that wall time
    /// (a shared machine may give the loop less than its wall time).
    #[test]
    fn cpu_time_counts_the_work() {
        let (sum, seconds, cpu) = timed_cpu(|| {
            let start = std::time::Instant::now();
            let mut x = 0u64;
            while start.elapsed().as_secs_f64() < 0.05 {
                x = std::hint::black_box(x.wrapping_add(1));
            }
            x
        });
        assert!(sum > 0 && seconds >= 0.05);
        if let Some(cpu) = cpu {
            assert!(cpu >= 0.0 && cpu <= seconds * 64.0 + 0.02, "{cpu} {seconds}");
        }
    }

    /// Self-intersection judging on two crossing triangles and two apart.
    #[test]
    fn judge_self_decides_each_pair_exactly() {
        use proxima::Vec3;
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.5, 0.5, -1.0),
            Vec3::new(0.5, 0.5, 1.0),
            Vec3::new(3.0, 3.0, 0.0),
            Vec3::new(9.0, 9.0, 9.0),
            Vec3::new(10.0, 9.0, 9.0),
            Vec3::new(9.0, 10.0, 9.0),
        ];
        let mesh = Mesh::from_triangles(p, &[[0, 1, 2], [3, 4, 5], [6, 7, 8]]).unwrap();
        let ours = pair::self_intersections(&MeshIndex::new(mesh.clone())).unwrap();
        assert_eq!(ours, [[0, 1]]);
        assert_eq!(judge_self(&mesh, &ours, &[[1, 0]]).unwrap(), [0, 0, 0, 0]);
        assert_eq!(judge_self(&mesh, &ours, &[[0, 2]]).unwrap(), [1, 1, 1, 0]);
        assert!(judge_self(&mesh, &ours, &[[0, 7]]).is_err());
    }
}
