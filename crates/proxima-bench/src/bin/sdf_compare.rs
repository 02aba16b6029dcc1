//! Signed distance, winding numbers and the plain closest query, single
//! thread, in one run; with `--export DIR`, the meshes, query sets and
//! answers that `peers/sdf_peers.py` times Open3D and libigl on.
//!
//! ```text
//! cargo run --release -p proxima-bench --bin sdf_compare -- [MESH|ico1m ...] [--queries N] [--check N] [--rounds N] [--export DIR] [--uncertified] [--sah]
//! ```
//!
//! For each mesh (default: the dragon and `ico1m`) and each query set (`near`
//! and `uniform`, seeded as `compare`): queries per second of the closest
//! query ([`WideTree::closest`]), of `signed_distance` with the
//! winding-number sign and with the pseudonormal sign, of `winding_number`
//! alone, one query after the other in input order, and as batches on a
//! one-thread pool (Morton order). The structures are timed in interleaved
//! rounds, each timing after an untimed run of the same queries, and the best
//! round of each is kept, as `compare` does; the time ratios to the closest
//! query come both as the ratio of best times and as the median of each
//! round's own ratio (steadier when the machine's load drifts).
//!
//! The sign check: the first `--check` points of each set (default 500) get
//! the exact winding number (every triangle's solid angle in `f64`, on all the
//! cores the process may use); printed are the largest error of the fast
//! winding number and the points whose fast and exact signs differ where
//! the exact winding number is more than 0.01 from ½ (must be none).
//!
//! `--export DIR` writes, per mesh, `DIR/NAME/mesh.ply` (binary little-endian,
//! float coordinates, the faces fanned into triangles), and per query set
//! `SET.npy` (the points, `(n, 3)` float32), `SET_sd.npy` and `SET_w.npy`
//! (signed distance and winding number with the winding-number sign),
//! `SET_pn_sd.npy` (signed distance with the pseudonormal sign), and
//! `SET_exact_w.npy` (the exact winding numbers of the checked points,
//! float64); `timings.json` holds the queries per second measured here.

use proxima::prelude::*;
use proxima::sdf::{WindingStats, winding_number_exact};
use proxima_bench::load_named;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Runs `f` once untimed, then times a second run: every method is measured
/// warm, and not cold from the rounds of the others in between.
fn warm<T>(f: impl Fn() -> T) -> (T, f64) {
    std::hint::black_box(f());
    let start = Instant::now();
    let v = f();
    (v, start.elapsed().as_secs_f64())
}

/// The median of `values` (sorted in place).
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The methods timed, in table order: a name for the table and for
/// `timings.json`.
const METHODS: [&str; 8] = [
    "closest",
    "closest_batch",
    "sd_winding",
    "sd_winding_batch",
    "sd_pseudonormal",
    "sd_pseudonormal_batch",
    "winding_number",
    "winding_number_batch",
];

/// What the command line asked for.
struct Options {
    names: Vec<String>,
    queries: usize,
    check: usize,
    rounds: usize,
    export: Option<PathBuf>,
    /// The winding-number field without its sign certificate
    /// (`SdfConfig::certify` off): every signed distance walks the winding
    /// number, as before the certificate.
    uncertified: bool,
    /// Trees split by the binned surface area heuristic
    /// (`BuildConfig::fast_queries`) instead of the default median split.
    sah: bool,
}

fn parse_options() -> Result<Options, String> {
    let mut options = Options {
        names: Vec::new(),
        queries: 20_000,
        check: 500,
        rounds: 5,
        export: None,
        uncertified: false,
        sah: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |flag: &str| args.next().ok_or_else(|| format!("{flag} needs a value"));
        let mut number = |flag: &str| -> Result<usize, String> {
            let v = value(flag)?;
            v.parse().map_err(|_| format!("{flag} {v}: not a whole number"))
        };
        match a.as_str() {
            "--queries" => options.queries = number("--queries")?.max(1),
            "--check" => options.check = number("--check")?,
            "--rounds" => options.rounds = number("--rounds")?.max(1),
            "--export" => options.export = Some(PathBuf::from(value("--export")?)),
            "--uncertified" => options.uncertified = true,
            "--sah" => options.sah = true,
            flag if flag.starts_with("--") => return Err(format!("unknown option {flag}")),
            _ => options.names.push(a),
        }
    }
    if options.names.is_empty() {
        options.names = vec!["dragon_vrip.ply.gz".into(), "ico1m".into()];
    }
    Ok(options)
}

