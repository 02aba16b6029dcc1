//! Hash grid, voxelization and traversal benchmarks:
//!
//! - `insert`: classic against scan-line insertion, at cell sizes where a
//!   triangle overlaps about 1, 10 and 100 cells (calibrated on the mesh);
//! - `hasher`: grid build and cell lookups with the classic hash, the fast
//!   hash and std's SipHash, and the compact storage against one `Vec` per cell;
//! - `voxelize`: 256³ on the dragon (or ico1m without the shared data),
//!   single-thread and on the rayon pool;
//! - `traversal`: Amanatides–Woo steps per second.
//!
//! `cargo bench -p proxima-bench --bench grid`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use proxima::grid::{
    Cell, ClassicHash, FastHash, GridConfig, GridInsert, GridLayout, HashGrid, InsertMethod, InsertParams, VoxelConfig,
    voxelize,
};
use proxima::grid::{GridTraversal, TraversalConfig};
use proxima::sample::Rng;
use proxima::{Mesh, PrimitiveSet, Triangle, Vec3};
use proxima_bench::load_named;
use std::collections::HashMap;
use std::collections::hash_map::RandomState;
use std::hash::BuildHasher;
use std::hint::black_box;
use std::time::Duration;

fn mesh_or(name: &str, fallback: &str) -> (String, Mesh) {
    match load_named(name) {
        Ok(m) => (name.to_string(), m),
        Err(_) => (fallback.to_string(), load_named(fallback).expect("generated mesh")),
    }
}

fn count_cells(tris: &[Triangle], layout: &GridLayout, method: InsertMethod) -> u64 {
    let params = InsertParams {
        method,
        max_cells: u64::MAX,
        ..InsertParams::new(layout)
    };
    let mut n = 0u64;
    for t in tris {
        t.visit_cells(&params, |_| n += 1).expect("finite");
    }
    n
}

/// The cubic cell size at which the triangles overlap `target` cells each on
/// average (bisection in log space on a sample).
fn calibrate(tris: &[Triangle], target: f64) -> f32 {
    let sample: Vec<Triangle> = tris.iter().step_by((tris.len() / 2000).max(1)).copied().collect();
    let side = sample.iter().map(|t| (t.b - t.a).length()).sum::<f32>() / sample.len() as f32;
    let (mut lo, mut hi) = ((side * 0.005).ln(), (side * 50.0).ln());
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        let layout = GridLayout::cubic(mid.exp()).expect("positive");
        let mean = count_cells(&sample, &layout, InsertMethod::Classic) as f64 / sample.len() as f64;
        if mean > target { lo = mid } else { hi = mid }
    }
    (0.5 * (lo + hi)).exp()
}

fn insert(c: &mut Criterion) {
    let (name, mesh) = mesh_or("stanford-bunny.obj", "ico100k");
    let tris = mesh.triangles().primitives;
    let mut group = c.benchmark_group(format!("grid/insert/{name}"));
    group.sample_size(10).measurement_time(Duration::from_secs(4));
    for target in [1.0, 10.0, 100.0] {
        let size = calibrate(&tris, target);
        let layout = GridLayout::cubic(size).expect("positive");
        // Fewer triangles at 100 cells each, so an iteration stays short.
        let subset = &tris[..if target > 50.0 { tris.len() / 8 } else { tris.len() }];
        let cells = count_cells(subset, &layout, InsertMethod::Classic) as f64 / subset.len() as f64;
        group.throughput(Throughput::Elements(subset.len() as u64));
        for method in [InsertMethod::Classic, InsertMethod::Scanline] {
            let id = BenchmarkId::new(format!("{method:?}"), format!("{cells:.1} cells per triangle"));
            group.bench_function(id, |b| b.iter(|| count_cells(black_box(subset), &layout, method)));
        }
    }
    group.finish();
}

/// The simple storage the compact one replaced: one `Vec` per cell.
fn vec_per_cell<S: BuildHasher + Default>(tris: &[Triangle], layout: &GridLayout) -> HashMap<Cell, Vec<u32>, S> {
    let params = InsertParams::new(layout);
    let mut map: HashMap<Cell, Vec<u32>, S> = HashMap::default();
    for (p, t) in tris.iter().enumerate() {
        t.visit_cells(&params, |c| map.entry(c).or_default().push(p as u32))
            .expect("finite");
    }
    map
}

