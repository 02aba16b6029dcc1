//! The CI stand-in for the libFuzzer runs: every fuzz target's body (shared
//! with `fuzz/fuzz_targets/`, see `fuzz/bodies.rs`) is fed the seed corpus,
//! the real meshes cut to a size limit, and a few thousand seeded random and
//! mutated inputs. A panic or a disagreement with brute force fails the test.
//! The long, coverage-guided runs are `fuzz/run.sh`.

use crate::bodies;
use crate::common;

use proxima::sample::Rng;
use serde_json::{Value, json};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Real meshes are cut to this many bytes before they become seeds.
const SEED_LIMIT: usize = 64 * 1024;
/// Random and mutated inputs per target.
const CASES: usize = 3000;

fn seed_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/seeds"))
}

fn read_cut(path: &Path) -> Vec<u8> {
    let mut bytes = std::fs::read(path).expect("readable seed");
    bytes.truncate(SEED_LIMIT);
    bytes
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

/// The seed files (committed ones, then the shared meshes cut to
/// [`SEED_LIMIT`]) whose name ends with `extension`.
fn seeds_for(extension: &str) -> Vec<Vec<u8>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(seed_dir())
        .expect("fuzz/seeds")
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files.extend(common::shared_meshes());
    files
        .iter()
        .filter(|p| p.to_string_lossy().to_lowercase().ends_with(extension))
        .map(|p| read_cut(p))
        .collect()
}