/// The folder name of a mesh in the export: its file name without the
/// extensions (`dragon_vrip.ply.gz` -> `dragon_vrip`).
fn export_name(name: &str) -> String {
    let file = Path::new(name).file_name().map_or(name.into(), |f| f.to_string_lossy());
    file.split('.').next().unwrap_or(&file).to_string()
}

/// A `.npy` file (format 1.0) of little-endian values of numpy type `descr`
/// (`<f4`, `<f8`), C order.
fn write_npy(path: &Path, descr: &str, shape: &[usize], data: &[u8]) -> std::io::Result<()> {
    let shape = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape.iter().map(|d| d.to_string()).collect::<Vec<_>>().join(", ")
        ),
    };
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // The magic, version and length take 10 bytes; numpy wants the data
    // aligned to 64 bytes and the header closed by a newline.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = Vec::with_capacity(10 + header.len() + data.len());
    bytes.extend_from_slice(b"\x93NUMPY\x01\x00");
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(data);
    std::fs::write(path, bytes)
}

fn f32_bytes(values: impl IntoIterator<Item = f32>) -> Vec<u8> {
    values.into_iter().flat_map(f32::to_le_bytes).collect()
}

/// The mesh as a binary little-endian PLY, polygons fanned into triangles
/// as [`Mesh::triangles`] fans them.
fn write_ply(path: &Path, mesh: &Mesh) -> std::io::Result<()> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.vertex_count(),
        mesh.triangle_count()
    );
    let mut bytes = header.into_bytes();
    bytes.extend(f32_bytes(mesh.positions().iter().flat_map(|p| p.to_array())));
    for face in mesh.faces() {
        for w in face[1..].windows(2) {
            bytes.push(3);
            for v in [face[0], w[0], w[1]] {
                bytes.extend_from_slice(&(v as i32).to_le_bytes());
            }
        }
    }
    std::fs::write(path, bytes)
}

/// The answers of one query set kept for the export.
struct SetAnswers {
    points: Vec<Vec3>,
    signed: Vec<f32>,
    winding: Vec<f32>,
    pseudonormal: Vec<f32>,
    exact: Vec<f64>,
    rates: Vec<f64>,
}

