//! The command-line contract of `raycast --method tree|grid` and `--any`.

use std::process::{Command, Output};

fn proxima(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .output()
        .expect("runs")
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn bunny() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj").to_string()
}

/// The hit line up to the method-specific count in parentheses.
fn hit_part(text: &str) -> &str {
    text.split(" (").next().unwrap()
}

#[test]
fn tree_and_grid_print_the_same_hits() {
    let rays = [
        ("-0.1,5,20", "0,0,-1"),
        ("0,20,0", "0,-1,0"),
        ("3,4,5", "-1,-0.5,-1"),
        ("0,4,0", "1,0,0"),
        ("0,50,0", "1,0,0"),
    ];
    for (origin, dir) in rays {
        let run = |extra: &[&str]| {
            let mesh = bunny();
            let mut args = vec!["raycast", mesh.as_str(), "--origin", origin, "--dir", dir];
            args.extend_from_slice(extra);
            let out = proxima(&args);
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            stdout(&out)
        };
        let (tree, grid, default) = (run(&["--method", "tree"]), run(&["--method", "grid"]), run(&[]));
        assert_eq!(hit_part(&tree), hit_part(&grid), "{origin} {dir}");
        assert_eq!(default, tree, "tree is the default");
        if tree.starts_with("hit face") {
            assert!(tree.contains("nodes visited, tree of"), "{tree}");
            assert!(grid.contains("cells visited, grid cell"), "{grid}");
        } else {
            assert_eq!(tree.trim(), "no hit");
        }
        let any = run(&["--any"]);
        assert_eq!(any.trim(), if tree.starts_with("hit") { "hit" } else { "no hit" });
        assert_eq!(run(&["--any", "--method", "grid"]), any);
        // JSON: the same hit fields, with the method's own count.
        let t: serde_json::Value = serde_json::from_str(&run(&["--json"])).unwrap();
        let g: serde_json::Value = serde_json::from_str(&run(&["--json", "--method", "grid"])).unwrap();
        assert_eq!(t["method"], "tree");
        assert_eq!(g["method"], "grid");
        for key in ["face", "t", "point"] {
            assert_eq!(t["hit"][key], g["hit"][key], "{key}");
        }
        let a: serde_json::Value = serde_json::from_str(&run(&["--json", "--any"])).unwrap();
        assert_eq!(a["any_hit"], !t["hit"].is_null());
    }
}