/// The seeds of a target, as the libFuzzer corpus of `fuzz/run.sh` holds them.
fn corpus(target: &str) -> Vec<Vec<u8>> {
    match target {
        "load_obj" => seeds_for(".obj"),
        "load_ply" => seeds_for(".ply"),
        "load_stl" => seeds_for(".stl"),
        "load_off" => seeds_for(".off"),
        "load_glb" => seeds_for(".glb"),
        "load_gzip" => [".obj", ".ply", ".stl", ".off", ".glb"]
            .iter()
            .enumerate()
            .flat_map(|(format, ext)| {
                seeds_for(ext).into_iter().map(move |s| {
                    let mut input = vec![format as u8];
                    input.extend(gzip(&s));
                    input
                })
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// Tokens a mutation may insert: the boundary values loaders must survive.
const TOKENS: &[&[u8]] = &[
    b" -1",
    b" 0",
    b" 4294967296",
    b" 1e999",
    b" nan",
    b" inf",
    b"\n",
    b"\r\n",
    b"/",
    b"//",
    b" 99999999999999999999",
    b"\nf 1 2 3\n",
    b"\nv 0 0 0\n",
    b"element vertex 1000000000000\n",
    b"\0",
    b"\\\n",
    b"endloop",
    b"3 0 0 0",
];

/// One mutation of `input`: byte flips, truncation, a duplicated or deleted
/// chunk, or an inserted token.
fn mutate(input: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut out = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = out.len();
        match rng.below(6) {
            0 if len > 0 => {
                let at = rng.below(len);
                out[at] ^= 1 << rng.below(8);
            }
            1 if len > 0 => out.truncate(rng.below(len)),
            2 if len > 0 => {
                let (a, b) = (rng.below(len), rng.below(len));
                let chunk = out[a.min(b)..a.max(b)].to_vec();
                let at = rng.below(out.len() + 1);
                out.splice(at..at, chunk);
            }
            3 if len > 0 => {
                let (a, b) = (rng.below(len), rng.below(len));
                out.drain(a.min(b)..a.max(b));
            }
            4 => {
                let at = rng.below(len + 1);
                out.splice(at..at, TOKENS[rng.below(TOKENS.len())].iter().copied());
            }
            _ => {
                let at = rng.below(len + 1);
                out.insert(at, rng.next_u64() as u8);
            }
        }
    }
    out
}

/// GLB inputs grown from the GLB seeds in the ways that cost a reader most
/// for their size: a mesh shown by many more nodes (instancing), a large
/// array in a member the reader skips (`extras`) or keeps (a node's
/// `children`, a scene's `nodes`), and accessor counts raised (more
/// triangles than the data holds).
const GLB_CASES: usize = 400;

/// One such mutation of a GLB `seed` (`None` when its JSON does not parse).
fn mutate_glb(seed: &[u8], rng: &mut Rng) -> Option<Vec<u8>> {
    let json_len = u32::from_le_bytes(seed.get(12..16)?.try_into().ok()?) as usize;
    let json = seed.get(20..20 + json_len)?;
    let rest = &seed[20 + json_len..];
    let mut doc: Value = serde_json::from_slice(json).ok()?;
    // Sizes spread over orders of magnitude, most of them small.
    let size = 1usize << rng.below(15);
    match rng.below(4) {
        0 => {
            // Instancing: many nodes showing one mesh, as roots or through a scene.
            let meshes = doc["meshes"].as_array().map_or(1, Vec::len).max(1);
            let mesh = rng.below(meshes);
            let n = size;
            let nodes = doc["nodes"].as_array().map_or(0, Vec::len);
            let added: Vec<Value> = (0..n)
                .map(|i| json!({"mesh": mesh, "translation": [i, 0, 0]}))
                .collect();
            if let Some(list) = doc["nodes"].as_array_mut() {
                list.extend(added);
            } else {
                doc["nodes"] = Value::Array(added);
            }
            if rng.below(2) == 0 {
                doc["scenes"] = json!([{"nodes": (nodes..nodes + n).collect::<Vec<_>>()}]);
                doc["scene"] = json!(0);
            } else if let Some(object) = doc.as_object_mut() {
                object.remove("scenes");
                object.remove("scene");
            }
        }
        1 => {
            // A large array the reader skips.
            doc["extras"] = Value::Array(vec![json!(0); 16 * size]);
        }
        2 => {
            // A large array the reader keeps.
            let big = Value::Array(vec![json!(0); 16 * size]);
            if rng.below(2) == 0 {
                doc["nodes"] = json!([{"children": big}]);
            } else {
                doc["scenes"] = json!([{"nodes": big}]);
            }
        }
        _ => {
            // Accessor counts raised, and strips (a triangle per index).
            let factor = size as u64;
            for accessor in doc["accessors"].as_array_mut()?.iter_mut() {
                if let Some(count) = accessor["count"].as_u64() {
                    accessor["count"] = json!(count.saturating_mul(factor));
                }
            }
            for mesh in doc["meshes"].as_array_mut()?.iter_mut() {
                for primitive in mesh["primitives"].as_array_mut()?.iter_mut() {
                    primitive["mode"] = json!(5);
                }
            }
        }
    }
    let mut json = serde_json::to_vec(&doc).ok()?;
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut out = seed[..12].to_vec();
    out[8..12].copy_from_slice(&((20 + json.len() + rest.len()) as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend(rest);
    Some(out)
}

fn random_bytes(rng: &mut Rng) -> Vec<u8> {
    let len = rng.below(512);
    (0..len).map(|_| rng.next_u64() as u8).collect()
}

/// Runs `body`; on a panic, saves the input where `cargo fuzz run NAME FILE`
/// (and the regression tests) can replay it, then fails.
fn run_or_save(name: &str, body: fn(&[u8]), input: &[u8]) {
    if std::panic::catch_unwind(|| body(input)).is_err() {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-smoke-failures");
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join(format!("{name}-{:016x}", fnv(input)));
        std::fs::write(&file, input).unwrap();
        panic!("fuzz target {name} failed; input saved to {}", file.display());
    }
}

fn fnv(bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(0xcbf29ce484222325, |h, &b| (h ^ b as u64).wrapping_mul(0x100000001b3))
}

#[test]
fn every_fuzz_target_survives_seeds_and_mutations() {
    for (index, &(name, body)) in bodies::TARGETS.iter().enumerate() {
        let seeds = corpus(name);
        let start = std::time::Instant::now();
        for seed in &seeds {
            run_or_save(name, body, seed);
        }
        // Mutations of big seeds cost time without finding more: mutate their heads.
        let heads: Vec<&[u8]> = seeds.iter().map(|s| &s[..s.len().min(4096)]).collect();
        let mut rng = Rng::new(0xF022 + index as u64);
        for case in 0..CASES {
            let input = if heads.is_empty() || case % 4 == 0 {
                random_bytes(&mut rng)
            } else {
                mutate(heads[rng.below(heads.len())], &mut rng)
            };
            run_or_save(name, body, &input);
        }
        let mut glb_cases = 0;
        if name == "load_glb" {
            // Outcomes: loaded, refused by the budget, other errors.
            let mut outcomes = [0; 3];
            let options = proxima::io::LoadOptions {
                memory_budget: bodies::LOAD_BUDGET,
                ..proxima::io::LoadOptions::default()
            };
            for _ in 0..GLB_CASES {
                let seed = &seeds[rng.below(seeds.len())];
                if let Some(input) = mutate_glb(seed, &mut rng) {
                    run_or_save(name, body, &input);
                    glb_cases += 1;
                    outcomes[match proxima::io::parse_with(&input, proxima::io::Format::Glb, "m.glb".as_ref(), &options)
                    {
                        Ok(_) => 0,
                        Err(e) if matches!(e.kind, proxima::LoadErrorKind::MemoryBudget { .. }) => 1,
                        Err(_) => 2,
                    }] += 1;
                }
            }
            assert!(glb_cases > GLB_CASES / 2, "the GLB seeds' JSON parses");
            // The mutations reach both sides of the budget.
            assert!(
                outcomes[0] > 0 && outcomes[1] > 0,
                "loaded, over the budget, other: {outcomes:?}"
            );
            println!("load_glb mutations: loaded, over the budget, other errors: {outcomes:?}");
        }
        println!(
            "{name}: {} seeds + {CASES} random/mutated inputs + {glb_cases} GLB mutations in {:.2} s",
            seeds.len(),
            start.elapsed().as_secs_f64()
        );
    }
}

/// Inputs that once failed (found by this smoke run or by libFuzzer), kept in
/// `fuzz/regressions/<target>/` and replayed: a tree that missed a triangle
/// whose closest-point computation overflowed `f32`, and grid rays that
/// lost hits to `f32` parameters on a long ray, to a tie on a cell boundary
/// and to an origin lying on a boundary.
#[test]
fn saved_fuzz_failures_stay_fixed() {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/regressions"));
    let mut replayed = 0;
    for &(name, body) in bodies::TARGETS {
        let Ok(entries) = std::fs::read_dir(dir.join(name)) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            println!("replaying {}", path.display());
            body(&std::fs::read(&path).unwrap());
            replayed += 1;
        }
    }
    assert!(replayed >= 5, "the saved failures are in fuzz/regressions");
}