fn run_set(
    set: &str,
    points: Vec<Vec3>,
    winding_field: &SignedDistanceField,
    pseudonormal_field: &SignedDistanceField,
    options: &Options,
) -> SetAnswers {
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let tree = winding_field.tree();
    let n = points.len();
    let mut best = [f64::INFINITY; METHODS.len()];
    // Each round's own time ratios to the closest query (pseudonormal,
    // winding-number sign) and to the closest batch (the same as batches).
    let mut round_ratios: [Vec<f64>; 4] = Default::default();
    let distances = |answers: &[Option<SignedDistance>]| -> Vec<f32> {
        answers.iter().map(|s| s.expect("finite query").distance).collect()
    };
    let (mut closest, mut signed, mut pseudonormal, mut winding) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..options.rounds {
        let mut t = [0.0; METHODS.len()];
        (closest, t[0]) = warm(|| points.iter().map(|&p| tree.closest(p)).collect::<Vec<_>>());
        let closest_batch;
        (closest_batch, t[1]) =
            warm(|| one_thread.install(|| tree.closest_batch_with(&points, BatchOptions::default())));
        assert_eq!(
            closest_batch, closest,
            "{set}: closest batch and single queries disagree"
        );
        let answers;
        (answers, t[2]) = warm(|| {
            points
                .iter()
                .map(|&p| winding_field.signed_distance(p))
                .collect::<Vec<_>>()
        });
        signed = distances(&answers);
        let batch;
        (batch, t[3]) = warm(|| one_thread.install(|| winding_field.signed_distance_batch(&points)));
        assert_eq!(
            batch, answers,
            "{set}: signed distance batch and single queries disagree"
        );
        let answers;
        (answers, t[4]) = warm(|| {
            points
                .iter()
                .map(|&p| pseudonormal_field.signed_distance(p))
                .collect::<Vec<_>>()
        });
        pseudonormal = distances(&answers);
        let batch;
        (batch, t[5]) = warm(|| one_thread.install(|| pseudonormal_field.signed_distance_batch(&points)));
        assert_eq!(batch, answers, "{set}: pseudonormal batch and single queries disagree");
        (winding, t[6]) = warm(|| {
            points
                .iter()
                .map(|&p| winding_field.winding_number(p))
                .collect::<Vec<_>>()
        });
        // Where the certificate decides, signed_distance's winding number
        // is the integer of its side plus the caps' winding number, not the
        // tree's value: the check below compares both sides with the exact one.
        let batch;
        (batch, t[7]) = warm(|| one_thread.install(|| winding_field.winding_number_batch(&points)));
        assert_eq!(
            batch, winding,
            "{set}: winding number batch and single queries disagree"
        );
        for (b, t) in best.iter_mut().zip(t) {
            *b = b.min(t);
        }
        round_ratios[0].push(t[4] / t[0]);
        round_ratios[1].push(t[2] / t[0]);
        round_ratios[2].push(t[5] / t[1]);
        round_ratios[3].push(t[3] / t[1]);
    }
    // Same triangle, same distance: only the sign may differ from the
    // closest query's answer.
    for (k, c) in closest.iter().enumerate() {
        let d = c.unwrap().distance;
        assert!(
            signed[k].abs() == d && pseudonormal[k].abs() == d,
            "{set}: point {k}: |signed distance| differs from the closest query's distance"
        );
    }
    let rates: Vec<f64> = best.iter().map(|&t| n as f64 / t).collect();
    let ratio = |a: usize, b: usize| best[a] / best[b];
    println!(
        "| {set} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.2}x ({:.2}x) | {:.2}x ({:.2}x) | {:.2}x ({:.2}x) | {:.2}x ({:.2}x) |",
        rates[0],
        rates[1],
        rates[2],
        rates[3],
        rates[4],
        rates[5],
        rates[6],
        rates[7],
        ratio(4, 0),
        median(&mut round_ratios[0]),
        ratio(2, 0),
        median(&mut round_ratios[1]),
        ratio(5, 1),
        median(&mut round_ratios[2]),
        ratio(3, 1),
        median(&mut round_ratios[3]),
    );
    // The oracle on the first points of the set, on all cores.
    let checked = &points[..options.check.min(n)];
    let triangles = winding_field.triangles();
    let exact: Vec<f64> = checked
        .par_iter()
        .map(|&p| winding_number_exact(triangles, p))
        .collect();
    SetAnswers {
        points,
        signed,
        winding,
        pseudonormal,
        exact,
        rates,
    }
}

/// The work per query of the closest query and of the winding number: what
/// the time of a signed distance is spent on.
fn work_profile(set: &str, points: &[Vec3], field: &SignedDistanceField) {
    let n = points.len() as f64;
    let (mut nodes, mut primitives) = (0, 0);
    let mut winding = WindingStats::default();
    let mut certified = 0usize;
    for &p in points {
        let (closest, stats) = field.tree().closest_with_stats(p);
        nodes += stats.nodes_visited;
        primitives += stats.primitives_tested;
        field.winding_numbers().winding_number_with_stats(p, &mut winding);
        if let (Some(certificate), Some(closest)) = (field.certificate(), closest) {
            certified += usize::from(certificate.winding_number(&closest, p).is_some());
        }
    }
    println!(
        "work per query, {set}: closest {:.1} wide nodes, {:.1} triangles; winding number {:.1} wide nodes, {:.1} expansions, {:.1} triangles summed exactly; sign from the certificate {:.2}%",
        nodes as f64 / n,
        primitives as f64 / n,
        winding.nodes as f64 / n,
        winding.expansions as f64 / n,
        winding.triangles as f64 / n,
        100.0 * certified as f64 / n,
    );
}

