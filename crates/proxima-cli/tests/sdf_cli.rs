//! `proxima sdf` and `proxima bench --query sdf`: the CSV against the
//! library's answers computed here, `closest`'s distances, and the `.npy` and
//! `.npz` files read back by an independent reader (`npyz`, the container by
//! `zip`'s reader).

mod common;

use common::temp_dir;
use proxima::sdf::{SdfGrid, certificate_pays};
use proxima::{Mesh, SdfConfig, Sign, SignedDistanceField, Vec3};
use std::path::Path;
use std::process::{Command, Output};

const BUNNY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/bunny-npm.obj");

fn proxima(args: &[&str]) -> Output {
    common::proxima_ok(args)
}

fn bunny() -> Mesh {
    proxima::io::load(BUNNY).unwrap()
}

/// The field `proxima sdf` makes for `queries` queries: with the sign
/// certificate only when they pay for it (its winding numbers are then the
/// certificate's integers, otherwise the walked ones).
fn field(mesh: &Mesh, sign: Sign, queries: usize) -> SignedDistanceField {
    SignedDistanceField::new(
        mesh,
        &SdfConfig {
            sign,
            certify: certificate_pays(queries, mesh.triangle_count()),
            ..SdfConfig::default()
        },
    )
    .unwrap()
}

/// Near-surface and uniform points around the bunny, written as a points
/// file (`{}` prints each `f32` so that it parses back to the same value).
fn points_file(mesh: &Mesh, dir: &Path) -> (Vec<Vec3>, String) {
    let mut points = proxima::sample::near_surface(mesh, 150, 0.01, 3);
    points.extend(proxima::sample::uniform_in_box(mesh, 100, 4));
    let text: String = points.iter().map(|p| format!("{} {} {}\n", p.x, p.y, p.z)).collect();
    let path = dir.join("q.pts");
    std::fs::write(&path, text).unwrap();
    (points, path.display().to_string())
}

/// The CSV rows of standard output, split at commas, after the header.
fn rows(out: &Output, header: &str) -> Vec<Vec<String>> {
    let text = String::from_utf8(out.stdout.clone()).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(header));
    lines.map(|l| l.split(',').map(str::to_string).collect()).collect()
}

const HEADER: &str = "query,signed_distance,winding_number,primitive,cx,cy,cz";

#[test]
fn csv_rows_are_the_library_answers_in_input_order() {
    let dir = temp_dir("sdf_csv");
    let mesh = bunny();
    let (points, path) = points_file(&mesh, &dir);
    let rows = rows(&proxima(&["sdf", BUNNY, "--points", &path]), HEADER);
    assert_eq!(rows.len(), points.len());
    let field = field(&mesh, Sign::WindingNumber, points.len());
    let mut inside = 0;
    for (i, (row, &p)) in rows.iter().zip(&points).enumerate() {
        let expected = field.signed_distance(p).unwrap();
        assert_eq!(row[0], i.to_string());
        assert_eq!(row[1].parse::<f32>().unwrap(), expected.distance, "row {i}");
        assert_eq!(
            row[2].parse::<f32>().unwrap(),
            expected.winding_number.unwrap(),
            "row {i}"
        );
        assert_eq!(row[3].parse::<u32>().unwrap(), expected.closest.source, "row {i}");
        let closest: Vec<f32> = row[4..].iter().map(|v| v.parse().unwrap()).collect();
        assert_eq!(closest, expected.closest.point.to_array(), "row {i}");
        inside += usize::from(expected.distance < 0.0);
    }
    // Both sides are exercised.
    assert!(inside > 10 && inside < points.len() - 10, "{inside} inside");
}