fn hashers(c: &mut Criterion) {
    for name in ["stanford-bunny.obj", "dragon_vrip_res2.ply"] {
        let Ok(mesh) = load_named(name) else { continue };
        let tris = mesh.triangles().primitives;
        let size = calibrate(&tris, 2.0);
        let config = GridConfig::cubic(size);
        let layout = config.layout().expect("valid");
        let set = PrimitiveSet::from_primitives(tris.clone());
        let mut group = c.benchmark_group(format!("grid/hasher/{name}"));
        group.sample_size(10).measurement_time(Duration::from_secs(4));
        group.throughput(Throughput::Elements(tris.len() as u64));
        group.bench_function("build classic", |b| {
            b.iter(|| HashGrid::<Triangle, ClassicHash>::build(set.clone(), &config))
        });
        group.bench_function("build fast", |b| {
            b.iter(|| HashGrid::<Triangle, FastHash>::build(set.clone(), &config))
        });
        group.bench_function("build siphash", |b| {
            b.iter(|| HashGrid::<Triangle, RandomState>::build(set.clone(), &config))
        });
        group.bench_function("build vec-per-cell fast", |b| {
            b.iter(|| vec_per_cell::<FastHash>(&tris, &layout))
        });
        // Lookups: every occupied cell and as many empty neighbours.
        let grid_c = HashGrid::<Triangle, ClassicHash>::build(set.clone(), &config).expect("grid");
        let grid_f = HashGrid::<Triangle, FastHash>::build(set.clone(), &config).expect("grid");
        let simple = vec_per_cell::<FastHash>(&tris, &layout);
        let keys: Vec<Cell> = grid_c
            .occupied()
            .flat_map(|(c, _)| [c, [c[0] + 7, c[1] - 5, c[2] + 3]])
            .collect();
        group.throughput(Throughput::Elements(keys.len() as u64));
        group.bench_function("lookup classic", |b| {
            b.iter(|| keys.iter().map(|k| grid_c.cell(k).len()).sum::<usize>())
        });
        group.bench_function("lookup fast", |b| {
            b.iter(|| keys.iter().map(|k| grid_f.cell(k).len()).sum::<usize>())
        });
        group.bench_function("lookup vec-per-cell fast", |b| {
            b.iter(|| keys.iter().map(|k| simple.get(k).map_or(0, Vec::len)).sum::<usize>())
        });
        group.finish();
    }
}

fn voxelization(c: &mut Criterion) {
    let (name, mesh) = mesh_or("dragon_vrip.ply.gz", "ico1m");
    let tris = mesh.triangles().primitives;
    let bounds = mesh.bounds();
    let mut group = c.benchmark_group(format!("grid/voxelize/{name}"));
    group.sample_size(10).measurement_time(Duration::from_secs(6));
    group.throughput(Throughput::Elements(tris.len() as u64));
    for res in [256] {
        for (label, parallel, insert) in [
            ("1 thread classic", false, InsertMethod::Classic),
            ("1 thread scanline", false, InsertMethod::Scanline),
            ("pool scanline", true, InsertMethod::Scanline),
        ] {
            let config = VoxelConfig {
                parallel,
                insert,
                ..VoxelConfig::new(res)
            };
            group.bench_function(BenchmarkId::new(label, res), |b| {
                b.iter(|| voxelize(&tris, &bounds, &config))
            });
        }
    }
    group.finish();
}

fn traversal(c: &mut Criterion) {
    let config = TraversalConfig {
        max_steps: 10_000,
        ..TraversalConfig::cubic(0.001)
    };
    let mut rng = Rng::new(3);
    let rays: Vec<(Vec3, Vec3)> = (0..200)
        .map(|_| {
            let o = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            (
                o,
                Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)).normalize_or(Vec3::X),
            )
        })
        .collect();
    let mut group = c.benchmark_group("grid/traversal");
    group.sample_size(20).measurement_time(Duration::from_secs(4));
    group.throughput(Throughput::Elements(200 * 10_000));
    group.bench_function("steps", |b| {
        b.iter(|| {
            let mut acc = 0i64;
            for &(o, d) in &rays {
                for s in GridTraversal::new(o, d, &config).expect("valid") {
                    acc = acc.wrapping_add(s.cell[0] ^ s.cell[1] ^ s.cell[2]);
                }
            }
            acc
        })
    });
    group.finish();
}

criterion_group!(benches, insert, hashers, voxelization, traversal);
criterion_main!(benches);