/// The sign check of one set: largest error of the fast winding number,
/// and the sign differences where the exact winding number is clear of ½.
fn print_check(set: &str, answers: &SetAnswers) -> usize {
    let clear = |w: f64| (w - 0.5).abs() > 0.01;
    let mut worst = 0f64;
    let (mut clear_points, mut wrong_fast, mut wrong_signed, mut wrong_pseudonormal) = (0, 0, 0, 0);
    for (k, &exact) in answers.exact.iter().enumerate() {
        worst = worst.max((answers.winding[k] as f64 - exact).abs());
        if !clear(exact) {
            continue;
        }
        clear_points += 1;
        let inside = exact > 0.5;
        wrong_fast += usize::from((answers.winding[k] > 0.5) != inside);
        // A point on the surface (distance 0) has no side to get wrong.
        let wrong = |d: f32| d != 0.0 && (d < 0.0) != inside;
        wrong_signed += usize::from(wrong(answers.signed[k]));
        wrong_pseudonormal += usize::from(wrong(answers.pseudonormal[k]));
    }
    println!(
        "sign check, {set}: {} points against the exact winding number: max |w - exact| {worst:.2e}; of the {clear_points} with |exact - 1/2| > 0.01, sign differs: fast winding number {wrong_fast}, signed distance {wrong_signed} (must be 0), pseudonormal {wrong_pseudonormal}",
        answers.exact.len()
    );
    wrong_fast + wrong_signed
}

fn export(dir: &Path, mesh: &Mesh, sets: &[(&str, SetAnswers)], json: &str) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    write_ply(&dir.join("mesh.ply"), mesh)?;
    for (set, a) in sets {
        let n = a.points.len();
        let points = f32_bytes(a.points.iter().flat_map(|p| p.to_array()));
        write_npy(&dir.join(format!("{set}.npy")), "<f4", &[n, 3], &points)?;
        for (suffix, values) in [("sd", &a.signed), ("w", &a.winding), ("pn_sd", &a.pseudonormal)] {
            let bytes = f32_bytes(values.iter().copied());
            write_npy(&dir.join(format!("{set}_{suffix}.npy")), "<f4", &[n], &bytes)?;
        }
        let exact: Vec<u8> = a.exact.iter().flat_map(|w| w.to_le_bytes()).collect();
        write_npy(&dir.join(format!("{set}_exact_w.npy")), "<f8", &[a.exact.len()], &exact)?;
    }
    std::fs::write(dir.join("timings.json"), json)
}

