//! `proxima distance`, `proxima collide` and `proxima self-intersections`:
//! unit cubes at known offsets (distances exact in `f64`, touching exactly
//! and one ulp apart), and the bunny against a rotated copy and itself,
//! every CSV field equal to the library's answer computed here on the same
//! file and the same poses.

mod common;

use common::temp_dir;
use proxima::pair::{self, RigidPose};
use proxima::{DVec3, Mesh, MeshIndex};
use std::path::Path;
use std::process::Output;

const BUNNY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj");

/// The unit cube [0, 1]³, twelve triangles, outward faces.
const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

fn run(args: &[&str]) -> Output {
    common::proxima_ok(args)
}

/// The CSV rows of standard output, split at commas, after the header.
fn rows(out: &Output, header: &str) -> Vec<Vec<String>> {
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(header));
    lines.map(|l| l.split(',').map(str::to_string).collect()).collect()
}

/// A pose as the 16 numbers of `--pose-b` (`{}` prints each `f64` so that
/// it parses back to the same value).
fn pose_text(pose: &RigidPose) -> String {
    pose.to_rows()
        .iter()
        .flatten()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

fn shift_x(t: f64) -> RigidPose {
    RigidPose::translation_only(DVec3::new(t, 0.0, 0.0)).unwrap()
}

fn cube_file(dir: &Path) -> String {
    let path = dir.join("cube.obj");
    std::fs::write(&path, CUBE).unwrap();
    path.display().to_string()
}

const DISTANCE_HEADER: &str = "pose,distance,ax,ay,az,bx,by,bz,face_a,face_b";

#[test]
fn cubes_apart_along_x_are_their_gap_apart() {
    let dir = temp_dir("cubes_apart");
    let cube = cube_file(&dir);
    // The gap t - 1 is exact in f64 for each t (Sterbenz), and so is the
    // distance of the two parallel faces x = 1 and x = t.
    for t in [3.0, 1.5, 1.0f64.next_up(), 1.0 + 1e-9, 1e6] {
        let out = run(&["distance", &cube, &cube, "--pose-b", &pose_text(&shift_x(t))]);
        let rows = rows(&out, DISTANCE_HEADER);
        assert_eq!(rows.len(), 1);
        let row = &rows[0];
        assert_eq!(row[0], "0");
        assert_eq!(row[1].parse::<f64>().unwrap(), t - 1.0, "t = {t}");
        assert_eq!(row[2].parse::<f64>().unwrap(), 1.0, "point on A at x = 1");
        assert_eq!(row[5].parse::<f64>().unwrap(), t, "point on B at x = t");
    }
    // Touching or overlapping: distance 0.
    for t in [1.0, 1.0f64.next_down(), 0.5, 0.0] {
        let out = run(&["distance", &cube, &cube, "--pose-b", &pose_text(&shift_x(t))]);
        assert_eq!(rows(&out, DISTANCE_HEADER)[0][1], "0", "t = {t}");
    }
}

#[test]
fn cubes_touch_exactly_at_their_width_and_not_one_ulp_beyond() {
    let dir = temp_dir("cubes_touch");
    let cube = cube_file(&dir);
    for (t, meets) in [
        (1.0, true),
        (1.0f64.next_down(), true),
        (1.0f64.next_up(), false),
        (-1.0, true),
        ((-1.0f64).next_down(), false),
        (0.25, true),
        (2.0, false),
    ] {
        let out = run(&["collide", &cube, &cube, "--pose-b", &pose_text(&shift_x(t))]);
        assert_eq!(
            rows(&out, "pose,intersects"),
            [["0", if meets { "1" } else { "0" }]],
            "t = {t}"
        );
    }
    // The same through a poses file (and --pose-a moving A instead of B).
    let poses = dir.join("p.txt");
    let lines: Vec<String> = [1.0, 1.0f64.next_up()]
        .iter()
        .map(|&t| pose_text(&shift_x(t)))
        .collect();
    std::fs::write(
        &poses,
        format!("# two poses\n{}\n\n{}\n", lines[0], lines[1].replace(',', " ")),
    )
    .unwrap();
    let out = run(&["collide", &cube, &cube, "--poses", poses.to_str().unwrap()]);
    assert_eq!(rows(&out, "pose,intersects"), [["0", "1"], ["1", "0"]]);
    let out = run(&[
        "collide",
        &cube,
        &cube,
        "--pose-a",
        &pose_text(&shift_x(-1.0f64.next_up())),
    ]);
    assert_eq!(rows(&out, "pose,intersects"), [["0", "0"]]);
}

#[test]
fn max_distance_answers_below_it_and_none_from_it_on() {
    let dir = temp_dir("max_distance");
    let cube = cube_file(&dir);
    let pose = pose_text(&shift_x(3.0)); // two apart
    for (d, answer) in [
        ("2", "none"),
        ("1.9999999999999998", "none"),
        ("2.0000000000000004", "2"),
        ("inf", "2"),
    ] {
        let out = run(&["distance", &cube, &cube, "--pose-b", &pose, "--max-distance", d]);
        let rows = rows(&out, DISTANCE_HEADER);
        assert_eq!(rows[0][1], answer, "--max-distance {d}");
        if answer == "none" {
            assert_eq!(rows[0], ["0", "none", "", "", "", "", "", "", "", ""]);
        }
    }
    let out = run(&[
        "distance",
        &cube,
        &cube,
        "--pose-b",
        &pose,
        "--max-distance",
        "1",
        "--json",
    ]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["answers"][0]["distance"], serde_json::Value::Null);
}

#[test]
fn within_lists_the_face_pairs_at_most_that_far() {
    let dir = temp_dir("within");
    let cube = cube_file(&dir);
    let pose = shift_x(3.0);
    let index = MeshIndex::new(proxima::io::load(&cube).unwrap());
    for d in [2.0, 2.0f64.next_down(), 2.5, 0.0] {
        let out = run(&[
            "collide",
            &cube,
            &cube,
            "--pose-b",
            &pose_text(&pose),
            "--within",
            &d.to_string(),
        ]);
        let got: Vec<[u32; 2]> = rows(&out, "pose,face_a,face_b")
            .iter()
            .map(|r| [r[1].parse().unwrap(), r[2].parse().unwrap()])
            .collect();
        let expected = pair::pairs_within(&index, &RigidPose::IDENTITY, &index, &pose, d).unwrap();
        assert_eq!(got, expected, "--within {d}");
        // Independently: some pair is exactly 2 apart (A's x = 1 faces, B's
        // x = 3 faces), none nearer.
        assert_eq!(got.is_empty(), d < 2.0, "--within {d}");
    }
}

/// Rotations about tilted axes and offsets that make the bunny copies
/// overlap and stand apart (the bunny is about 10 wide, its diagonal 15.8).
fn bunny_poses() -> Vec<RigidPose> {
    let mut poses = vec![RigidPose::IDENTITY];
    for (k, offset) in [0.0, 1.0, 4.0, 12.0, 30.0].iter().enumerate() {
        let angle = 0.7 * (k as f64 + 1.0);
        let axis = DVec3::new(1.0, 2.0, 0.5 + k as f64).normalize();
        let (s, c) = (angle / 2.0).sin_cos();
        let q = [axis.x * s, axis.y * s, axis.z * s, c];
        poses.push(RigidPose::from_quaternion(q, [*offset, 0.5 * offset, -0.25 * offset]).unwrap());
    }
    poses
}

#[test]
fn bunny_distances_equal_the_library_answers_field_for_field() {
    let dir = temp_dir("bunny_distance");
    let index = MeshIndex::new(proxima::io::load(BUNNY).unwrap());
    let poses = bunny_poses();
    let file = dir.join("poses.txt");
    std::fs::write(&file, poses.iter().map(|p| pose_text(p) + "\n").collect::<String>()).unwrap();
    let file = file.to_str().unwrap();
    let expected = pair::distance_batch(&index, &index, &poses).unwrap();
    let out = run(&["distance", BUNNY, BUNNY, "--poses", file, "--threads", "2"]);
    let rows = rows(&out, DISTANCE_HEADER);
    assert_eq!(rows.len(), poses.len());
    for (i, (row, d)) in rows.iter().zip(&expected).enumerate() {
        let numbers: Vec<f64> = row[1..8].iter().map(|x| x.parse().unwrap()).collect();
        assert_eq!(row[0], i.to_string());
        assert_eq!(numbers[0], d.distance, "pose {i}");
        assert_eq!(&numbers[1..4], &d.point_a.to_array(), "pose {i}");
        assert_eq!(&numbers[4..7], &d.point_b.to_array(), "pose {i}");
        assert_eq!(
            [row[8].parse::<u32>().unwrap(), row[9].parse().unwrap()],
            [d.face_a, d.face_b]
        );
    }
    assert!(expected.iter().any(|d| d.distance == 0.0) && expected.iter().any(|d| d.distance > 0.0));
    // One pose at a time, A moved too: the library's `distance`.
    let pose_a = poses[2];
    let pose_b = poses[4];
    let d = pair::distance(&index, &pose_a, &index, &pose_b).unwrap();
    let out = run(&[
        "distance",
        BUNNY,
        BUNNY,
        "--pose-a",
        &pose_text(&pose_a),
        "--pose-b",
        &pose_text(&pose_b),
        "--json",
    ]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let answer = &json["answers"][0];
    assert_eq!(answer["distance"].as_f64(), Some(d.distance));
    assert_eq!(answer["point_a"], serde_json::json!(d.point_a.to_array()));
    assert_eq!(answer["point_b"], serde_json::json!(d.point_b.to_array()));
    assert_eq!(answer["face_a"], d.face_a);
    assert_eq!(answer["face_b"], d.face_b);
    assert_eq!(json["poses"], 1);
}

#[test]
fn bunny_collisions_equal_the_library_answers() {
    let dir = temp_dir("bunny_collide");
    let index = MeshIndex::new(proxima::io::load(BUNNY).unwrap());
    let poses = bunny_poses();
    let file = dir.join("poses.txt");
    std::fs::write(&file, poses.iter().map(|p| pose_text(p) + "\n").collect::<String>()).unwrap();
    let file = file.to_str().unwrap();
    let expected = pair::intersects_batch(&index, &index, &poses).unwrap();
    assert!(expected.contains(&true) && expected.contains(&false));
    let out = run(&["collide", BUNNY, BUNNY, "--poses", file]);
    let got: Vec<bool> = rows(&out, "pose,intersects").iter().map(|r| r[1] == "1").collect();
    assert_eq!(got, expected);
    // The pairs, per pose, in CSV and in JSON.
    let out = run(&["collide", BUNNY, BUNNY, "--poses", file, "--pairs"]);
    let csv = rows(&out, "pose,face_a,face_b");
    let out = run(&["collide", BUNNY, BUNNY, "--poses", file, "--pairs", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut total = 0;
    for (i, pose) in poses.iter().enumerate() {
        let pairs = pair::intersecting_pairs(&index, &RigidPose::IDENTITY, &index, pose).unwrap();
        let from_csv: Vec<[u32; 2]> = csv
            .iter()
            .filter(|r| r[0] == i.to_string())
            .map(|r| [r[1].parse().unwrap(), r[2].parse().unwrap()])
            .collect();
        assert_eq!(from_csv, pairs, "pose {i}");
        assert_eq!(json["answers"][i]["pairs"], serde_json::json!(pairs), "pose {i}");
        assert_eq!(!pairs.is_empty(), expected[i], "pose {i}");
        total += pairs.len();
    }
    assert_eq!(csv.len(), total);
    assert_eq!(json["pairs"], total);
}

#[test]
fn self_intersections_of_crossing_triangles_and_the_bunny() {
    let dir = temp_dir("self");
    // Two triangles crossing each other, a third apart (the library's doc
    // example), and a fourth sharing an edge with the first, hinged along it.
    let crossing = dir.join("crossing.obj");
    std::fs::write(
        &crossing,
        "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0.5 0.5 -1\nv 0.5 0.5 1\nv 3 3 0\nv 9 9 9\nv 10 9 9\nv 9 10 9\nv 1 0 1\n\
         f 1 2 3\nf 4 5 6\nf 7 8 9\nf 1 2 10\n",
    )
    .unwrap();
    let crossing = crossing.to_str().unwrap();
    let out = run(&["self-intersections", crossing]);
    assert_eq!(rows(&out, "face_a,face_b"), [["0", "1"]]);
    let csv = dir.join("pairs.csv");
    let out = run(&["self-intersections", crossing, "--out", csv.to_str().unwrap(), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["count"], 1);
    assert_eq!(json["faces"], 4);
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), "face_a,face_b\n0,1\n");

    // The bunny (which has self-intersections or none: the library decides).
    let index = MeshIndex::new(proxima::io::load(BUNNY).unwrap());
    let expected = pair::self_intersections(&index).unwrap();
    let out = run(&["self-intersections", BUNNY, "--json", "--threads", "1"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["pairs"], serde_json::json!(expected));
    assert_eq!(json["count"], expected.len());
    // A mesh crossing itself by construction: the bunny and a turned copy in
    // one file; the pairs between the halves are `collide --pairs`'s.
    let bunny = proxima::io::load(BUNNY).unwrap();
    let pose = bunny_poses()[1];
    let n = bunny.vertex_count() as u32;
    let mut positions: Vec<proxima::Vec3> = bunny.positions().to_vec();
    positions.extend(bunny.positions().iter().map(|&p| pose.apply(p).as_vec3()));
    let mut faces: Vec<[u32; 3]> = bunny.triangle_vertex_indices();
    let first = faces.len() as u32;
    faces.extend(bunny.triangle_vertex_indices().iter().map(|f| f.map(|v| v + n)));
    let twice = Mesh::from_triangles(positions, &faces).unwrap();
    let twice_index = MeshIndex::new(twice);
    let expected = pair::self_intersections(&twice_index).unwrap();
    let path = dir.join("twice.obj");
    let mut text = String::new();
    for p in twice_index.mesh().positions() {
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for f in &faces {
        text += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    std::fs::write(&path, text).unwrap();
    let out = run(&["self-intersections", path.to_str().unwrap()]);
    let got: Vec<[u32; 2]> = rows(&out, "face_a,face_b")
        .iter()
        .map(|r| [r[0].parse().unwrap(), r[1].parse().unwrap()])
        .collect();
    assert_eq!(got, expected);
    assert!(got.iter().any(|&[a, b]| a < first && b >= first), "the copies cross");
}

/// `proxima hausdorff` on two surfaces prints the library's bounds; on point
/// files (text and `.npy`) the exact distance of brute force over the points.
#[test]
fn hausdorff_of_surfaces_and_of_point_files() {
    let dir = temp_dir("hausdorff_cli");
    // A unit square, and a 2 x 2 square lifted by 1: from the large one's
    // far corner the small square is sqrt(3) away.
    std::fs::write(dir.join("small.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    std::fs::write(dir.join("large.obj"), "v 0 0 1\nv 2 0 1\nv 2 2 1\nv 0 2 1\nf 1 2 3 4\n").unwrap();
    let (small, large) = (dir.join("small.obj"), dir.join("large.obj"));
    let out = run(&[
        "hausdorff",
        small.to_str().unwrap(),
        large.to_str().unwrap(),
        "--tolerance",
        "1e-6",
    ]);
    let surfaces = rows(&out, HAUSDORFF_HEADER);
    let library = pair::hausdorff(
        &MeshIndex::new(proxima::io::load(&small).unwrap()),
        &MeshIndex::new(proxima::io::load(&large).unwrap()),
        1e-6,
    )
    .unwrap();
    assert_eq!(surfaces[0][0], "a_to_b");
    assert_eq!(surfaces[0][1].parse::<f64>().unwrap(), library.forward.lower);
    assert_eq!(surfaces[1][1].parse::<f64>().unwrap(), library.backward.lower);
    assert_eq!(surfaces[1][2].parse::<f64>().unwrap(), library.backward.upper);
    assert_eq!(surfaces[1][1].parse::<f64>().unwrap(), 3f64.sqrt());
    assert_eq!(&surfaces[1][3..6], ["2", "2", "1"]);
    let json = run(&[
        "hausdorff",
        small.to_str().unwrap(),
        large.to_str().unwrap(),
        "--json",
        "--one-sided",
    ]);
    let json: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(json["compared"], "surfaces");
    assert_eq!(json["directions"].as_array().unwrap().len(), 1);
    assert_eq!(json["lower"], 1.0);

    // Point sets: random points in a text file against others in a .npy
    // (float64, rounded to f32 as the text's are).
    let mut rng = proxima::sample::Rng::new(3);
    let a: Vec<[f32; 3]> = (0..200)
        .map(|_| [rng.range(0.0, 1.0), rng.range(0.0, 1.0), rng.range(0.0, 1.0)])
        .collect();
    let b: Vec<[f64; 3]> = (0..150).map(|_| [rng.unit(), rng.unit(), rng.unit() + 0.5]).collect();
    let text: String = a.iter().map(|p| format!("{} {} {}\n", p[0], p[1], p[2])).collect();
    std::fs::write(dir.join("a.xyz"), text).unwrap();
    let dict = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, 3), }}",
        b.len()
    );
    let mut npy = b"\x93NUMPY\x01\x00\x76\x00".to_vec();
    npy.extend(format!("{dict:<117}\n").bytes());
    npy.extend(b.iter().flatten().flat_map(|v| v.to_le_bytes()));
    std::fs::write(dir.join("b.npy"), npy).unwrap();
    let d = |p: [f32; 3], q: [f64; 3]| {
        let q = q.map(|v| f64::from(v as f32));
        (0..3).map(|k| (f64::from(p[k]) - q[k]).powi(2)).sum::<f64>().sqrt()
    };
    let forward = a
        .iter()
        .map(|&p| b.iter().map(|&q| d(p, q)).fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max);
    let backward = b
        .iter()
        .map(|&q| a.iter().map(|&p| d(p, q)).fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max);
    let (pa, pb) = (dir.join("a.xyz"), dir.join("b.npy"));
    let out = run(&["hausdorff", pa.to_str().unwrap(), pb.to_str().unwrap()]);
    let points = rows(&out, HAUSDORFF_HEADER);
    assert_eq!(points[0][1].parse::<f64>().unwrap(), forward);
    assert_eq!(points[1][1].parse::<f64>().unwrap(), backward);
    assert_eq!(points[1][1], points[1][2]);
}

/// The header of `proxima hausdorff`'s CSV.
const HAUSDORFF_HEADER: &str = "direction,lower,upper,px,py,pz,qx,qy,qz,index_p,index_q";