/// `--gradient` adds gx,gy,gz: the library's gradients, unit length,
/// pointing from the printed closest point to the query outside and back
/// inside; the other columns are unchanged.
#[test]
fn gradient_columns_point_away_from_the_closest_point() {
    let dir = temp_dir("sdf_gradient");
    let mesh = bunny();
    let (mut points, _) = points_file(&mesh, &dir);
    // Vertices: on the surface, where the gradient is the vertex pseudonormal.
    points.extend(&mesh.positions()[..20]);
    let text: String = points.iter().map(|p| format!("{} {} {}\n", p.x, p.y, p.z)).collect();
    let path = dir.join("with_vertices.pts");
    std::fs::write(&path, text).unwrap();
    let path = path.display().to_string();
    for sign in ["winding", "pseudonormal"] {
        let plain = rows(&proxima(&["sdf", BUNNY, "--points", &path, "--sign", sign]), HEADER);
        let header = format!("{HEADER},gx,gy,gz");
        let out = proxima(&["sdf", BUNNY, "--points", &path, "--sign", sign, "--gradient"]);
        let with = rows(&out, &header);
        assert_eq!(with.len(), points.len());
        let normals = proxima::surface::vertex_normals(&mesh);
        for (i, ((row, plain), p)) in with.iter().zip(&plain).zip(&points).enumerate() {
            assert_eq!(row[..7], plain[..], "row {i}");
            let number = |k: usize| row[k].parse::<f64>().unwrap();
            let g = proxima::DVec3::new(number(7), number(8), number(9));
            assert!((g.length() - 1.0).abs() < 1e-9, "row {i}: {g}");
            let d = number(1);
            if d == 0.0 {
                let v = i - (points.len() - 20);
                assert!((g - normals[v].as_dvec3()).length() < 1e-5, "vertex {v}: {g}");
                continue;
            }
            let c = proxima::DVec3::new(number(4), number(5), number(6));
            let away = (p.as_dvec3() - c) * d.signum();
            if away.length() > 1e-3 {
                assert!((g - away.normalize()).length() < 1e-3, "row {i}: {g} vs {away}");
            }
        }
    }
}