/// Returns the number of sign errors found by the check.
fn run_mesh(name: &str, mesh: &Mesh, options: &Options) -> Result<usize, String> {
    println!(
        "\n## {name}: {} triangles, {} queries per set, best of {} interleaved rounds, one thread",
        mesh.triangle_count(),
        options.queries,
        options.rounds
    );
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let build = |sign| {
        let config = SdfConfig {
            sign,
            certify: !options.uncertified,
            build: if options.sah {
                proxima::BuildConfig::fast_queries()
            } else {
                proxima::BuildConfig::default()
            },
            ..SdfConfig::default()
        };
        let start = Instant::now();
        let field = one_thread.install(|| SignedDistanceField::new(mesh, &config));
        field
            .map(|f| (f, start.elapsed().as_secs_f64()))
            .map_err(|e| e.to_string())
    };
    let (winding_field, t_winding) = build(Sign::WindingNumber)?;
    let (pseudonormal_field, t_pseudonormal) = build(Sign::Pseudonormal)?;
    println!(
        "build on 1 thread (wide tree and expansions): winding-number sign {t_winding:.2} s, pseudonormal sign {t_pseudonormal:.2} s"
    );
    match winding_field.certificate() {
        Some(c) => {
            let s = c.stats();
            println!(
                "sign certificate: {} of {} triangles certified ({:.2}%), {} components, {} boundary loops capped, {} triangles meet another or a cap",
                s.certified,
                s.triangles,
                100.0 * s.certified as f64 / s.triangles.max(1) as f64,
                s.components,
                s.boundary_loops,
                s.meeting
            );
        }
        None => println!("sign certificate: off (--uncertified)"),
    }
    println!(
        "\nqueries per second; ratios are times to the closest query's (best rounds, median of each round's own ratio in parentheses); batches on a 1-thread pool in Morton order"
    );
    println!(
        "| query set | closest | closest batch | sd winding | sd winding batch | sd pseudonormal | sd pseudonormal batch | winding number | winding number batch | pseudonormal / closest | winding sd / closest | pseudonormal batch / closest batch | winding sd batch / closest batch |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut sets = Vec::new();
    for (set, points) in [
        ("near", proxima::sample::near_surface(mesh, options.queries, 0.01, 1)),
        ("uniform", proxima::sample::uniform_in_box(mesh, options.queries, 2)),
    ] {
        sets.push((set, run_set(set, points, &winding_field, &pseudonormal_field, options)));
    }
    for (set, answers) in &sets {
        work_profile(set, &answers.points, &winding_field);
    }
    let mut errors = 0;
    for (set, answers) in &sets {
        errors += print_check(set, answers);
    }
    let mut sign_differences = String::new();
    for (set, a) in &sets {
        let differ = a
            .signed
            .iter()
            .zip(&a.pseudonormal)
            .filter(|(w, p)| (**w < 0.0) != (**p < 0.0))
            .count();
        let _ = write!(sign_differences, " {set} {differ} of {};", a.points.len());
    }
    println!("pseudonormal sign differs from the winding-number sign:{sign_differences}");
    if let Some(dir) = &options.export {
        let mut json = format!(
            "{{\n  \"mesh\": \"{}\",\n  \"triangles\": {},\n  \"queries\": {},\n  \"rounds\": {},\n  \"sets\": {{",
            name.replace('\\', "/").replace('"', ""),
            mesh.triangle_count(),
            options.queries,
            options.rounds
        );
        for (s, (set, a)) in sets.iter().enumerate() {
            let rates: Vec<String> = METHODS
                .iter()
                .zip(&a.rates)
                .map(|(m, r)| format!("\"{m}\": {r:.1}"))
                .collect();
            let comma = if s + 1 < sets.len() { "," } else { "" };
            let _ = write!(json, "\n    \"{set}\": {{{}}}{comma}", rates.join(", "));
        }
        json.push_str("\n  }\n}\n");
        let dir = dir.join(export_name(name));
        export(&dir, mesh, &sets, &json).map_err(|e| format!("export to {}: {e}", dir.display()))?;
        println!("exported to {}", dir.display());
    }
    Ok(errors)
}

fn main() {
    let options = parse_options().unwrap_or_else(|e| {
        eprintln!("sdf_compare: {e}");
        std::process::exit(2);
    });
    let mut failed = false;
    for name in &options.names {
        let outcome = load_named(name).and_then(|mesh| run_mesh(name, &mesh, &options));
        match outcome {
            Ok(0) => {}
            Ok(errors) => {
                eprintln!("sdf_compare: {name}: {errors} sign errors against the exact winding number");
                failed = true;
            }
            Err(e) => {
                eprintln!("sdf_compare: {name}: {e}");
                failed = true;
            }
        }
    }
    if failed {
        std::process::exit(1);
    }
}