#[test]
fn raycast_errors() {
    let out = proxima(&["raycast", &bunny(), "--origin", "0,0,0", "--dir", "0,0,0"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("direction") && err.lines().count() == 1, "{err}");
    let out = proxima(&[
        "raycast",
        &bunny(),
        "--origin",
        "0,0,0",
        "--dir",
        "0,0,1",
        "--method",
        "tree",
        "--cell",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(2), "usage error");
    let out = proxima(&[
        "raycast",
        &bunny(),
        "--origin",
        "0,0,0",
        "--dir",
        "0,0,1",
        "--method",
        "octree",
    ]);
    assert_eq!(out.status.code(), Some(2), "usage error");
    let out = proxima(&["raycast", "/nonexistent.obj", "--origin", "0,0,0", "--dir", "0,0,1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent.obj"));
}

mod common;

use proxima::DVec3;
use proxima::prelude::*;
use proxima::sample::Rng;

/// Rays at the bunny: random ones (many missing), ones from inside, and
/// ones aimed exactly at vertices and edge midpoints from outside (the
/// watertight test lets none of them slip through the closed mesh).
fn batch_rays(mesh: &Mesh) -> Vec<(Vec3, Vec3)> {
    let mut rng = Rng::new(31);
    let b = mesh.bounds();
    let centre = b.center();
    let mut rays = Vec::new();
    let random = |rng: &mut Rng| Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
    for _ in 0..300 {
        let origin = centre + random(&mut rng) * b.diagonal();
        rays.push((origin, random(&mut rng)));
    }
    for _ in 0..100 {
        rays.push((centre + random(&mut rng) * 0.5, random(&mut rng)));
    }
    // Aimed exactly: rays along ±x, ±y, ±z through a vertex, or through an
    // edge midpoint whose two other coordinates are exact in f32 (so the
    // ray meets the edge itself). The watertight test lets none of them
    // slip through the closed mesh.
    let positions = mesh.positions();
    let edges = mesh.edge_indices();
    let far = b.diagonal() * 2.0;
    let axis_ray = |p: Vec3, k: usize| {
        let mut direction = Vec3::ZERO;
        direction[k % 3] = if k < 3 { 1.0 } else { -1.0 };
        (p - direction * far, direction)
    };
    for n in 0..200 {
        rays.push(axis_ray(positions[rng.below(positions.len())], n % 6));
        let [a, c] = edges[rng.below(edges.len())];
        let (a, c) = (positions[a as usize], positions[c as usize]);
        let midpoint = (a + c) * 0.5;
        let exact = (a.as_dvec3() + c.as_dvec3()) * 0.5;
        let axis = n % 6;
        let others_exact = (0..3)
            .filter(|&k| k != axis % 3)
            .all(|k| midpoint[k] as f64 == exact[k]);
        rays.push(if others_exact {
            axis_ray(midpoint, axis)
        } else {
            axis_ray(a, axis)
        });
    }
    // Axis-aligned, with zero direction components.
    rays.push((Vec3::new(0.0, 4.0, -20.0), Vec3::Z));
    rays.push((Vec3::new(0.5, -5.0, 0.2), Vec3::Y));
    rays
}

/// The unit direction the CLI casts: normalized in `f64`, then rounded.
fn unit(d: Vec3) -> Vec3 {
    let d64 = d.as_dvec3();
    (d64 / d64.length()).as_vec3()
}

fn write_rays(dir: &std::path::Path, rays: &[(Vec3, Vec3)]) -> std::path::PathBuf {
    let mut text = String::from("# ox oy oz dx dy dz\n");
    for (o, d) in rays {
        text += &format!("{} {} {}, {} {} {}\n", o.x, o.y, o.z, d.x, d.y, d.z);
    }
    let path = dir.join("batch.rays");
    std::fs::write(&path, text).unwrap();
    path
}

/// `--rays`: one row per ray in input order, equal to brute force over all
/// triangles (the same t and face: `f32` printed in full round-trips); with
/// `--any`, 1 exactly where brute force hits.
#[test]
fn batch_rays_equal_brute_force() {
    let mesh = proxima::io::load(bunny()).unwrap();
    let rays = batch_rays(&mesh);
    let dir = common::temp_dir("batch_rays_equal_brute_force");
    let file = write_rays(&dir, &rays);
    let out = proxima(&["raycast", &bunny(), "--rays", file.to_str().unwrap(), "--threads", "2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = stdout(&out);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("ray,t,face"));
    let linear = LinearSearch::new(mesh.triangles());
    let mut aimed_misses = 0;
    for (i, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields[0], i.to_string());
        let (o, d) = rays[i];
        let d = unit(d);
        let expected = linear.first_hit(o, d, 0.0, f32::INFINITY).unwrap();
        match expected {
            None => assert_eq!(&fields[1..], ["inf", "-1"], "ray {i}"),
            Some(hit) => {
                // The tree's answer is brute force's, field for field (ties
                // to the lowest index): the same t and face, exactly.
                let t: f32 = fields[1].parse().unwrap();
                let face: u32 = fields[2].parse().unwrap();
                assert_eq!((t, face), (hit.t, hit.source), "ray {i}");
            }
        }
        if (400..800).contains(&i) && expected.is_none() {
            aimed_misses += 1;
        }
    }
    assert_eq!(aimed_misses, 0, "rays aimed at vertices and edges slipped through");
    assert_eq!(text.lines().count(), rays.len() + 1);

    let out = proxima(&["raycast", &bunny(), "--rays", file.to_str().unwrap(), "--any"]);
    assert!(out.status.success());
    let text = stdout(&out);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("ray,hit"));
    for (i, line) in lines.enumerate() {
        let (o, d) = rays[i];
        let hit = linear
            .first_hit(o, d / d.length(), 0.0, f32::INFINITY)
            .unwrap()
            .is_some();
        assert_eq!(line, format!("{i},{}", u8::from(hit)));
    }
}

/// `--rays --json`: one object with the counts, the casting time alone and
/// the build time.
#[test]
fn batch_rays_json_summary() {
    let mesh = proxima::io::load(bunny()).unwrap();
    let rays = batch_rays(&mesh);
    let dir = common::temp_dir("batch_rays_json_summary");
    let file = write_rays(&dir, &rays);
    let out = proxima(&[
        "raycast",
        &bunny(),
        "--rays",
        file.to_str().unwrap(),
        "--json",
        "--threads",
        "1",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let linear = LinearSearch::new(mesh.triangles());
    let hits = rays
        .iter()
        .filter(|(o, d)| linear.first_hit(*o, unit(*d), 0.0, f32::INFINITY).unwrap().is_some())
        .count();
    assert_eq!(json["rays"], rays.len());
    assert_eq!(json["hits"], hits);
    assert_eq!(json["threads"], 1);
    for key in ["seconds", "rays_per_second", "build_seconds"] {
        assert!(json[key].as_f64().unwrap() >= 0.0, "{key}");
    }
}

/// `bench --query rays`: every method casts the same rays, proxima's agree
/// with linear search (on the first rays) and with each other, and the
/// rates are positive.
#[test]
fn bench_measures_rays() {
    let out = proxima(&["bench", &bunny(), "--query", "rays", "--queries", "3000", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["query"], "rays");
    let results = json["results"].as_array().unwrap();
    for method in ["linear", "tree-wide", "ray-tree", "ray-tree-batch"] {
        let r = results
            .iter()
            .find(|r| r["method"] == method)
            .unwrap_or_else(|| panic!("{method} missing: {json}"));
        assert_eq!(r["agree"], true, "{r}");
        assert!(r["rays_per_second"].as_f64().unwrap() > 0.0, "{r}");
        assert!(r["rays"].as_u64().unwrap() > 0, "{r}");
    }
    let text = stdout(&proxima(&["bench", &bunny(), "--query", "rays", "--queries", "500"]));
    assert!(
        text.contains("500 rays of the BENCHMARKS rays set") && text.contains("ray-tree-batch"),
        "{text}"
    );
}

/// A mesh whose faces all sit on one point has no area, so every ray misses
/// it: `no hit` from near or far, with `--any`, `--json` and a `--rays`
/// file, never "ray origin lies too far from the mesh". (Far means within
/// 2^30 times the point's coordinates for a point away from 0, where the
/// tree's box has the size of a few `f32` ulps.)
#[test]
fn point_sized_mesh_is_missed_not_refused() {
    let dir = common::temp_dir("point_sized_mesh_is_missed_not_refused");
    for (name, vertex, origins) in [
        (
            "origin.obj",
            "0 0 0",
            &["0,0,5", "0.5,0,1000", "0,0,1e9", "1,1,1e30"][..],
        ),
        ("offset.obj", "1 2 3", &["1,2,5", "1.5,2,1000", "1,2,1e9"][..]),
    ] {
        let mesh = dir.join(name);
        std::fs::write(&mesh, format!("v {vertex}\n{}", "f 1 1 1\n".repeat(10_000))).unwrap();
        let mesh = mesh.to_str().unwrap();
        let mut rays = String::new();
        for origin in origins {
            let run = |extra: &[&str]| {
                let out = proxima(&[&["raycast", mesh, "--origin", origin, "--dir", "0,0,-1"], extra].concat());
                let err = String::from_utf8_lossy(&out.stderr);
                assert!(out.status.success(), "{name} from {origin}: {err}");
                assert!(err.is_empty(), "{err}");
                stdout(&out)
            };
            assert_eq!(run(&[]), "no hit\n", "{name} from {origin}");
            assert_eq!(run(&["--any"]), "no hit\n", "{name} from {origin}");
            let json: serde_json::Value = serde_json::from_str(&run(&["--json"])).unwrap();
            assert!(json["hit"].is_null(), "{json}");
            // Rays files keep origins within ±2^62 (the points files' bound).
            if !origin.contains("e30") {
                rays += &format!("{} 0 0 -1\n", origin.replace(',', " "));
            }
        }
        let count = rays.lines().count();
        let file = dir.join(format!("{name}.rays"));
        std::fs::write(&file, rays).unwrap();
        let out = proxima(&["raycast", mesh, "--rays", file.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let expected: String = (0..count).map(|i| format!("{i},inf,-1\n")).collect();
        assert_eq!(stdout(&out), format!("ray,t,face\n{expected}"));
        let out = proxima(&["raycast", mesh, "--rays", file.to_str().unwrap(), "--any"]);
        let expected: String = (0..count).map(|i| format!("{i},0\n")).collect();
        assert_eq!(stdout(&out), format!("ray,hit\n{expected}"));
    }
}

/// `--rays --attributes`: each hit's row adds the surface columns, which
/// reproduce the hit point (origin + t·direction) from the triangle's
/// corners; a miss's columns are empty; the rest of the row is unchanged.
#[test]
fn batch_ray_attributes_locate_the_hits() {
    let mesh = proxima::io::load(bunny()).unwrap();
    let rays = batch_rays(&mesh);
    let dir = common::temp_dir("batch_ray_attributes");
    let file = write_rays(&dir, &rays);
    let file = file.to_str().unwrap();
    let plain = stdout(&proxima(&["raycast", &bunny(), "--rays", file]));
    let out = proxima(&["raycast", &bunny(), "--rays", file, "--attributes"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = stdout(&out);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("ray,t,face,triangle,u,v,feature,fa,fb,nx,ny,nz,fnx,fny,fnz,tu,tv")
    );
    let triangles = mesh.triangle_vertex_indices();
    let (mut hits, mut edges) = (0, 0);
    for ((i, line), plain) in lines.enumerate().zip(plain.lines().skip(1)) {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields[..3].join(","), plain, "ray {i}");
        if fields[2] == "-1" {
            assert!(fields[3..].iter().all(|f| f.is_empty()), "{line}");
            continue;
        }
        hits += 1;
        let number = |k: usize| fields[k].parse::<f64>().unwrap();
        let corners = triangles[fields[3].parse::<usize>().unwrap()];
        let p = corners.map(|v| mesh.positions()[v as usize].as_dvec3());
        let (u, v) = (number(4), number(5));
        let at = p[0] * (1.0 - u - v) + p[1] * u + p[2] * v;
        let (o, d) = rays[i];
        let expected = o.as_dvec3() + unit(d).as_dvec3() * number(1);
        assert!((at - expected).length() < 1e-4, "ray {i}: {at} vs {expected}");
        let normal = DVec3::new(number(9), number(10), number(11));
        let face_normal = DVec3::new(number(12), number(13), number(14));
        assert!((normal.length() - 1.0).abs() < 1e-9 && (face_normal.length() - 1.0).abs() < 1e-9);
        let expected_normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        assert!((face_normal - expected_normal).length() < 1e-9);
        edges += usize::from(fields[6] != "face");
    }
    assert!(hits > 500, "{hits}");
    // Rays aimed at vertices and edges hit them.
    assert!(edges > 0);
    let out = proxima(&["raycast", &bunny(), "--rays", file, "--attributes", "--any"]);
    assert!(!out.status.success());
}