/// `closest --attributes`: the surface columns reproduce the printed closest
/// point from the fan triangle's corners, and are the library's.
#[test]
fn closest_attributes_reproduce_the_closest_points() {
    let dir = temp_dir("closest_attributes");
    let mesh = bunny();
    let (points, path) = points_file(&mesh, &dir);
    let header = "query,rank,primitive,cx,cy,cz,distance,triangle,u,v,feature,fa,fb,nx,ny,nz,fnx,fny,fnz,tu,tv";
    let plain = rows(
        &proxima(&["closest", BUNNY, "--points", &path, "-k", "2"]),
        "query,rank,primitive,cx,cy,cz,distance",
    );
    for method in ["tree", "linear"] {
        let out = proxima(&[
            "closest",
            BUNNY,
            "--points",
            &path,
            "-k",
            "2",
            "--attributes",
            "--method",
            method,
        ]);
        let with = rows(&out, header);
        assert_eq!(with.len(), 2 * points.len());
        let triangles = mesh.triangle_vertex_indices();
        for (row, plain) in with.iter().zip(&plain) {
            assert_eq!(row[..7], plain[..]);
            let number = |k: usize| row[k].parse::<f64>().unwrap();
            let corners = triangles[row[7].parse::<usize>().unwrap()];
            let p = corners.map(|v| mesh.positions()[v as usize].as_dvec3());
            let (u, v) = (number(8), number(9));
            let at = p[0] * (1.0 - u - v) + p[1] * u + p[2] * v;
            let printed = proxima::DVec3::new(number(3), number(4), number(5));
            assert!((at - printed).length() < 1e-5, "{row:?}");
            let feature = row[10].as_str();
            // u, v are printed; the first weight, 1 - u - v, is zero where it rounds to it.
            let zeros = usize::from(u == 0.0) + usize::from(v == 0.0) + usize::from((1.0 - u - v).abs() < 1e-12);
            assert_eq!(feature, ["face", "edge", "vertex"][zeros], "{row:?}");
            match feature {
                "vertex" => assert!(corners.contains(&row[11].parse().unwrap()) && row[12].is_empty()),
                "edge" => {
                    assert!(corners.contains(&row[11].parse().unwrap()) && corners.contains(&row[12].parse().unwrap()))
                }
                _ => assert!(row[11].is_empty() && row[12].is_empty()),
            }
        }
    }
    // The bunny has no texture coordinates: tu, tv empty. A square whose UVs
    // are its x, y: tu, tv are the closest point's.
    let bunny_rows = rows(&proxima(&["closest", BUNNY, "--points", &path, "--attributes"]), header);
    assert!(bunny_rows.iter().all(|row| row[19].is_empty() && row[20].is_empty()));
    let square = dir.join("square.obj");
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    std::fs::write(&square, text).unwrap();
    let square = square.display().to_string();
    let out = proxima(&["closest", &square, "--point", "0.25,0.625,3", "--attributes"]);
    let row = &rows(&out, header)[0];
    assert_eq!((row[19].as_str(), row[20].as_str()), ("0.25", "0.625"));
    let out = Command::new(env!("CARGO_BIN_EXE_proxima"))
        .args([
            "closest",
            BUNNY,
            "--points",
            &path,
            "--attributes",
            "--primitives",
            "vertices",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--attributes"));
}

#[test]
fn distances_are_closest_distances_and_the_faces_its_faces() {
    let dir = temp_dir("sdf_closest");
    let mesh = bunny();
    let (points, path) = points_file(&mesh, &dir);
    let closest = rows(
        &proxima(&["closest", BUNNY, "--points", &path]),
        "query,rank,primitive,cx,cy,cz,distance",
    );
    for sign in ["winding", "pseudonormal"] {
        let sdf = rows(&proxima(&["sdf", BUNNY, "--points", &path, "--sign", sign]), HEADER);
        assert_eq!(sdf.len(), points.len());
        assert_eq!(closest.len(), points.len());
        for (s, c) in sdf.iter().zip(&closest) {
            assert_eq!(s[0], c[0]);
            let signed: f32 = s[1].parse().unwrap();
            assert_eq!(signed.abs(), c[6].parse::<f32>().unwrap(), "{sign}: {s:?} / {c:?}");
            assert_eq!(s[3], c[2], "{sign}: the face");
            assert_eq!(s[4..7], c[3..6], "{sign}: the closest point");
        }
    }
}

#[test]
fn pseudonormal_sign_leaves_the_winding_number_empty() {
    let dir = temp_dir("sdf_pseudonormal");
    let mesh = bunny();
    let (points, path) = points_file(&mesh, &dir);
    let rows = rows(
        &proxima(&["sdf", BUNNY, "--points", &path, "--sign", "pseudonormal"]),
        HEADER,
    );
    let field = field(&mesh, Sign::Pseudonormal, usize::MAX);
    for (row, &p) in rows.iter().zip(&points) {
        assert_eq!(row.len(), 7);
        assert_eq!(row[2], "", "{row:?}");
        assert_eq!(
            row[1].parse::<f32>().unwrap(),
            field.signed_distance(p).unwrap().distance
        );
    }
}

#[test]
fn json_answers_and_timings() {
    let mesh = bunny();
    let p = Vec3::new(0.1, 4.0, 0.2);
    let out = proxima(&["sdf", BUNNY, "--point", "0.1,4,0.2", "--threads", "2", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let expected = field(&mesh, Sign::WindingNumber, 1).signed_distance(p).unwrap();
    assert_eq!(json["queries"], 1);
    assert_eq!(json["inside"], usize::from(expected.is_inside()));
    assert_eq!(json["threads"], 2);
    assert_eq!(json["sign"], "winding");
    assert_eq!(json["triangles"], mesh.triangle_count());
    for key in ["seconds", "queries_per_second", "build_seconds"] {
        assert!(json[key].as_f64().unwrap() > 0.0, "{key}: {json}");
    }
    let answer = &json["answers"][0];
    assert_eq!(answer["query"], 0);
    assert_eq!(answer["signed_distance"].as_f64().unwrap() as f32, expected.distance);
    assert_eq!(
        answer["winding_number"].as_f64().unwrap() as f32,
        expected.winding_number.unwrap()
    );
    assert_eq!(answer["primitive"], expected.closest.source);
    assert_eq!(answer["inside"], expected.is_inside());

    let out = proxima(&["sdf", BUNNY, "--point", "0.1,4,0.2", "--sign", "pseudonormal", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["sign"], "pseudonormal");
    assert!(json["answers"][0]["winding_number"].is_null(), "{json}");
}

/// Reads a `.npy` with `npyz`: its shape, whether it is in Fortran order,
/// and its values in file order.
fn read_npy(bytes: &[u8]) -> (Vec<u64>, bool, Vec<f32>) {
    let file = npyz::NpyFile::new(bytes).unwrap();
    assert_eq!(file.dtype(), npyz::DType::Plain("<f4".parse().unwrap()));
    let shape = file.shape().to_vec();
    let fortran = file.order() == npyz::Order::Fortran;
    (shape, fortran, file.into_vec::<f32>().unwrap())
}

#[test]
fn grid_npy_reads_back_as_x_y_z_indexed_values() {
    let dir = temp_dir("sdf_grid");
    let path = dir.join("g.npy");
    let n = 13;
    let out = proxima(&["sdf", BUNNY, "--grid", "13", "--out", path.to_str().unwrap(), "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let (shape, fortran, values) = read_npy(&bytes);
    assert_eq!(shape, [13, 13, 13]);
    assert!(fortran, "x varies fastest: Fortran order");
    assert_eq!(values.len(), n * n * n);

    let mesh = bunny();
    let field = field(&mesh, Sign::WindingNumber, n * n * n);
    let grid = SdfGrid::around(&field.bounds(), n, 0.05).unwrap();
    let origin: Vec<f32> = json["origin"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() as f32)
        .collect();
    assert_eq!(origin, grid.origin().to_array());
    assert_eq!(json["cells"], n * n * n);
    // Asymmetric cells, so a transposed layout would be caught.
    for (i, j, k) in [
        (0, 0, 0),
        (12, 0, 0),
        (0, 12, 3),
        (6, 6, 6),
        (3, 7, 11),
        (12, 12, 12),
        (5, 2, 9),
    ] {
        let expected = field.signed_distance(grid.point(i, j, k)).unwrap().distance;
        let value = values[i + n * (j + n * k)];
        assert!(
            (value - expected).abs() <= 1e-6 * expected.abs().max(1e-3),
            "[{i},{j},{k}]: {value} against {expected}"
        );
    }
    assert!(values.iter().any(|&v| v < 0.0) && values[0] > 0.0);

    // To a redirected standard output: the same bytes, and the note (and a
    // progress bar, were stderr a terminal) only on stderr.
    let out = proxima(&["sdf", BUNNY, "--grid", "13"]);
    assert!(out.stdout == bytes, "stdout differs from the --out file");
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("origin") && err.contains("cell"), "{err}");
}

#[test]
fn samples_npz_reads_back_with_their_signed_distances() {
    let dir = temp_dir("sdf_sample");
    let path = dir.join("s.npz");
    let n = 101;
    proxima(&[
        "sdf",
        BUNNY,
        "--sample",
        "101",
        "--near-sigma",
        "0.02",
        "--seed",
        "5",
        "--out",
        path.to_str().unwrap(),
    ]);
    let mut archive = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
    let mut names: Vec<String> = archive.file_names().map(|n| n.unwrap().to_string()).collect();
    names.sort();
    assert_eq!(names, ["points.npy", "sdf.npy"]);
    let mut read = |name: &str| {
        let mut entry = archive.by_name(name).unwrap();
        assert_eq!(entry.compression(), zip::CompressionMethod::Stored);
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut entry, &mut bytes).unwrap();
        read_npy(&bytes)
    };
    let (points_shape, points_fortran, points) = read("points.npy");
    let (sdf_shape, sdf_fortran, sdf) = read("sdf.npy");
    assert_eq!(points_shape, [n as u64, 3]);
    assert_eq!(sdf_shape, [n as u64]);
    assert!(!points_fortran && !sdf_fortran, "C order");

    let mesh = bunny();
    let field = field(&mesh, Sign::WindingNumber, n);
    let points: Vec<Vec3> = points.chunks(3).map(Vec3::from_slice).collect();
    for (i, (&p, &value)) in points.iter().zip(&sdf).enumerate() {
        assert_eq!(value, field.signed_distance(p).unwrap().distance, "sample {i}");
    }
    // The first half (rounded up) near the surface, as the library draws them.
    let near = field.sample_near_surface(51, 0.02, 5).unwrap();
    assert_eq!(points[..51], near.points[..]);
    assert!(sdf[..51].iter().all(|d| d.abs() < 0.2), "near samples within 10 sigma");
    // The rest uniform in the box grown by 5%.
    let bounds = field.bounds();
    let grow = bounds.size() * 0.05;
    assert!(
        points[51..]
            .iter()
            .all(|p| p.cmpge(bounds.min - grow).all() && p.cmple(bounds.max + grow).all())
    );
    assert!(
        sdf[51..].iter().any(|d| d.abs() > 1.0),
        "uniform samples reach away from the surface"
    );
}

#[test]
fn bench_measures_signed_distances_on_both_sets() {
    let out = proxima(&["bench", BUNNY, "--query", "sdf", "--queries", "300", "--json"]);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["query"], "sdf");
    let results = json["results"].as_array().unwrap();
    for set in ["near", "uniform"] {
        for method in [
            "linear",
            "closest",
            "closest-batch",
            "winding",
            "winding-batch",
            "pseudonormal",
            "pseudonormal-batch",
        ] {
            let r = results
                .iter()
                .find(|r| r["query_set"] == set && r["method"] == method)
                .unwrap_or_else(|| panic!("{set} {method} missing: {json}"));
            assert_eq!(r["agree"], true, "{r}");
            assert!(r["queries_per_second"].as_f64().unwrap() > 0.0);
        }
    }
    for signs in json["signs"].as_array().unwrap() {
        assert!(signs["decisive"].as_u64().unwrap() > 0, "{signs}");
        assert_eq!(signs["winding_agrees"], signs["decisive"], "{signs}");
    }
    // The table names both sets.
    let out = proxima(&["bench", BUNNY, "--query", "sdf", "--queries", "100", "--set", "uniform"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("uniform set") && !text.contains("near set"), "{text}");
    assert!(text.contains("pseudonormal takes"), "{text}");
}

/// `--cube H` and `--uniform-fraction F` (the options `proxima.dataset`
/// samples with): the library's training samples in that cube, split as
/// `training_sample_counts` says, and the grid over the cube; values out of
/// range are refused in one line before the mesh is read.
#[test]
fn samples_and_grids_in_a_cube() {
    let dir = temp_dir("sdf_cube");
    let (samples, values) = (dir.join("s.npz"), dir.join("g.npy"));
    let (samples, values) = (samples.to_str().unwrap(), values.to_str().unwrap());
    fn bunny_args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
        [&["sdf", BUNNY][..], extra].concat()
    }
    proxima(&bunny_args(&[
        "--sample",
        "300",
        "--near-sigma",
        "0.01",
        "--uniform-fraction",
        "0.25",
        "--cube",
        "2",
        "--seed",
        "9",
        "--out",
        samples,
    ]));
    let mut archive = zip::ZipArchive::new(std::fs::File::open(samples).unwrap()).unwrap();
    let mut read = |name: &str| {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut archive.by_name(name).unwrap(), &mut bytes).unwrap();
        read_npy(&bytes).2
    };
    let (points, sdf) = (read("points.npy"), read("sdf.npy"));
    let points: Vec<Vec3> = points.chunks(3).map(Vec3::from_slice).collect();
    let field = field(&bunny(), Sign::WindingNumber, 300);
    let (near, uniform) = proxima::sample::training_sample_counts(300, 0.25);
    assert_eq!((near, uniform), (225, 75));
    let cube = proxima::Aabb::new(Vec3::splat(-2.0), Vec3::splat(2.0));
    let expected = field.training_samples(near, 0.01, uniform, &cube, 9).unwrap();
    assert_eq!(points, expected.points);
    assert_eq!(sdf, expected.signed_distances);
    assert!(points[near..].iter().all(|p| p.abs().max_element() <= 2.0));
    assert!(
        points[near..].iter().any(|p| p.abs().max_element() > 1.9),
        "the whole cube, not the box"
    );

    proxima(&bunny_args(&["--grid", "5", "--cube", "2", "--out", values]));
    let (shape, fortran, grid) = read_npy(&std::fs::read(values).unwrap());
    assert_eq!((shape, fortran), (vec![5, 5, 5], true));
    let over = SdfGrid::over(&cube, [5; 3]).unwrap();
    assert_eq!(grid, field.sdf_grid(&over, |_, _| {}).unwrap());

    for (extra, message) in [
        (
            &["--sample", "10", "--uniform-fraction", "1.5"][..],
            "--uniform-fraction must be between 0 and 1, got 1.5",
        ),
        (
            &["--sample", "10", "--cube", "0"][..],
            "--cube must be a finite number above 0, got 0",
        ),
        (
            &["--grid", "4", "--cube", "-inf"][..],
            "--cube must be a finite number above 0, got -inf",
        ),
    ] {
        let args = [
            &bunny_args(extra)[..],
            &["--out", samples.strip_suffix(".npz").unwrap()],
        ]
        .concat();
        let out = Command::new(env!("CARGO_BIN_EXE_proxima"))
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert_eq!(err.trim_end(), format!("proxima: {message}"));
    }
}
